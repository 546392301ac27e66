#!/usr/bin/env python3
"""Add the exact tier (convex pieces, ur_pieces.py) to crates/robot/data/ur_links.json.

usage: derive_pieces.py <Universal_Robots_ROS2_Description repo> [model ...]

Reads the fitted cylinders from ur_links.json and the visual meshes from the repo (bare clones are
fine). Writes ur_pieces_<model>.json: per cylinder (by name) its "pieces" (vertex lists, link DH
frame) and "slack" (m), loaded by the library only for the models a scene uses; ur_links.json gets
per link "pieces_excess_mm" / "pieces_excess_at"; ur_link_vertices.json per link "piece_vertices"
(the visual vertices nearest the pieces' boundary, for the containment test). Every file is
written atomically; the report goes to pieces_report.md.
"""
import fcntl
import json
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402

import derive_ur  # noqa: E402
import ur_pieces  # noqa: E402
import ur_polytopes  # noqa: E402
import ur_vis  # noqa: E402
from common import r6  # noqa: E402
from derive import DATA, dump  # noqa: E402
from ur_kin import DH, LINKS, URDescription  # noqa: E402


def split_pieces(J, model):
    """Move the pieces of `model` out of the shapes in J into ur_pieces_<model>.json."""
    out = {"generator": "tools/geometry/derive_pieces.py", "source": J.get("source"),
           "frames": "each piece in its link's standard-DH frame", "shapes": {}}
    for link in J["models"][model]["links"]:
        for s in link["shapes"]:
            if "pieces" in s:
                out["shapes"][s["name"]] = {"pieces": s.pop("pieces"), "slack": s.pop("slack")}
    if out["shapes"]:
        dump(os.path.join(DATA, f"ur_pieces_{model}.json"), out)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    repo = sys.argv[1]
    links_path = os.path.join(DATA, "ur_links.json")
    verts_path = os.path.join(DATA, "ur_link_vertices.json")
    J = json.load(open(links_path))
    VJ = json.load(open(verts_path))
    models = sys.argv[2:] or list(J["models"])
    DH.setdefault("ur5", dict(d1=0.089159, a2=-0.425, a3=-0.39225, d4=0.10915, d5=0.09465, d6=0.0823))
    rows = []
    for model in models:
        d = URDescription(repo, model)
        X, *_ = d.link_to_dh()
        links = {l["name"]: l for l in J["models"][model]["links"]}
        vlinks = {l["name"]: l for l in VJ["models"][model]["links"]}
        for (name, _, key, fi) in LINKS:
            t0 = time.time()
            vm = derive_ur.load_visual(d, key)
            vm.apply_transform(X[name] @ d.mesh_origin[name])
            V = np.asarray(vm.vertices)
            surf = ur_vis.Surface(V, np.asarray(vm.faces))
            shapes = links[name]["shapes"]
            per = ur_pieces.pieces(name, shapes, V, surf)
            polys, names = [], []
            for s, L in zip(shapes, per):
                s["pieces"] = [r6(P) for P, _ in L]
                s["slack"] = round(max([sl for _, sl in L] or [0.0]) + 2e-6, 6) if L else 0.0
                polys += [np.asarray(P) for P in s["pieces"]]
                names += [s["name"]] * len(L)
            e, at, who = ur_polytopes.measure(polys, surf, names)
            Vc, Sc = ur_vis._cover_points(name, V), ur_vis._cover_points(name, surf.S)
            unc_v = ur_polytopes.uncovered(polys, Vc)
            unc_s = ur_polytopes.uncovered(polys, Sc)
            if unc_v > 1e-6:
                raise SystemExit(f"COVERAGE FAILURE {model} {name}: a visual vertex is {unc_v:.2e} m outside")
            near, _ = ur_polytopes.nearest_boundary(polys, Vc)
            vlinks[name]["piece_vertices"] = r6(near)
            links[name]["pieces_excess_mm"] = round(e * 1e3, 1)
            links[name]["pieces_excess_at"] = r6(np.round(at, 6))
            nv = [len(P) for P in polys]
            rows.append((model, name, links[name]["excess_mm"], e * 1e3, at, who, len(polys), sum(nv),
                         max(s["slack"] for s in shapes) * 1e3, unc_s * 1e3))
            print(f"  {model} {name}: cylinders {links[name]['excess_mm']} mm, pieces {e*1e3:.1f} mm "
                  f"({len(polys)} pieces, {sum(nv)} vertices, {time.time()-t0:.0f} s)", flush=True)
        split_pieces(J, model)
        # several runs (different models) may share the files: merge this model into the latest
        with open(os.path.join(tempfile.gettempdir(), "pregrasp-derive-pieces.lock"), "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            J2, VJ2 = json.load(open(links_path)), json.load(open(verts_path))
            J2["models"][model] = J["models"][model]
            VJ2["models"][model] = VJ["models"][model]
            dump(links_path, J2)
            dump(verts_path, VJ2)
    L = ["### Exact tier: convex pieces inside the cylinders (mm)",
         "excess = as for the cylinders (union boundary sampled every 1.5 mm, distance to the visual surface);"
         " every visual vertex is in the union of the pieces (1e-6 m); samples outside = how far the 0.6 mm"
         " surface samples lie outside it (facets spanning two pieces).",
         "| model | link | cylinders | pieces | worst point (DH frame, m) | on piece of | pieces | vertices |"
         " largest slack | samples outside |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for (m, n, ec, e, at, who, k, nv, sl, us) in rows:
        L.append(f"| {m} | {n} | {ec:.1f} | {e:.1f} | (" + ", ".join(f"{v:.4f}" for v in at) +
                 f") | {who} | {k} | {nv} | {sl:.2f} | {us:.2f} |")
    txt = "\n".join(L)
    print(txt)
    name = "pieces_report.md" if not sys.argv[2:] else f"pieces_report_{'_'.join(models)}.md"
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), name), "w") as f:
        f.write(txt + "\n")


if __name__ == "__main__":
    main()

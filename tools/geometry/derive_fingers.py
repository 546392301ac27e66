#!/usr/bin/env python3
"""Robotiq 2F-85 finger linkage (underactuated, 2 DoF per finger) and convex finger pieces, from the
MuJoCo Menagerie model `robotiq_2f85/` (2f85.xml + assets/*.stl).

usage: derive_fingers.py <mujoco_menagerie repo> [--rev COMMIT]
  The repository may be a bare clone (files are read with `git show COMMIT:path`); COMMIT defaults to
  PINNED below (any commit whose robotiq_2f85/ holds the same files gives the same output).
Writes crates/robot/data/robotiq_2f85_fingers.json (linkage, sampled poses, pieces) and
crates/robot/data/robotiq_2f85_finger_vertices.json (test data: the mesh vertices the pieces must hold).
Needs: numpy scipy trimesh rtree mujoco (pip).

Frames. G = UR flange (tool0): origin on the flange face, +z approach, x closing (pads at ±x), y the
finger width; the data describe the +x finger (the other is its mirror x -> -x). The Menagerie model's
world frame is G up to a turn about z (its origin is the underside of `base_mount`, which sits on the
flange): the turn is chosen so the finger named `right_*` lies at +x. Each link frame L has the body's
origin and G's axes at the zero pose (L = body frame turned by R0, the bodies' common orientation at
qpos = 0); a link pose is [x, z, phi]: translation (x, 0, z) in G and rotation phi about G's +y. Every
Menagerie finger joint axis is G's -y, so a joint angle theta (MuJoCo's sign) turns its link by
phi = -theta about +y.
"""
import os
import subprocess
import sys

import numpy as np
import trimesh
from scipy.spatial import ConvexHull

# The work is in fingers_model.py (the Menagerie model: frames, linkage parameters, link meshes, MuJoCo's
# FK), fingers_linkage.py (the closed-form linkage and the sampled poses), fingers_surface.py (the reference
# solid) and fingers_pieces.py (the convex pieces); this file checks, tabulates and writes the JSON.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import r6  # noqa: E402
from derive import DATA, dump  # noqa: E402
from fingers_linkage import LINKS, kinematics  # noqa: E402
from fingers_model import load, setup  # noqa: E402
from fingers_pieces import (FILL_R, FINAL_STEP, check_inside, decompose, finalize,  # noqa: E402
                            measure, test_vertices)
from fingers_surface import Surface  # noqa: E402

# google-deepmind/mujoco_menagerie, "Improve 2f85 grasp stability by adding some armature to joints."
# (2024-02-15): the last upstream change to robotiq_2f85/ in the snapshot used; the meshes are unchanged
# since the initial launch (1b93125c, 2022-09-07).
PINNED = "a9f3e331238e5ca82923dfbeb93f4589af97b011"

# our robotiq_2f85.json / derive_gripper.MENAGERIE: gap (m) -> pad centre z (m), tips open / closed
TABLE = [(0.0852, 0.1416), (0.0700, 0.1467), (0.0533, 0.1507), (0.0356, 0.1534), (0.0172, 0.1547),
         (0.0, 0.1547)]
TIP_OPEN, TIP_CLOSED = 0.1603, 0.1735

ALIASES = {"driver": "outer_knuckle", "coupler": "outer_finger", "spring_link": "inner_knuckle",
           "follower": "finger_tip (distal phalanx)", "pad": "pad + silicone_pad"}


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    rev = PINNED
    if "--rev" in sys.argv:
        rev = sys.argv[sys.argv.index("--rev") + 1]
        args = [a for a in args if a != rev]
    if len(args) != 1:
        sys.exit(__doc__)
    repo = args[0]
    commit = subprocess.run(["git", "-C", repo, "rev-parse", rev + "^{commit}"], capture_output=True,
                            check=True, text=True).stdout.strip()
    L = []

    def log(s):
        print(s, flush=True)
        L.append(s)

    m, meshes = load(repo, commit)
    S = setup(m, meshes)
    p = S["params"]
    log(f"Menagerie robotiq_2f85 at {commit}; +x finger = Menagerie's '{S['prefix'][:-1]}' finger; "
        f"G = model frame turned by {np.degrees(np.arctan2(S['Rg'][1, 0], S['Rg'][0, 0])):.1f} deg about z")
    lk, par, blocked, worst, pad_c, extras = kinematics(S, L)
    log(f"closed-form linkage vs MuJoCo FK (loop closed, residual <= {worst['closure']:.1e} m): "
        f"max deviation {worst['pose']:.1e} (m / rad)")
    # residuals vs our table (robotiq_2f85.json, derived from the ROS description and aligned to Menagerie)
    res = []
    log("| gap mm | table pad z | Menagerie pad z (this model) | residual mm |")
    log("|---|---|---|---|")
    fine = [lk.parallel(t) for t in np.linspace(S["ranges"]["driver"][0], S["ranges"]["driver"][1], 801)]
    fgap, fpz, ftip = [], [], []
    for q in fine:
        e = extras(lk.poses(q))
        fgap.append(e["gap"]); fpz.append(e["pad_center"][1]); ftip.append(e["tip_z"])
    fgap, fpz, ftip = map(np.array, (fgap, fpz, ftip))
    for g, z in TABLE:
        zz = float(np.interp(g, fgap[::-1], fpz[::-1]))
        res.append({"gap": g, "table_pad_z": z, "pad_z": r6(zz), "residual_mm": round((zz - z) * 1e3, 3)})
        log(f"| {g*1e3:.1f} | {z*1e3:.1f} | {zz*1e3:.2f} | {(zz-z)*1e3:+.2f} |")
    tip_open = float(ftip[0]); tip_closed = float(ftip.max())
    log(f"open (driver 0): gap {fgap[0]*1e3:.2f} mm, pad centre z {fpz[0]*1e3:.2f} (table 141.6, "
        f"{(fpz[0]-0.1416)*1e3:+.2f}), tip z {tip_open*1e3:.2f} (table 160.3, {(tip_open-TIP_OPEN)*1e3:+.2f})")
    log(f"closed: pads touch (gap 0) at driver {float(np.interp(0.0, fgap[::-1], np.linspace(0, 0.8, 801)[::-1])):.4f} rad, "
        f"pad centre z {float(np.interp(0.0, fgap[::-1], fpz[::-1]))*1e3:.2f} (table 154.7); deepest tip z over the stroke "
        f"{tip_closed*1e3:.2f} (table 173.5, {(tip_closed-TIP_CLOSED)*1e3:+.2f}); at driver 0.8: gap {fgap[-1]*1e3:.2f} mm, "
        f"pad z {fpz[-1]*1e3:.2f}, tip z {ftip[-1]*1e3:.2f}")
    log(f"parallel mode: follower tilt (pad angle) {min(s['links']['pad'][2] for s in par):.4f} .. "
        f"{max(s['links']['pad'][2] for s in par):.4f} rad")
    # mirror symmetry (the -x finger is the +x one turned by pi about z in Menagerie; = mirror x -> -x
    # where the links are symmetric in y)
    sym = {}
    for n in LINKS:
        t = S["link_mesh"][n][0]
        Vm = t.vertices * np.array([1, -1, 1])
        sym[n] = float(trimesh.proximity.closest_point(t, Vm)[1].max())
    log("y-mirror asymmetry of the link meshes (mm): " + ", ".join(f"{n} {v*1e3:.3f}" for n, v in sym.items()))

    # pieces
    links_out, verts_out = [], []
    log("| link | meshes | pieces | piece vertices | test vertices | excess mm (holes filled) | worst point (link frame, mm) | excess mm (raw mesh) | filled holes |")
    log("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for n in LINKS:
        t, parts = S["link_mesh"][n]
        surf, cut, pts, hulls = decompose(n, t, log)
        pieces = finalize(n, t, cut, pts, hulls, log)
        ph = [ConvexHull(Q) for Q in pieces]
        e, at = measure(surf, ph)
        raw = Surface(t, 0.0)
        e_raw, _ = measure(raw, ph)
        V, must = test_vertices(t, pieces)
        out = check_inside(pieces, V)
        out_all = check_inside(pieces, np.unique(np.round(t.vertices, 12), axis=0))
        if out > 1e-6 or out_all > 1e-6:
            raise SystemExit(f"{n}: a mesh vertex lies {max(out, out_all)*1e3:.4f} mm outside the pieces")
        rows.append(f"| {n} | {'+'.join(S['geoms'][n]['visual'])} | {len(pieces)} | {sum(len(Q) for Q in pieces)} | "
                    f"{len(V)} | {e*1e3:.2f} | ({at[0]*1e3:.1f}, {at[1]*1e3:.1f}, {at[2]*1e3:.1f}) | {e_raw*1e3:.2f} | "
                    f"{surf.fill_parts} ({surf.fill_volume*1e9:.0f} mm^3) |")
        log(rows[-1])
        links_out.append({
            "name": n, "alias": ALIASES[n],
            "meshes": S["geoms"][n]["visual"], "collision_geoms": S["geoms"][n]["collision"],
            "mesh_vertices": int(len(np.unique(np.round(t.vertices, 12), axis=0))),
            "pieces": [r6(Q) for Q in pieces],
            "excess_mm": round(e * 1e3, 3), "excess_at": r6(at),
            "raw_excess_mm": round(e_raw * 1e3, 3),
            "filled_holes": {"count": surf.fill_parts, "volume_mm3": round(surf.fill_volume * 1e9, 1)},
            "y_mirror_asymmetry_mm": round(sym[n] * 1e3, 3)})
        verts_out.append({"name": n, "vertices": r6(V)})
    log("\n".join(["", "summary:"] + rows))

    lin = {
        "coordinates": "q = (driver, coupler, spring_link, follower): MuJoCo joint angles (rad) of right_driver_joint, "
                       "right_coupler_joint, right_spring_link_joint, right_follower_joint. Two are independent; the natural "
                       "pair is (driver, spring_link) (both pivots on the base); coupler and follower follow from the loop.",
        "axes": "every joint axis is G's -y: a joint angle theta turns its link by phi = -theta about +y; "
                "rot(phi) (x, z) = (x cos phi + z sin phi, -x sin phi + z cos phi)",
        "base": {"driver_pivot": r6(p["A"]), "spring_link_pivot": r6(p["B"])},
        "driver": {"frame_origin": "driver pivot A", "coupler_joint": r6(p["Cd"]), "length": r6(np.linalg.norm(p["Cd"]))},
        "coupler": {"frame_origin": "coupler joint C", "follower_point": r6(p["Dc"]), "length": r6(lk.lc)},
        "spring_link": {"frame_origin": "spring_link pivot B", "follower_joint": r6(p["Es"]), "length": r6(lk.ls)},
        "follower": {"frame_origin": "D, the point the coupler holds (MuJoCo `connect` anchor 0 0 0)",
                     "follower_joint": r6(p["Ef"]), "length": r6(lk.lf)},
        "pad": {"frame_in_follower": r6(p["Pf"]), "angle": "the follower's",
                "contact_face_x": r6(pad_c[0]), "contact_face_center": r6([pad_c[0], 0.0, pad_c[1]]),
                "contact_face_note": "pad frame; the +x finger's pad faces -x; gap = 2 x (pad face x in G)"},
        "ground_length": r6(np.linalg.norm(np.subtract(p["A"], p["B"]))),
        "parallel_crank_length": r6(lk.lk),
        "ranges": {k: r6(v) for k, v in S["ranges"].items()},
        "springs": S["springs"],
        "equations": [
            "C = A + rot(-driver) Cd                      (coupler joint, G)",
            "E = B + rot(-spring_link) Es                 (follower joint, G)",
            "D: |D - C| = |Dc| and |D - E| = |Ef|, the branch with sign(cross(E - C, D - C)) = %+d  (loop closure)" % lk.side_D,
            "coupler angle:  phi_c = ang(D - C) - ang(Dc),  coupler = -phi_c - driver     (ang(v) = atan2(-v.z, v.x))",
            "follower angle: phi_f = ang(D - E) - ang(-Ef), follower = -phi_f - spring_link",
            "poses [x, z, phi] in G: driver [A, -driver]; coupler [C, phi_c]; spring_link [B, -spring_link]; "
            "follower [D, phi_f]; pad [D + rot(phi_f) Pf, phi_f]",
            "parallel (spring-held) mode: coupler = 0 (its upper limit: MuJoCo's spring on spring_link, stiffness 0.05 "
            "towards 2.62 rad, keeps it there until the proximal link is stopped): D = A + rot(-driver)(Cd + Dc); "
            "E: |E - B| = |Es|, |E - D| = |Ef|, the branch with sign(cross(B - D, E - D)) = %+d; spring_link = -(ang(E - B) - ang(Es))" % lk.side_E,
            "blocked (adaptive) mode: spring_link fixed where the proximal link was stopped, driver turns on: "
            "coupler < 0 leaves its limit and the follower curls (pad turns towards -x, tip towards the palm)"],
    }
    fingers = {
        "generator": "tools/geometry/derive_fingers.py",
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "commit": commit,
                   "files": ["robotiq_2f85/2f85.xml"] + [f"robotiq_2f85/assets/{k}.stl" for k in sorted(meshes)],
                   "license": "BSD-2-Clause (robotiq_2f85/LICENSE, Copyright (c) 2013, ROS-Industrial)"},
        "frame": "G = UR flange/tool0: origin on the flange face (the underside of Menagerie's base_mount), +z approach, "
                 "x closing (pads at +-x), y finger width. Data for the +x finger (Menagerie's 'right' finger); the -x finger "
                 "is its mirror x -> -x (Menagerie turns it by pi about z; the links are y-symmetric, see y_mirror_asymmetry_mm).",
        "link_frames": "each link frame has its Menagerie body's origin and G's axes at q = 0; a pose [x, z, phi] is the "
                       "translation (x, 0, z) and the rotation phi about G's +y (finger.rs convention). Pieces and vertices "
                       "are in the link frames.",
        "units": "m, rad",
        "linkage": lin,
        "samples": {"parallel": par, "blocked": blocked,
                    "note": "from MuJoCo's forward kinematics with the connect equality solved (Gauss-Newton, residual "
                            "<= %.0e m); the closed form above reproduces them within %.0e. tip_z = deepest z of the "
                            "follower and pad meshes; pad_center = pad contact face centre (x, z) in G; gap = 2 pad_face_x."
                            % (max(worst["closure"], 1e-15), max(worst["pose"], 1e-15))},
        "table_residuals": {"pad_center": res, "tip_open": {"table": TIP_OPEN, "model": r6(tip_open)},
                            "tip_closed_max": {"table": TIP_CLOSED, "model": r6(tip_closed)}},
        "pieces_method": "convex polytopes (vertex lists) per link frame; every visual-mesh vertex lies in their union "
                         "(>= 1 um deep before rounding); excess = largest distance from the union's boundary (sampled every "
                         "%.1f mm; points outside the link only) to the link's surface, with through-holes of radius <= %.1f mm "
                         "(pin bores, screw holes) counted as solid; raw_excess_mm without that fill" % (FINAL_STEP * 1e3, FILL_R * 1e3),
        "links": links_out,
    }
    vertices = {"generator": "tools/geometry/derive_fingers.py", "source": fingers["source"],
                "frame": "link frames of robotiq_2f85_fingers.json", "links": verts_out}
    dump(os.path.join(DATA, "robotiq_2f85_fingers.json"), fingers)
    dump(os.path.join(DATA, "robotiq_2f85_finger_vertices.json"), vertices)
    print("wrote crates/robot/data/robotiq_2f85_fingers.json, crates/robot/data/robotiq_2f85_finger_vertices.json")


if __name__ == "__main__":
    main()

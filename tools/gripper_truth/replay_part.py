"""The part of replay.py as MuJoCo gets it: an exact convex decomposition of an extruded outline
(`decompose_extrusion`; CoACD as the fallback for another shape) and its mass properties."""
import numpy as np
import trimesh


def decompose_extrusion(mesh, tol=1e-6):
    """Exact convex decomposition of a prism (a planar outline, holes allowed, extruded along z).

    The mesh's bottom-face triangles are merged greedily across shared edges while the union stays convex
    (Hertel-Mehlhorn: at most 4x the minimum number of pieces), and every convex polygon is extruded over
    the mesh's z range. The pieces tile the part exactly; `info` reports the area/volume check.
    Returns (list of (k, 3) vertex arrays, info dict). Raises ValueError if the mesh is not such a prism.
    """
    V = np.asarray(mesh.vertices, float)
    z0, z1 = V[:, 2].min(), V[:, 2].max()
    on = (np.abs(V[:, 2] - z0) < tol) | (np.abs(V[:, 2] - z1) < tol)
    if not on.all():
        raise ValueError("not an extrusion along z: vertices between the bottom and top faces")
    key = {}
    pts = []

    def k_of(i):
        kk = (round(V[i, 0] / tol), round(V[i, 1] / tol))
        if kk not in key:
            key[kk] = len(pts)
            pts.append(V[i, :2])
        return key[kk]

    polys = []
    for f in mesh.faces:
        if all(abs(V[i, 2] - z0) < tol for i in f):
            ids = [k_of(i) for i in f]
            a, b, c = (pts[i] for i in ids)
            if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
                ids = ids[::-1]  # counter-clockwise seen from +z
            polys.append(ids)
    P = np.array(pts)
    tri_area = sum(poly_area(P[p]) for p in polys)

    def convex(cycle):
        Q = P[cycle]
        n = len(Q)
        for i in range(n):
            a, b, c = Q[i - 1], Q[i], Q[(i + 1) % n]
            if (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < -1e-12:
                return False
        return True

    changed = True
    while changed:
        changed = False
        edge = {}
        for pi, p in enumerate(polys):
            if p is None:
                continue
            for i in range(len(p)):
                edge[(p[i], p[(i + 1) % len(p)])] = pi
        # longest shared edges first (removing long diagonals gives fewer, fatter pieces); ties by ids
        shared = [(a, b) for (a, b) in edge if (b, a) in edge and a < b]
        shared.sort(key=lambda e: (-np.linalg.norm(P[e[0]] - P[e[1]]), e))
        for a, b in shared:
            pi, qi = edge.get((a, b)), edge.get((b, a))
            if pi is None or qi is None or pi == qi or polys[pi] is None or polys[qi] is None:
                continue
            p, q = polys[pi], polys[qi]
            if (a, b) not in zip(p, p[1:] + p[:1]) or (b, a) not in zip(q, q[1:] + q[:1]):
                continue
            i = p.index(a)
            pr = p[i + 1:] + p[:i + 1]  # b ... a
            j = q.index(b)
            qr = q[j + 1:] + q[:j + 1]  # a ... b
            merged = pr + qr[1:-1]
            if convex(merged):
                polys[pi], polys[qi] = merged, None
                for e in zip(merged, merged[1:] + merged[:1]):
                    edge[e] = pi
                changed = True
    polys = [p for p in polys if p is not None]
    pieces = []
    for p in polys:
        Q = P[p]
        pieces.append(np.vstack([np.c_[Q, np.full(len(Q), z0)], np.c_[Q, np.full(len(Q), z1)]]))
    area = sum(poly_area(P[p]) for p in polys)
    vol = area * (z1 - z0)
    info = {"method": "exact: Hertel-Mehlhorn merge of the STL's bottom-face triangles, each convex polygon "
                      "extruded over the part's thickness (the parts are extruded outlines)",
            "pieces": len(pieces), "bottom_triangles": int(sum(1 for f in mesh.faces if all(abs(V[i, 2] - z0) < tol for i in f))),
            "thickness": z1 - z0, "mesh_volume": float(mesh.volume), "pieces_volume": vol,
            "volume_rel_error": abs(vol - mesh.volume) / mesh.volume, "area_rel_error_vs_triangles": abs(area - tri_area) / tri_area}
    return pieces, info


def poly_area(Q):
    x, y = Q[:, 0], Q[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def decompose_coacd(mesh, threshold=0.02):
    """Fallback for a part that is not an extrusion: CoACD (pip install coacd)."""
    import coacd
    parts = coacd.run_coacd(coacd.Mesh(mesh.vertices, mesh.faces), threshold=threshold, seed=0)
    pieces = [np.asarray(v) for v, _ in parts]
    vol = sum(trimesh.Trimesh(v).convex_hull.volume for v in pieces)
    return pieces, {"method": f"coacd threshold {threshold}", "pieces": len(pieces), "mesh_volume": float(mesh.volume),
                    "pieces_volume": vol, "volume_rel_error": abs(vol - mesh.volume) / mesh.volume}


def mass_properties(mesh, mass, scale):
    """Uniform-density mass properties of the (scaled) closed mesh in the object frame."""
    m = mesh.copy()
    m.apply_scale(scale)
    vol = m.volume
    m.density = mass / vol
    I = m.moment_inertia  # about the centre of mass, axes of the object frame
    return {"mass": mass, "com": m.center_mass.tolist(), "volume": vol,
            "fullinertia": [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]}

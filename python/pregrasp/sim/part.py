"""The part as MuJoCo gets it, with numpy alone: the STL read (`read_stl`), its uniform-density mass properties
(`mass_properties`, the polyhedral integrals trimesh uses), an exact convex decomposition of an extruded outline
(`decompose_extrusion`; CoACD, when installed, for another shape) and each convex piece as a closed mesh
(`prism_mesh`)."""
import struct

import numpy as np


def read_stl(path):
    """The triangles (n, 3, 3) float64 of a binary or ASCII STL file."""
    data = open(path, "rb").read()
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if len(data) == 84 + 50 * n:
            rec = np.frombuffer(data, dtype=np.dtype([("normal", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")]),
                                count=n, offset=84)
            return rec["v"].astype(np.float64)
    text = data.decode("ascii", errors="replace")
    if not text.lstrip().startswith("solid"):
        raise ValueError(f"{path}: neither a binary STL (size) nor an ASCII STL (no 'solid')")
    verts = [[float(x) for x in line.split()[1:4]] for line in text.splitlines() if line.strip().startswith("vertex")]
    if not verts or len(verts) % 3:
        raise ValueError(f"{path}: an ASCII STL without whole triangles")
    return np.array(verts, float).reshape(-1, 3, 3)


def _integrals(tri):
    """Volume, first and second moments of a closed triangle mesh (Eberly, "Polyhedral Mass Properties";
    the same operations as trimesh.triangles.mass_properties)."""
    vec = tri[:, 1:, :] - tri[:, :2, :]
    crosses = np.cross(vec[:, 0], vec[:, 1])
    f1 = tri[:, 0, :] + tri[:, 1, :] + tri[:, 2, :]
    f2 = tri[:, 0, :] ** 2 + tri[:, 1, :] ** 2 + tri[:, 0, :] * tri[:, 1, :] + tri[:, 2, :] * f1
    f3 = ((tri[:, 0, :] ** 3) + (tri[:, 0, :] ** 2) * (tri[:, 1, :]) + (tri[:, 0, :]) * (tri[:, 1, :] ** 2)
          + (tri[:, 1, :] ** 3) + (tri[:, 2, :] * f2))
    g0 = f2 + (tri[:, 0, :] + f1) * tri[:, 0, :]
    g1 = f2 + (tri[:, 1, :] + f1) * tri[:, 1, :]
    g2 = f2 + (tri[:, 2, :] + f1) * tri[:, 2, :]
    integral = np.zeros((10, len(f1)))
    integral[0] = crosses[:, 0] * f1[:, 0]
    integral[1:4] = (crosses * f2).T
    integral[4:7] = (crosses * f3).T
    for i in range(3):
        j = np.mod(i + 1, 3)
        integral[i + 7] = crosses[:, i] * ((tri[:, 0, j] * g0[:, i]) + (tri[:, 1, j] * g1[:, i])
                                           + (tri[:, 2, j] * g2[:, i]))
    return integral.sum(axis=1) / np.array([6, 24, 24, 24, 60, 60, 60, 120, 120, 120], dtype=np.float64)


def volume(tri):
    return float(_integrals(tri)[0])


def mass_properties(tri, mass):
    """Uniform-density mass properties of the (scaled) closed mesh `tri` in the object frame."""
    s = _integrals(tri)
    vol = s[0]
    c = s[1:4] / vol
    inertia = np.zeros((3, 3))
    inertia[0, 0] = s[5] + s[6] - (vol * (c[[1, 2]] ** 2).sum())
    inertia[1, 1] = s[4] + s[6] - (vol * (c[[0, 2]] ** 2).sum())
    inertia[2, 2] = s[4] + s[5] - (vol * (c[[0, 1]] ** 2).sum())
    inertia[0, 1] = -(s[7] - (vol * np.prod(c[[0, 1]])))
    inertia[1, 2] = -(s[8] - (vol * np.prod(c[[1, 2]])))
    inertia[0, 2] = -(s[9] - (vol * np.prod(c[[0, 2]])))
    inertia = inertia * (mass / vol)
    return {"mass": mass, "com": c.tolist(), "volume": float(vol),
            "fullinertia": [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]}


def decompose_extrusion(tri, tol=1e-6):
    """Exact convex decomposition of a prism (a planar outline, holes allowed, extruded along z).

    The mesh's bottom-face triangles are merged greedily across shared edges while the union stays convex
    (Hertel-Mehlhorn: at most 4x the minimum number of pieces), and every convex polygon is extruded over
    the mesh's z range. The pieces tile the part exactly; `info` reports the area/volume check.
    Returns (list of (k, 3) vertex arrays: the bottom polygon counter-clockwise seen from +z, then the top one;
    info dict). Raises ValueError if the mesh is not such a prism.
    """
    V = tri.reshape(-1, 3)
    faces = np.arange(len(V)).reshape(-1, 3)
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
    for f in faces:
        if all(abs(V[i, 2] - z0) < tol for i in f):
            ids = [k_of(i) for i in f]
            a, b, c = (pts[i] for i in ids)
            if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
                ids = ids[::-1]  # counter-clockwise seen from +z
            polys.append(ids)
    if not polys:
        raise ValueError("not an extrusion along z: no bottom face")
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
    mesh_vol = volume(tri)
    info = {"method": "exact: Hertel-Mehlhorn merge of the STL's bottom-face triangles, each convex polygon "
                      "extruded over the part's thickness (the parts are extruded outlines)",
            "pieces": len(pieces),
            "bottom_triangles": int(sum(1 for f in faces if all(abs(V[i, 2] - z0) < tol for i in f))),
            "thickness": z1 - z0, "mesh_volume": mesh_vol, "pieces_volume": vol,
            "volume_rel_error": abs(vol - mesh_vol) / mesh_vol,
            "area_rel_error_vs_triangles": abs(area - tri_area) / tri_area}
    return pieces, info


def poly_area(Q):
    x, y = Q[:, 0], Q[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def prism_mesh(P):
    """A piece of decompose_extrusion as a closed, outward-wound mesh: (vertices (k, 3), faces (m, 3)). Vertices
    on a straight stretch of the outline (not corners of the convex polygon) are left out, as a convex hull would."""
    n = len(P) // 2
    Q = P[:n, :2]
    keep = []
    for i in range(n):
        a, b, c = Q[i - 1], Q[(i + 1) % n], Q[i]
        if abs((c[0] - a[0]) * (b[1] - c[1]) - (c[1] - a[1]) * (b[0] - c[0])) > 1e-12:
            keep.append(i)
    k = len(keep)
    V = np.vstack([P[:n][keep], P[n:][keep]])
    F = [(0, i + 1, i) for i in range(1, k - 1)] + [(k, k + i, k + i + 1) for i in range(1, k - 1)]
    for i in range(k):
        j = (i + 1) % k
        F += [(i, j, k + j), (i, k + j, k + i)]
    return V, np.array(F, dtype=np.int64)


def decompose_coacd(tri, threshold=0.02):
    """Fallback for a part that is not an extrusion: CoACD (pip install coacd); each piece is its convex mesh."""
    try:
        import coacd
    except ImportError:
        raise ValueError("the part is not an extruded outline, and its convex decomposition needs CoACD "
                         "(pip install coacd)") from None
    V = tri.reshape(-1, 3)
    parts = coacd.run_coacd(coacd.Mesh(V, np.arange(len(V)).reshape(-1, 3)), threshold=threshold, seed=0)
    meshes = [(np.asarray(v, float), np.asarray(f, np.int64)) for v, f in parts]
    vol = sum(volume(v[f]) for v, f in meshes)
    mesh_vol = volume(tri)
    return meshes, {"method": f"coacd threshold {threshold}", "pieces": len(meshes), "mesh_volume": mesh_vol,
                    "pieces_volume": vol, "volume_rel_error": abs(vol - mesh_vol) / mesh_vol}

"""One convex piece inside a fitted cylinder, and the measures of a union of pieces: the base of the
exact tier (ur_pieces.py, which describes the method).

* `assign`, `with_axis`: the points a cylinder's pieces must hold;
* `polytope`: the piece P ⊇ hull(S) with few faces, cut by the cylinder's tangent planes where it
  would reach more than `SLACK` outside it, and its slack;
* `measure` (outward excess of the union: boundary samples every 1.5 mm outside the link, `solid`,
  distance to the visual surface), `uncovered` (containment), `nearest_boundary` (test vertices).
"""
import logging

import numpy as np
import trimesh
from scipy import ndimage
from scipy.spatial import ConvexHull, HalfspaceIntersection

from shapes import dist_outside

logging.getLogger("trimesh").setLevel(logging.ERROR)  # sample_surface_even: "only got n/m samples"

ANGLE = np.radians(10.0)  # least angle between two kept face normals
SLACK = 0.0003            # a piece may exceed its cylinder by this much (m); the runtime grows
                          # the broad-phase margin by it, so "cylinder clear" still implies "piece clear"
OUT = 2e-6                # vertices are pushed out by this before rounding to 6 decimals
MAX_ROUNDS = 40           # rounds of tangent cuts per piece
OVERLAP = 0.0015          # axial overlap of neighbouring slabs (m)


def assign(shapes, P):
    """Index of the cylinder each point belongs to: among those containing it (dist <= 1e-6), the one
    whose boundary is nearest; a point outside all goes to the nearest one."""
    D = np.array([dist_outside(s, P) for s in shapes])     # (n_shapes, n_points), <= 0 inside
    inside = D <= 1e-6
    key = np.where(inside, D, -np.inf)
    best = np.argmax(key, axis=0)
    none = ~inside.any(axis=0)
    best[none] = np.argmin(D[:, none], axis=0)
    return best


def _tangent(shape, p):
    """Outward unit normal and offset of the tangent plane of the (round-edged) cylinder at the
    boundary point nearest to p (p outside or on it)."""
    a, b, r = np.asarray(shape["a"], float), np.asarray(shape["b"], float), float(shape["radius"])
    e = float(shape.get("border", 0.0))
    ab = b - a; L = np.linalg.norm(ab); u = ab / L
    # nearest point of the inner flat cylinder (a+e u .. b-e u, radius r-e), then push out by e
    t = (p - a) @ u
    radial = p - a - t * u
    rho = np.linalg.norm(radial)
    w = radial / rho if rho > 1e-12 else np.array([1.0, 0, 0]) - u * u[0]
    w /= np.linalg.norm(w)
    tc = np.clip(t, e, L - e)
    rc = min(rho, r - e)
    q = a + tc * u + rc * w
    d = p - q
    if np.linalg.norm(d) < 1e-12:
        n = w if rho >= r - e else (u if t > L / 2 else -u)
    else:
        n = d / np.linalg.norm(d)
    x = q + e * n
    return n, float(n @ x)


def polytope(shape, S):
    """(vertices, slack) of P (see module doc) for the points S assigned to `shape`; slack = how far
    P's vertices reach outside the cylinder (>= 0), which the runtime adds to the broad-phase margin.
    The cuts never pass inside a point of S, so P ⊇ hull(S) always; a point of S already outside the
    cylinder (a long facet between two cylinders) stays covered and sets the slack."""
    h = ConvexHull(S)
    eq = h.equations                                   # n·x + c <= 0
    tri = S[h.simplices]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    order = np.argsort(-area, kind="stable")
    kept = []
    cos = np.cos(ANGLE)
    for i in order:
        n = eq[i, :3]
        if all(n @ m < cos for m in kept):
            kept.append(n)
    N = np.array(kept)
    H = S[h.vertices]
    off = (H @ N.T).max(axis=0)
    inner = H.mean(axis=0)
    target = SLACK + max(0.0, float(dist_outside(shape, H).max()))
    last = []
    for _ in range(MAX_ROUNDS):
        Vp = HalfspaceIntersection(np.c_[N, -off], inner).intersections
        d = dist_outside(shape, Vp)
        last.append(d.max())
        if d.max() <= target or (len(last) > 3 and last[-4] - last[-1] < 1e-6):
            break
        # cut the worst vertices (up to 64 per round) by the cylinder's tangent planes there
        for j in np.argsort(-d)[:64]:
            if d[j] <= target:
                break
            n, o = _tangent(shape, Vp[j])
            N = np.vstack([N, n]); off = np.append(off, max(o, float((H @ n).max())))
    V = ConvexHull(Vp)
    P0 = Vp[V.vertices]
    dirs = P0 - P0.mean(axis=0)
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    # push the vertices out by OUT, more (x2, x4, ...) where the piece rounded to 6 decimals (as
    # stored) would leave a point of S less than 1 um inside it (a facet nearly along the push;
    # the stored test vertices are rounded to 6 decimals too)
    for k in range(10):
        P = P0 + OUT * 2 ** k * dirs
        eq = ConvexHull(np.round(P, 6)).equations
        if (H @ eq[:, :3].T + eq[:, 3]).max() <= -1e-6:
            break
    return P, max(0.0, float(dist_outside(shape, P).max()))


def with_axis(shape, S, step=0.002):
    """S plus points of the cylinder's axis between its two caps: the link is solid around its
    joint and tube axes, so the piece is a solid wedge from the axis out to its surface points and
    pieces that share a housing or a tube (split by `assign`) fill its interior between them. The
    caps are where S meets the axis (points within 0.3 r of it); without such points at both ends
    no axis is added (a dished or open end is not filled past its surface)."""
    if len(S) == 0:
        return S
    a, b = np.asarray(shape["a"], float), np.asarray(shape["b"], float)
    L = np.linalg.norm(b - a); u = (b - a) / L
    t = (S - a) @ u
    rho = np.linalg.norm(S - a - t[:, None] * u, axis=1)
    near = t[rho <= 0.3 * float(shape["radius"])]
    if len(near) < 2:
        return S
    lo, hi = max(near.min(), 0.0), min(near.max(), L)
    if hi <= lo:
        return S
    n = max(2, int(np.ceil((hi - lo) / step)) + 1)
    return np.vstack([S, a + np.linspace(lo, hi, n)[:, None] * u])


def _violation(h, X, chunk=4096):
    """Per point of X, the largest facet violation n·x + c of the hull h (<= 0 inside), in chunks
    (a (points x facets) matrix of a whole link would not fit in memory)."""
    out = np.empty(len(X))
    for i in range(0, len(X), chunk):
        out[i:i + chunk] = (X[i:i + chunk] @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1)
    return out


def inside(P, X, tol=1e-6):
    """Whether each point X is in the convex hull of P (within tol)."""
    return _violation(ConvexHull(P), X) <= tol


def boundary_samples(polys, step=0.0015):
    res = []
    for i, P in enumerate(polys):
        m = trimesh.convex.convex_hull(P)
        n = int(m.area / (step * step)) + 1
        X, _ = trimesh.sample.sample_surface_even(m, n, seed=5)
        X = np.vstack([X, P])
        keep = np.ones(len(X), bool)
        for j, Q in enumerate(polys):
            if j != i:
                keep &= ~inside(Q, X, tol=-1e-6)
        res.append(X[keep])
    return res


def solid(surf, P, h=0.001):
    """Whether each point of P lies inside the link: the visual surface samples rasterised on an
    h-voxel grid, closed by one voxel of dilation (seams and small openings of the visual mesh),
    then hole-filled; inside = in a filled voxel that is not itself a surface voxel's neighbour
    (points within ~2h of the surface count as outside, which only matters for excess < 2h)."""
    if not hasattr(surf, "_solid"):
        pad = 3 * h
        lo = surf.S.min(0) - pad
        n = np.ceil((surf.S.max(0) + pad - lo) / h).astype(int) + 1
        occ = np.zeros(n, bool)
        idx = np.floor((surf.S - lo) / h).astype(int)
        occ[idx[:, 0], idx[:, 1], idx[:, 2]] = True
        shell = ndimage.binary_dilation(occ, iterations=1)
        filled = ndimage.binary_fill_holes(shell)
        surf._solid = (lo, h, filled & ~shell)
    lo, h, G = surf._solid
    idx = np.floor((P - lo) / h).astype(int)
    ok = np.all((idx >= 0) & (idx < np.array(G.shape)), axis=1)
    out = np.zeros(len(P), bool)
    out[ok] = G[idx[ok, 0], idx[ok, 1], idx[ok, 2]]
    return out


def outward(surf, P):
    """(distance, point) of the point of P farthest from the visual surface among those OUTSIDE
    the link (`solid`); a union of pieces need not fill the link's interior, and its boundary
    there is no outward excess."""
    P = P[~solid(surf, P)]
    return surf.max_dist(P, exact=True)


def measure(polys, surf, names=None):
    """Outward excess of the union of the polytopes: the largest distance from a point of the
    union's boundary (1.5 mm samples) outside the link to the visual surface, (m, point, piece)."""
    worst, at, who = 0.0, np.zeros(3), None
    for i, X in enumerate(boundary_samples(polys)):
        dd, p = outward(surf, X)
        if dd > worst:
            worst, at, who = dd, p, (names[i] if names else i)
    return worst, at, who


def uncovered(polys, X):
    """Largest distance (approximate: max over pieces of the least facet violation) by which points X
    lie outside the union of the pieces."""
    best = np.full(len(X), np.inf)
    for P in polys:
        best = np.minimum(best, _violation(ConvexHull(P), X))
    return float(max(best.max(), 0.0))


def nearest_boundary(polys, V, n=1500):
    """Up to n vertices of V (deduplicated, 6 decimals) that lie deepest-last in the union of the
    pieces, i.e. closest to its boundary: the test data for "no vertex outside" (the rest lie
    deeper inside). Deterministic."""
    U = np.unique(np.round(V, 6), axis=0)
    depth = np.full(len(U), -np.inf)
    for P in polys:
        depth = np.maximum(depth, -_violation(ConvexHull(P), U))
    order = np.lexsort((U[:, 2], U[:, 1], U[:, 0], depth))
    return U[np.sort(order[:n])], float(depth.min())

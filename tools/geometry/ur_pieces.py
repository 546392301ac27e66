"""Convex pieces inside the fitted cylinders: the exact tier of the arm's collision model.

For every cylinder C of a link (`ur_links.json`, fitted by ur_vis), its pieces are convex polytopes
P with C ⊕ slack ⊇ P ⊇ hull(S), where S are the link's surface points assigned to C (or to one
slab / sector of it):

* points = the visual vertices and dense surface samples (`ur_vis.Surface`, 0.6 mm; base points below
  z = 0.002 lifted to it, as for the cylinders);
* a point goes to the cylinder that contains it with the least depth (the cylinder whose surface it is
  nearest to: a tube point inside a housing's cylinder belongs to the tube), so a piece wraps one
  housing or one tube and bridges no concavity between them; the cylinder's axis between its caps
  is added (`with_axis`: the link is solid there), so pieces sharing a housing fill it;
* P = the intersection of half-spaces n·x ≤ max_{s ∈ S} n·s over the hull's facet normals, thinned
  to directions at least `ANGLE` apart (largest facets first): an outer approximation of hull(S)
  with few faces; where a vertex of P lies more than `SLACK` outside C, the tangent half-space of C
  there is added (never cutting a point of S), and `slack` = how far P's vertices still reach out;
* a piece whose own outward excess exceeds GOAL is split (`_refine`): into axial halves
  (overlapping slabs, recursively) or, for a whole cylinder's piece, into the best of SECTORINGS
  (4 or 8 sectors about the axis at two phases), as is or with its sectors halved axially too;
  the fewest pieces that reach GOAL, else a split only where it measures 0.1 mm better;
* then, while the link's excess exceeds TARGET and it has fewer than MAX_PIECES pieces, the piece
  at the link's worst point is cut there (`repair`: planes across the bridged concavity, along,
  across or through the axis, or wedges about a hole), a cut kept only where it lowers the excess
  near that point.

The runtime uses C grown by its slack as the conservative broad phase (a pair clear of it is clear
of the pieces) and the pieces as the exact test where it is within the margin. Excess is measured
on the union of the pieces like the cylinders' (ur_vis.measure: boundary samples every 1.5 mm,
distance to the visual surface), at the samples outside the link (`solid`).
"""
import logging

import numpy as np
import trimesh
from scipy import ndimage
from scipy.spatial import ConvexHull, HalfspaceIntersection, QhullError

from shapes import _frame, dist_outside
from ur_vis import _cover_points

logging.getLogger("trimesh").setLevel(logging.ERROR)  # sample_surface_even: "only got n/m samples"

ANGLE = np.radians(10.0)  # least angle between two kept face normals
SLACK = 0.0003            # a piece may exceed its cylinder by this much (m); the runtime grows
                          # the broad-phase margin by it, so "cylinder clear" still implies "piece clear"
OUT = 2e-6                # vertices are pushed out by this before rounding to 6 decimals
MAX_ROUNDS = 40           # rounds of tangent cuts per piece
OVERLAP = 0.0015          # axial overlap of neighbouring slabs (m)
GOAL = 0.0045             # a piece is cut into slabs until its outward excess is at most this
SECTORS = 8               # default sector count of `_sectors`
SECTORINGS = [(4, 0.0), (4, np.pi / 4), (8, 0.0), (8, np.pi / 8)]   # (k sectors, phase) tried
SECTOR_OVERLAP = np.radians(1.0)
SECTOR_DEPTH = 0          # only a whole cylinder's piece is tried in sectors
SECTOR_AXIAL = 2          # a sector is halved along the axis at most this often
MAX_DEPTH = 6             # a cylinder's points are halved at most this often (slabs >= 1/64 of it)
TARGET = 0.0045           # `repair` cuts the pieces further while the link's excess exceeds this
MAX_PIECES = 60           # ... and while the link has fewer pieces than this
REPAIR_RADIUS = 0.010     # a repair cut must lower the excess within this distance of the worst point
VERBOSE = False           # print each repair cut


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


def _sectors(shape, S, k=SECTORS, phase=0.0):
    """S cut into k sectors about the cylinder's axis, the first starting at angle `phase` from
    the frame's v axis, each widened by SECTOR_OVERLAP on both sides; points on the axis belong to
    every sector."""
    a, b = np.asarray(shape["a"], float), np.asarray(shape["b"], float)
    u, v, w = _frame(b - a)
    R = S - a
    ang = (np.arctan2(R @ w, R @ v) - phase) % (2 * np.pi)
    rho = np.linalg.norm(R - np.outer(R @ u, u), axis=1)
    on_axis = rho < 1e-4
    step = 2 * np.pi / k
    out = []
    for j in range(k):
        d = (ang - (j + 0.5) * step + np.pi) % (2 * np.pi) - np.pi
        out.append(S[(np.abs(d) <= 0.5 * step + SECTOR_OVERLAP) | on_axis])
    return out


def _refine(shape, S, surf, lo, hi, depth, sectors=True, limit=MAX_DEPTH):
    """Cells for the points of S whose axial coordinate (along the cylinder) lies in [lo, hi]
    (widened by OVERLAP), as (points, piece) pairs: one polytope if its own outward excess is at
    most GOAL; else the best of the candidate splits: its two axial halves (refined the same way,
    at most `limit` levels deep: the cuts land where the profile bends, at flares and junctions)
    and, for the first SECTOR_DEPTH levels, the sectoring of SECTORINGS (k sectors about the axis
    at a phase: a pocket or a bore in a housing, which no axial cut can follow) that measures best,
    as it is and with every sector refined axially (at most SECTOR_AXIAL more levels, no further
    sectors). The candidates are taken by increasing piece count; one replaces the current best
    only if it measures 0.1 mm better, and the search stops at the first that reaches GOAL."""
    a, b = np.asarray(shape["a"], float), np.asarray(shape["b"], float)
    u = (b - a) / np.linalg.norm(b - a)
    t = (S - a) @ u
    part = S[(t >= lo - OVERLAP) & (t <= hi + OVERLAP)]
    if len(part) < 8:
        return []
    P = polytope(shape, part)
    e = measure([P[0]], surf)[0]
    if e <= GOAL:
        return [(part, P)]
    cands = [(e, [(part, P)])]
    if depth < limit and hi - lo >= 4 * OVERLAP:
        mid = 0.5 * (lo + hi)
        try:
            halves = (_refine(shape, S, surf, lo, mid, depth + 1, sectors, limit)
                      + _refine(shape, S, surf, mid, hi, depth + 1, sectors, limit))
            cands.append((measure([p for _, (p, _) in halves], surf)[0], halves))
        except QhullError:  # a flat slab (a sliver of a thin sector): no halves here
            pass
    if sectors and depth <= SECTOR_DEPTH:
        best = None
        for k, phase in SECTORINGS:
            try:
                cells = [(Sj, polytope(shape, Sj)) for Sj in _sectors(shape, part, k, phase) if len(Sj) >= 8]
            except QhullError:  # a flat sector (a sliver of a thin part): not this sectoring
                continue
            if cells:
                e3 = measure([p for _, (p, _) in cells], surf)[0]
                if best is None or e3 < best[0] - 1e-4:
                    best = (e3, cells)
        if best is not None:
            cands.append(best)
            if best[0] > GOAL:   # the best sectoring, its sectors refined axially
                deeper = min(limit, depth + 1 + SECTOR_AXIAL)
                cells = [c for Sj, _ in best[1] for c in _refine(shape, Sj, surf, lo, hi, depth + 1, False, deeper)]
                cands.append((measure([p for _, (p, _) in cells], surf)[0], cells))
    cands.sort(key=lambda c: len(c[1]))   # stable: ties keep the order above
    best = cands[0]
    for c in cands[1:]:
        if best[0] <= GOAL:
            break
        if c[0] < best[0] - 1e-4:
            best = c
    return best[1]


def pieces(link, shapes, V, surf):
    """Per cylinder (same order as shapes) a list of (vertices, slack) pieces: one convex piece, or
    axial slabs or sectors of it where one piece bridges a concavity (a waisted tube, a tube's
    junction with a housing, a pocket) by more than GOAL (`_refine`); then, while the link's
    excess exceeds TARGET, the pieces at its worst points are cut further (`repair`). [] where no
    point is assigned. Base points below the mounting gap are lifted to it
    (`ur_vis._cover_points`)."""
    Q = np.unique(np.round(_cover_points(link, np.vstack([V, surf.S])), 7), axis=0)
    who = assign(shapes, Q)
    cells = []
    for i, s in enumerate(shapes):
        S = with_axis(s, Q[who == i])
        if len(S) < 8:
            cells.append([])
            continue
        a, b = np.asarray(s["a"], float), np.asarray(s["b"], float)
        t = (S - a) @ ((b - a) / np.linalg.norm(b - a))
        cells.append(_refine(s, S, surf, t.min(), t.max(), 0))
    cells = repair(shapes, cells, surf, budget=max(0, MAX_PIECES - sum(len(c) for c in cells)))
    return [[piece for _, piece in c] for c in cells]


# ---------------------------------------------------------------------------------------------
# Repair: cuts at the link's worst points.
#
# _refine cuts along the axis at fixed (halving) positions and into fixed sectors; a concavity
# that lies across such a cut (a bolt pocket on a sector boundary), that needs a cut at one
# particular height (a step in a housing cap), or that is a hole (a bolt bore: any two convex
# pieces leave a chord across it) is still bridged. `repair` finds where the link's excess is
# largest and cuts the piece there at that point.


class _Cell:
    """A piece with the points it must contain; its hull's equations and bounding box."""

    serial = 0

    def __init__(self, S, piece):
        self.S, self.piece = S, piece
        _Cell.serial += 1
        self.key = _Cell.serial
        self.eq = ConvexHull(piece[0]).equations
        self.lo, self.hi = piece[0].min(axis=0), piece[0].max(axis=0)


def _inside_cells(cells, X, tol=-1e-6):
    """Whether each point of X lies inside (by more than -tol) one of the cells' pieces."""
    res = np.zeros(len(X), bool)
    if len(X) == 0:
        return res
    for c in cells:
        cand = ~res & np.all((X >= c.lo - 1e-6) & (X <= c.hi + 1e-6), axis=1)
        if not cand.any():
            continue
        idx = np.where(cand)[0]
        for k in range(0, len(idx), 4096):
            j = idx[k:k + 4096]
            res[j] = (X[j] @ c.eq[:, :3].T + c.eq[:, 3]).max(axis=1) <= tol
    return res


def _exposed(piece, others, surf):
    """The boundary samples (1.5 mm, as `measure`) of `piece` not inside another piece and outside
    the link (`solid`)."""
    m = trimesh.convex.convex_hull(piece)
    X, _ = trimesh.sample.sample_surface_even(m, int(m.area / 0.0015 ** 2) + 1, seed=5)
    X = np.vstack([X, piece])
    X = X[~_inside_cells(others, X)]
    return X[~solid(surf, X)]


def _local(pieces, others, surf, x, radius=REPAIR_RADIUS):
    """(largest excess, largest excess within `radius` of x) of the pieces' boundary samples that
    are not inside one another or `others` (k-d tree distances: for ranking cuts)."""
    cells = [_Cell(None, (p, 0.0)) for p in pieces]
    worst = near = 0.0
    for i, p in enumerate(cells):
        X = _exposed(p.piece[0], [c for j, c in enumerate(cells) if j != i] + others, surf)
        if len(X) == 0:
            continue
        d, _ = surf.tree.query(X)
        worst = max(worst, float(d.max()))
        m = np.linalg.norm(X - x, axis=1) <= radius
        if m.any():
            near = max(near, float(d[m].max()))
    return worst, near


def _halfspace_split(S, m, c):
    """S cut by the plane m.x = c into two overlapping parts (each reaching OVERLAP past it)."""
    s = S @ m
    return [S[s <= c + OVERLAP], S[s >= c - OVERLAP]]


def _wedge_distance(x, y, a0, a1):
    """Distance of the 2-D points (x, y) from the wedge {angle in [a0, a1]} (a1 - a0 <= pi) with
    its apex at the origin."""
    ang = np.arctan2(y, x)
    half = 0.5 * (a1 - a0)
    inside = np.abs((ang - 0.5 * (a0 + a1) + np.pi) % (2 * np.pi) - np.pi) <= half
    out = np.full(len(x), np.inf)
    for a in (a0, a1):
        along = x * np.cos(a) + y * np.sin(a)
        across = np.abs(x * np.sin(a) - y * np.cos(a))
        out = np.minimum(out, np.where(along >= 0, across, np.hypot(x, y)))
    return np.where(inside, 0.0, out)


def _polar_split(S, x, d, k, phase):
    """S cut into k wedges about the line through x along d (each reaching OVERLAP past its
    sides): the pieces around a hole (a bore: any two convex pieces leave a chord across it)."""
    _, e1, e2 = _frame(d)
    R = S - x
    px, py = R @ e1, R @ e2
    step = 2 * np.pi / k
    return [S[_wedge_distance(px, py, phase + j * step, phase + (j + 1) * step) <= OVERLAP]
            for j in range(k)]


def _banks(P, S, x):
    """The face of P at x (the one x lies on) and the points of S on it, split into the two banks
    the face bridges (by the side of x along their principal direction in the face): (normal,
    bank 1, bank 2); a bank may be empty."""
    h = ConvexHull(P)
    f = int(np.argmax(h.equations[:, :3] @ x + h.equations[:, 3]))
    n = h.equations[f, :3]
    on = S[np.abs(S @ n + h.equations[f, 3]) < 3e-4]
    if len(on) < 2:
        return n, on[:0], on[:0]
    q = on - on.mean(axis=0)
    q -= np.outer(q @ n, n)
    m = np.linalg.svd(q, full_matrices=False)[2][0]
    side = (on - x) @ m
    return n, on[side < 0], on[side > 0]


def _cuts(shape, S, P, x):
    """Candidate splits of the points S (piece P) at its worst point x, as (name, parts):

    * planes across the bridge at x: normal along the line between the two banks of the face at x
      (`_banks`), the cylinder's axis (a step or a flare), and the radial and tangential directions
      of x about the axis; each through x, midway between the banks, and just clear of either bank
      (OVERLAP + 0.5 mm past its edge nearest to x, so that one part holds that bank only), and
      3 mm either side of x;
    * the plane through the axis and x;
    * k = 3 or 4 wedges about the line through x along the axis or the face normal (a hole)."""
    a, b = np.asarray(shape["a"], float), np.asarray(shape["b"], float)
    u = (b - a) / np.linalg.norm(b - a)
    nf, b1, b2 = _banks(P, S, x)
    dirs = []
    if len(b1) and len(b2):
        m = b2.mean(axis=0) - b1.mean(axis=0)
        m -= (m @ nf) * nf
        if np.linalg.norm(m) > 1e-9:
            dirs.append(("bridge", m / np.linalg.norm(m)))
    dirs.append(("axial", u))
    rad = x - a - ((x - a) @ u) * u
    off_axis = np.linalg.norm(rad) > 1e-3
    if off_axis:
        rad /= np.linalg.norm(rad)
        dirs += [("radial", rad), ("tangential", np.cross(u, rad))]
    out = []
    for name, m in dirs:
        c0 = m @ x
        cs = [c0, c0 - 0.003, c0 + 0.003]
        s1, s2 = b1 @ m, b2 @ m
        e1 = s1[s1 <= c0].max() if (s1 <= c0).any() else None
        e2 = s2[s2 >= c0].min() if (s2 >= c0).any() else None
        if name != "bridge":  # the banks' sides along m, not along the bridge
            both = np.concatenate([s1, s2])
            e1 = both[both <= c0].max() if (both <= c0).any() else None
            e2 = both[both >= c0].min() if (both >= c0).any() else None
        if e1 is not None:
            cs.append(e1 + OVERLAP + 0.0005)
        if e2 is not None:
            cs.append(e2 - OVERLAP - 0.0005)
        if e1 is not None and e2 is not None:
            cs.append(0.5 * (e1 + e2))
        seen = []
        for c in cs:
            if all(abs(c - o) > 3e-4 for o in seen):
                seen.append(c)
                out.append((f"{name}{(c - c0) * 1e3:+.1f}", _halfspace_split(S, m, c)))
    if off_axis:
        tq = np.cross(u, rad)
        out.append(("through-axis", _halfspace_split(S, tq, tq @ a)))
    for dname, d in (("axis", u), ("normal", nf)):
        if dname == "normal" and abs(nf @ u) > 0.95:
            continue
        for k in (3, 4):
            for phase in (0.0, np.pi / k):
                out.append((f"wedges{k}/{dname}/{np.degrees(phase):.0f}", _polar_split(S, x, d, k, phase)))
    return out


def repair(shapes, cells, surf, budget):
    """Cut the pieces at the link's worst points while its excess exceeds TARGET.

    cells: per cylinder a list of (points, piece). Each round takes the worst exposed boundary
    point x of the link (exact distance) on a piece not yet given up, and tries the cuts of
    `_cuts` on that piece alone and on it merged with the other pieces of its cylinder that
    contain x (a concavity on the border between two cells); a cut must lower the excess near x
    (within REPAIR_RADIUS) without raising the pieces' excess elsewhere. Among the cuts that bring
    it below TARGET - 0.3 mm the one adding the fewest pieces wins (then the lower excess), else
    the lowest excess (then fewer pieces). A piece no cut improves is given up. At most `budget`
    pieces are added. Deterministic."""
    flat = [(i, _Cell(S, p)) for i, c in enumerate(cells) for S, p in c]
    given_up = set()
    cache = {}                      # cell key -> (excess, point) of its exposed boundary
    added = 0
    while True:
        allc = [c for _, c in flat]
        worst = []
        for j, (i, c) in enumerate(flat):
            if c.key not in cache:
                X = _exposed(c.piece[0], allc[:j] + allc[j + 1:], surf)
                cache[c.key] = surf.max_dist(X, exact=True) if len(X) else (0.0, None)
            d, p = cache[c.key]
            worst.append((d, j, p))
        worst.sort(key=lambda r: (-r[0], r[1]))
        todo = [(d, j, p) for d, j, p in worst if d > TARGET and flat[j][1].key not in given_up]
        if not todo or added >= budget:
            break
        d0, j, x = todo[0]
        i, cell = flat[j]
        same = [jj for jj, (ii, c) in enumerate(flat) if ii == i and jj != j and
                (c.eq[:, :3] @ x + c.eq[:, 3]).max() <= 0.001]
        found = []
        for group in ([j], [j] + same) if same else ([j],):
            S = cell.S if len(group) == 1 else np.unique(np.vstack([flat[g][1].S for g in group]), axis=0)
            P = cell.piece[0] if len(group) == 1 else polytope(shapes[i], S)[0]
            others = [c for jj, (_, c) in enumerate(flat) if jj not in group]
            g0, n0 = _local([flat[g][1].piece[0] for g in group], others, surf, x)
            for name, parts in _cuts(shapes[i], S, P, x):
                parts = [q for q in parts if len(q) >= 8]
                net = len(parts) - len(group)
                if len(parts) < 2 or any(len(q) == len(S) for q in parts) or net > budget - added:
                    continue
                try:
                    new = [polytope(shapes[i], q) for q in parts]
                except QhullError:
                    continue
                g, n = _local([p for p, _ in new], others, surf, x)
                if g <= g0 + 1e-4 and n < n0 - 1e-4:
                    found.append((n, net, g, f"{name} ({len(group)})", group, parts, new))
        if not found:
            if VERBOSE:
                print(f"    repair {shapes[i]['name']}: {d0 * 1e3:.2f} mm at {np.round(x, 4)}: no cut helps", flush=True)
            given_up.add(cell.key)
            continue
        low = min(f[0] for f in found)
        good = [f for f in found if f[0] <= TARGET - 0.0003]
        if good:
            best = min(good, key=lambda f: (f[1], round(f[2], 4), f[0]))
        else:
            best = min((f for f in found if f[0] <= low + 0.0002), key=lambda f: (f[1], f[0]))
        n, net, g, name, group, parts, new = best
        if VERBOSE:
            print(f"    repair {shapes[i]['name']}: {d0 * 1e3:.2f} mm at {np.round(x, 4)}: {name} -> "
                  f"{n * 1e3:.2f} mm near it ({g * 1e3:.2f} mm on the new pieces), {net:+d} pieces", flush=True)
        at = min(group)
        keep = [f for jj, f in enumerate(flat) if jj not in group]
        flat = keep[:at] + [(i, _Cell(q, p)) for q, p in zip(parts, new)] + keep[at:]
        # pieces that overlap the replaced ones may have been exposed: measure them again
        lo = np.min([allc[g].lo for g in group], axis=0) - 1e-3
        hi = np.max([allc[g].hi for g in group], axis=0) + 1e-3
        for _, c in flat:
            if np.all(c.lo <= hi) and np.all(c.hi >= lo):
                cache.pop(c.key, None)
        added += net
    out = [[] for _ in cells]
    for i, c in flat:
        out[i].append((c.S, c.piece))
    return out


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

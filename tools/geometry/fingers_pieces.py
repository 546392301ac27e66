"""Convex pieces of a finger link for `derive_fingers.py` (`decompose`: plane over-segmentation, then
agglomeration; `finalize`: the pieces as stored), their excess (`measure`), the test vertices and the
containment check."""
import numpy as np
from scipy.spatial import ConvexHull, HalfspaceIntersection, cKDTree

from fingers_surface import Surface, tri_samples

TARGET = 0.0009        # split while a piece's excess exceeds this (m); goal 1 mm
TAU = 0.0005           # cuts are ranked by the excess above this, summed over the boundary
MAX_PIECES = 8         # per link (reported if exceeded)
MAX_CELLS = 64         # over-segmentation budget per link
SEG_TARGETS = [0.0009, 0.0007, 0.0005]  # over-segmentation snapshots (cell excess, m)
OVERLAP = 0.0001       # each side of a cut keeps the points within this of the plane (m)
OUT = 2e-6             # piece planes moved outward by this before rounding (doubled as needed)
THIN = np.radians(3.0) # least angle between two kept facet normals of a stored piece
MIN_SEP = 2e-5         # stored piece vertices are at least this far apart (robust hulls downstream)
SEARCH_STEP = 0.0005   # boundary sampling while searching cuts (m)
FINAL_STEP = 0.0002    # boundary sampling of the reported excess (m)
FILL_R = 0.0031        # through-holes up to this radius (pin bores, screw holes) count as solid


class Cutter:
    """Cells of a link = convex regions (half-spaces n.x <= c); a cell's piece = the convex hull of the
    link's surface clipped to the region (mesh vertices inside + edge/cut-plane crossings)."""

    def __init__(self, mesh, surf):
        self.V = mesh.vertices
        E = mesh.edges_unique
        self.a, self.b = self.V[E[:, 0]], self.V[E[:, 1]]
        self.surf = surf

    def points(self, region):
        keep = np.ones(len(self.V), bool)
        for n, c in region:
            keep &= self.V @ n <= c + 1e-12
        pts = [self.V[keep]]
        for i, (n, c) in enumerate(region):
            da, db = self.a @ n - c, self.b @ n - c
            x = (da * db) < 0
            t = da[x] / (da[x] - db[x])
            X = self.a[x] + t[:, None] * (self.b[x] - self.a[x])
            ok = np.ones(len(X), bool)
            for j, (m, d) in enumerate(region):
                if j != i:
                    ok &= X @ m <= d + 1e-12
            pts.append(X[ok])
        return np.vstack(pts)

    def piece(self, region):
        return _hull(self.points(region))

    def score(self, h, step=SEARCH_STEP):
        """(excess above TAU summed over the boundary samples x step^2, max excess) of one piece alone
        (approximate distances); (0, 0) for an empty piece."""
        if h is None:
            return 0.0, 0.0
        X = np.vstack([tri_samples(h.points[h.simplices], step), h.points[h.vertices]])
        e = self.surf.fast(X)
        return float(np.maximum(e - TAU, 0).sum() * step * step), float(e.max())


def _dirs(mesh):
    """Cut normals: every 15 deg in the x-z plane, y, four y-diagonals, and the normals of the mesh's 12
    largest planar facets (directions within 3 deg of one already listed are dropped)."""
    out = [np.array([np.cos(a), 0.0, np.sin(a)]) for a in np.radians(np.arange(0, 180, 15))]
    out.append(np.array([0.0, 1.0, 0.0]))
    s = np.sqrt(0.5)
    out += [np.array(v) for v in ([s, s, 0.0], [s, -s, 0.0], [0.0, s, s], [0.0, s, -s])]
    if len(mesh.facets):
        order = np.argsort(-mesh.facets_area, kind="stable")[:12]
        for k in order:
            n = np.asarray(mesh.facets_normal[k], float)
            if all(abs(n @ m) < np.cos(np.radians(3)) for m in out):
                out.append(n / np.linalg.norm(n))
    return out


def best_cut(cut, region, dirs):
    """The plane splitting the cell that minimises the two pieces' summed excess above TAU (ties: the
    larger maximum): normals `dirs`, offsets every 0.5 mm, then every 0.1 mm around the 4 best."""
    P = cut.points(region)
    cands = []

    def trial(n, c):
        s1, m1 = cut.score(cut.piece(region + [(n, c + OVERLAP)]))
        s2, m2 = cut.score(cut.piece(region + [(-n, -c + OVERLAP)]))
        cands.append((round(s1 + s2, 15), round(max(m1, m2), 9), len(cands), n, c))

    for n in dirs:
        pr = P @ n
        lo, hi = pr.min(), pr.max()
        for c in np.arange(lo + 0.0003, hi - 0.0003 + 1e-12, 0.0005):
            trial(n, float(c))
    if not cands:
        return None
    for _, _, _, n, c in sorted(cands, key=lambda t: t[:3])[:4]:
        for dc in np.arange(-0.0004, 0.00041, 0.0001):
            if abs(dc) > 1e-12:
                trial(n, c + dc)
    best = min(cands, key=lambda t: t[:3])
    return best


def union_samples(hulls, step):
    """Boundary samples of the union of the hulls: each hull's samples not inside another hull."""
    out = []
    for i, h in enumerate(hulls):
        X = np.vstack([tri_samples(h.points[h.simplices], step), h.points[h.vertices]])
        keep = np.ones(len(X), bool)
        for j, g in enumerate(hulls):
            if j != i:
                keep &= (X @ g.equations[:, :3].T + g.equations[:, 3]).max(axis=1) > -1e-9
        out.append(X[keep])
    return np.vstack(out)


def measure(surf, hulls, step=FINAL_STEP, exact=True):
    """Excess of the union (largest distance of a boundary point outside the link to the link's surface)
    and the worst point: boundary samples every `step`, k-d tree distances, the candidates within
    0.25 mm of the maximum refined with exact closest points (`exact`)."""
    X = union_samples(hulls, step)
    e = surf.excess(X)
    if exact:
        cand = e >= e.max() - 0.00025
        e = e.copy(); e[cand] = surf.exact(X[cand])
        e[~cand] = np.minimum(e[~cand], e[cand].max())  # below the refined maximum anyway
    i = int(np.argmax(e))
    return float(e[i]), X[i]


def _hull(P):
    """Convex hull of P; a degenerate point set (a sliver cell: coplanar or collinear points) is
    thickened by 0.1 um along x, y and z first. None for fewer than 4 points."""
    if len(P) < 4:
        return None
    try:
        return ConvexHull(P)
    except Exception:
        try:
            return ConvexHull(np.vstack([P + 1e-7 * e for e in np.vstack([np.eye(3), -np.eye(3)])]))
        except Exception:
            return None


def _split(cut, region, dirs):
    """Best cut of a cell (best_cut); where no plane lowers its excess (a ring, a hole) the cell is
    halved across its longest extent among `dirs` instead, so the over-segmentation always progresses."""
    b = best_cut(cut, region, dirs)
    if b is not None:
        n, c = b[3], b[4]
        h0 = cut.piece(region)
        s0 = cut.score(h0)
        if b[0] < s0[0] - 1e-15 or b[1] < s0[1] - 1e-4:
            return n, c
    P = cut.points(region)
    spans = [(np.ptp(P @ n), k) for k, n in enumerate(dirs)]
    _, k = max(spans, key=lambda t: (round(t[0], 9), -t[1]))
    n = dirs[k]
    return n, float(0.5 * ((P @ n).min() + (P @ n).max()))


def agglomerate(cut, pts, order):
    """Merge pieces (point sets) while some merged hull (the hull of both point sets; any two pieces,
    not only neighbours) stays within TARGET: `order` "least" takes the merge of least excess first,
    "largest" the one of largest merged volume. Then a piece whose points all lie in the others is
    dropped. Returns (points, hulls, own excesses)."""
    pts = [P for P in pts if _hull(P) is not None]
    hulls = [_hull(P) for P in pts]
    own = [cut.score(h)[1] for h in hulls]
    uid = list(range(len(pts)))
    nxt = len(pts)
    cache = {}
    while len(pts) > 1:
        best = None
        for i in range(len(pts)):
            for j in range(i + 1, len(pts)):
                key = (uid[i], uid[j])
                if key not in cache:
                    h = _hull(np.vstack([pts[i], pts[j]]))
                    cache[key] = (cut.score(h)[1], h)
                e, h = cache[key]
                if e > TARGET:
                    continue
                rank = (round(e, 9), i, j) if order == "least" else (-round(h.volume, 15), i, j)
                if best is None or rank < best[0]:
                    best = (rank, e, i, j, h)
        if best is None:
            break
        _, e, i, j, h = best
        P = np.vstack([pts[i], pts[j]])
        for k in (j, i):
            del pts[k], hulls[k], own[k], uid[k]
        pts.append(P); hulls.append(h); own.append(e); uid.append(nxt); nxt += 1
    k = 0
    while k < len(pts) and len(pts) > 1:
        inside = np.zeros(len(pts[k]), bool)
        for m, g in enumerate(hulls):
            if m != k:
                inside |= (pts[k] @ g.equations[:, :3].T + g.equations[:, 3]).max(axis=1) <= -1e-9
        if inside.all():
            del pts[k], hulls[k], own[k]
        else:
            k += 1
    return pts, hulls, own


def decompose(name, mesh, log):
    """Convex pieces of one link.
    (1) Over-segmentation: the cell with the largest (approximate) excess is cut by a plane (_split);
        snapshots when every cell is within each of SEG_TARGETS (at most MAX_CELLS cells).
    (2) Agglomeration of each snapshot, both merge orders (agglomerate).
    The variant with the fewest pieces wins (ties: the smaller union excess, approximate; then the
    earlier variant). Pieces may overlap; each holds the mesh vertices of its cell(s)."""
    surf = Surface(mesh, FILL_R)
    log(f"  {name}: {surf.fill_parts} small hole(s) filled ({surf.fill_volume*1e9:.1f} mm^3)")
    cut = Cutter(mesh, surf)
    dirs = _dirs(mesh)
    cells = [[]]
    sc = [cut.score(cut.piece([]))]
    snaps = []
    for target in SEG_TARGETS:
        while True:
            todo = [i for i in np.argsort([-m for _, m in sc], kind="stable") if sc[i][1] > target]
            if not todo or len(cells) >= MAX_CELLS:
                break
            i = int(todo[0])
            n, c = _split(cut, cells[i], dirs)
            new = [r for r in (cells[i] + [(n, c + OVERLAP)], cells[i] + [(-n, -c + OVERLAP)])
                   if len(cut.points(r)) > 0]
            cells[i:i + 1] = new
            sc[i:i + 1] = [cut.score(cut.piece(r)) for r in new]
        if max(m for _, m in sc) <= TARGET:
            snaps.append((target, list(cells)))
    variants = []
    for target, cl in snaps:
        for order in ("least", "largest"):
            pts, hulls, own = agglomerate(cut, [cut.points(r) for r in cl], order)
            e = measure(surf, hulls, SEARCH_STEP, exact=False)[0]
            log(f"  {name}: cells within {target*1e3:.1f} mm: {len(cl)}; merged ({order} first): "
                f"{len(hulls)} pieces, excess ~{e*1e3:.2f} mm")
            variants.append(((len(hulls), round(e, 5), len(variants)), pts, hulls))
    if not variants:
        raise SystemExit(f"{name}: no decomposition within {TARGET*1e3:.1f} mm in {MAX_CELLS} cells")
    _, pts, hulls = min(variants, key=lambda v: v[0])
    return surf, cut, pts, hulls


def finalize(name, mesh, cut, pts, hulls, log):
    """Pieces as stored: every mesh vertex is given to a piece (a vertex of a dropped sliver cell joins
    the piece it widens least); each piece's hull facet normals are thinned to THIN apart (largest
    facets first; each plane at the support of the piece's points), its planes are moved out by OUT (doubled until every point of the piece lies >= 1 um
    inside the piece rounded to 6 decimals, its vertices thinned to MIN_SEP apart) and its vertices
    recomputed."""
    V = np.unique(np.round(mesh.vertices, 12), axis=0)
    pts = [np.asarray(P) for P in pts]

    def depth(h, X):   # > 0 inside
        return -(X @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1)

    D = np.array([depth(h, V) for h in hulls])
    orphan = D.max(axis=0) < -1e-9
    for v in V[orphan]:
        # a vertex of a dropped sliver cell: the piece that takes it with the least excess
        tries = [(cut.score(_hull(np.vstack([P, v])))[1], k) for k, P in enumerate(pts)]
        k = min(tries)[1]
        pts[k] = np.vstack([pts[k], v]); hulls[k] = _hull(pts[k])
    if orphan.any():
        log(f"  {name}: {int(orphan.sum())} vertices outside every piece joined the piece they widen least")
    out = []
    for P, h in zip(pts, hulls):
        # facet normals thinned to THIN apart (largest facets first), each plane at the support of
        # the piece's points: an outer approximation without clusters of near-coincident vertices
        tri = h.points[h.simplices]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        kept = []
        for i in np.argsort(-area, kind="stable"):
            nrm = h.equations[i, :3]
            if all(nrm @ m < np.cos(THIN) for m in kept):
                kept.append(nrm)
        Nk = np.array(kept)
        eq = np.c_[Nk, -(P @ Nk.T).max(axis=0)]
        inner = h.points[h.vertices].mean(axis=0)
        for k in range(12):
            hs = eq.copy(); hs[:, 3] -= OUT * 2 ** k           # every plane moved out by OUT 2^k
            try:
                Q = _sparse(np.round(HalfspaceIntersection(hs, inner).intersections, 6), MIN_SEP)
                g = ConvexHull(Q)
            except Exception:
                continue
            if depth(g, P).min() >= 1e-6:
                break
        else:
            raise SystemExit(f"{name}: a piece cannot be rounded")
        out.append(Q[g.vertices])
    return out


def _sparse(Q, r):
    """Q without vertices closer than r to an earlier kept one (lexicographic order): the hull shrinks
    by at most r, which the outward offset covers (checked)."""
    Q = Q[np.lexsort(Q.T[::-1])]
    tree = cKDTree(Q)
    keep = np.ones(len(Q), bool)
    for i in range(len(Q)):
        if keep[i]:
            for j in tree.query_ball_point(Q[i], r):
                if j > i:
                    keep[j] = False
    return Q[keep]


def test_vertices(mesh, pieces, cap=1500):
    """Test data: the deduplicated mesh vertices (6 decimals) — all of them if <= cap, else the hull
    vertices and those within 1 mm of the pieces' boundary, topped up / cut by depth inside."""
    V = np.unique(np.round(mesh.vertices, 6), axis=0)
    if len(V) <= cap:
        return V, len(V)
    hs = [ConvexHull(Q) for Q in pieces]
    dep = np.max([-(V @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1) for h in hs], axis=0)
    must = np.zeros(len(V), bool)
    must[ConvexHull(V).vertices] = True
    must |= dep <= 0.001
    order = np.lexsort((dep, ~must))
    return V[np.sort(order[:cap])], int(must.sum())


def check_inside(pieces, V, tol=1e-6):
    """Largest distance outside the union of the pieces over V (0 if all inside, by facet planes: a
    lower bound of the distance, exact for the containment test at tol)."""
    worst = np.full(len(V), np.inf)
    for Q in pieces:
        h = ConvexHull(Q)
        worst = np.minimum(worst, (V @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1))
    return float(max(worst.max(), 0.0))

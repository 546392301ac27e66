"""`repair`: cuts of the exact tier's pieces at the link's worst points (see ur_pieces.py)."""
import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

from shapes import _frame
from ur_polytopes import OVERLAP, polytope, solid

TARGET = 0.0045           # `repair` cuts the pieces further while the link's excess exceeds this
REPAIR_RADIUS = 0.010     # a repair cut must lower the excess within this distance of the worst point
VERBOSE = False           # print each repair cut


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

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

Modules: ur_polytopes.py (one piece: `polytope`, `assign`, `with_axis`; measuring a union of pieces:
`measure`, `solid`, `uncovered`, `nearest_boundary`), ur_repair.py (`repair`), this file (`pieces`,
`_refine`).

The runtime uses C grown by its slack as the conservative broad phase (a pair clear of it is clear
of the pieces) and the pieces as the exact test where it is within the margin. Excess is measured
on the union of the pieces like the cylinders' (ur_vis.measure: boundary samples every 1.5 mm,
distance to the visual surface), at the samples outside the link (`solid`).
"""
import numpy as np
from scipy.spatial import QhullError

from shapes import _frame
from ur_polytopes import OVERLAP, assign, measure, polytope, with_axis
from ur_repair import repair
from ur_vis import _cover_points

GOAL = 0.0045             # a piece is cut into slabs until its outward excess is at most this
SECTORS = 8               # default sector count of `_sectors`
SECTORINGS = [(4, 0.0), (4, np.pi / 4), (8, 0.0), (8, np.pi / 8)]   # (k sectors, phase) tried
SECTOR_OVERLAP = np.radians(1.0)
SECTOR_DEPTH = 0          # only a whole cylinder's piece is tried in sectors
SECTOR_AXIAL = 2          # a sector is halved along the axis at most this often
MAX_DEPTH = 6             # a cylinder's points are halved at most this often (slabs >= 1/64 of it)
MAX_PIECES = 60           # `repair` cuts further only while the link has fewer pieces than this


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

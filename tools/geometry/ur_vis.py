"""Fit cylinder/capsule sets to the UR link VISUAL meshes (in DH frames), measure the excess.

Every shape is a cylinder, flat-ended or round-edged ("border", see shapes.py), either in a stack of
coaxial cylinders on a joint axis (housings, base, flange)
or on the tube axis (upper-arm / forearm tubes, ends buried in the housings), or a small radial
cylinder ("nub") for a local protrusion (CB3 base cable connector, wrist_3 bump).

Stack fitting is a 1-D minimax partition (DP) of the axial range into <= k segments, each segment's
radius = the largest radial distance of its points; the segment cost is the 2-D distance (axial,
radial) from the segment's outer edge to the link's rotational envelope (max radius per axial bin),
where cells already covered by a perpendicular housing count as inside.  Borders (rounded rims) are then
chosen per cylinder by `round_edges`.  The 3-D excess is measured against the real visual mesh (`measure`).
"""
import numpy as np
import trimesh
from scipy import ndimage
from scipy.spatial import cKDTree

from shapes import dist_outside, radius_for_border, sample_surface, union_dist
from ur_kin import DH

BASE_CLEAR = 0.002   # base cylinder starts 2 mm above the mounting plane
COL = 0.0005         # axial bin of the 2-D profile (m)
ROW = 0.00025        # radial raster of the 2-D distance field (m)
SLACK = 0.001       # points this close outside a through-housing's main radius stay in it
NSEC = 72           # angular sectors of the excess envelope
TARGET = 0.0035      # 2-D cost at which a stack stops adding segments (3-D adds ~1 mm)
X, Y, Z = np.eye(3)
O = np.zeros(3)


def axial(P, p0, u):
    t = (P - p0) @ u
    r = np.linalg.norm(P - p0 - t[:, None] * u, axis=1)
    return t, r


def stack(name, PS, p0, u, kmax=3, covers=(), tmin=None, tmax=None, clip=None, names=None):
    """Coaxial cylinders on axis (p0,u) containing all vertices P of PS = (P, S); S = surface samples of
    the same part, used for the excess envelope (flat facets lie inside their vertices' radius).

    covers: [(t_c, R)] perpendicular cylinders crossing the axis at t_c with radius R; a cross-section
    (t, rho) with (t-t_c)^2 + rho^2 <= R^2 lies inside them (worst direction), so it is no excess.
    clip: lowest allowed t (points below are only covered radially).  Returns (shapes, cost2d)."""
    P, S = PS
    u = np.asarray(u, float); p0 = np.asarray(p0, float)
    t, r = axial(P, p0, u)
    t0 = t.min() if tmin is None else tmin
    t1 = t.max() if tmax is None else tmax
    if clip is not None:
        t0 = max(t0, clip)
    tc = np.clip(t, t0, t1)
    nb = max(1, int(np.ceil((t1 - t0) / max(COL, (t1 - t0) / 300))))
    edges = t0 + (t1 - t0) * np.arange(nb + 1) / nb
    b = np.minimum(((tc - t0) / (t1 - t0 + 1e-15) * nb).astype(int), nb - 1)
    cen = 0.5 * (edges[:-1] + edges[1:])
    # coverage envelope: max radius per axial bin (interpolated over empty bins)
    prof = np.full(nb, -1.0)
    np.maximum.at(prof, b, r)
    have = prof >= 0
    cover = np.interp(cen, cen[have], prof[have])
    # excess envelope: per angular sector the max radius per bin, then the minimum over sectors
    # (a recess at one angle is judged there); sectors with too few points are ignored
    v1 = np.cross(u, [1.0, 0, 0] if abs(u[0]) < 0.9 else [0, 1.0, 0]); v1 /= np.linalg.norm(v1)
    v2 = np.cross(u, v1)
    W = S - p0
    ts, rs = axial(S, p0, u)
    bs = np.minimum((np.clip((ts - t0) / (t1 - t0 + 1e-15), 0, 1) * nb).astype(int), nb - 1)
    sec = ((np.arctan2(W @ v2, W @ v1) + np.pi) / (2 * np.pi) * NSEC).astype(int) % NSEC
    prof = cover.copy()
    for k in range(NSEC):
        m = sec == k
        if m.sum() < 8:
            continue
        pk = np.full(nb, -1.0)
        np.maximum.at(pk, bs[m], rs[m])
        hk = pk >= 0
        if hk.sum() < 2:
            continue
        pk = np.interp(cen, cen[hk], pk[hk])
        lo, hi = cen[hk].min(), cen[hk].max()  # outside the sector's own axial range: no information
        pk[(cen < lo) | (cen > hi)] = cover[(cen < lo) | (cen > hi)]
        prof = np.minimum(prof, pk)
    prof = np.maximum(prof, 0.0)
    # 2-D raster: rows = radius, columns = axial bins (+ margin columns outside the range)
    nr = int(np.ceil((cover.max() + 0.002) / ROW)) + 1
    rho = np.arange(nr) * ROW
    inside = rho[:, None] <= prof[None, :] + 1e-12
    for (tcov, R) in covers:
        inside |= (cen[None, :] - tcov) ** 2 + rho[:, None] ** 2 <= R * R
    dist = ndimage.distance_transform_edt(~inside, sampling=(ROW, COL))
    # cost[i][j]: segment of bins i..j (inclusive)
    INF = 1e9
    cost = np.full((nb, nb), INF)
    for i in range(nb):
        R = np.maximum.accumulate(cover[i:])
        ri = np.minimum(np.ceil(R / ROW - 1e-9).astype(int), nr - 1)
        cm = np.maximum.accumulate(dist[:, i:], axis=1)
        cost[i, i:] = cm[ri, np.arange(nb - i)]
    best = None
    dp = [np.full(nb + 1, INF) for _ in range(kmax + 1)]
    arg = [np.zeros(nb + 1, int) for _ in range(kmax + 1)]
    dp[0][0] = 0.0
    for k in range(1, kmax + 1):
        for j in range(1, nb + 1):
            c = np.maximum(dp[k - 1][:j], cost[np.arange(j), j - 1])
            i = int(np.argmin(c)); dp[k][j] = c[i]; arg[k][j] = i
        if best is None or dp[k][nb] < best[1] - 1e-4:
            best = (k, dp[k][nb])
        if dp[k][nb] <= TARGET:
            break
    k = best[0]
    cuts = [nb]
    for kk in range(k, 0, -1):
        cuts.append(arg[kk][cuts[-1]])
    cuts = cuts[::-1]
    out = []
    for s in range(k):
        lo, hi = edges[cuts[s]], edges[cuts[s + 1]]
        if s == 0:
            lo = t0
        if s == k - 1:
            hi = t1
        sel = (tc >= lo - 1e-12) & (tc <= hi + 1e-12)
        rad = float(r[sel].max()) if sel.any() else float(cover[cuts[s]:cuts[s + 1]].max())
        nm = names[s] if names and s < len(names) else (name if s == 0 else f"{name}_{s + 1}")
        out.append({"name": nm, "kind": "cylinder", "a": p0 + lo * u, "b": p0 + hi * u, "radius": rad})
    return out, float(best[1])


def nub(name, P, p0, u, r_in):
    """Small cylinder for a local radial protrusion of points P off the axis (p0,u): its axis is radial
    (through the points' centroid), from radius r_in (buried in the main body) to the outermost point."""
    u = np.asarray(u, float)
    c = P.mean(0)
    tcen = (c - p0) @ u
    d = c - p0 - tcen * u; d /= np.linalg.norm(d)
    q0 = p0 + tcen * u
    t, r = axial(P, q0, d)
    # recentre the nub axis on the points' cross-section
    w = np.cross(u, d)
    cu, cw = 0.5 * (((P - q0) @ u).min() + ((P - q0) @ u).max()), 0.5 * ((P @ w).min() + (P @ w).max() - 2 * q0 @ w)
    q0 = q0 + cu * u + cw * w
    t, r = axial(P, q0, d)
    return {"name": name, "kind": "cylinder", "a": q0 + r_in * d, "b": q0 + t.max() * d, "radius": float(r.max())}


def _sel(PS, f):
    P, S = PS
    return (P[f(P)], S[f(S)])


def _main_radius(P, u):
    """Radius reached by most angular sectors around axis u through the origin (median of sector maxima)."""
    t, r = axial(P, O, u)
    v1 = np.cross(u, [1.0, 0, 0] if abs(u[0]) < 0.9 else [0, 1.0, 0]); v1 /= np.linalg.norm(v1)
    v2 = np.cross(u, v1)
    sec = ((np.arctan2(P @ v2, P @ v1) + np.pi) / (2 * np.pi) * NSEC).astype(int) % NSEC
    mx = np.full(NSEC, 0.0)
    np.maximum.at(mx, sec, r)
    return float(np.median(mx))


def fit(model, link, V, S, opts=None):
    """V: visual-mesh vertices, S: surface samples, both in the link's DH frame."""
    opts = opts or {}
    p = DH[model]
    PS = (V, S)
    rZ = lambda Q: np.hypot(Q[:, 0], Q[:, 1])
    if link == "base":
        shapes = []
        main_r = _main_radius(V, Z)
        far = rZ(V) > main_r + 0.01  # CB3 cable connector
        body = PS
        if far.any():
            body = _sel(PS, lambda Q: rZ(Q) <= main_r + 0.001)
        sh, c2 = stack("base", body, O, Z, kmax=opts.get("k", 3), clip=BASE_CLEAR,
                       names=["base", "base_mid", "base_top", "base_4"])
        if opts.get("debug"):
            print("   2d cost", c2)
        shapes += sh
        if far.any():
            shapes.append(nub("base_connector", V[rZ(V) > main_r + 0.001], O, Z, main_r - 0.015))
        return shapes
    if link == "wrist_3":
        main_r = _main_radius(V, Z)
        shapes = []
        body = PS
        far = rZ(V) > main_r + 0.001
        if far.any():
            ang = np.arctan2(V[far, 1], V[far, 0])
            a0 = np.arctan2(np.sin(ang).mean(), np.cos(ang).mean())
            bump = lambda Q: (np.abs(np.angle(np.exp(1j * (np.arctan2(Q[:, 1], Q[:, 0]) - a0)))) < 0.35) & \
                (rZ(Q) > main_r + 0.001)
            body = _sel(PS, lambda Q: ~bump(Q))
            shapes.append(nub("flange_bump", V[bump(V)], O, Z, main_r - 0.006))
        sh, _ = stack("flange", body, O, Z, kmax=opts.get("k", 3), names=["flange_base", "flange_mid", "flange"])
        return sh + shapes
    if link in ("shoulder", "wrist_1", "wrist_2"):
        names = {"shoulder": ("shoulder_pan", "shoulder_lift"),
                 "wrist_1": ("wrist_1_joint", "wrist_1_to_wrist_2"),
                 "wrist_2": ("wrist_2_joint", "wrist_2_to_wrist_3")}[link]
        axes = {names[0]: Y, names[1]: Z}
        first = opts.get("through", names[1])
        second = names[0] if first == names[1] else names[1]
        ua, ub = axes[first], axes[second]
        Ra = _main_radius(V, ua) if "Ra" not in opts else opts["Ra"]
        ra = lambda Q: axial(Q, O, ua)[1]
        A = _sel(PS, lambda Q: ra(Q) <= Ra + SLACK)
        B = _sel(PS, lambda Q: ra(Q) > Ra + SLACK)
        shA, cA = stack(first, A, O, ua, kmax=opts.get("ka", 3), names=[first + s for s in ("", "_2", "_3")])
        ra_max = max(s["radius"] for s in shA)
        if len(B[0]) == 0:
            return shA
        shB, cB = stack(second, B, O, ub, kmax=opts.get("kb", 3), covers=[(0.0, ra_max)],
                       names=[second + s for s in ("", "_2", "_3")])
        if opts.get("debug"):
            print("   2d cost", first, cA, second, cB)
        return shA + shB
    if link in ("upper_arm", "forearm"):
        L = -p["a2"] if link == "upper_arm" else -p["a3"]
        far, near = ("shoulder", "elbow") if link == "upper_arm" else ("elbow", "wrist_1")
        pf, pn = np.array([L, 0, 0]), O
        rf = lambda Q: np.hypot(Q[:, 0] - L, Q[:, 1])
        Rf = rf(V)[V[:, 0] > L].max()
        Rn = rZ(V)[V[:, 0] < 0].max()
        mid = V[(V[:, 0] > Rn + 0.01) & (V[:, 0] < L - Rf - 0.01)]
        c = 0.5 * (mid.min(0) + mid.max(0)); c[0] = 0.0
        Rt = float(np.hypot(mid[:, 1] - c[1], mid[:, 2] - c[2]).max())
        # tube core first (inside the tube's mid-section radius, between the joint axes), then housings
        core = lambda Q: (np.hypot(Q[:, 1] - c[1], Q[:, 2] - c[2]) <= Rt + SLACK) & (Q[:, 0] >= 0) & (Q[:, 0] <= L)
        # housing axial range from the side away from the tube (pure housing); what lies beyond it on
        # the tube side (flares, oblique junctions) belongs to the tube stack
        zf = (V[V[:, 0] > L][:, 2].min() - SLACK, V[V[:, 0] > L][:, 2].max() + SLACK)
        zn = (V[V[:, 0] < 0][:, 2].min() - SLACK, V[V[:, 0] < 0][:, 2].max() + SLACK)
        if not opts.get("split"):
            zf = zn = (-np.inf, np.inf)
        inF = lambda Q: (rf(Q) <= Rf + 2 * SLACK) & ~core(Q) & (((Q[:, 2] >= zf[0]) & (Q[:, 2] <= zf[1])) | (Q[:, 0] > L))
        inN = lambda Q: (rZ(Q) <= Rn + 2 * SLACK) & ~inF(Q) & ~core(Q) & (((Q[:, 2] >= zn[0]) & (Q[:, 2] <= zn[1])) |
                                                                    (Q[:, 0] < 0))
        tube = _sel(PS, lambda Q: ~inF(Q) & ~inN(Q))
        sh_t, _ = stack(f"{link}_tube", tube, c, X, kmax=opts.get("kt", 2), tmin=0.0, tmax=L,
                        covers=[(0.0, Rn), (L, Rf)], names=[f"{link}_tube" + s for s in ("", "_2", "_3")])
        sh_f, _ = stack(f"{link}_{far}", _sel(PS, inF), pf, Z, kmax=opts.get("kf", 2),
                        names=[f"{link}_{far}", f"{link}_{far}_cap", f"{link}_{far}_3"])
        sh_n, _ = stack(f"{link}_{near}", _sel(PS, inN), pn, Z, kmax=opts.get("kn", 2),
                        names=[f"{link}_{near}", f"{link}_{near}_cap", f"{link}_{near}_3"])
        return sh_f + sh_t + sh_n
    raise ValueError(link)


def capped(V, F, planar_tol=0.0005, min_span=0.01):
    """Visual mesh with its planar open boundary loops (joint interfaces hidden inside the adjacent
    link, e.g. the flange's underside, the base's top) closed by fans from the loop centroid.
    Non-planar loops (seams between surface patches) are left open.  Returns (mesh, n_caps)."""
    import networkx as nx
    m = trimesh.Trimesh(V, F, process=True)
    m.merge_vertices(digits_vertex=6)
    e = m.edges_sorted
    u, c = np.unique(e, axis=0, return_counts=True)
    bnd = u[c == 1]
    if len(bnd) == 0:
        return m, 0
    g = nx.Graph(); g.add_edges_from(bnd.tolist())
    comps = sorted((sorted(cc) for cc in nx.connected_components(g)), key=lambda cc: cc[0])
    Vn, Fn, caps = [m.vertices], [m.faces], 0
    nv = len(m.vertices)
    for cc in comps:
        P = m.vertices[cc]
        ctr = P.mean(0)
        sv = np.linalg.svd(P - ctr, compute_uv=False)
        if np.ptp(P, axis=0).max() < min_span or sv[-1] / np.sqrt(len(P)) > planar_tol or \
                np.abs((P - ctr) @ np.linalg.svd(P - ctr)[2][-1]).max() > planar_tol:
            continue
        ccs = set(cc)
        E = np.array([ed for ed in bnd.tolist() if ed[0] in ccs])
        Vn.append(ctr[None]); Fn.append(np.column_stack([np.full(len(E), nv), E]))
        nv += 1; caps += 1
    return trimesh.Trimesh(np.vstack(Vn), np.vstack(Fn), process=False), caps


class Surface:
    """Distance to a (possibly open, multi-piece) triangle mesh: k-d tree on dense surface samples,
    exact closest-point refinement of the candidates near the maximum."""

    def __init__(self, V, F, spacing=0.0006, seed=11):
        self.mesh, self.caps = capped(V, F)
        n = int(self.mesh.area / (spacing * spacing)) + 1
        S, _ = trimesh.sample.sample_surface(self.mesh, n, seed=seed)
        self.S = np.vstack([S, V])
        self.tree = cKDTree(self.S)
        self.spacing = spacing

    def field(self, P, h=0.001, pad=0.04):
        """Approximate distance to the surface samples (|error| <~ h): trilinear interpolation of a
        Euclidean distance transform on an h-voxel grid (built on first use).  Used to rank fit
        candidates only; the reported excess is measured with the k-d tree."""
        if not hasattr(self, "_grid"):
            lo = self.S.min(0) - pad
            n = np.ceil((self.S.max(0) + pad - lo) / h).astype(int) + 1
            occ = np.zeros(n, bool)
            idx = np.round((self.S - lo) / h).astype(int)
            occ[idx[:, 0], idx[:, 1], idx[:, 2]] = True
            self._grid = (lo, h, ndimage.distance_transform_edt(~occ, sampling=h).astype(np.float32))
        lo, h, G = self._grid
        if len(P) == 0:
            return np.zeros(0)
        c = ((P - lo) / h).T
        return ndimage.map_coordinates(G, c, order=1, mode="nearest")

    def max_dist(self, P, exact=True):
        if len(P) == 0:
            return 0.0, None
        d, _ = self.tree.query(P)
        if not exact:
            i = int(np.argmax(d))
            return float(d[i]), P[i]
        cand = np.where(d >= d.max() - 2 * self.spacing)[0]
        if len(cand) > 4000:
            cand = cand[np.argsort(-d[cand])[:4000]]
        _, de, _ = trimesh.proximity.closest_point(self.mesh, P[cand])
        i = int(np.argmax(de))
        return float(de[i]), P[cand[i]]


def boundary_samples(shapes, step=0.0015):
    """Surface samples of each shape that lie on the union's boundary (not on/inside another shape)."""
    out = []
    for i, s in enumerate(shapes):
        P = sample_surface(s, step)
        others = [t for j, t in enumerate(shapes) if j != i]
        if others:
            P = P[union_dist(others, P) > 1e-6]
        out.append(P)
    return out


def measure(shapes, surf, step=0.0015, exact=True):
    """Largest outward excess (distance of union-boundary points to the visual surface) and where."""
    worst, at, who = 0.0, np.zeros(3), None
    for s, P in zip(shapes, boundary_samples(shapes, step)):
        d, p = surf.max_dist(P, exact)
        if d > worst:
            worst, at, who = d, p, s["name"]
    return worst, at, who


def check_cover(link, shapes, V, tol=1e-6):
    P = V.copy()
    if link == "base":  # the 2 mm clearance above the mounting plane is intentional
        P[:, 2] = np.maximum(P[:, 2], BASE_CLEAR)
    d = union_dist(shapes, P)
    if d.max() > tol:
        raise SystemExit(f"COVERAGE FAILURE {link}: visual vertex {P[d.argmax()]} outside by {d.max():.3e} m")
    return float(d.max())


def _cover_points(link, V):
    P = V.copy()
    if link == "base":  # the 2 mm clearance above the mounting plane is intentional
        P[:, 2] = np.maximum(P[:, 2], BASE_CLEAR)
    return P


def _with(s, lo, hi, r, e):
    a, b = np.asarray(s["a"], float), np.asarray(s["b"], float)
    u = (b - a) / np.linalg.norm(b - a)
    out = dict(s)
    out.update(a=a + lo * u, b=a + hi * u, radius=float(r), border=float(e))
    return out


def round_edges(link, shapes, V, surf, step=0.003, de=0.001, passes=2, refine=True):
    """Give every cylinder a border e (round-edged cylinder; e = 0 is the flat cylinder) by coordinate
    descent over the shapes, deterministic:

    for cylinder i, the vertices it must contain are those outside all other shapes (so containment
    holds after every step); its axial range is kept or an end is pushed out by e; for each border e on a
    grid (de steps, then de/4 around the best) its radius is the smallest containing them,
    r(e) = max(rho + e - sqrt(e^2 - dt^2)) (dt = axial distance beyond the inner range [lo+e, hi-e]).
    The variant with the smallest link excess is kept (union-boundary samples at `step`, distance from
    `Surface.field`, an approximate distance field of the visual surface samples; ties: the cylinder's
    own excess, smaller e, no push-out).  The base's lowest cylinder keeps its bottom at BASE_CLEAR."""
    shapes = [dict(s, border=float(s.get("border", 0.0))) for s in shapes]
    P = _cover_points(link, V)
    n = len(shapes)
    if n == 0:
        return shapes
    D = np.array([dist_outside(s, P) for s in shapes])

    def samples(s):
        S = sample_surface(s, step)
        return S, surf.field(S)

    smp = [samples(s) for s in shapes]
    for _ in range(passes):
        changed = False
        for i, s in enumerate(shapes):
            if s["kind"] != "cylinder":
                continue
            oth = [j for j in range(n) if j != i]
            Do = D[oth].min(0) if oth else np.full(len(P), np.inf)
            M = P[Do > 1e-9]
            if len(M) == 0:
                continue
            a, b = np.asarray(s["a"], float), np.asarray(s["b"], float)
            L = np.linalg.norm(b - a); u = (b - a) / L
            t = (M - a) @ u
            rho = np.linalg.norm(M - a - t[:, None] * u, axis=1)
            if t.min() < -1e-7 or t.max() > L + 1e-7:
                raise SystemExit(f"round_edges {link}: vertex outside the axial range of {s['name']}: {t.min()} {t.max()} {L}")
            # other shapes' samples and their exposure without shape i
            other = []
            for j in oth:
                Sj, dj = smp[j]
                ex = np.ones(len(Sj), bool)
                for k in oth:
                    if k != j:
                        ex &= dist_outside(shapes[k], Sj) > 1e-6
                other.append((Sj[ex], dj[ex]))
            others_s = [shapes[j] for j in oth]
            # the axial range is kept (trimming it would open slits at stack junctions whose
            # inner faces then count as excess); ends may only be pushed out (below)
            lo, hi = 0.0, L
            # the base's lowest cylinder keeps its bottom at BASE_CLEAR (no extension below it)
            fixed_lo = link == "base" and abs(a[2] - BASE_CLEAR) < 1e-9 and abs(u[2]) > 0.999
            ext_lo = (0.0,) if fixed_lo else (0.0, 1.0)

            def evaluate(e, xl, xh):
                # end(s) may be pushed out by e (an end buried in another shape can then be rounded
                # without the rounding having to contain the vertices near that end)
                l0, h0 = lo - xl * e, hi + xh * e
                r = max(radius_for_border(t, rho, l0, h0, e), e, 1e-4)
                c = _with(s, l0, h0, r, e)
                S = sample_surface(c, step)
                if others_s:
                    S = S[union_dist(others_s, S) > 1e-6]
                own = float(surf.field(S).max()) if len(S) else 0.0
                worst = own
                for (Sj, dj) in other:
                    if len(Sj):
                        m = dist_outside(c, Sj) > 1e-6
                        if m.any():
                            worst = max(worst, float(dj[m].max()))
                return (round(worst, 6), round(own, 6), round(e, 7), xl + xh, xl), c

            best = None
            emax = min(0.5 * (hi - lo), float(rho.max()))
            for xl in ext_lo:
                for xh in (0.0, 1.0):
                    grid = np.arange(0.0, emax + 1e-12, de) if xl + xh == 0 else \
                        np.arange(de, min(float(rho.max()), emax * 2) + 1e-12, de)
                    cands = [evaluate(float(e), xl, xh) for e in grid]
                    if not cands:
                        continue
                    k0 = min(range(len(cands)), key=lambda k: cands[k][0])
                    if refine and de > 0:
                        e0 = float(grid[k0])
                        fine = [e0 + f * de / 4 for f in (-3, -2, -1, 1, 2, 3)]
                        cands += [evaluate(e, xl, xh) for e in fine if 0 <= e <= grid[-1]]
                    for c in cands:
                        if best is None or c[0] < best[0]:
                            best = c
            new = best[1]
            if new["radius"] != s["radius"] or new["border"] != s["border"] or \
                    not np.array_equal(new["a"], s["a"]) or not np.array_equal(new["b"], s["b"]):
                changed = True
            shapes[i] = new
            D[i] = dist_outside(new, P)
            smp[i] = samples(new)
        if not changed:
            break
    return shapes

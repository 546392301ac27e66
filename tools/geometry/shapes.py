"""Cylinder (optionally round-edged) / capsule primitives: containment, surface sampling, fitting."""
import numpy as np


def _frame(u):
    u = u / np.linalg.norm(u)
    t = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    v = np.cross(u, t); v /= np.linalg.norm(v)
    w = np.cross(u, v)
    return u, v, w


def dist_outside(shape, P):
    """Positive = distance outside the shape, <=0 inside (approximate inside depth).

    A cylinder may carry a "border" e (round-edged cylinder): the Minkowski sum of the flat cylinder
    with end centres a + e*u, b - e*u and radius r - e with a ball of radius e, i.e. the same outer
    envelope (a..b axially, r radially) with both rims rounded by radius e.  Its distance is the inner
    flat cylinder's distance minus e (exact outside, so `<= 0` is exact containment)."""
    a, b, r = np.asarray(shape["a"], float), np.asarray(shape["b"], float), shape["radius"]
    ab = b - a; L = np.linalg.norm(ab); u = ab / L
    t = (P - a) @ u
    if shape["kind"] == "capsule":
        tc = np.clip(t, 0, L)
        return np.linalg.norm(P - (a + tc[:, None] * u), axis=1) - r
    e = float(shape.get("border", 0.0))
    rad = np.linalg.norm(P - (a + t[:, None] * u), axis=1)
    dr = rad - (r - e)
    dz = np.maximum(e - t, t - (L - e))
    out = np.where((dr > 0) & (dz > 0), np.hypot(np.maximum(dr, 0), np.maximum(dz, 0)), np.maximum(dr, dz))
    return out - e


def contains_rounded(a, b, r, e, P, tol=0.0):
    """Exact containment test of the round-edged cylinder (a, b, r, border e): with t the axial
    coordinate from a, rho the radial distance, dt = max(e - t, t - (L - e), 0), drho = max(rho - (r - e), 0):
    inside iff 0 <= t <= L, rho <= r and dt^2 + drho^2 <= e^2 (each within tol)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ab = b - a; L = np.linalg.norm(ab); u = ab / L
    t = (P - a) @ u
    rho = np.linalg.norm(P - a - t[:, None] * u, axis=1)
    dt = np.maximum(np.maximum(e - t, t - (L - e)), 0.0)
    dr = np.maximum(rho - (r - e), 0.0)
    return (t >= -tol) & (t <= L + tol) & (rho <= r + tol) & (np.hypot(dt, dr) <= e + tol)


def radius_for_border(t, rho, lo, hi, e):
    """Smallest radius r of the round-edged cylinder spanning [lo, hi] axially with border e that
    contains the points (t, rho) (t within [lo, hi]): max of rho + e - sqrt(e^2 - dt^2)."""
    dt = np.maximum(np.maximum(lo + e - t, t - (hi - e)), 0.0)
    dt = np.minimum(dt, e)
    return float((rho + e - np.sqrt(np.maximum(e * e - dt * dt, 0.0))).max()) if len(t) else 0.0


def union_dist(shapes, P):
    return np.min([dist_outside(s, P) for s in shapes], axis=0)


def sample_surface(shape, step=0.002):
    """Points on the shape's surface, spaced about `step` (round-edged cylinder: side band, end discs of
    radius r - e and the two torus quarter sections of the rims)."""
    a, b, r = np.asarray(shape["a"], float), np.asarray(shape["b"], float), shape["radius"]
    ab = b - a; L = np.linalg.norm(ab)
    u, v, w = _frame(ab)
    e = float(shape.get("border", 0.0)) if shape["kind"] == "cylinder" else 0.0

    def ring_at(rr, n_min=12):
        nth = max(n_min, int(np.ceil(2 * np.pi * rr / step)))
        th = np.arange(nth) * 2 * np.pi / nth
        return np.cos(th)[:, None] * v + np.sin(th)[:, None] * w

    ring = ring_at(r)
    if shape["kind"] == "cylinder":
        Ls = L - 2 * e
        nz = max(2, int(np.ceil(Ls / step)) + 1)
        ts = e + np.linspace(0, Ls, nz)
        pts = [a + t * u + r * ring for t in ts]
        for rr in np.arange(r - e, 0, -step):
            rg = ring_at(rr, 6)
            pts += [a + rr * rg, b + rr * rg]
        pts += [a[None], b[None]]
        if e > 0:
            nphi = max(2, int(np.ceil(np.pi / 2 * e / step)))
            for phi in np.linspace(0, np.pi / 2, nphi + 1)[1:-1]:
                rr, h = (r - e) + e * np.cos(phi), e * np.sin(phi)
                rg = ring_at(rr)
                pts += [a + (e - h) * u + rr * rg, b - (e - h) * u + rr * rg]
    else:
        nz = max(2, int(np.ceil(L / step)) + 1)
        ts = np.linspace(0, L, nz)
        pts = [a + t * u + r * ring for t in ts]
        nphi = max(4, int(np.ceil(np.pi / 2 * r / step)))
        for phi in np.linspace(0, np.pi / 2, nphi + 1)[1:]:
            rr, h = r * np.cos(phi), r * np.sin(phi)
            pts += [a - h * u + rr * ring, b + h * u + rr * ring]
    return np.vstack(pts)


def fit_cylinder(name, P, point, axis, zmin_clip=None):
    """Tightest cylinder with the given axis line containing all points P."""
    u = np.asarray(axis, float); u /= np.linalg.norm(u)
    p0 = np.asarray(point, float)
    t = (P - p0) @ u
    rad = np.linalg.norm(P - p0 - t[:, None] * u, axis=1)
    t0, t1 = t.min(), t.max()
    if zmin_clip is not None:
        t0 = max(t0, zmin_clip)
    return {"name": name, "kind": "cylinder", "a": p0 + t0 * u, "b": p0 + t1 * u, "radius": float(rad.max())}


def fit_capsule(name, P, point, axis, radius=None):
    """Capsule on a given axis line; radius = max radial distance (or given, >= it); end points pulled in
    as far as the round caps still contain every point."""
    u = np.asarray(axis, float); u /= np.linalg.norm(u)
    p0 = np.asarray(point, float)
    t = (P - p0) @ u
    rad = np.linalg.norm(P - p0 - t[:, None] * u, axis=1)
    r = float(rad.max()) if radius is None else max(float(radius), float(rad.max()))
    slack = np.sqrt(np.maximum(r * r - rad * rad, 0))
    t0 = (t + slack).min(); t1 = (t - slack).max()
    if t1 < t0:
        t0 = t1 = 0.5 * (t0 + t1)
    return {"name": name, "kind": "capsule", "a": p0 + t0 * u, "b": p0 + t1 * u, "radius": r}

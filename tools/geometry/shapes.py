"""Cylinder / capsule primitives: containment, surface sampling, fitting."""
import numpy as np


def _frame(u):
    u = u / np.linalg.norm(u)
    t = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
    v = np.cross(u, t); v /= np.linalg.norm(v)
    w = np.cross(u, v)
    return u, v, w


def dist_outside(shape, P):
    """Positive = distance outside the shape, <=0 inside (approximate inside depth)."""
    a, b, r = np.asarray(shape["a"]), np.asarray(shape["b"]), shape["radius"]
    ab = b - a; L = np.linalg.norm(ab); u = ab / L
    t = (P - a) @ u
    if shape["kind"] == "capsule":
        tc = np.clip(t, 0, L)
        return np.linalg.norm(P - (a + tc[:, None] * u), axis=1) - r
    rad = np.linalg.norm(P - (a + t[:, None] * u), axis=1)
    dr = rad - r
    dz = np.maximum(-t, t - L)
    out = np.where((dr > 0) & (dz > 0), np.hypot(np.maximum(dr, 0), np.maximum(dz, 0)), np.maximum(dr, dz))
    return out


def union_dist(shapes, P):
    return np.min([dist_outside(s, P) for s in shapes], axis=0)


def sample_surface(shape, step=0.002):
    a, b, r = np.asarray(shape["a"], float), np.asarray(shape["b"], float), shape["radius"]
    ab = b - a; L = np.linalg.norm(ab)
    u, v, w = _frame(ab)
    nth = max(12, int(np.ceil(2 * np.pi * r / step)))
    th = np.arange(nth) * 2 * np.pi / nth
    ring = np.cos(th)[:, None] * v + np.sin(th)[:, None] * w
    nz = max(2, int(np.ceil(L / step)) + 1)
    ts = np.linspace(0, L, nz)
    pts = [a + t * u + r * ring for t in ts]
    if shape["kind"] == "cylinder":
        for rr in np.arange(r, 0, -step):
            n = max(6, int(np.ceil(2 * np.pi * rr / step)))
            th2 = np.arange(n) * 2 * np.pi / n
            rg = np.cos(th2)[:, None] * v + np.sin(th2)[:, None] * w
            pts += [a + rr * rg, b + rr * rg]
        pts += [a[None], b[None]]
    else:
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

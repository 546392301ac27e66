"""Robotiq 2F-85 finger linkage in closed form (planar, in G's x-z plane) and its check against
MuJoCo's forward kinematics: the sampled poses of `derive_fingers.py`.

A link pose is [x, z, phi]: translation (x, 0, z) in G and rotation phi about G's +y; rot(phi) acts on
(x, z). Every Menagerie finger joint axis is G's -y, so a joint angle theta (MuJoCo's sign) turns its
link by phi = -theta about +y.
"""
import numpy as np

from common import r6

LINKS = ["driver", "coupler", "spring_link", "follower", "pad"]


# ----------------------------------------------------------------------------------------------
# planar kinematics in G's x-z plane.  rot(phi) = rotation about +y by phi acting on (x, z).

def rot(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, s], [-s, c]])


def ang(v):
    """Angle of a planar vector (x, z) in the rot() sense: rot(phi) @ (1, 0) has ang = phi."""
    return float(np.arctan2(-v[1], v[0]))


def circle_meet(P, rp, Q, rq, side):
    """Intersection of circles (P, rp), (Q, rq): the one with sign(cross(Q - P, X - P)) == side."""
    d = Q - P; L = np.linalg.norm(d)
    a = (rp * rp - rq * rq + L * L) / (2 * L)
    h2 = rp * rp - a * a
    if h2 < -1e-12:
        raise ValueError("loop does not close")
    h = np.sqrt(max(h2, 0.0))
    u = d / L; w = np.array([-u[1], u[0]])
    X = P + a * u + h * w
    if np.sign(u[0] * (X - P)[1] - u[1] * (X - P)[0]) != side and h > 0:
        X = P + a * u - h * w
    return X


def cross2(a, b):
    return float(a[0] * b[1] - a[1] * b[0])


class Linkage:
    """The +x finger: pivots A (driver), B (spring_link) on the base; the driver carries the coupler
    joint C at Cd; the coupler meets the follower's frame origin D at Dc (the `connect` equality);
    the spring_link carries the follower joint E at Es; in the follower frame E is at Ef; the pad frame
    is at Pf in the follower frame (parallel to it). All in link frames (x, z)."""

    def __init__(self, p):
        self.__dict__.update({k: np.asarray(v, float) if isinstance(v, (list, tuple, np.ndarray)) else v
                              for k, v in p.items()})
        self.lc = np.linalg.norm(self.Dc); self.lf = np.linalg.norm(self.Ef)
        self.ls = np.linalg.norm(self.Es); self.lk = np.linalg.norm(self.Cd + self.Dc)
        # branches, from the zero pose (all joint angles 0)
        C0 = self.A + self.Cd; E0 = self.B + self.Es; D0 = E0 - self.Ef
        self.side_D = np.sign(cross2(E0 - C0, D0 - C0))
        self.side_E = np.sign(cross2(self.B - D0, E0 - D0))

    def solve(self, td, ts):
        """Joint angles (driver, coupler, spring_link, follower) from driver and spring_link angles."""
        C = self.A + rot(-td) @ self.Cd
        E = self.B + rot(-ts) @ self.Es
        D = circle_meet(C, self.lc, E, self.lf, self.side_D)
        phic = ang(D - C) - ang(self.Dc)
        phif = ang(D - E) - ang(-self.Ef)
        tc = _wrap(-phic - td); tf = _wrap(-phif - ts)
        return np.array([td, tc, ts, tf])

    def parallel(self, td):
        """Spring-held mode (coupler at its limit 0): the driver and coupler move as one crank A->D."""
        D = self.A + rot(-td) @ (self.Cd + self.Dc)
        E = circle_meet(D, self.lf, self.B, self.ls, self.side_E)
        ts = _wrap(-(ang(E - self.B) - ang(self.Es)))
        return self.solve(td, ts)

    def poses(self, q):
        """Link poses [x, z, phi] in G for joint angles q = (driver, coupler, spring_link, follower)."""
        td, tc, ts, tf = q
        C = self.A + rot(-td) @ self.Cd
        E = self.B + rot(-ts) @ self.Es
        phif = -(ts + tf)
        D = E + rot(phif) @ (-self.Ef)
        P = D + rot(phif) @ self.Pf
        return {"driver": [*self.A, -td], "coupler": [*C, -(td + tc)], "spring_link": [*self.B, -ts],
                "follower": [*D, phif], "pad": [*P, phif]}


def _wrap(a):
    return float((a + np.pi) % (2 * np.pi) - np.pi)


def pose_T(p):
    """4x4 of a planar pose [x, z, phi]."""
    x, z, phi = p
    c, s = np.cos(phi), np.sin(phi)
    T = np.eye(4); T[0, 0] = c; T[0, 2] = s; T[2, 0] = -s; T[2, 2] = c; T[0, 3] = x; T[2, 3] = z
    return T


def kinematics(S, L):
    """Closed form vs MuJoCo; pad centre / tips vs our table; sampled poses."""
    lk = Linkage(S["params"])
    fk = S["fk"]
    padV = S["link_mesh"]["pad"][0].vertices
    xface = padV[:, 0].min()
    face = padV[padV[:, 0] <= xface + 1e-6]
    pad_c = np.array([xface, 0.5 * (face[:, 2].min() + face[:, 2].max())])
    follV = S["link_mesh"]["follower"][0].vertices

    def extras(P):
        Tp = pose_T(P["pad"]); Tf = pose_T(P["follower"])
        c = Tp[:3, :3] @ np.array([pad_c[0], 0, pad_c[1]]) + Tp[:3, 3]
        tip = max((follV @ Tf[:3, :3].T + Tf[:3, 3])[:, 2].max(), (padV @ Tp[:3, :3].T + Tp[:3, 3])[:, 2].max())
        facex = (padV @ Tp[:3, :3].T + Tp[:3, 3])[:, 0].min()
        return {"pad_center": [c[0], c[2]], "pad_face_x": facex, "gap": 2 * facex, "tip_z": tip}

    worst = {"pose": 0.0, "closure": 0.0}

    def sample(q_mj, mode):
        """One sample from MuJoCo's FK (loop closed), compared with the closed form."""
        P = fk.poses(q_mj)
        q_cf = lk.solve(q_mj[0], q_mj[2])
        Pc = lk.poses(q_cf)
        dev = max(max(abs(a - b) for a, b in zip(P[n], Pc[n])) for n in LINKS)
        dev = max(dev, float(np.abs(q_cf - q_mj).max()))
        worst["pose"] = max(worst["pose"], dev)
        return {"mode": mode, "q": r6(q_mj), "links": {n: r6(P[n]) for n in LINKS},
                **{k: r6(v) for k, v in extras(P).items()}}, dev

    # spring-held (parallel) mode: coupler at 0, driver 0..0.8 in 20 steps
    lo, hi = S["ranges"]["driver"]
    par = []
    q = np.zeros(4)
    for td in np.linspace(lo, hi, 21):
        q[0] = td; q[1] = 0.0
        q, res = fk.close(q, [2, 3])
        worst["closure"] = max(worst["closure"], res)
        qc = lk.parallel(td)
        worst["pose"] = max(worst["pose"], float(np.abs(qc - q).max()))
        s, dev = sample(q.copy(), "parallel")
        par.append(s)
    # blocked proximal phalanx: spring_link held where the parallel mode had it at driver angle t0,
    # the driver turns on by dt (coupler leaves its limit, the follower curls)
    blocked = []
    for t0 in (0.0, 0.2, 0.4, 0.6):
        qp = lk.parallel(t0)
        for dt in (0.05, 0.1, 0.2, 0.3, 0.4):
            td = t0 + dt
            if td > hi + 1e-12:
                continue
            q = qp.copy(); q[0] = td
            q, res = fk.close(q, [1, 3])
            worst["closure"] = max(worst["closure"], res)
            ok = all(S["ranges"][n][0] - 1e-9 <= v <= S["ranges"][n][1] + 1e-9
                     for n, v in zip(["driver", "coupler", "spring_link", "follower"], q))
            if not ok:
                continue
            s, dev = sample(q.copy(), "blocked")
            s["blocked_at_driver"] = r6(t0)
            blocked.append(s)
    return lk, par, blocked, worst, pad_c, extras


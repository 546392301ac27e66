"""Index of the compiled Menagerie 2F-85 for closing.py (`Gripper`): bodies, joints, finger geometry
points, the frame G, and the finger points and angles read in G."""
import math

import mujoco
import numpy as np

from transforms import mat_of_quat, rz

LINKS = ["driver", "coupler", "spring_link", "follower", "pad"]  # Menagerie body names (pad incl. silicone_pad)
PROXIMAL = {"driver", "coupler", "spring_link"}
DISTAL = {"follower", "pad"}
SIDES = {"pos": "right", "neg": "left"}  # our side name (+x / -x finger in G) -> Menagerie prefix
SIGN = {"pos": 1.0, "neg": -1.0}


def geom_points(m, g):
    """Geom `g`'s points in its body's frame: a mesh's convex-hull vertices (all its vertices where it has no
    hull), a box's corners; None for any other type."""
    if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
        mid = m.geom_dataid[g]
        V = m.mesh_vert[m.mesh_vertadr[mid]:m.mesh_vertadr[mid] + m.mesh_vertnum[mid]]
        ga = m.mesh_graphadr[mid]
        if ga >= 0:
            nv = m.mesh_graph[ga]
            V = V[m.mesh_graph[ga + 2 + nv:ga + 2 + 2 * nv]]
    elif m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
        V = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]) * m.geom_size[g]
    else:
        return None
    return V @ mat_of_quat(m.geom_quat[g]).T + m.geom_pos[g]


class Gripper:
    """Index of the compiled model: bodies, joints, finger geometry points, G frame."""

    def __init__(self, m):
        self.m = m
        name = lambda kind, n: mujoco.mj_name2id(m, kind, n)
        self.body = {}
        for s, pre in SIDES.items():
            for ln in LINKS:
                self.body[(s, ln)] = name(mujoco.mjtObj.mjOBJ_BODY, f"{pre}_{ln}")
            self.body[(s, "silicone_pad")] = name(mujoco.mjtObj.mjOBJ_BODY, f"{pre}_silicone_pad")
        assert min(self.body.values()) > 0, "Menagerie body names changed"
        self.bm = name(mujoco.mjtObj.mjOBJ_BODY, "base_mount")
        self.base = name(mujoco.mjtObj.mjOBJ_BODY, "base")
        self.jq = {}
        self.jv = {}
        for s, pre in SIDES.items():
            for j in ["driver", "coupler", "spring_link", "follower"]:
                jid = name(mujoco.mjtObj.mjOBJ_JOINT, f"{pre}_{j}_joint")
                assert jid >= 0
                self.jq[(s, j)] = m.jnt_qposadr[jid]
                self.jv[(s, j)] = m.jnt_dofadr[jid]
        # geom roles: link of each finger geom
        self.geom_side = {}
        self.geom_link = {}
        for g in range(m.ngeom):
            b = m.geom_bodyid[g]
            for (s, ln), bid in self.body.items():
                if b == bid:
                    self.geom_side[g] = s
                    self.geom_link[g] = "pad" if ln == "silicone_pad" else ln
        self.palm_geoms = {g for g in range(m.ngeom) if m.geom_bodyid[g] in (self.bm, self.base)}
        self.gripper_geoms = set(self.geom_side) | self.palm_geoms
        # finger geometry points per body (body frame): mesh convex-hull vertices (all vertices where the
        # mesh has no hull), box corners
        self.pts = {}
        for (s, ln), bid in self.body.items():
            P = []
            for g in range(m.ngeom):
                if m.geom_bodyid[g] != bid:
                    continue
                V = geom_points(m, g)
                if V is None:
                    raise ValueError(f"unexpected finger geom type {m.geom_type[g]}")
                P.append(V)
            self.pts[(s, ln)] = np.vstack(P)
        # pad contact face (pad body frame) from the two pad boxes
        boxes = [g for g in range(m.ngeom) if m.geom_bodyid[g] == self.body[("pos", "pad")]
                 and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
        assert len(boxes) == 2
        for g in boxes:
            assert np.allclose(m.geom_quat[g], [1, 0, 0, 0])
        lo = np.min([m.geom_pos[g] - m.geom_size[g] for g in boxes], axis=0)
        hi = np.max([m.geom_pos[g] + m.geom_size[g] for g in boxes], axis=0)
        self.pad_lo, self.pad_hi = lo, hi

    def setup_frame(self, d):
        """G frame from the open pose (d after mj_forward at qpos0)."""
        m = self.m
        Rbm, obm = d.xmat[self.bm].reshape(3, 3), d.xpos[self.bm].copy()
        # mounting face: lowest base_mount vertex along the base_mount z axis (all vertices, not hull)
        g_bm = [g for g in range(m.ngeom) if m.geom_bodyid[g] == self.bm and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH][0]
        mid = m.geom_dataid[g_bm]
        V = m.mesh_vert[m.mesh_vertadr[mid]:m.mesh_vertadr[mid] + m.mesh_vertnum[mid]]
        Vb = V @ mat_of_quat(m.geom_quat[g_bm]).T + m.geom_pos[g_bm]
        zface = Vb[:, 2].min()
        self.face_vertices = int(np.sum(Vb[:, 2] <= zface + 1e-4))
        # rotation about z putting the +x ("right") pad at +x
        prp = Rbm.T @ (d.xpos[self.body[("pos", "pad")]] - obm)
        phi = round(math.atan2(prp[1], prp[0]) / (math.pi / 2)) * (math.pi / 2)
        self.R_bm_G = rz(phi)
        self.p_bm_G = np.array([0.0, 0.0, zface])
        self.R_w_G = Rbm @ self.R_bm_G
        self.o_w_G = obm + Rbm @ self.p_bm_G
        # contact side of the pad boxes: the +/-y face nearer the gripper axis
        best = None
        for yf in (self.pad_lo[1], self.pad_hi[1]):
            c = self.to_G(d, ("pos", "pad"), [[0.0, yf, 0.5 * (self.pad_lo[2] + self.pad_hi[2])]])[0]
            if best is None or abs(c[0]) < best[0]:
                best = (abs(c[0]), yf)
        yf = best[1]
        zmid = 0.5 * (self.pad_lo[2] + self.pad_hi[2])
        ends = [self.to_G(d, ("pos", "pad"), [[0.0, yf, z]])[0][2] for z in (self.pad_lo[2], self.pad_hi[2])]
        zfar = self.pad_hi[2] if ends[1] > ends[0] else self.pad_lo[2]
        self.pad_face_local = np.array([0.0, yf, zmid])
        self.pad_tip_local = np.array([0.0, yf, zfar])

    def to_G(self, d, key, P):
        b = self.body[key]
        W = np.asarray(P, float) @ d.xmat[b].reshape(3, 3).T + d.xpos[b]
        return (W - self.o_w_G) @ self.R_w_G

    def pad_points(self, d, s):
        P = self.to_G(d, (s, "pad"), [self.pad_face_local, self.pad_tip_local])
        return P[0], P[1]

    def deepest(self, d):
        """(max z in G over all finger geometry points, side, link)."""
        best = (-1e9, None, None)
        zrow = self.R_w_G[:, 2]
        for (s, ln), P in self.pts.items():
            b = self.body[(s, ln)]
            z = (P @ (d.xmat[b].reshape(3, 3).T @ zrow)).max() + (d.xpos[b] - self.o_w_G) @ zrow
            if z > best[0]:
                best = (z, s, "pad" if ln == "silicone_pad" else ln)
        return best

    def deepest_side(self, d, s, links):
        zrow = self.R_w_G[:, 2]
        z = -1e9
        for (ss, ln), P in self.pts.items():
            if ss == s and (ln in links or (ln == "silicone_pad" and "pad" in links)):
                b = self.body[(ss, ln)]
                z = max(z, (P @ (d.xmat[b].reshape(3, 3).T @ zrow)).max() + (d.xpos[b] - self.o_w_G) @ zrow)
        return z

    def pitch(self, d, s):
        """Distal (pad) pitch about G y: 0 = pad axis along +z; > 0 = tip curled towards the other finger."""
        a_tip = self.R_w_G.T @ (d.xmat[self.body[(s, "pad")]].reshape(3, 3) @ (self.pad_tip_local - self.pad_face_local))
        return math.atan2(-SIGN[s] * a_tip[0], a_tip[2])

    def joints(self, d, s):
        return {j: float(d.qpos[self.jq[(s, j)]]) for j in ["driver", "coupler", "spring_link", "follower"]}

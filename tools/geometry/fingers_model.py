"""Loading the Menagerie `robotiq_2f85/` model (2f85.xml + assets/*.stl, read from a git commit) and
what `derive_fingers.py` takes from it: the frame G, the link frames, the linkage parameters, the link
meshes, and MuJoCo's own forward kinematics of the +x finger with the loop closed (`MjFinger`)."""
import io
import os
import xml.etree.ElementTree as ET

import numpy as np
import trimesh

from common import git_show
from fingers_linkage import LINKS

SUB = "robotiq_2f85/"


# ----------------------------------------------------------------------------------------------
# loading

def load(repo, rev):
    """(MjModel, xml text, {mesh name: trimesh in its body frame (scaled)})."""
    import mujoco
    xml = git_show(repo, SUB + "2f85.xml", rev).decode()
    root = ET.fromstring(xml)
    comp = root.find("compiler")
    meshdir = comp.get("meshdir", "") if comp is not None else ""
    files = {}
    for mesh in root.iter("mesh"):
        f = mesh.get("file")
        if f:
            files[f] = git_show(repo, SUB + (meshdir + "/" if meshdir else "") + f, rev)
    assets = dict(files)   # MuJoCo's asset dict is keyed by the file attribute
    m = mujoco.MjModel.from_xml_string(xml, assets)
    meshes = {}
    for k in range(m.nmesh):
        name = m.mesh(k).name
        fname = [f for f in files if os.path.splitext(os.path.basename(f))[0] == name]
        assert len(fname) == 1, name
        t = trimesh.load(io.BytesIO(files[fname[0]]), file_type="stl", process=True)
        t.merge_vertices()
        t = trimesh.Trimesh(t.vertices * m.mesh_scale[k], t.faces, process=True)
        meshes[name] = t
    return m, meshes


def quat_mat(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def body_meshes(m, meshes, body, skip=()):
    """Visual meshes of a body and of its rigidly attached children (no joint, not in `skip`), in the
    body frame, and the geoms of every class (visual group 2, collision group 3)."""
    import mujoco
    out, visual, collision = [], [], []
    bodies = [body]
    for b in range(m.nbody):
        if m.body_parentid[b] == body and m.body_jntnum[b] == 0 and b != body and b not in skip:
            bodies.append(b)
    for b in bodies:
        # child pose in body frame (one level, as in 2f85.xml: silicone_pad in pad)
        Tb = np.eye(4)
        if b != body:
            Tb[:3, :3] = quat_mat(m.body_quat[b]); Tb[:3, 3] = m.body_pos[b]
        for g in range(m.ngeom):
            if m.geom_bodyid[g] != b:
                continue
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
                name = m.mesh(m.geom_dataid[g]).name
                (visual if m.geom_group[g] == 2 else collision).append(name)
                if m.geom_group[g] == 2:
                    t = meshes[name].copy(); t.apply_transform(Tb)
                    out.append(t)
            else:
                collision.append(f"{['plane','hfield','sphere','capsule','ellipsoid','cylinder','box'][m.geom_type[g]]}"
                                 f" size {np.round(m.geom_size[g], 6).tolist()} at {np.round(m.geom_pos[g], 6).tolist()}")
    return out, visual, collision


class MjFinger:
    """MuJoCo's own forward kinematics of the +x finger with the loop closed numerically: the
    `connect` equality (follower anchor == coupler anchor) is solved by Gauss-Newton over two free
    joints, the others fixed."""

    def __init__(self, m, prefix, R0, eq):
        import mujoco
        self.mj = mujoco
        self.m = m; self.d = mujoco.MjData(m); self.R0 = R0
        self.jq = {n: m.jnt_qposadr[m.joint(prefix + n + "_joint").id] for n in ["driver", "coupler", "spring_link", "follower"]}
        self.bid = {n: m.body(prefix + n).id for n in LINKS}
        self.eq = eq  # (body1, anchor1, body2, anchor2)

    def _set(self, q):
        self.d.qpos[:] = 0
        for n, v in zip(["driver", "coupler", "spring_link", "follower"], q):
            self.d.qpos[self.jq[n]] = v
        self.mj.mj_kinematics(self.m, self.d)

    def residual(self, q):
        self._set(q)
        b1, a1, b2, a2 = self.eq
        p1 = self.d.xpos[b1] + self.d.xmat[b1].reshape(3, 3) @ a1
        p2 = self.d.xpos[b2] + self.d.xmat[b2].reshape(3, 3) @ a2
        return p1 - p2

    def close(self, q, free):
        """Solve the loop for the joints `free` (two indices into q), the others fixed."""
        q = np.array(q, float)
        for _ in range(50):
            r = self.residual(q)
            if np.linalg.norm(r) < 1e-14:
                break
            J = np.zeros((3, len(free)))
            for k, i in enumerate(free):
                dq = q.copy(); dq[i] += 1e-7
                J[:, k] = (self.residual(dq) - r) / 1e-7
            q[free] -= np.linalg.lstsq(J, r, rcond=None)[0]
        return q, float(np.linalg.norm(self.residual(q)))

    def poses(self, q):
        """Link poses [x, z, phi] in G (G = world turned by Rg about z) from MuJoCo's xpos/xmat."""
        self._set(q)
        out = {}
        for n in LINKS:
            b = self.bid[n]
            p = self.Rg @ self.d.xpos[b]
            R = self.Rg @ self.d.xmat[b].reshape(3, 3) @ self.R0.T
            assert abs(p[1]) < 1e-9 and abs(R[1, 1] - 1) < 1e-9, (n, p, R)
            out[n] = [p[0], p[2], float(np.arctan2(R[0, 2], R[0, 0]))]
        return out


def setup(m, meshes):
    """The +x finger: G rotation, link frames, linkage parameters, link meshes (link frames)."""
    import mujoco
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    # the finger whose driver lies at +x after the turn Rg about z; Menagerie calls it "right"
    sides = [p for p in ("right_", "left_") if m.body(p + "driver").id >= 0]
    best = None
    for p in sides:
        x, y = d.xpos[m.body(p + "driver").id][:2]
        a = np.arctan2(y, x)
        if best is None or abs(a) < abs(best[1]):
            best = (p, a)
    prefix, a = best
    a = -a
    Rg = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    Rg[np.abs(Rg) < 1e-12] = 0.0
    bid = {n: m.body(prefix + n).id for n in LINKS}
    R0 = Rg @ d.xmat[bid["driver"]].reshape(3, 3)
    for n in LINKS:
        assert np.allclose(Rg @ d.xmat[bid[n]].reshape(3, 3), R0, atol=1e-12), n
    jid = {n: m.joint(prefix + n + "_joint").id for n in ["driver", "coupler", "spring_link", "follower"]}
    for n, j in jid.items():
        axis = R0 @ m.jnt_axis[j]
        assert np.allclose(axis, [0, -1, 0], atol=1e-12), (n, axis)
    for n in ["driver", "coupler", "spring_link"]:
        assert np.allclose(m.jnt_pos[jid[n]], 0), n
    for n in ["coupler", "follower", "pad"]:
        assert np.allclose(m.body_quat[bid[n]], [1, 0, 0, 0]), n
    assert m.body_parentid[bid["coupler"]] == bid["driver"]
    assert m.body_parentid[bid["follower"]] == bid["spring_link"]
    assert m.body_parentid[bid["pad"]] == bid["follower"]
    eq = None
    for k in range(m.neq):
        if m.eq_type[k] == mujoco.mjtEq.mjEQ_CONNECT and {m.eq_obj1id[k], m.eq_obj2id[k]} == {bid["follower"], bid["coupler"]}:
            b1, b2 = m.eq_obj1id[k], m.eq_obj2id[k]
            a1, a2 = m.eq_data[k][0:3].copy(), m.eq_data[k][3:6].copy()
            if b1 != bid["follower"]:
                b1, b2, a1, a2 = b2, b1, a2, a1
            eq = (b1, a1, b2, a2)
    assert eq is not None and np.allclose(eq[1], 0), "connect anchor must be the follower's origin"
    xz = lambda v: [float(v[0]), float(v[2])]
    g = lambda b: Rg @ d.xpos[b]
    for v in (g(bid["driver"]), g(bid["spring_link"])):
        assert abs(v[1]) < 1e-12
    params = {
        "A": xz(g(bid["driver"])), "B": xz(g(bid["spring_link"])),
        "Cd": xz(R0 @ m.body_pos[bid["coupler"]]),
        "Dc": xz(R0 @ eq[3]),
        "Es": xz(R0 @ (m.body_pos[bid["follower"]] + m.jnt_pos[jid["follower"]])),
        "Ef": xz(R0 @ m.jnt_pos[jid["follower"]]),
        "Pf": xz(R0 @ m.body_pos[bid["pad"]]),
    }
    for v in [R0 @ m.body_pos[bid["coupler"]], R0 @ eq[3], R0 @ m.jnt_pos[jid["follower"]], R0 @ m.body_pos[bid["pad"]]]:
        assert abs(v[1]) < 1e-12
    ranges = {n: [float(m.jnt_range[j][0]), float(m.jnt_range[j][1])] for n, j in jid.items()}
    extra = {n: {"stiffness": float(m.jnt_stiffness[j]), "springref": float(m.qpos_spring[m.jnt_qposadr[j]])}
             for n, j in jid.items() if m.jnt_stiffness[j] > 0}
    # link meshes in link frames (visual meshes; collision geoms listed for the record)
    link_mesh, geoms = {}, {}
    for n in LINKS:
        parts, vis, col = body_meshes(m, meshes, bid[n], skip=set(bid.values()))
        t = trimesh.util.concatenate(parts)
        t.apply_transform(np.block([[R0, np.zeros((3, 1))], [np.zeros((1, 3)), np.ones((1, 1))]]))
        link_mesh[n] = (t, parts)
        geoms[n] = {"visual": vis, "collision": col}
    fk = MjFinger(m, prefix, R0, eq)
    fk.Rg = Rg
    return dict(prefix=prefix, Rg=Rg, R0=R0, params=params, ranges=ranges, springs=extra,
                link_mesh=link_mesh, geoms=geoms, fk=fk, bid=bid)

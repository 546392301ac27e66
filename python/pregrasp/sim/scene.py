"""The scene of the whole-plan replay (`PlanScene`): the table, the part (a free body) and two Menagerie Robotiq
2F-85 grippers (prefixes `sup_`, `mas_`), each on a free base welded to a mocap body at its arm's flange pose.
Model: tools/gripper_truth/README.md, section "Replay of the whole plan", "What is modelled"."""
import mujoco
import numpy as np

from .geometry import T_of, inv, pose_T
from .geometry import quat

TAU_OPEN = -1.0  # N (tendon force) holding the fingers open
GRIPPER_BODIES = ["base_mount", "base"] + [f"{s}_{ln}" for s in ("right", "left")
                                            for ln in ("driver", "coupler", "spring_link", "follower", "pad",
                                                       "silicone_pad")]
PAD_GEOMS = {"pos": ["right_pad1", "right_pad2"], "neg": ["left_pad1", "left_pad2"]}
PAD_POINT = np.array([0.0, -0.0066, 0.01875])  # pad contact-face centre in the pad body (README "Points")
TIP_POINT = np.array([0.0, -0.0066, 0.0375])  # the far end of that face (the fingertip)
# With pad condim 4: each pad contact point's torsional friction is mu_pad times this radius (m), the rotation
# replay's (tools/gripper_truth/replay.py `--torsion-radius`).
PAD_TORSION_RADIUS = 0.0116


class PlanScene:
    """Table, part (free body), two 2F-85 (prefixes `sup_`, `mas_`) on free bases welded to mocap flanges.
    `meshes`: the part's convex pieces as (vertices, faces) in the object frame (scaled); `mp`: its mass
    properties (part.mass_properties). `pad_condim`: the pad boxes' contact dimension, 3 (no torsional friction
    at a contact point: a pad resists a twist only through the spread of its contact points) or 4 (each point
    also resists a twist up to mu_pad * PAD_TORSION_RADIUS * its normal force)."""

    def __init__(self, gripper_xml, doc, meshes, mp, mu_pad, mu_sup, dt, noslip, pad_condim=3):
        if pad_condim not in (3, 4):
            raise ValueError(f"pad_condim must be 3 or 4, found {pad_condim}")
        sp = mujoco.MjSpec()
        sp.option.timestep = dt
        sp.option.noslip_iterations = noslip
        sp.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        sp.option.impratio = 10.0
        sp.option.gravity = [0.0, 0.0, -9.81]
        for arm in ("sup", "mas"):
            sp.worldbody.add_body(name=f"{arm}_target", mocap=True)
        for arm in ("sup", "mas"):
            c = mujoco.MjSpec.from_file(str(gripper_xml))
            for b in GRIPPER_BODIES:
                c.body(b).gravcomp = 1.0
            c.body("base_mount").add_freejoint(name="free")
            for g in c.geoms:
                if g.name in PAD_GEOMS["pos"] + PAD_GEOMS["neg"]:
                    g.friction = [mu_pad, mu_pad * PAD_TORSION_RADIUS if pad_condim == 4 else 0.0, 0.0001]
                    g.condim = pad_condim
                elif g.contype or g.conaffinity:
                    g.friction = [mu_pad, 0.005, 0.0001]
            act = c.actuator("fingers_actuator")
            act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            act.gainprm = [1.0] + [0.0] * 9
            act.biastype = mujoco.mjtBias.mjBIAS_NONE
            act.biasprm = [0.0] * 10
            act.ctrlrange = [-1000.0, 1000.0]
            act.forcerange = [-1000.0, 1000.0]
            fr = sp.worldbody.add_frame()
            sp.attach(c, prefix=f"{arm}_", frame=fr)
            eq = sp.add_equality(name=f"{arm}_weld", type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                                 name1=f"{arm}_target", name2=f"{arm}_base_mount")
            eq.solref = [0.002, 1.0]
            eq.solimp = [0.99, 0.999, 0.001, 0.5, 2]
        sp.worldbody.add_geom(name="table", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[3, 3, 0.1],
                              pos=[0, 0, doc.get("support_height", 0.0)], friction=[mu_sup, 0.005, 0.0001],
                              priority=2, condim=3)
        T0 = pose_T(doc["object"]["initial_pose"])
        part = sp.worldbody.add_body(name="part", pos=list(T0[:3, 3]), quat=list(quat(T0[:3, :3])))
        part.add_freejoint(name="part_free")
        part.explicitinertial = True
        part.mass = mp["mass"]
        part.ipos = list(mp["com"])
        part.fullinertia = list(mp["fullinertia"])
        for i, (V, F) in enumerate(meshes):
            sp.add_mesh(name=f"piece{i}", uservert=list(np.asarray(V).ravel()), userface=list(np.asarray(F).ravel()))
            part.add_geom(name=f"part{i}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"piece{i}",
                          friction=[mu_sup, 0.005, 0.0001], condim=3, mass=0)
        self.part_verts = np.vstack([V for V, _ in meshes])  # object frame (scaled)
        self.m = m = sp.compile()
        nid = lambda t, n: mujoco.mj_name2id(m, t, n)
        B, G, J = mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_GEOM, mujoco.mjtObj.mjOBJ_JOINT
        self.part_body = nid(B, "part")
        self.part_geoms = set(g for g in range(m.ngeom) if m.geom_bodyid[g] == self.part_body)
        self.table_geom = nid(G, "table")
        self.jpart = m.jnt_qposadr[nid(J, "part_free")]
        self.g = {}
        for arm in ("sup", "mas"):
            bodies = {nid(B, f"{arm}_{b}") for b in GRIPPER_BODIES}
            self.g[arm] = {
                "mocap": m.body_mocapid[nid(B, f"{arm}_target")],
                "bm": nid(B, f"{arm}_base_mount"),
                "jfree": m.jnt_qposadr[nid(J, f"{arm}_free")],
                "act": nid(mujoco.mjtObj.mjOBJ_ACTUATOR, f"{arm}_fingers_actuator"),
                "pad": {s: set(nid(G, f"{arm}_{n}") for n in ns) for s, ns in PAD_GEOMS.items()},
                "pad_body": {"pos": nid(B, f"{arm}_right_pad"), "neg": nid(B, f"{arm}_left_pad")},
                "side_geoms": {s: set(g for g in range(m.ngeom) if m.geom_bodyid[g] in
                                      {nid(B, f"{arm}_{pre}_{ln}") for ln in ("driver", "coupler", "spring_link",
                                                                               "follower", "pad", "silicone_pad")})
                               for s, pre in (("pos", "right"), ("neg", "left"))},
                "geoms": set(g for g in range(m.ngeom) if m.geom_bodyid[g] in bodies),
            }
        self.bm_off = T_of(m.body_pos[self.g["sup"]["bm"]], [1, 0, 0, 0])  # base_mount in G (0, 0, 0.007)
        self.d = mujoco.MjData(m)

    def set_flange(self, arm, T, init=False):
        g, d = self.g[arm], self.d
        d.mocap_pos[g["mocap"]] = T[:3, 3]
        d.mocap_quat[g["mocap"]] = quat(T[:3, :3])
        if init:
            Tb = T @ self.bm_off
            d.qpos[g["jfree"]:g["jfree"] + 3] = Tb[:3, 3]
            d.qpos[g["jfree"] + 3:g["jfree"] + 7] = quat(Tb[:3, :3])

    def flange_actual(self, arm):
        bm = self.g[arm]["bm"]
        return T_of(self.d.xpos[bm], self.d.xquat[bm]) @ inv(self.bm_off)

    def part_T(self):
        return T_of(self.d.xpos[self.part_body], self.d.xquat[self.part_body])

    def contacts(self, arm):
        """Normal force of this gripper on the part: per pad side and for its other links."""
        d, g = self.d, self.g[arm]
        out = {"pos": 0.0, "neg": 0.0, "other": 0.0}
        f6 = np.zeros(6)
        for i in range(d.ncon):
            a, b = d.contact.geom[i]
            if b in self.part_geoms:
                a, b = b, a
            if a not in self.part_geoms or b not in g["geoms"]:
                continue
            side = "pos" if b in g["pad"]["pos"] else "neg" if b in g["pad"]["neg"] else "other"
            mujoco.mj_contactForce(self.m, d, i, f6)
            out[side] += f6[0]
        return out

    def pad_gap(self, arm, point=PAD_POINT):
        """x distance (m) between the two fingers' `point` (pad face centre or tip) in the actual flange frame."""
        Tf_inv = inv(self.flange_actual(arm))
        xs = {}
        for s, b in self.g[arm]["pad_body"].items():
            p = T_of(self.d.xpos[b], self.d.xquat[b]) @ np.r_[point, 1]
            xs[s] = (Tf_inv @ p)[0]
        return float(xs["pos"] - xs["neg"])

    def table_contact(self):
        """Summed normal force of the table on the part (N)."""
        f6, tot = np.zeros(6), 0.0
        tid = self.table_geom
        for i in range(self.d.ncon):
            a, b = self.d.contact.geom[i]
            if (a == tid and b in self.part_geoms) or (b == tid and a in self.part_geoms):
                mujoco.mj_contactForce(self.m, self.d, i, f6)
                tot += f6[0]
        return tot

    def fingers_touch(self, arm):
        """The +x and -x fingers of this gripper touch each other."""
        sg = self.g[arm]["side_geoms"]
        for i in range(self.d.ncon):
            a, b = self.d.contact.geom[i]
            if (a in sg["pos"] and b in sg["neg"]) or (a in sg["neg"] and b in sg["pos"]):
                return True
        return False

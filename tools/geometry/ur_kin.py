"""UR kinematics: URDF chain (ur_macro.xacro + default_kinematics.yaml) vs standard DH."""
import numpy as np
import yaml

from common import apply, git_show, load_stl, rotx, rotz, trans, urdf_origin

# Nominal DH the planner uses (metres).  Verified against default_kinematics.yaml below.
DH = {
    "ur3e": dict(d1=0.15185, a2=-0.24355, a3=-0.2132, d4=0.13105, d5=0.08535, d6=0.0921),
    "ur5e": dict(d1=0.1625, a2=-0.425, a3=-0.3922, d4=0.1333, d5=0.0997, d6=0.0996),
    "ur10e": dict(d1=0.1807, a2=-0.6127, a3=-0.57155, d4=0.17415, d5=0.11985, d6=0.11655),
    "ur16e": dict(d1=0.1807, a2=-0.4784, a3=-0.36, d4=0.17415, d5=0.11985, d6=0.11655),
}
ALPHA = [np.pi / 2, 0, 0, np.pi / 2, -np.pi / 2, 0]

# our link name -> (URDF link, yaml mesh key, DH frame index)
LINKS = [
    ("base", "base_link_inertia", "base", 0),
    ("shoulder", "shoulder_link", "shoulder", 1),
    ("upper_arm", "upper_arm_link", "upper_arm", 2),
    ("forearm", "forearm_link", "forearm", 3),
    ("wrist_1", "wrist_1_link", "wrist_1", 4),
    ("wrist_2", "wrist_2_link", "wrist_2", 5),
    ("wrist_3", "wrist_3_link", "wrist_3", 6),
]
JOINT_KEYS = ["shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"]


def dh_params(model):
    p = DH[model]
    d = [p["d1"], 0, 0, p["d4"], p["d5"], p["d6"]]
    a = [0, p["a2"], p["a3"], 0, 0, 0]
    return d, a


def dh_frames(model, q):
    """Frames 0..6 of the standard-DH chain, expressed in frame 0 (controller base)."""
    d, a = dh_params(model)
    T = np.eye(4)
    out = [T]
    for i in range(6):
        T = T @ rotz(q[i]) @ trans(0, 0, d[i]) @ trans(a[i], 0, 0) @ rotx(ALPHA[i])
        out.append(T)
    return out


class URDescription:
    def __init__(self, repo, model):
        self.repo, self.model = repo, model
        self.kin = yaml.safe_load(git_show(repo, f"config/{model}/default_kinematics.yaml"))["kinematics"]
        self.vis = yaml.safe_load(git_show(repo, f"config/{model}/visual_parameters.yaml"))["mesh_files"]
        self.phys = yaml.safe_load(git_show(repo, f"config/{model}/physical_parameters.yaml"))
        off = self.phys["offsets"]
        so, eo = off["shoulder_offset"], off["elbow_offset"]
        pi = np.pi
        # collision <origin> of each link, transcribed from urdf/ur_macro.xacro
        self.mesh_origin = {
            "base": urdf_origin((0, 0, 0), (0, 0, pi)),
            "shoulder": urdf_origin((0, 0, 0), (0, 0, pi)),
            "upper_arm": urdf_origin((0, 0, so), (pi / 2, 0, -pi / 2)),
            "forearm": urdf_origin((0, 0, eo), (pi / 2, 0, -pi / 2)),
            "wrist_1": urdf_origin((0, 0, self.vis["wrist_1"]["visual_offset"]), (pi / 2, 0, 0)),
            "wrist_2": urdf_origin((0, 0, self.vis["wrist_2"]["visual_offset"]), (0, 0, 0)),
            "wrist_3": urdf_origin((0, 0, self.vis["wrist_3"]["visual_offset"]), (pi / 2, 0, 0)),
        }

    def mesh_path(self, key):
        return self.vis[key]["collision"]["mesh"]["path"]

    def urdf_frames(self, q):
        """URDF link frames in base_link (REP-103) coordinates."""
        T = rotz(np.pi)  # base_link -> base_link_inertia
        out = {"base": T}
        names = ["shoulder", "upper_arm", "forearm", "wrist_1", "wrist_2", "wrist_3"]
        for i, key in enumerate(JOINT_KEYS):
            j = self.kin[key]
            T = T @ urdf_origin((j["x"], j["y"], j["z"]), (j["roll"], j["pitch"], j["yaw"])) @ rotz(q[i])
            out[names[i]] = T
        # flange / tool0 fixed frames
        out["tool0"] = T @ urdf_origin((0, 0, 0), (0, -np.pi / 2, -np.pi / 2)) @ urdf_origin((0, 0, 0), (np.pi / 2, 0, np.pi / 2))
        return out

    def link_to_dh(self, n_samples=25, seed=1):
        """Constant transform X_l with  T_dh_frame(q) @ X_l == T_urdf_link(q)  (both in base_link).

        Returns dict of X_l and the max translation / rotation residual over random q."""
        rng = np.random.default_rng(seed)
        Rb = rotz(np.pi)  # base_link -> controller base (frame 0)
        X, res_t, res_r = {}, {}, {}
        samples = [np.zeros(6)] + [rng.uniform(-np.pi, np.pi, 6) for _ in range(n_samples)]
        for (name, _, _, fi) in LINKS + [("tool0", None, None, 6)]:
            Xs = []
            for q in samples:
                F = dh_frames(self.model, q)
                U = self.urdf_frames(q)
                Xs.append(np.linalg.inv(Rb @ F[fi]) @ U[name])
            X0 = Xs[0]
            X[name] = X0
            res_t[name] = max(np.linalg.norm(x[:3, 3] - X0[:3, 3]) for x in Xs)
            res_r[name] = max(np.linalg.norm(x[:3, :3] - X0[:3, :3]) for x in Xs)
        return X, res_t, res_r, len(samples)

    def dh_vs_yaml(self):
        k = self.kin
        yaml_vals = dict(d1=k["shoulder"]["z"], a2=k["forearm"]["x"], a3=k["wrist_1"]["x"],
                         d4=k["wrist_1"]["z"], d5=-k["wrist_2"]["y"], d6=k["wrist_3"]["y"])
        return {n: (DH[self.model][n], yaml_vals[n], yaml_vals[n] - DH[self.model][n]) for n in yaml_vals}

    def link_mesh_in_dh(self, X):
        """Collision meshes of every link, transformed into their DH frame."""
        out = {}
        for (name, _, key, fi) in LINKS:
            m = load_stl(self.repo, self.mesh_path(key))
            # X = inv(F_dh) @ U maps URDF-link coordinates into DH-frame coordinates
            T = X[name] @ self.mesh_origin[name]
            m = m.copy()
            m.apply_transform(T)
            out[name] = (fi, m, self.mesh_path(key))
        return out

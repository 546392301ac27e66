"""Robotiq 2F-85 (PickNik ros2_robotiq_gripper) -> crates/robot/data/robotiq_2f85.json"""
import numpy as np

from common import apply, git_head, load_stl, r6, roty, trans

MESH = "robotiq_description/meshes/collision/2f_85/"
ADAPTER_Z = 0.011  # ur_to_robotiq_adapter.urdf.xacro: gripper_side_joint origin z
# robotiq_2f_85_macro.urdf.xacro (left = +x finger); all revolute axes are (0,-1,0)
KNUCKLE = (0.03060114, 0.0, 0.05490452)
FINGER_IN_KNUCKLE = (0.03152616, 0.0, -0.00376347)
INNER_KNUCKLE = (0.0127, 0.0, 0.06142)
TIP_IN_FINGER = (0.00563134, 0.0, 0.04718515)
Q_MAX = 0.8
PAD_THICK = 0.008  # menagerie pad thickness (x)
# MuJoCo Menagerie reference: gap (m) -> pad centre z (m)
MENAGERIE = [(0.0852, 0.1416), (0.0700, 0.1467), (0.0533, 0.1507), (0.0356, 0.1534), (0.0172, 0.1547), (0.0, 0.1547)]
MEN_TIP_OPEN, MEN_TIP_CLOSED = 0.1603, 0.1735


def poses(q, zoff):
    """Link frames in G for knuckle angle q (rotation about +y by -q). Returns {link: 4x4}."""
    B = trans(0, 0, ADAPTER_Z + zoff)
    K = B @ trans(*KNUCKLE) @ roty(-q)
    F = K @ trans(*FINGER_IN_KNUCKLE)
    I = B @ trans(*INNER_KNUCKLE) @ roty(-q)
    T = F @ trans(*TIP_IN_FINGER) @ roty(+q)  # mimic -1: tip stays parallel
    return {"outer_knuckle": K, "outer_finger": F, "inner_knuckle": I, "finger_tip": T, "pad": T}


def box_of(V):
    lo, hi = V.min(0), V.max(0)
    return {"center": (lo + hi) / 2, "half": (hi - lo) / 2}


def run(repo):
    L = []
    meshes = {n: load_stl(repo, MESH + f + ".stl") for n, f in
              [("outer_knuckle", "left_knuckle"), ("outer_finger", "left_finger"),
               ("inner_knuckle", "left_inner_knuckle"), ("finger_tip", "left_finger_tip"),
               ("base", "robotiq_base"), ("adapter", "ur_to_robotiq_adapter")]}
    hull = {n: meshes[n].convex_hull.vertices for n in ["outer_knuckle", "outer_finger", "inner_knuckle", "finger_tip"]}
    # pad = contact face of the finger tip: the inner (-x) face of the +x finger tip, 8 mm deep
    tipV = hull["finger_tip"]
    xface = tipV[:, 0].min()
    pad_face_vs = tipV[tipV[:, 0] <= xface + 1e-4]
    fy, fz = pad_face_vs[:, 1], pad_face_vs[:, 2]
    # pad = slab of the tip hull within 8 mm of the contact face, limited to the face's y/z extent
    padV = tipV[(tipV[:, 0] <= xface + PAD_THICK + 1e-9) & (tipV[:, 2] >= fz.min() - 1e-9)]
    L.append(f"pad contact face in finger_tip frame: x = {xface:.4f}, y [{pad_face_vs[:,1].min():.4f},{pad_face_vs[:,1].max():.4f}],"
             f" z [{pad_face_vs[:,2].min():.4f},{pad_face_vs[:,2].max():.4f}] ({len(pad_face_vs)} vertices)")
    pad_box = box_of(padV)
    pad_c = 0.5 * (pad_face_vs.min(0) + pad_face_vs.max(0)); pad_c[0] = xface

    def gap_of(q, zoff=0.0):
        return 2 * apply(poses(q, zoff)["finger_tip"], [[xface, 0, 0]])[0, 0]

    qs = np.linspace(0, Q_MAX, 8001)
    gaps = np.array([gap_of(q) for q in qs])
    L.append(f"ROS model: gap at q=0 {gaps[0]*1e3:.2f} mm, q=0.8 {gaps[-1]*1e3:.2f} mm; monotonic={bool(np.all(np.diff(gaps) < 0))}")
    q_of_gap = lambda g: float(np.interp(g, gaps[::-1], qs[::-1]))
    g_open, g_closed = 0.0852, 0.0
    if gaps[0] < g_open - 1e-4 or gaps[-1] > g_closed + 1e-4:
        L.append("WARNING: ROS stroke does not span 0..85.2 mm; gaps clamped to the reachable range")

    def padz(q, zoff):
        return apply(poses(q, zoff)["finger_tip"], [pad_c])[0, 2]

    def tipz(q, zoff):
        return apply(poses(q, zoff)["finger_tip"], tipV)[:, 2].max()

    # raw comparison with zoff = 0 (adapter mounting face at z = 0)
    qo, qc = q_of_gap(min(g_open, gaps[0])), q_of_gap(max(g_closed, gaps[-1]))
    raw_open, raw_tip_open, raw_tip_closed = padz(qo, 0), tipz(qo, 0), tipz(qc, 0)
    L.append(f"raw (adapter face z=0): open pad-centre z {raw_open:.4f} (menagerie 0.1416, Δ {1e3*(raw_open-0.1416):+.1f} mm); "
             f"tip z open {raw_tip_open:.4f} (0.1603, Δ {1e3*(raw_tip_open-MEN_TIP_OPEN):+.1f}), "
             f"closed {raw_tip_closed:.4f} (0.1735, Δ {1e3*(raw_tip_closed-MEN_TIP_CLOSED):+.1f})")
    # z offset: least squares over the menagerie table (pad centre z)
    res0 = [padz(q_of_gap(g), 0) - z for g, z in MENAGERIE]
    zoff = -float(np.mean(res0)) if abs(np.mean(res0)) > 0.002 else 0.0
    L.append(f"applied z offset {zoff*1e3:+.2f} mm (mean pad-centre residual before: {1e3*np.mean(res0):+.2f} mm)")
    L.append("| gap mm | menagerie pad z | ROS pad z (after offset) | residual mm |")
    L.append("|---|---|---|---|")
    for g, z in MENAGERIE:
        zz = padz(q_of_gap(g), zoff)
        L.append(f"| {g*1e3:.1f} | {z*1e3:.1f} | {zz*1e3:.1f} | {1e3*(zz-z):+.1f} |")
    L.append(f"tip z after offset: open {tipz(qo, zoff):.4f} (menagerie 0.1603), closed {tipz(qc, zoff):.4f} (0.1735)")

    # link boxes in own frames
    links = []
    for n in ["outer_knuckle", "inner_knuckle", "outer_finger", "finger_tip"]:
        links.append({"name": n, "hull": r6(hull[n]), "box": {k: r6(v) for k, v in box_of(hull[n]).items()}})
    links.append({"name": "pad", "box": {k: r6(v) for k, v in pad_box.items()}, "face_x": r6(xface)})
    # static boxes (base mesh + adapter, below z=0 spigot clipped)
    bV = apply(trans(0, 0, ADAPTER_Z + zoff), meshes["base"].vertices)
    aV = meshes["adapter"].vertices.copy(); aV = aV[aV[:, 2] >= 0]
    static = [{"name": "gripper_body", **{k: r6(v) for k, v in box_of(bV).items()}},
              {"name": "gripper_coupling", **{k: r6(v) for k, v in box_of(np.vstack([aV, [[0, 0, 0]]])).items()}}]
    table = []
    L.append("| gap mm | pad z | pad face x | tip z | finger lowest-z point (max z all finger verts) |")
    L.append("|---|---|---|---|---|")
    for g in np.linspace(g_open, g_closed, 18):
        g = float(np.clip(g, gaps[-1], gaps[0]))
        q = q_of_gap(g)
        P = poses(q, zoff)
        row = {"gap": r6(g), "q": r6(q), "pad_center_z": r6(padz(q, zoff)),
               "pad_face_x": r6(apply(P["finger_tip"], [[xface, 0, 0]])[0, 0]), "tip_z": r6(tipz(q, zoff)), "links": {}}
        allz = []
        for ln in links:
            n = ln["name"]; T = P[n]
            ang = -q if n in ("outer_knuckle", "outer_finger", "inner_knuckle") else 0.0
            row["links"][n] = r6([T[0, 3], T[2, 3], ang])
            Vn = hull["finger_tip"] if n == "pad" else hull[n]
            Vn = padV if n == "pad" else Vn
            Vg = apply(T, Vn)
            allz.append(Vg[:, 2].max())
            # box check: posed vertices inside posed box
            b = box_of(Vn); loc = Vn - b["center"]
            assert np.all(np.abs(loc) <= b["half"] + 1e-9), n
        table.append(row)
        L.append(f"| {g*1e3:.1f} | {row['pad_center_z']*1e3:.1f} | {row['pad_face_x']*1e3:.2f} | {row['tip_z']*1e3:.1f} | {max(allz)*1e3:.1f} |")
    out = {"generator": "tools/geometry/derive.py",
           "source": {"repo": "https://github.com/PickNikRobotics/ros2_robotiq_gripper", "commit": git_head(repo)},
           "frame": "G = UR flange/tool0 frame: origin on the adapter mounting face, +z approach, x closing (pads at ±x), y finger width. Data for the +x finger; mirror x->-x for the other.",
           "z_offset_applied": r6(zoff),
           "static": static, "links": links, "table": table}
    return out, "\n".join(L)

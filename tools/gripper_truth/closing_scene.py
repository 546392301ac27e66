"""The scenes of closing.py: the bar grid (`grid`, `bar_geometry`), the Menagerie model with a bar and a
table (`Scene`), and one simulated closing (`simulate_row`)."""
import math

import mujoco
import numpy as np

from closing_gripper import DISTAL, LINKS, PROXIMAL, SIDES, Gripper
from transforms import mat_of_quat, quat_axis_angle, quat_of_mat

# ----------------------------------------------------------------------------------------------------
# Scene grid (G frame, metres / degrees)
POWER_Z = 0.115  # power point: G z of the palm-side grasp reference
BAR_LEN = 0.3  # along y, centred on the fingers
WIDTHS_MM = [15, 25, 35, 45, 55, 65, 75]  # along x (closing axis)
THICKS_MM = [15, 25, 35, 45]  # along z (approach)
DEPTHS_MM = [0, 5, 10, 15, 20, 25]  # bar top past the power point
TILTS_DEG = [0, 10, 20, 30]  # about the bar's own long axis (G y through the bar centre)
# tilted bars: a sub-grid (every w is not needed, the tilt mostly matters for the extreme widths)
TILTED_WIDTHS_MM = [15, 35, 55, 75]
TILTED_DEPTHS_MM = [0, 10, 25]

# Simulation
CTRL_CLOSED = 255.0
T_RAMP = 1.0  # s, ctrl ramps linearly 0 -> 255 (about 85 mm/s of gap; the real 2F-85 closes at 20-150 mm/s)
T_CAP = T_RAMP + 7.0  # s, simulated time cap (slow creeps and late snap-throughs, see README)
T_MIN = T_RAMP + 0.3  # s, never stop before
SETTLE_WIN = 0.25  # s, window of the settle test
SETTLE_TOL = 5e-5  # m: every tracked point (pad centres, tips) moved less than this over the window
SAMPLE_EVERY = 25  # steps between samples of the tracked points (0.05 s at dt = 0.002)
GRAVITY_G = (0.0, 0.0, 9.81)  # gripper pointing down at the table: gravity along +z of G
OPEN_TOL = 1e-5  # m: penetration tolerated at the open pose before a row is flagged
CURL_RAD = 0.1  # distal pitch above which a distal is called curled


def bar_geometry(w, t, dep, tilt_deg):
    th = math.radians(tilt_deg)
    half_z = 0.5 * (w * math.sin(th) + t * math.cos(th))
    half_x = 0.5 * (w * math.cos(th) + t * math.sin(th))
    z_top = POWER_Z + dep
    return {"z_top": z_top, "z_center": z_top + half_z, "z_bottom": z_top + 2 * half_z, "half_extent_x": half_x}


def grid():
    rows = []
    for tilt in TILTS_DEG:
        ws = WIDTHS_MM if tilt == 0 else TILTED_WIDTHS_MM
        ds = DEPTHS_MM if tilt == 0 else TILTED_DEPTHS_MM
        for w in ws:
            for t in THICKS_MM:
                for dep in ds:
                    for table in (False, True):
                        rows.append((w, t, dep, tilt, table))
    return rows


def row_id(w, t, dep, tilt, table):
    return f"w{w:02d}_t{t:02d}_d{dep:02d}_a{tilt:02d}_{'table' if table else 'free'}"


class Scene:
    def __init__(self, xml):
        self.spec = mujoco.MjSpec.from_file(str(xml))
        self.spec.option.gravity = [0.0, 0.0, 0.0]
        m0 = self.spec.compile()
        d0 = mujoco.MjData(m0)
        mujoco.mj_forward(m0, d0)
        self.gr0 = Gripper(m0)
        self.gr0.setup_frame(d0)
        self.R_w_G, self.o_w_G = self.gr0.R_w_G, self.gr0.o_w_G
        wb = self.spec.worldbody
        self.bar = wb.add_geom(name="gt_bar", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.01, BAR_LEN / 2, 0.01])
        self.table = wb.add_geom(name="gt_table", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.3, 0.3, 0.01])
        self.bar.rgba = [0.2, 0.5, 0.9, 1]
        self.table.rgba = [0.8, 0.8, 0.7, 1]

    def compile(self, w=None, t=None, dep=None, tilt=None, table=False, gravity=True):
        g = self.R_w_G @ np.array(GRAVITY_G) if gravity else np.zeros(3)
        self.spec.option.gravity = list(g)
        if w is None:
            for geom in (self.bar, self.table):
                geom.contype, geom.conaffinity = 0, 0
                geom.pos = list(self.o_w_G + self.R_w_G @ np.array([0, 0, 1.0]))
        else:
            bg = bar_geometry(w, t, dep, tilt)
            self.bar.size = [w / 2, BAR_LEN / 2, t / 2]
            self.bar.pos = list(self.o_w_G + self.R_w_G @ np.array([0.0, 0.0, bg["z_center"]]))
            self.bar.quat = list(quat_of_mat(self.R_w_G @ mat_of_quat(quat_axis_angle([0, 1, 0], math.radians(tilt)))))
            self.bar.contype, self.bar.conaffinity = 1, 1
            # plane normal = its local +z; turned to -z of G (facing the gripper)
            self.table.pos = list(self.o_w_G + self.R_w_G @ np.array([0.0, 0.0, bg["z_bottom"]]))
            self.table.quat = list(quat_of_mat(self.R_w_G @ mat_of_quat([0.0, 1.0, 0.0, 0.0])))
            self.table.contype, self.table.conaffinity = (1, 1) if table else (0, 0)
        m = self.spec.compile()
        gr = Gripper(m)
        gr.R_w_G, gr.o_w_G = self.R_w_G, self.o_w_G
        gr.R_bm_G, gr.p_bm_G = self.gr0.R_bm_G, self.gr0.p_bm_G
        gr.pad_face_local, gr.pad_tip_local = self.gr0.pad_face_local, self.gr0.pad_tip_local
        gr.bar = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "gt_bar")
        gr.table = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "gt_table")
        return m, gr


def contacts(d):
    n = d.ncon
    if n == 0:
        return np.zeros((0, 2), int), np.zeros(0)
    return np.array(d.contact.geom[:n]), np.array(d.contact.dist[:n])


def tracked(gr, d):
    P = []
    for s in SIDES:
        P.extend(gr.pad_points(d, s))
    return np.array(P)


def simulate_row(scene, spec_row, rid=None):
    """One closing on the bar of `spec_row` = (w, t, depth past the power point (mm), tilt (deg), table);
    `rid`: the row's id (default `row_id(*spec_row)`)."""
    w_mm, t_mm, dep_mm, tilt, table = spec_row
    w, t, dep = w_mm / 1000, t_mm / 1000, dep_mm / 1000
    bg = bar_geometry(w, t, dep, tilt)
    row = {"id": rid or row_id(*spec_row),
           "bar": {"width": w, "thickness": t, "depth_past_power_point": dep, "tilt_deg": float(tilt),
                   "z_top": bg["z_top"], "z_center": bg["z_center"], "z_bottom": bg["z_bottom"],
                   "half_extent_x": bg["half_extent_x"]},
           "table": table, "table_z": bg["z_bottom"] if table else None}
    m, gr = scene.compile(w, t, dep, tilt, table)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    # open-pose intersection test
    G, D = contacts(d)
    pen_bar, pen_table = 0.0, 0.0
    for (g1, g2), dist in zip(G, D):
        for a, b in ((g1, g2), (g2, g1)):
            if a in gr.gripper_geoms and b == gr.bar:
                pen_bar = max(pen_bar, -dist)
            if a in gr.gripper_geoms and b == gr.table:
                pen_table = max(pen_table, -dist)
    open_deep = gr.deepest(d)[0]
    row["open_penetration_bar"] = pen_bar
    row["open_penetration_table"] = pen_table if table else None
    flags = []
    if pen_bar > OPEN_TOL:
        flags.append("bar")
    if table and pen_table > OPEN_TOL:
        flags.append("table")
    if flags:
        row["status"] = "open_intersects_" + "_and_".join(flags)
        return row
    row["status"] = "simulated"

    dt = m.opt.timestep
    nmax = int(round(T_CAP / dt))
    nmin = int(round(T_MIN / dt))
    nwin = int(round(SETTLE_WIN / dt)) // SAMPLE_EVERY
    first = {s: None for s in SIDES}  # (t, link, dist)
    table_contact = False
    table_first_t = None
    table_links = set()
    snap_tmin = None
    max_deep = (open_deep, None, None, 0.0)
    tip_max = {s: gr.pad_points(d, s)[1][2] for s in SIDES}
    hist = [tracked(gr, d)]
    settled = False
    step = 0
    while step < nmax:
        d.ctrl[0] = CTRL_CLOSED * min(1.0, step * dt / T_RAMP)
        mujoco.mj_step(m, d)
        step += 1
        G, D = contacts(d)
        for (g1, g2), dist in zip(G, D):
            for a, b in ((g1, g2), (g2, g1)):
                if b == gr.bar and a in gr.geom_side:
                    s = gr.geom_side[a]
                    if first[s] is None or (first[s][0] == step * dt and dist < first[s][2]):
                        first[s] = (step * dt, gr.geom_link[a], dist)
                if b == gr.table and a in gr.geom_side:
                    table_contact = True
                    table_links.add(f"{gr.geom_side[a]}.{gr.geom_link[a]}")
                    if table_first_t is None:
                        table_first_t = step * dt
        if step == nmin:
            snap_tmin = tracked(gr, d)
        z, s, ln = gr.deepest(d)
        if z > max_deep[0]:
            max_deep = (z, s, ln, step * dt)
        for s in SIDES:
            tip_max[s] = max(tip_max[s], gr.pad_points(d, s)[1][2])
        if step % SAMPLE_EVERY == 0:
            hist.append(tracked(gr, d))
            if step >= nmin and len(hist) > nwin:
                moved = np.linalg.norm(hist[-1] - hist[-1 - nwin], axis=1).max()
                if moved < SETTLE_TOL:
                    settled = True
                    break
    t_end = step * dt
    k = min(nwin, len(hist) - 1)
    creep = np.linalg.norm(hist[-1] - hist[-1 - k], axis=1).max() / (k * SAMPLE_EVERY * dt)
    creep_since = float(np.linalg.norm(hist[-1] - snap_tmin, axis=1).max()) if snap_tmin is not None else 0.0

    # final state
    G, D = contacts(d)
    touching = {s: set() for s in SIDES}
    # normal force of the bar on each finger's distal (follower + pad) and proximal links, and on the palm (N)
    force = {s: {"distal": 0.0, "proximal": 0.0} for s in SIDES}
    force_palm = 0.0
    f6 = np.zeros(6)
    palm_bar = False
    fingers_touch = False
    table_end = False
    for i, ((g1, g2), dist) in enumerate(zip(G, D)):
        for a, b in ((g1, g2), (g2, g1)):
            if b == gr.bar and a in gr.geom_side:
                touching[gr.geom_side[a]].add(gr.geom_link[a])
                mujoco.mj_contactForce(m, d, i, f6)
                force[gr.geom_side[a]]["distal" if gr.geom_link[a] in DISTAL else "proximal"] += f6[0]
            if b == gr.bar and a in gr.palm_geoms:
                palm_bar = True
                mujoco.mj_contactForce(m, d, i, f6)
                force_palm += f6[0]
            if b == gr.table and a in gr.geom_side:
                table_end = True
        if g1 in gr.geom_side and g2 in gr.geom_side and gr.geom_side[g1] != gr.geom_side[g2]:
            fingers_touch = True
    fingers = {}
    for s in SIDES:
        pc, tip = gr.pad_points(d, s)
        jt = gr.joints(d, s)
        f = {"driver_angle": jt["driver"], "follower_angle": jt["follower"], "spring_link_angle": jt["spring_link"],
             "coupler_angle": jt["coupler"], "distal_pitch": gr.pitch(d, s),
             "pad_center": list(pc), "tip": list(tip), "tip_z_max_during": tip_max[s],
             "tip_rise": tip_max[s] - tip[2],
             "deepest_z_end": gr.deepest_side(d, s, set(LINKS)),
             "distal_deepest_z_end": gr.deepest_side(d, s, DISTAL),
             "touching_bar_end": sorted(touching[s]),
             "bar_force_end": force[s],
             "first_touch_link": first[s][1] if first[s] else None,
             "first_touch_t": first[s][0] if first[s] else None}
        f["distal_curled"] = f["distal_pitch"] > CURL_RAD
        fingers[s] = f
    row["fingers"] = fingers
    pp, pn = fingers["pos"]["pad_center"], fingers["neg"]["pad_center"]
    row["pad_gap"] = pp[0] - pn[0]
    row["tip_gap"] = fingers["pos"]["tip"][0] - fingers["neg"]["tip"][0]
    z_end = gr.deepest(d)
    row["deepest_z_end"] = z_end[0]
    row["deepest_end_link"] = f"{z_end[1]}.{z_end[2]}"
    row["deepest_z_max"] = max_deep[0]
    row["deepest_max_link"] = f"{max_deep[1]}.{max_deep[2]}" if max_deep[1] else "open_pose"
    row["deepest_max_t"] = max_deep[3]
    firsts = [(v[0], v[2], s, v[1]) for s, v in first.items() if v]
    if firsts:
        t0, _, s0, l0 = min(firsts)
        row["first_touch"] = {"side": s0, "link": l0, "t": t0}
        prox = any(v and v[1] in PROXIMAL for v in first.values())
        row["mode"] = "encompassing" if prox else "pinch"
    else:
        row["first_touch"] = {"side": None, "link": None, "t": None}
        row["mode"] = "none"
    # a tip is under the bar if, in the bar's cross-section frame (u along the width, v along the thickness,
    # v > 0 towards the bottom face), it lies within the width (1 mm inboard) and beyond the bottom face
    Rb = mat_of_quat(quat_axis_angle([0, 1, 0], math.radians(tilt)))
    for s in SIDES:
        loc = Rb.T @ (np.array(fingers[s]["tip"]) - np.array([0.0, 0.0, bg["z_center"]]))
        fingers[s]["tip_inboard"] = w / 2 - abs(loc[0])
        fingers[s]["tip_under_bar"] = bool(abs(loc[0]) < w / 2 - 1e-3 and loc[2] > t / 2)
    row["caged"] = all(fingers[s]["tip_under_bar"] for s in SIDES)
    row["fingers_touch_each_other_end"] = fingers_touch
    row["palm_touches_bar_end"] = palm_bar
    row["palm_force_end"] = force_palm
    if table:
        row["table_touched"] = table_contact
        row["table_touched_end"] = table_end
        row["table_first_touch_t"] = table_first_t
        row["table_min_clearance"] = bg["z_bottom"] - max_deep[0]
        row["table_touch_links"] = sorted(table_links)
    else:
        row["table_touch_links"] = None
        row["table_touched"] = None
        row["table_touched_end"] = None
        row["table_first_touch_t"] = None
        row["table_min_clearance"] = None
    row["settled"] = settled
    row["t_end"] = t_end
    row["creep_speed"] = creep
    row["creep_since_t_min"] = creep_since
    return row

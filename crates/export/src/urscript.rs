//! URScript, one program per arm (`<name>.script`), for two arms on two controllers.
//!
//! **Motion.** A `movej` to the arm's first point (at `movej_speed` / `movej_accel`), then its
//! segments as `servoj` at the controller's 500 Hz: every interval between neighbouring plan
//! points (duration `d`) is one `pg_line(from, to, n)` call that commands `n = ⌈d / 2 ms⌉`
//! targets on the straight joint-space line — the plan format's motion between points — each
//! held 2 ms. Every plan point is a `servoj` target exactly; an interval lasts `n · 2 ms`, at
//! most 2 ms longer than planned, so no joint is ever faster than in the plan. At the end of
//! each segment the last point is held for twice the lookahead time (`pg_hold`), so the arm,
//! which trails its targets by about the lookahead, stands on the point before its gripper acts
//! or the other arm moves. The arm that a segment does not name runs nothing and holds still.
//! The file is one `def pregrasp_<arm>():` program (send it to the controller as is, or call
//! it from a PolyScope Script node).
//!
//! **Gripper.** Robotiq 2F-85 through the URCap's ASCII socket (127.0.0.1:63352): activated
//! with `SET ACT 1`, `SET GTO 1`, `SET SPE`, `SET FOR` at start; before every close `SET FOR`
//! with the closing's force: the segment's own `grip_force` ([`force_register`]; for the
//! support grasp, else the plan's recommended `physics.grip_force_recommended`), else
//! `grip_force`; `support_grip_force` / `power_grip_force` override the plan;
//! `SET POS 0` (open) when a
//! `reach` / `regrasp` begins, and `SET POS p` at its last point: from the segment's `fingers`
//! (where the real closing stops, curled around a bar or not) as [`grip_pos_for_driver`] —
//! the register follows the driver angle, 0..255 for 0..0.8 rad — plus the squeeze; else from
//! its `grip_width` `g` as [`grip_pos`]`(g − squeeze)` (the 2F-85 maps 0..85 mm linearly to
//! 255..0, approximately); 255 when the plan gives neither. After a close the program waits
//! for the fingers to stop and requires `GET OBJ` = 2 (object detected); before every segment
//! in which the arm holds the part it asks again. Otherwise: `popup(…, error=True)` and `halt`.
//!
//! **Hand-off** (`docs/export.md`). `standard_digital_out[OUT]` of each controller is wired to
//! `standard_digital_in[IN]` of the other. Each program holds its OUT low until it stands at its
//! first point with the gripper ready, then high (*ready*), and waits for the other's ready.
//! When it finishes a segment that the other arm's segment follows, it sends a *hand-off
//! pulse*: OUT low for `PULSE` (0.2 s), then high again. A thread counts the other controller's
//! pulses (a low on IN lasting 20 ms … 1 s, followed by high, counts one); before a segment that
//! follows the other arm's, the program waits until the count reaches the number of hand-offs
//! the other arm has made by then. Nothing is missed (the thread samples every 2 ms and a pulse
//! lasts 100 cycles), nothing is counted twice (one count per low-to-high edge, after a low of
//! the right length), and no state waits on a signal that only comes after it: the plan's
//! segment order is one sequence, and every wait is for a hand-off the other program sends
//! without waiting on anything later. A low longer than 1 s means the other program stopped
//! (with its OUT set to "Low when program is not running"): a waiting program halts.

use std::fmt::Write;

use pregrasp_model::{GraspKind, PlanSet, Timeline};
use pregrasp_robot::Joints;

use crate::{float, ur_models, ExportError, Options, OutFile};

/// The control period of a UR controller (s): `servoj` targets are 2 ms apart.
pub const DT: f64 = 0.002;
/// Length of a hand-off pulse (s).
pub const PULSE: f64 = 0.2;
/// A low on IN counts as a pulse when it lasts at least this many control cycles (20 ms) …
pub const PULSE_MIN_TICKS: u32 = 10;
/// … and at most this many (1 s); longer means the other program stopped.
pub const PULSE_MAX_TICKS: u32 = 500;
/// The 2F-85's stroke (m): `SET POS 0` opens the pads to about this gap.
pub const STROKE: f64 = 0.085;

/// The 2F-85's grip force range (N): force register 0 ↦ 20 N, 255 ↦ 235 N.
pub const FORCE_RANGE: (f64, f64) = (20.0, 235.0);

/// Robotiq force register for a grip force `f` (N): 2F-85, 20..235 N ↦ 0..255, linear
/// (approximate, as the gripper's own force control), rounded up so the gripper squeezes at
/// least `f`; clamped.
pub fn force_register(f: f64) -> u8 {
    let (lo, hi) = FORCE_RANGE;
    (255.0 * (f - lo) / (hi - lo)).ceil().clamp(0.0, 255.0) as u8
}

/// Robotiq position register for a gap `g` (m) between the pads: 2F-85, 0..85 mm ↦ 255..0,
/// linear (approximate; the real mapping is within a few counts), clamped.
pub fn grip_pos(g: f64) -> u8 {
    (255.0 * (1.0 - g / STROKE)).round().clamp(0.0, 255.0) as u8
}

/// The driver (outer knuckle) angle of the fully closed 2F-85 (rad): register 255.
pub const DRIVER_CLOSED: f64 = 0.8;

/// Robotiq position register for fingers that stop at driver angle `driver` (rad) on the part,
/// commanded `squeeze` (m, as the parallel stroke counts it: 255 per 85 mm) further so that
/// they press on it: the register follows the driver, `255·driver/0.8` (the MuJoCo Menagerie
/// actuator's mapping), rounded up; clamped. For a pinch it agrees with [`grip_pos`] within a few
/// counts; for a power grasp whose fingers curl around the bar it is the one that gets there
/// (the pads' gap says nothing of how far the driver turned).
pub fn grip_pos_for_driver(driver: f64, squeeze: f64) -> u8 {
    let counts = 255.0 * driver / DRIVER_CLOSED + 255.0 * squeeze / STROKE;
    counts.ceil().clamp(0.0, 255.0) as u8
}

/// Number of 2 ms ticks for an interval of `d` seconds: `⌈d / DT⌉`, at least 1.
pub fn ticks(d: f64) -> u32 {
    ((d / DT) - 1e-9).ceil().max(1.0) as u32
}

/// Cycles a segment's last point is held for: twice the lookahead time.
pub fn settle_ticks(lookahead: f64) -> u32 {
    ticks(2.0 * lookahead)
}

fn arr(q: &Joints) -> String {
    let items: Vec<String> = q.iter().map(|x| format!("{x:.12}")).collect();
    format!("[{}]", items.join(", "))
}

/// Hand-offs: segment `i` ends with one when segment `i + 1` belongs to the other arm.
fn handoff_after(timeline: &Timeline, i: usize) -> bool {
    i + 1 < timeline.segments.len() && timeline.segments[i + 1].arm != timeline.segments[i].arm
}

/// Number of hand-offs arm `arm`'s peer has sent before segment `j` begins.
fn peer_handoffs_before(timeline: &Timeline, arm: usize, j: usize) -> usize {
    (0..j)
        .filter(|&i| timeline.segments[i].arm != arm && handoff_after(timeline, i))
        .count()
}

const PRELUDE: &str = r#"
  # ---- the Robotiq 2F-85 through the URCap's socket -------------------------------------
  def pg_grip_fail(msg):
    popup(msg, "pregrasp: gripper", error=True)
    halt
  end
  def pg_grip_get(var):
    socket_send_line(str_cat("GET ", var), "pg_gripper")
    return socket_read_string("pg_gripper", timeout=2.0)
  end
  def pg_grip_set(cmd):
    socket_send_line(cmd, "pg_gripper")
    reply = socket_read_string("pg_gripper", timeout=2.0)
    if str_find(reply, "ack") < 0:
      pg_grip_fail(str_cat("no ack for ", cmd))
    end
  end
  # Waits until the fingers have stopped (GET OBJ is no longer 0), at most 5 s.
  def pg_grip_wait():
    sleep(0.2)
    polls = 0
    while str_find(pg_grip_get("OBJ"), "OBJ 0") >= 0:
      polls = polls + 1
      if polls > 50:
        pg_grip_fail("the fingers did not stop within 5 s")
      end
      sleep(0.1)
    end
  end
  def pg_grip_open():
    pg_grip_set("SET POS 0")
    pg_grip_wait()
  end
  # Requires an object between the fingers (GET OBJ = 2).
  def pg_grip_check(where):
    if str_find(pg_grip_get("OBJ"), "OBJ 2") < 0:
      pg_grip_fail(str_cat("no object in the gripper ", where))
    end
  end
  def pg_grip_close(cmd, where):
    pg_grip_set(cmd)
    pg_grip_wait()
    pg_grip_check(where)
  end

  # ---- hand-off with the other controller -----------------------------------------------
  global pg_peer_ready = False
  global pg_peer_pulses = 0
  global pg_peer_lost = False
  # Counts the other controller's hand-off pulses on IN: high = ready, a low of
  # PG_PULSE_MIN..PG_PULSE_MAX cycles followed by high = one hand-off.
  thread pg_watch_peer():
    low = 0
    while True:
      if get_standard_digital_in(PG_SYNC_IN):
        if pg_peer_ready and low >= PG_PULSE_MIN and low <= PG_PULSE_MAX:
          pg_peer_pulses = pg_peer_pulses + 1
        end
        pg_peer_ready = True
        low = 0
      else:
        low = low + 1
        if pg_peer_ready and low > PG_PULSE_MAX:
          pg_peer_lost = True
        end
      end
      sync()
    end
  end
  def pg_wait_ready():
    while not pg_peer_ready:
      sync()
    end
  end
  # Waits until the other arm has handed over k times.
  def pg_wait_peer(k, what):
    while pg_peer_pulses < k:
      if pg_peer_lost:
        popup(str_cat("the other controller stopped; waiting to start ", what), "pregrasp: hand-off", error=True)
        halt
      end
      sync()
    end
  end
  def pg_handoff():
    set_standard_digital_out(PG_SYNC_OUT, False)
    sleep(PG_PULSE)
    set_standard_digital_out(PG_SYNC_OUT, True)
  end

  # ---- motion ---------------------------------------------------------------------------
  # n targets on the straight joint-space line from q0 to q1, one every 2 ms; the last is q1.
  def pg_line(q0, q1, n):
    i = 1
    while i <= n:
      f = i / n
      servoj([q0[0] + (q1[0] - q0[0]) * f, q0[1] + (q1[1] - q0[1]) * f, q0[2] + (q1[2] - q0[2]) * f, q0[3] + (q1[3] - q0[3]) * f, q0[4] + (q1[4] - q0[4]) * f, q0[5] + (q1[5] - q0[5]) * f], t=PG_DT, lookahead_time=PG_LOOKAHEAD, gain=PG_GAIN)
      i = i + 1
    end
  end
  # Holds q for n cycles: the arm, which trails its servoj targets by about the lookahead
  # time, settles on the segment's last point before the gripper acts or the other arm moves.
  def pg_hold(q, n):
    i = 1
    while i <= n:
      servoj(q, t=PG_DT, lookahead_time=PG_LOOKAHEAD, gain=PG_GAIN)
      i = i + 1
    end
  end
"#;

/// The program of arm `arm` of `set`, whose plan `timeline` is.
pub fn arm_script(set: &PlanSet, timeline: &Timeline, arm: usize, o: &Options) -> String {
    let a = &set.arms[arm];
    let peer = &set.arms[1 - arm];
    let knots = &timeline.arms[arm].knots;
    let mut s = String::new();
    let w = &mut s;
    let fname: String = a
        .name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let _ = writeln!(
        w,
        "# pregrasp plan for arm {:?} ({}), generated by `pregrasp export`.",
        a.name, a.model
    );
    let _ = writeln!(
        w,
        "# Runs on the controller of {:?}; {}.script runs on the other one.",
        a.name, peer.name
    );
    let _ = writeln!(
        w,
        "# Wiring: standard_digital_out[{}] of this controller -> standard_digital_in[IN]",
        o.sync_out
    );
    let _ = writeln!(
        w,
        "#   of the other; the other's OUT -> standard_digital_in[{}] here (common 0 V).",
        o.sync_in
    );
    let _ = writeln!(
        w,
        "#   Set OUT's action to \"Low when program is not running\" (Installation > I/O Setup)."
    );
    let _ = writeln!(
        w,
        "# First run: speed slider at 10-25 %, everyone clear of both arms, each arm alone first."
    );
    let _ = writeln!(
        w,
        "# Needs the Robotiq Grippers URCap (socket 127.0.0.1:63352). See docs/export.md."
    );
    let _ = writeln!(w, "# Segments:");
    for seg in &timeline.segments {
        let _ = writeln!(
            w,
            "#   {:5} {:8} {:>7} s  {}",
            seg.name,
            seg.kind,
            format!("{:.3}", seg.t_end() - seg.t0),
            if seg.arm == arm {
                "this arm"
            } else {
                "other arm (this one holds still)"
            }
        );
    }
    let _ = writeln!(w, "def pregrasp_{fname}():");
    let _ = writeln!(
        w,
        "  # ---- parameters ----------------------------------------------------------------"
    );
    let _ = writeln!(w, "  PG_DT = {}", float(DT));
    let _ = writeln!(w, "  PG_LOOKAHEAD = {}", float(o.lookahead));
    let _ = writeln!(w, "  PG_GAIN = {}", float(o.gain));
    let _ = writeln!(w, "  PG_SYNC_OUT = {}", o.sync_out);
    let _ = writeln!(w, "  PG_SYNC_IN = {}", o.sync_in);
    let _ = writeln!(w, "  PG_PULSE = {}", float(PULSE));
    let _ = writeln!(w, "  PG_PULSE_MIN = {PULSE_MIN_TICKS}");
    let _ = writeln!(w, "  PG_PULSE_MAX = {PULSE_MAX_TICKS}");
    s.push_str(PRELUDE);
    let w = &mut s;
    let _ = writeln!(w);
    let _ = writeln!(
        w,
        "  # ---- start ---------------------------------------------------------------------"
    );
    let _ = writeln!(w, "  set_standard_digital_out(PG_SYNC_OUT, False)");
    let _ = writeln!(w, "  pg_watcher = run pg_watch_peer()");
    let _ = writeln!(
        w,
        "  if not socket_open(\"127.0.0.1\", 63352, \"pg_gripper\"):"
    );
    let _ = writeln!(
        w,
        "    pg_grip_fail(\"cannot open the Robotiq URCap socket 127.0.0.1:63352\")"
    );
    let _ = writeln!(w, "  end");
    let _ = writeln!(w, "  pg_grip_set(\"SET ACT 1\")");
    let _ = writeln!(w, "  pg_tries = 0");
    let _ = writeln!(w, "  while str_find(pg_grip_get(\"STA\"), \"STA 3\") < 0:");
    let _ = writeln!(w, "    pg_tries = pg_tries + 1");
    let _ = writeln!(w, "    if pg_tries > 150:");
    let _ = writeln!(
        w,
        "      pg_grip_fail(\"activation did not complete within 15 s\")"
    );
    let _ = writeln!(w, "    end");
    let _ = writeln!(w, "    sleep(0.1)");
    let _ = writeln!(w, "  end");
    let _ = writeln!(w, "  pg_grip_set(\"SET SPE {}\")", o.grip_speed);
    let _ = writeln!(w, "  pg_grip_set(\"SET FOR {}\")", o.grip_force);
    let _ = writeln!(w, "  pg_grip_set(\"SET GTO 1\")");
    let first = knots[0].1;
    let _ = writeln!(w, "  # to the first point at a safe speed");
    let _ = writeln!(
        w,
        "  movej({}, a={}, v={})",
        arr(&first),
        float(o.movej_accel),
        float(o.movej_speed)
    );
    let _ = writeln!(w, "  set_standard_digital_out(PG_SYNC_OUT, True)");
    let _ = writeln!(w, "  pg_wait_ready()");
    let mut last_handoff = false;
    for (j, seg) in timeline.segments.iter().enumerate() {
        if seg.arm != arm {
            continue;
        }
        let _ = writeln!(w);
        let _ = writeln!(
            w,
            "  # ---- segment {} ({}, {} points) --------------------------------------",
            seg.name,
            seg.kind,
            seg.points.len()
        );
        if j > 0 && timeline.segments[j - 1].arm != arm {
            let k = peer_handoffs_before(timeline, arm, j);
            let _ = writeln!(w, "  pg_wait_peer({k}, \"{}\")", seg.name);
        }
        let holding = j > 0 && timeline.gripper_at(arm, seg.t0).0;
        let opens = seg.kind.closes_at_end();
        if holding && !opens {
            let _ = writeln!(w, "  pg_grip_check(\"before {}\")", seg.name);
        }
        if opens {
            let _ = writeln!(w, "  pg_grip_open()");
        }
        for win in seg.points.windows(2) {
            let n = ticks(win[1].0 - win[0].0);
            let _ = writeln!(
                w,
                "  pg_line({}, {}, {n}.0)",
                arr(&win[0].1),
                arr(&win[1].1)
            );
        }
        let last = seg.points.last().expect("non-empty").1;
        let _ = writeln!(
            w,
            "  pg_hold({}, {}.0)",
            arr(&last),
            settle_ticks(o.lookahead)
        );
        if opens {
            // A user's register first, then the closing's own force (for the pinch, the
            // plan's recommended one when `sup1` has none), then the default register.
            let (chosen, own) = match seg.grasp {
                GraspKind::Support => (
                    o.support_grip_force,
                    seg.grip_force.or(timeline.support_grip_force),
                ),
                GraspKind::Power => (o.power_grip_force, seg.grip_force),
            };
            let force = chosen.or(own.map(force_register)).unwrap_or(o.grip_force);
            let _ = writeln!(w, "  pg_grip_set(\"SET FOR {force}\")");
            let pos = match (seg.closing.fingers, seg.closing.width) {
                (Some(f), _) => grip_pos_for_driver(f.driver, o.grip_squeeze),
                (None, Some(g)) => grip_pos((g - o.grip_squeeze).max(0.0)),
                (None, None) => 255,
            };
            let _ = writeln!(
                w,
                "  pg_grip_close(\"SET POS {pos}\", \"at the end of {}\")",
                seg.name
            );
        }
        last_handoff = handoff_after(timeline, j);
        if last_handoff {
            let _ = writeln!(w, "  pg_handoff()");
        }
    }
    let _ = writeln!(w);
    let _ = writeln!(
        w,
        "  # ---- end -----------------------------------------------------------------------"
    );
    if last_handoff {
        let _ = writeln!(
            w,
            "  sleep(1.0)  # keep OUT high so the other controller sees the last hand-off end"
        );
    }
    let _ = writeln!(w, "  stopj(2.0)");
    let _ = writeln!(w, "  set_standard_digital_out(PG_SYNC_OUT, False)");
    let _ = writeln!(w, "end");
    s
}

/// `<name>.script` for both arms.
pub fn export(
    set: &PlanSet,
    timeline: &Timeline,
    options: &Options,
) -> Result<Vec<OutFile>, ExportError> {
    if set.arms.len() != 2 {
        return Err(ExportError::ArmCount {
            count: set.arms.len(),
        });
    }
    ur_models(set, "urscript", "URScript runs on UR controllers")?;
    Ok((0..2)
        .map(|a| OutFile {
            name: format!("{}.script", set.arms[a].name),
            bytes: arm_script(set, timeline, a, options).into_bytes(),
        })
        .collect())
}

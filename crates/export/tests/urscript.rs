//! The URScript programs, read back by a small interpreter of what they emit: the motion
//! reproduces the plan, stays within the arm's limits, the gripper acts at the right moments,
//! and the hand-off between the two programs can neither deadlock nor let both arms move.

// Joint loops index several arrays at once (`for j in 0..6`): clearer than zipped iterators.
#![allow(clippy::needless_range_loop)]

mod common;

use pregrasp_io::plan_file::{GraspKind, SegmentKind};
use std::collections::HashSet;

use pregrasp_export::urscript::{force_register, grip_pos, grip_pos_for_driver, DT};
use pregrasp_export::{Format, Options};

/// One statement of a program, as the reader understands it.
#[derive(Clone, Debug, PartialEq)]
enum Op {
    MoveJ([f64; 6]),
    Ready,
    Segment(String),
    WaitPeer(usize),
    Line([f64; 6], [f64; 6], u32),
    Hold([f64; 6], u32),
    Open,
    Force(u8),
    Close(u8),
    Check,
    Handoff,
}

fn nums(s: &str) -> Vec<f64> {
    s.split(',')
        .map(|x| x.trim().parse::<f64>().unwrap())
        .collect()
}

fn arr6(s: &str) -> [f64; 6] {
    let v = nums(s);
    assert_eq!(v.len(), 6, "{s}");
    std::array::from_fn(|i| v[i])
}

/// The statements of the main body (after the function definitions).
fn read(script: &str) -> Vec<Op> {
    let mut ops = Vec::new();
    let body = script
        .split("# ---- start ---")
        .nth(1)
        .expect("a start section");
    for line in body.lines().map(str::trim) {
        if let Some(rest) = line.strip_prefix("movej([") {
            ops.push(Op::MoveJ(arr6(rest.split(']').next().unwrap())));
        } else if line == "pg_wait_ready()" {
            ops.push(Op::Ready);
        } else if let Some(rest) = line.strip_prefix("# ---- segment ") {
            ops.push(Op::Segment(rest.split(' ').next().unwrap().to_string()));
        } else if let Some(rest) = line.strip_prefix("pg_wait_peer(") {
            ops.push(Op::WaitPeer(
                rest.split(',').next().unwrap().parse().unwrap(),
            ));
        } else if let Some(rest) = line.strip_prefix("pg_line([") {
            let mut parts = rest.split(']');
            let a = arr6(parts.next().unwrap());
            let b = arr6(parts.next().unwrap().trim_start_matches(", ["));
            let n: f64 = parts
                .next()
                .unwrap()
                .trim_start_matches(',')
                .trim_end_matches(')')
                .trim()
                .parse()
                .unwrap();
            assert_eq!(n.fract(), 0.0);
            ops.push(Op::Line(a, b, n as u32));
        } else if let Some(rest) = line.strip_prefix("pg_hold([") {
            let mut parts = rest.split(']');
            let q = arr6(parts.next().unwrap());
            let n: f64 = parts
                .next()
                .unwrap()
                .trim_start_matches(',')
                .trim_end_matches(')')
                .trim()
                .parse()
                .unwrap();
            ops.push(Op::Hold(q, n as u32));
        } else if let Some(rest) = line.strip_prefix("pg_grip_set(\"SET FOR ") {
            ops.push(Op::Force(rest.split('"').next().unwrap().parse().unwrap()));
        } else if line == "pg_grip_open()" {
            ops.push(Op::Open);
        } else if let Some(rest) = line.strip_prefix("pg_grip_close(\"SET POS ") {
            ops.push(Op::Close(rest.split('"').next().unwrap().parse().unwrap()));
        } else if line.starts_with("pg_grip_check(") {
            ops.push(Op::Check);
        } else if line == "pg_handoff()" {
            ops.push(Op::Handoff);
        }
    }
    ops
}

fn scripts(options: &Options) -> Vec<(String, String)> {
    let (file, _) = common::chair_side();
    common::export_file(file, 0, &[Format::UrScript], options, None)
        .unwrap()
        .into_iter()
        .map(|f| (f.name, String::from_utf8(f.bytes).unwrap()))
        .collect()
}

/// The `servoj` targets `pg_line` commands, in order, as URScript computes them.
fn expand(a: &[f64; 6], b: &[f64; 6], n: u32) -> Vec<[f64; 6]> {
    (1..=n)
        .map(|i| {
            let f = i as f64 / n as f64;
            std::array::from_fn(|j| a[j] + (b[j] - a[j]) * f)
        })
        .collect()
}

#[test]
fn one_program_per_arm_with_its_name() {
    let s = scripts(&Options::default());
    let names: Vec<&str> = s.iter().map(|x| x.0.as_str()).collect();
    let (file, _) = common::chair_side();
    let expected: Vec<String> = file
        .robots
        .iter()
        .map(|r| format!("{}.script", r.name))
        .collect();
    assert_eq!(names, expected);
    for (_, text) in &s {
        assert!(text.contains("def pregrasp_"));
        assert!(text.contains("PG_LOOKAHEAD = 0.1\n") && text.contains("PG_GAIN = 300.0\n"));
        assert!(text.contains("socket_open(\"127.0.0.1\", 63352, \"pg_gripper\")"));
        assert!(text.contains("popup(") && text.contains("error=True") && text.contains("halt"));
        assert!(text.contains("servoj("));
    }
}

/// The interpreted motion passes through every plan point in order (within 1e-6 rad), every
/// target lies on the plan's straight joint-space line between two points, each interval takes
/// between its planned duration and 2 ms more, and no target exceeds a joint speed or position
/// limit.
#[test]
fn interpreted_servoj_stream_reproduces_the_plan_within_limits() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    for (name, text) in scripts(&Options::default()) {
        let robot = file
            .robots
            .iter()
            .find(|r| format!("{}.script", r.name) == name)
            .unwrap();
        let model = robot.model.builtin().expect("a built-in arm");
        let vmax = model.max_joint_speed();
        let limits = model.joint_limits();
        // (the force register settings do not move the arm)
        let ops: Vec<Op> = read(&text)
            .into_iter()
            .filter(|o| !matches!(o, Op::Force(_)))
            .collect();
        let Op::MoveJ(first) = ops[0] else {
            panic!("movej first")
        };
        assert_eq!(first, robot.start, "{name}: movej to the first point");
        // The plan's points of this arm, in order, with their intervals.
        let mut expected = Vec::new();
        for seg in plan.segments.iter().filter(|s| s.robot == robot.name) {
            for w in seg.points.windows(2) {
                expected.push((w[0].q, w[1].q, w[1].t - w[0].t));
            }
        }
        let lines: Vec<_> = ops
            .iter()
            .filter_map(|o| match o {
                Op::Line(a, b, n) => Some((*a, *b, *n)),
                _ => None,
            })
            .collect();
        assert_eq!(
            lines.len(),
            expected.len(),
            "{name}: one pg_line per interval"
        );
        let mut current = first;
        let mut checked = 0;
        for ((a, b, n), (pa, pb, d)) in lines.iter().zip(&expected) {
            for j in 0..6 {
                assert!(
                    (a[j] - pa[j]).abs() < 1e-6 && (b[j] - pb[j]).abs() < 1e-6,
                    "{name}"
                );
                assert!(
                    (a[j] - current[j]).abs() < 1e-6,
                    "{name}: the line starts where the arm is"
                );
            }
            let dur = *n as f64 * DT;
            assert!(
                dur >= d - 1e-12 && dur < d + DT + 1e-12,
                "{name}: {dur} s for a {d} s interval"
            );
            for target in expand(a, b, *n) {
                for j in 0..6 {
                    let speed = (target[j] - current[j]).abs() / DT;
                    assert!(
                        speed <= vmax[j] + 1e-9,
                        "{name}: joint {j} at {speed} rad/s"
                    );
                    assert!(
                        target[j] >= limits[j].0 && target[j] <= limits[j].1,
                        "{name}"
                    );
                }
                current = target;
                checked += 1;
            }
            // The interval's last target is the plan point.
            for j in 0..6 {
                assert!(
                    (current[j] - pb[j]).abs() < 1e-6,
                    "{name}: plan point missed"
                );
            }
        }
        assert!(checked > 1000, "{name}: only {checked} servoj targets");
        // Every segment of the arm ends with a hold of its last point (zero speed), long
        // enough for the lookahead filter to settle, and nothing else holds.
        let holds: Vec<_> = ops
            .iter()
            .enumerate()
            .filter_map(|(i, o)| match o {
                Op::Hold(q, n) => Some((i, *q, *n)),
                _ => None,
            })
            .collect();
        let own: Vec<_> = plan
            .segments
            .iter()
            .filter(|s| s.robot == robot.name)
            .collect();
        assert_eq!(holds.len(), own.len(), "{name}");
        for ((i, q, n), seg) in holds.iter().zip(&own) {
            let last = seg.points.last().unwrap().q;
            assert!(
                (0..6).all(|j| (q[j] - last[j]).abs() < 1e-9),
                "{name}: hold at the end"
            );
            assert!(*n as f64 * DT >= 2.0 * Options::default().lookahead - 1e-12);
            assert!(
                matches!(ops[i - 1], Op::Line(..)),
                "{name}: hold right after the motion"
            );
        }
    }
}

/// Open at the start of every reach/regrasp, close at its last point with the mapped width,
/// check before a segment the arm holds the part in.
#[test]
fn gripper_commands_at_the_right_moments() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    let squeeze = Options::default().grip_squeeze;
    for (name, text) in scripts(&Options::default()) {
        let ops = read(&text);
        let mut segment = String::new();
        let mut seen_line_in_segment = false;
        let mut closed = false;
        let mut closes = Vec::new();
        for op in &ops {
            match op {
                Op::Segment(s) => {
                    segment = s.clone();
                    seen_line_in_segment = false;
                }
                Op::Open => {
                    assert!(
                        !seen_line_in_segment,
                        "{name}: open before the motion of {segment}"
                    );
                    closed = false;
                }
                Op::Close(pos) => {
                    closed = true;
                    closes.push((segment.clone(), *pos));
                }
                Op::Check => assert!(closed, "{name}: check while open"),
                Op::Line(..) => {
                    seen_line_in_segment = true;
                }
                _ => {}
            }
        }
        let robot = name.trim_end_matches(".script");
        let expected: Vec<(String, u8)> = plan
            .segments
            .iter()
            .filter(|s| s.robot == robot && s.kind.closes_at_end())
            .map(|s| {
                let pos = match (&s.fingers, s.grip_width) {
                    (Some(f), _) => grip_pos_for_driver(f.driver, squeeze),
                    (None, Some(g)) => grip_pos((g - squeeze).max(0.0)),
                    (None, None) => 255,
                };
                (s.name.to_string(), pos)
            })
            .collect();
        assert_eq!(closes, expected, "{name}");
        // A close is the last thing of its segment's motion: the next pg_line is in another
        // segment.
        for (i, op) in ops.iter().enumerate() {
            if matches!(op, Op::Close(_)) {
                let next_seg = ops[i..].iter().position(|o| matches!(o, Op::Segment(_)));
                let next_line = ops[i..].iter().position(|o| matches!(o, Op::Line(..)));
                if let Some(l) = next_line {
                    assert!(
                        next_seg.is_some_and(|s| s < l),
                        "{name}: motion after a close"
                    );
                }
            }
        }
    }
    // The mapping: 0 m gap fully closed, the full stroke open, linear between.
    // A pinch: the driver's register and the gap's agree within a few counts.
    for gap in [0.02, 0.04, 0.06] {
        let driver = pregrasp_robot::FingerPair::at_gap(gap).driver;
        let (a, b) = (grip_pos_for_driver(driver, 0.0), grip_pos(gap));
        assert!(a.abs_diff(b) <= 12, "gap {gap}: {a} vs {b}");
    }
    assert_eq!(grip_pos_for_driver(0.8, 0.0), 255);
    assert_eq!(grip_pos_for_driver(0.0, 0.0), 0);
    assert_eq!(grip_pos(0.0), 255);
    assert_eq!(grip_pos(0.085), 0);
    assert_eq!(grip_pos(0.0425), 128);
    assert_eq!(grip_pos(-0.01), 255);
}

/// Both programs run against each other in every interleaving of their steps (each segment's
/// motion is a start and an end step, a hand-off pulse is counted by the other's watcher): no
/// interleaving deadlocks, the segments start in the plan's order, and the two arms never move
/// at the same time.
#[test]
fn hand_off_never_deadlocks_nor_overlaps_in_any_interleaving() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    let programs: Vec<Vec<Op>> = scripts(&Options::default())
        .iter()
        .map(|s| read(&s.1))
        .collect();
    // Steps per program: Raise (OUT high: ready), AwaitReady, Wait(k), Start(segment), End,
    // Handoff (a pulse the other's watcher counts).
    #[derive(Clone, Debug, PartialEq)]
    enum Step {
        Raise,
        AwaitReady,
        Wait(usize),
        Start(String),
        End,
        Handoff,
    }
    let steps: Vec<Vec<Step>> = programs
        .iter()
        .map(|ops| {
            let mut out = Vec::new();
            let mut in_seg = false;
            for op in ops {
                match op {
                    Op::Ready => out.extend([Step::Raise, Step::AwaitReady]),
                    Op::Segment(s) => {
                        if in_seg {
                            out.push(Step::End);
                        }
                        out.push(Step::Start(s.clone()));
                        in_seg = true;
                    }
                    // The wait is written first thing in its segment: it precedes the motion.
                    Op::WaitPeer(k) => {
                        let start = out.pop().expect("a wait follows a segment marker");
                        assert!(matches!(start, Step::Start(_)), "{start:?}");
                        out.push(Step::Wait(*k));
                        out.push(start);
                    }
                    Op::Handoff => {
                        if in_seg {
                            out.push(Step::End);
                            in_seg = false;
                        }
                        out.push(Step::Handoff)
                    }
                    _ => {}
                }
            }
            if in_seg {
                out.push(Step::End);
            }
            out
        })
        .collect();
    // State: program counters, ready flags, pulses sent, moving arm, segments started.
    type State = ([usize; 2], [usize; 2], Vec<String>);
    let mut seen: HashSet<([usize; 2], [usize; 2], usize)> = HashSet::new();
    let mut stack: Vec<State> = vec![([0, 0], [0, 0], Vec::new())];
    let mut finished = 0;
    let order: Vec<String> = plan.segments.iter().map(|s| s.name.to_string()).collect();
    while let Some((pc, pulses, started)) = stack.pop() {
        if !seen.insert((pc, pulses, started.len())) {
            continue;
        }
        let done = [pc[0] == steps[0].len(), pc[1] == steps[1].len()];
        if done[0] && done[1] {
            assert_eq!(started, order, "segments start in the plan's order");
            finished += 1;
            continue;
        }
        let moving = |p: usize| {
            // Inside a segment: the last Start not yet matched by an End.
            let mut m = false;
            for s in &steps[p][..pc[p]] {
                match s {
                    Step::Start(_) => m = true,
                    Step::End => m = false,
                    _ => {}
                }
            }
            m
        };
        assert!(!(moving(0) && moving(1)), "both arms move at once: {pc:?}");
        let mut progressed = false;
        for p in 0..2 {
            if done[p] {
                continue;
            }
            let other = 1 - p;
            let runnable = match &steps[p][pc[p]] {
                Step::AwaitReady => pc[other] >= 1,
                Step::Wait(k) => pulses[other] >= *k,
                _ => true,
            };
            if !runnable {
                continue;
            }
            progressed = true;
            let mut npc = pc;
            let mut npulses = pulses;
            let mut nstarted = started.clone();
            match &steps[p][pc[p]] {
                Step::Handoff => npulses[p] += 1,
                Step::Start(s) => nstarted.push(s.clone()),
                _ => {}
            }
            npc[p] += 1;
            stack.push((npc, npulses, nstarted));
        }
        assert!(
            progressed,
            "deadlock at {pc:?}, pulses {pulses:?}: {steps:?}"
        );
    }
    assert!(finished > 0);
}

#[test]
fn options_reach_the_program_and_output_is_deterministic() {
    let o = Options {
        lookahead: 0.05,
        gain: 500.0,
        sync_out: 3,
        sync_in: 5,
        movej_speed: 0.2,
        ..Options::default()
    };
    let a = scripts(&o);
    assert_eq!(a, scripts(&o), "same plan, same bytes");
    for (_, text) in &a {
        assert!(text.contains("PG_LOOKAHEAD = 0.05\n"));
        assert!(text.contains("PG_GAIN = 500.0\n"));
        assert!(text.contains("PG_SYNC_OUT = 3\n") && text.contains("PG_SYNC_IN = 5\n"));
        assert!(text.contains(", a=0.5, v=0.2)"));
    }
}

/// The fingertip pinch of the support grasp squeezes with the force the plan's quasi-static
/// check recommends (`physics.grip_force_recommended`, issue 15), the power grasps with their
/// segments' `grip_force` (235 N on the chair side: register 255); `--support-grip-force` and
/// `--grip-force` override the plan.
#[test]
fn support_grasp_squeezes_with_the_recommended_force() {
    let (file, _) = common::chair_side();
    let plan = &file.plans[0];
    let recommended = plan
        .physics
        .as_ref()
        .and_then(|p| p.grip_force_recommended)
        .expect("the example plan holds and has a recommended force");
    let pinch = force_register(recommended);
    let force_before_closes = |options: &Options| -> Vec<(String, u8)> {
        let mut out = Vec::new();
        for (_, text) in scripts(options) {
            let (mut segment, mut force) = (String::new(), None);
            for op in read(&text) {
                match op {
                    Op::Segment(s) => segment = s,
                    Op::Force(f) => force = Some(f),
                    Op::Close(_) => {
                        out.push((segment.clone(), force.expect("SET FOR before a close")))
                    }
                    _ => {}
                }
            }
        }
        out.sort();
        out
    };
    let expect = |support: u8, power: u8| -> Vec<(String, u8)> {
        let mut v: Vec<(String, u8)> = plan
            .segments
            .iter()
            .filter(|s| s.kind != SegmentKind::Rotate)
            .map(|s| {
                (
                    s.name.to_string(),
                    if s.grasp == GraspKind::Support {
                        support
                    } else {
                        power
                    },
                )
            })
            .collect();
        v.sort();
        v
    };
    assert_eq!(force_before_closes(&Options::default()), expect(pinch, 255));
    // `--grip-force` is `power_grip_force`: it overrides the plan's power-grasp forces.
    let custom = Options {
        grip_force: 200,
        power_grip_force: Some(200),
        support_grip_force: Some(17),
        ..Options::default()
    };
    assert_eq!(force_before_closes(&custom), expect(17, 200));
    // The register mapping: 20 N ↦ 0, 235 N ↦ 255, rounded up (never less than asked).
    assert_eq!(force_register(20.0), 0);
    assert_eq!(force_register(235.0), 255);
    assert_eq!(force_register(500.0), 255);
    let f = 100.0;
    let back = 20.0 + force_register(f) as f64 / 255.0 * 215.0;
    assert!(back >= f && back - f < 215.0 / 255.0);
}

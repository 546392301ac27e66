//! Power grasps seated on the palm (issue 48, closings that do not push).
//!
//! A 2F-85 power grasp wraps the bar: once its fingers touch the bar's top corners, their tips
//! curl under it and pull it towards the palm until it rests there. A bar that the scene's
//! grasp holds a few millimetres below the palm is therefore pulled up by that gap while the
//! other gripper still pinches the part — the master's closing shoves the pinched part (the
//! whole-plan replay measured 3–8 mm on bars held 4–5 mm below the palm, along the approach
//! axis, and under 2 mm once the bar sat on the palm: `docs/physics.md`, "Closings that do not
//! push").
//!
//! [`seat_power_grasps`] moves each power grasp deeper along its approach (the gripper frame's
//! `z`, pointing from the palm to the fingertips) until the palm is [`SEAT_GAP`] from the part
//! as it rests on the support — the planned part is `lift` higher (P_init), so the planned
//! palm ends `lift · cos(approach, down) − SEAT_GAP` inside it, at most [`SEAT_DEPTH`] —
//! when all of these hold:
//! - the gripper is the 2F-85 (jaws translate; they pull nothing);
//! - the bar is at least [`MIN_SEAT_THICKNESS`] thick along the approach through the grasp
//!   ([`thickness_at`]);
//! - the palm (the gripper's static shapes) is more than [`SEAT_TOLERANCE`] and at most
//!   [`SEAT_REACH`] from the part along the approach (the time of impact of the palm's boxes
//!   moved along `z`, `parry3d::query::cast_shapes`);
//! - the closing at the scene's grasp wraps the bar ([`HoldKind::Encompassing`]) — fingertips
//!   that meet under a thin bar stop the pull — or pinches it with the pads
//!   ([`HoldKind::Pinch`], below);
//! - the closing at the seated grasp still squeezes the bar from both sides (a pinch or an
//!   encompassing grasp, not caged or one-sided) and starts from a free open hand; where it
//!   would not, the grasp is seated against the part as planned ([`SEAT_GAP`] from it) if the
//!   closing squeezes there.
//!
//! A wrap that squeezes on neither is not held short of the palm: its fingers pull the bar
//! onto the palm, where the closing cages it, so it is a grasp caged where the scene holds it
//! (below, held at the fingertips). Until 2026-11-30 it moved as deep as the closing still
//! squeezed, the closing then pulling the bar by what was left; on panel_27 (24 mm bars, 31 mm
//! stock), held 1.5 mm short of the palm, the whole-plan replay pulled the master's bar in and
//! caged it (4–12 N on the bar) and the part turned 12.3° when the supportive gripper opened.
//! Held at the fingertips, it lifts (47.8 mm, 1.6°). MuJoCo's closings on fixed bars agree:
//! on 25 × 30 mm bars with the top 0.5 or 2 mm below the palm its fingertips meet under the
//! bar, 4 mm below they squeeze (`closing_2f85_power.json`).
//!
//! A pinch near the palm pulls the bar too: the pads touch it above the 2F-85's equilibrium
//! line, so the fingers curl in (the replay pulled the pinched legs of stool_1, stool_5 and
//! h_frame_6 in by 4.3–5.5 mm). Such a grasp moves [`PINCH_SEAT_FRACTION`] of the way to
//! the palm, where its closing still squeezes (else back in [`PARTIAL_SEAT_STEP`] steps, by
//! at least [`PARTIAL_SEAT_MIN`]).
//!
//! **Held at the fingertips.** A grasp whose closing at the scene's depth cages the bar (the
//! tips meet under it) or closes on one side cannot be seated: the wrap would pull the bar to
//! the palm and cage it there. It moves *out* instead, so that the bar lies between the pads
//! at the gripper's precision point (the scene's `precision_point_z`, where it holds G_s), and
//! back towards the palm in [`FINGERTIP_STEP`] steps ([`FINGERTIP_TRIES`] depths) to the first
//! where our closing squeezes: the pads meet the bar low on the fingers and close in parallel,
//! without curling (the whole-plan replay squeezes there with the full force, ~221 N per pad at
//! 235 N, and the part does not move: `docs/physics.md`, "Thin bars held at the fingertips").
//! The move is negative; the plan file writes it as `grasps.fingertips`. The held grasp lies
//! on the bar's mid-plane ([`bar_mid_plane`], at most [`CENTRE_REACH`] across): the 2F-85's
//! fingers close together, and the pad that meets an off-centre bar first stops both, so our
//! closing ended on one side on 13 caged masters of the replay tables, 0.01–0.06 mm off
//! the mid-plane (the scene files' 0.1 mm rounding), and they stayed caged. The mid-plane is
//! halfway between the faces each pad meets first over its width: on a tapered leg (its
//! face sloping 2° along the bar) a pad meets the face at its edge, 0.1–0.3 mm before its
//! centre would, and the fifteen chamfered parts of the hard families closed on one side at
//! every fingertip depth until the edges were read too. The plan file writes that move as
//! `grasps.centred`.
//!
//! **Off-centre grasps.** Any 2F-85 power grasp whose origin lies more than [`CENTRE_REACH`]
//! off the mid-plane of its bar (the stretch of material its closing line crosses) is moved
//! across onto it before everything above ([`off_centre`]): the pad that meets the bar first
//! would shove it (a user's scene with its grasps moved up to 2 cm across: the master's closing
//! pushed the pinched part 3.7–20 mm, or closed on one side).
//!
//! **Fingertips first** (the planner's rule, [`SeatRule::PLANNER`]). A wrap pulls its bar to
//! the palm while the other gripper only pinches the part: the whole-plan replay measured the
//! master's closing moving the part 0.5–2.6 mm on seated wraps (15 of 122 plans over the 2 mm
//! allowed), against at most 0.1 mm for a pinch at the fingertips. So every 2F-85 grasp whose
//! closing squeezes the bar with the pads at the fingertips is held there, whatever its closing
//! at the scene's depth; a bar the pads cannot pinch there is seated as above. The pinch holds
//! less than the wrap: where the carry check finds it cannot carry the part, the pipeline plans
//! again with [`SeatRule::WRAPS`] (`docs/physics.md`, "Fingertips first").
//!
//! A pinch whose palm lies beyond [`SEAT_REACH`] holds its bar at the fingertips already (a
//! plan file's grasps, planned again) only where the bar's middle lies at a fingertip depth
//! ([`bar_depth`]); a scene whose power point is declared nearer the palm than that (a user's
//! tool offset: u_frame_70__p272's, 6 mm short of the precision point, where the master's
//! closing pushed the part 7.7 mm) is held at the fingertips like any other grasp.
//!
//! Frames: grasps in the object frame; the flange at `grasp · point⁻¹` (the arm's power point);
//! the part's mesh in the object frame. The move is `grasp · Translation(0, 0, d)`.

use nalgebra::{Isometry3, Translation3, Vector3};
use parry3d_f64::query::{cast_shapes, ShapeCastOptions};
use parry3d_f64::shape::Cuboid;
use pregrasp_collision::{close_on_part, ArmModel, Grip, GripFailure, ObjectGeometry};
use pregrasp_physics::HoldKind;
use pregrasp_robot::{GripperState, Primitive};

use crate::hold_kind::{hold_kind, squeezes};

mod bar;
pub use bar::{bar_depth, bar_mid_plane, material_along, off_centre, thickness_at};

/// Gap (m) left between the palm and the part as it rests on the support once a grasp is
/// seated: touching, with room for the mesh's and the arm's tolerances.
pub const SEAT_GAP: f64 = 0.0005;
/// Deepest (m) a seated palm may lie in the part as planned: the planner plans the part
/// `[planner] lift` above the support (P_init), so where the part really rests the palm is
/// that much farther from it; rule 2 of the plan format lets a gripper touch the part it
/// holds up to 0.5 mm deep.
pub const SEAT_DEPTH: f64 = 0.0004;
/// A palm at most this far (m) from the part is seated already.
pub const SEAT_TOLERANCE: f64 = 0.0015;
/// Farthest (m) a grasp is moved: a palm farther from the part holds a bar by the pads.
pub const SEAT_REACH: f64 = 0.025;
/// Thinnest bar (m, its material along the approach through the grasp) that is seated: under
/// a thinner bar against the palm the curling fingertips meet each other (caged) or close on
/// one side. Whole-plan replay of the examples and 60 generated parts with every wrapped bar
/// seated (`plan_replay_generated_seat_all_2f85.csv`, seeds 1–5, and
/// `plan_replay_generated_seeds_6_10_seat_all_2f85.csv`; test `seat_truth`): every plan with a
/// seated bar 18–22 mm thick had a power closing end caged or one-sided (4 of 4), and 73 of
/// the 74 closings on bars 23.9–44 mm thick seated on the palm squeezed from both sides
/// (stool_10's 23.9 mm legs among them: 24 mm here before, which kept them unseated).
pub const MIN_SEAT_THICKNESS: f64 = 0.023;

/// Step (m) of the search for the deepest pinch that still squeezes, where one moved
/// [`PINCH_SEAT_FRACTION`] of its way to the palm would not.
pub const PARTIAL_SEAT_STEP: f64 = 0.0005;
/// Least move (m) worth making in that search.
pub const PARTIAL_SEAT_MIN: f64 = 0.001;
/// Share of its way to the palm (`gap − SEAT_GAP`) a pinched bar is moved. Whole-plan replay
/// of the 65 plans of the examples and seeds 1–10 (test `seat_truth`): seated on the palm (1),
/// stool_1's closings end one-sided at `mas1` and `sup2`; at 0.5 and 0.75 stool_1 and stool_5
/// squeeze and their master pushes the part 0.95 / 1.81 mm and 0.65 / 1.40 mm (2.06 / 2.57
/// unmoved), and no other plan changes its verdict. The larger share keeps the larger margin.
pub const PINCH_SEAT_FRACTION: f64 = 0.75;

/// Step (m) back towards the palm from the precision point for a grasp held at the fingertips.
pub const FINGERTIP_STEP: f64 = 0.002;
/// Farthest (m) a grasp held at the fingertips moves across its bar (the gripper's `x`, the
/// closing direction) onto the bar's mid-plane ([`bar_mid_plane`]). The 2F-85's drivers turn
/// together: the pad that meets an off-centre bar first stops both fingers, and our closing
/// then ends on one side even 0.01–0.06 mm off the mid-plane (the scene file's 0.1 mm
/// rounding), where the real fingers push the bar by that much until both pads squeeze.
pub const CENTRE_REACH: f64 = 0.002;

/// How many depths a grasp held at the fingertips tries (the precision point and 2, 4 mm
/// nearer the palm): on 12 caged masters the replay pulled bars held 16–22 mm nearer the palm
/// than the precision point in by up to 7.7 mm, and squeezed 11 held 4 mm from it (6 at 10 mm)
/// with the full force, without moving the part. The nearer the palm the pads meet the bar,
/// the more the 2F-85's fingers curl at 235 N (a 54 × 19 mm bar fixed in MuJoCo: tips 1.2, 1.6
/// and 2.2 mm nearer than the pads at 2.5, 4.5 and 6.5 mm short of the precision point); at
/// 6 mm the whole-plan replay saw frame_80's master (1.83 kg) curl under its bar and pry the
/// pinched part up 5.2° (`docs/physics.md`, "Fingertip holds no deeper than 4 mm").
pub const FINGERTIP_TRIES: usize = 3;

/// How far (m) the middle of a bar a pinch holds with the palm out of reach may lie off the
/// fingertip depths (the precision point and up to `(FINGERTIP_TRIES − 1) · FINGERTIP_STEP`
/// nearer the palm) and still count as held at the fingertips already: a plan file's grasps
/// held there come back to the planner (`replan`) at those depths to the 0.01 mm.
const FINGERTIP_DEPTH_TOLERANCE: f64 = 0.0005;

/// Which power grasps move, and how far: the planner's is [`SeatRule::PLANNER`]; the replay
/// sweeps that set its numbers used others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeatRule {
    /// Thinnest bar (m) moved at all ([`MIN_SEAT_THICKNESS`]).
    pub min_thickness: f64,
    /// Share of the way to the palm a pinched bar moves ([`PINCH_SEAT_FRACTION`]; 0: pinches
    /// stay).
    pub pinch_fraction: f64,
    /// Whether a grasp whose closing cages the bar or closes on one side, or wraps it and cages
    /// it once on the palm, moves out to the fingertips (see the module documentation).
    pub fingertips: bool,
    /// Whether every grasp whose closing squeezes the bar at the fingertips is held there,
    /// the wrap kept for bars the pads cannot pinch (see the module documentation).
    pub fingertips_first: bool,
}

impl SeatRule {
    /// The rule a scene's `[planner] power_hold` asks for first: the wraps for `"wraps"`, else
    /// [`SeatRule::PLANNER`].
    pub fn first_for(hold: pregrasp_io::scene::PowerHold) -> SeatRule {
        match hold {
            pregrasp_io::scene::PowerHold::Wraps => SeatRule::WRAPS,
            _ => SeatRule::PLANNER,
        }
    }

    /// The planner's rule.
    pub const PLANNER: SeatRule = SeatRule {
        min_thickness: MIN_SEAT_THICKNESS,
        pinch_fraction: PINCH_SEAT_FRACTION,
        fingertips: true,
        fingertips_first: true,
    };

    /// The wraps: grasps held at the fingertips only where their closing cages the bar or
    /// closes on one side, the others seated on the palm. The pipeline plans with them where
    /// the pads' pinch at the fingertips cannot carry the part (the carry check).
    pub const WRAPS: SeatRule = SeatRule {
        fingertips_first: false,
        ..SeatRule::PLANNER
    };
}

/// The power grasps after seating, and how far each moved along its approach (m; 0: kept).
#[derive(Clone, Debug)]
pub struct SeatedGrasps {
    pub power: [Isometry3<f64>; 2],
    /// Deeper (> 0: seated on the palm) or out (< 0: held at the fingertips).
    pub moved: [f64; 2],
    /// The closing at each grasp of `power` (the planning context takes it rather than
    /// closing again).
    pub grips: [Result<Grip, GripFailure>; 2],
}

/// How far (m) the palm of `arm`'s gripper, the flange at `flange` (object frame), may move
/// along its approach before it touches the part: `None` beyond [`SEAT_REACH`].
fn palm_gap(object: &ObjectGeometry, arm: &ArmModel, flange: &Isometry3<f64>) -> Option<f64> {
    let gripper = &arm.gripper;
    let statics = gripper.static_count();
    let direction = flange.rotation * Vector3::z();
    let part_pose = Isometry3::identity();
    let mut nearest: Option<f64> = None;
    gripper.for_each_shape(GripperState::Open, |k, _, primitive| {
        let Primitive::Cuboid { pose, half_extents } = primitive else {
            return;
        };
        if k >= statics {
            return;
        }
        let hit = cast_shapes(
            &(flange * pose),
            &direction,
            &Cuboid::new(half_extents),
            &part_pose,
            &Vector3::zeros(),
            object.trimesh(),
            ShapeCastOptions::with_max_time_of_impact(SEAT_REACH),
        );
        if let Ok(Some(hit)) = hit {
            nearest = Some(nearest.map_or(hit.time_of_impact, |n| n.min(hit.time_of_impact)));
        }
    });
    nearest
}

/// `arm`'s closing with its flange at `flange`, and its kind if it closes on the part.
pub(crate) fn closing(
    object: &ObjectGeometry,
    arm: &ArmModel,
    flange: &Isometry3<f64>,
) -> (Result<Grip, GripFailure>, Option<HoldKind>) {
    let grip = close_on_part(object, &arm.gripper, flange);
    let kind = grip.as_ref().ok().map(|g| hold_kind(&g.kinds));
    (grip, kind)
}

/// The scene's power grasps `power` (object frame) seated on the palm where that stops the
/// closing from pulling the part (see the module documentation).
///
/// `rest`: how far (m) the part as it rests lies from the planned part along each grasp's
/// approach (`lift` times the cosine between the approach at P_init and the world's down).
pub fn seat_power_grasps(
    object: &ObjectGeometry,
    arms: &[ArmModel; 2],
    power: &[Isometry3<f64>; 2],
    rest: [f64; 2],
) -> SeatedGrasps {
    seat_power_grasps_by(object, arms, power, rest, SeatRule::PLANNER)
}

/// [`seat_power_grasps`] by another `rule`: the replay sweep that set [`MIN_SEAT_THICKNESS`]
/// seated every wrapped bar (thickness 0) and no pinch.
pub fn seat_power_grasps_by(
    object: &ObjectGeometry,
    arms: &[ArmModel; 2],
    power: &[Isometry3<f64>; 2],
    rest: [f64; 2],
    rule: SeatRule,
) -> SeatedGrasps {
    type Seat = (Isometry3<f64>, f64, Result<Grip, GripFailure>);
    // Rounded down to 0.01 mm: the time of impact converges to within ~1e-7 m, which a finer
    // tessellation of the same part moves; the plan must not (same part, same plan).
    let round = |m: f64| (m * 1e5).floor() / 1e5;
    let seat = |k: usize| -> Seat {
        let arm = &arms[k];
        let point = arm.gripper.power_point();
        // A grasp that stays is closed here too: the planning context takes the closing
        // rather than closing it after the seating, while the other arm's seating still runs.
        let Some(robotiq) = arm.gripper.robotiq() else {
            return (
                power[k],
                0.0,
                closing(object, arm, &(power[k] * point.inverse())).0,
            );
        };
        // Off its bar's mid-plane: moved across onto it first, whatever follows.
        let grasp = match off_centre(object, &power[k]) {
            Some(across) => power[k] * Translation3::new(across, 0.0, 0.0),
            None => power[k],
        };
        let flange = grasp * point.inverse();
        // The pads at the fingertips, where they pinch in parallel, on the bar's mid-plane:
        // closed once, however many of the rules below ask.
        let at_fingertips = std::cell::OnceCell::new();
        let fingertips = || -> Option<Seat> {
            let across = bar_mid_plane(object, &grasp)
                .filter(|x| x.abs() <= CENTRE_REACH)
                .map_or(0.0, |x| (x * 1e6).round() / 1e6);
            let out = point.translation.z - robotiq.precision_point_z;
            for step in 0..FINGERTIP_TRIES {
                let out = round(out + step as f64 * FINGERTIP_STEP);
                if out >= 0.0 {
                    break;
                }
                let held = grasp * Translation3::new(across, 0.0, out);
                let (grip, kind) = closing(object, arm, &(held * point.inverse()));
                if squeezes(kind) {
                    return Some((held, out, grip));
                }
            }
            None
        };
        let fingertip_hold = || at_fingertips.get_or_init(fingertips).clone();
        let gap = palm_gap(object, arm, &flange);
        // Fingertips first, the palm within reach: a grasp whose pads squeeze the bar at the
        // fingertips is held there whatever its closing at the scene's depth (below), so that
        // closing is not needed where they do.
        if rule.fingertips_first && rule.fingertips && gap.is_some() {
            if let Some(held) = fingertip_hold() {
                return held;
            }
        }
        let (here, kind) = closing(object, arm, &flange);
        if !squeezes(kind) {
            // Caged or on one side.
            let held = rule.fingertips.then(fingertip_hold).flatten();
            return held.unwrap_or((grasp, 0.0, here));
        }
        // A pinch with the palm beyond SEAT_REACH holds the bar at the fingertips already (a
        // grasp held there before: `replan` plans again from a plan file's grasps).
        // Only where the bar lies between the pads at a fingertip depth: a scene's power point
        // farther from the precision point has the pads pinch it nearer the palm, where the
        // fingers curl (`FINGERTIP_TRIES`).
        let at_a_fingertip_depth = || {
            bar_depth(object, &grasp).is_some_and(|c| {
                let beyond = point.translation.z + c - robotiq.precision_point_z;
                let nearest = -FINGERTIP_STEP * (FINGERTIP_TRIES - 1) as f64;
                (nearest - FINGERTIP_DEPTH_TOLERANCE..=FINGERTIP_DEPTH_TOLERANCE).contains(&beyond)
            })
        };
        let held_already = kind == Some(HoldKind::Pinch) && gap.is_none() && at_a_fingertip_depth();
        if rule.fingertips_first && !held_already {
            if let Some(held) = fingertip_hold() {
                return held;
            }
        }
        let Some(gap) = gap else {
            return (grasp, 0.0, here);
        };
        let thick = thickness_at(object, &grasp).is_some_and(|t| t >= rule.min_thickness);
        if gap <= SEAT_TOLERANCE || !thick {
            return (grasp, 0.0, here);
        }
        // A pinch as deep as the closing still squeezes, back from `from`: the pull is what is
        // left between the bar and the palm.
        let back_from = |from: f64| {
            (1..)
                .map(move |j| round(from - j as f64 * PARTIAL_SEAT_STEP))
                .take_while(|&moved| moved >= PARTIAL_SEAT_MIN)
        };
        let tries: Vec<f64> = match kind {
            // Seated against the part as it rests, else against the part as planned. Not part
            // of the way: the wrap pulls its bar onto the palm, so where it cages there it
            // cages (below).
            Some(HoldKind::Encompassing) => {
                let deepest = gap + (rest[k] - SEAT_GAP).clamp(-SEAT_GAP, SEAT_DEPTH);
                vec![round(deepest), round(gap - SEAT_GAP)]
            }
            Some(HoldKind::Pinch) if rule.pinch_fraction > 0.0 => {
                let share = round(rule.pinch_fraction * (gap - SEAT_GAP));
                (share >= PARTIAL_SEAT_MIN)
                    .then_some(share)
                    .into_iter()
                    .chain(back_from(share))
                    .collect()
            }
            _ => return (grasp, 0.0, here),
        };
        for moved in tries {
            let seated = grasp * Translation3::new(0.0, 0.0, moved);
            let (grip, kind) = closing(object, arm, &(seated * point.inverse()));
            if squeezes(kind) {
                return (seated, moved, grip);
            }
        }
        // A wrap that cages its bar on the palm: as a grasp caged where the scene holds it.
        let wrap = kind == Some(HoldKind::Encompassing);
        let held = (wrap && rule.fingertips).then(fingertip_hold).flatten();
        held.unwrap_or((grasp, 0.0, here))
    };
    let [a, b] = crate::closings::each_arm(seat);
    SeatedGrasps {
        power: [a.0, b.0],
        moved: [a.1, b.1],
        grips: [a.2, b.2],
    }
}

/// `scene` with its power grasps seated ([`seat_power_grasps`]) on `part`, and how far each
/// moved; `None` when none moved.
pub fn seated_scene(
    scene: &pregrasp_io::scene::Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
) -> Option<(pregrasp_io::scene::Scene, [f64; 2])> {
    seated_scene_by(scene, part, arms, SeatRule::PLANNER)
}

/// [`seated_scene`] by another `rule` ([`seat_power_grasps_by`]).
pub fn seated_scene_by(
    scene: &pregrasp_io::scene::Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    rule: SeatRule,
) -> Option<(pregrasp_io::scene::Scene, [f64; 2])> {
    with_seated(scene, seating(scene, part, arms, rule)).0
}

/// `scene` with the seated grasps (`None` when none moved, with how far each moved), and the
/// closings the seating computed.
#[allow(clippy::type_complexity)]
fn with_seated(
    scene: &pregrasp_io::scene::Scene,
    seated: SeatedGrasps,
) -> (
    Option<(pregrasp_io::scene::Scene, [f64; 2])>,
    [Result<Grip, GripFailure>; 2],
) {
    // Moved along the approach, or only across onto the bar's mid-plane.
    let moved = (seated.power != scene.grasps.power).then(|| {
        let mut s = scene.clone();
        s.grasps.power = seated.power;
        (s, seated.moved)
    });
    (moved, seated.grips)
}

/// [`seat_power_grasps_by`] of `scene`'s power grasps, the part resting `lift` below P_init.
pub fn seating(
    scene: &pregrasp_io::scene::Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    rule: SeatRule,
) -> SeatedGrasps {
    let rest = rest_offsets(scene);
    seat_power_grasps_by(part, arms, &scene.grasps.power, rest, rule)
}

/// How far (m) the part as it rests lies from the planned part (P_init, `lift` higher) along
/// each of `scene`'s power grasps' approaches: `lift` times the cosine between the approach at
/// P_init and the world's down, to the nanometre (the part measured again, turned about the
/// vertical, gives the same offsets: the pipeline then reuses a known part's seating).
pub fn rest_offsets(scene: &pregrasp_io::scene::Scene) -> [f64; 2] {
    let p_init = scene.initial_object_pose();
    scene.grasps.power.each_ref().map(|g| {
        let approach = (p_init * g).rotation * Vector3::z();
        (scene.planner.lift * (-approach.z).max(0.0) * 1e9).round() / 1e9
    })
}

/// What the planner plans with: `scene` with its power grasps seated by `rule`
/// ([`seated_scene_by`]; `None` when none moved, with how far each moved), and the closings
/// the seating computed at its grasps (for the planning context).
#[allow(clippy::type_complexity)]
pub fn planned_scene(
    scene: &pregrasp_io::scene::Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    rule: SeatRule,
) -> (
    Option<(pregrasp_io::scene::Scene, [f64; 2])>,
    [Result<Grip, GripFailure>; 2],
) {
    with_seated(scene, seating(scene, part, arms, rule))
}

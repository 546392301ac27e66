//! Power grasps slid along their bars towards the centre of mass (issue 48, carrying the part).
//!
//! The two power grasps lift the part together. Its weight's moment about the line through
//! them is held only by the grips around the bars: on a thin bar, or a closing that cages it,
//! the part turns in both hands as it rises (the whole-plan replay: ladder_4, 55.8 mm from the
//! line, rose 42.9 of 50 mm tilted 7.0°; with its grasps moved along their end rungs until the
//! line passed the centre of mass it rose 49.6 mm). Where the carry check finds that the scene's
//! power grasps cannot carry the part, the planner tries them slid along their bars so that the
//! line through them passes the centre of mass, and keeps the slid plan if it carries. It tries
//! them slid too where a plan carries but leaves the weight hanging more than [`HANGING_ARM`]
//! off that line ([`weight_arm`]): the part then tilts in the pads as it rises.
//!
//! The bar runs along each grasp's `y` axis (across the closing direction `x` and the approach
//! `z`). With `pᵢ` the grasp origins, `uᵢ` their `y` axes (object frame), `c` the centre of mass
//! and `t` where `c` projects on the line `p₀p₁`, the shifts `s` are the least-norm solution of
//! `(1 − t) s₀ u₀ + t s₁ u₁ = c − (p₀ + t (p₁ − p₀))` (the point of the line at `t` moved onto
//! `c`), solved again on the moved grasps until the shifts settle (at most 8 times). A share
//! of them ([`SLIDE_SHARES`], largest first) is kept where both slid grasps still hold their
//! bar: the line along the approach still crosses material, and the closing still squeezes
//! where the scene's did (a bar's junction with another, where an open finger would meet it,
//! stops the slide short of it), and both open hands keep the link clearance on their straight
//! approaches ([`OpenFingers::approach_clear`]).
//!
//! Where together they do not slide the whole way — one of them beside the end of its hole,
//! say, with little or nowhere to go — they are also slid one at a time ([`slide_alone`]): the
//! one that stops sooner stays at its largest shift that held (or where it is), and the other
//! slides by the shift [`shift_alone`] that brings the line nearest the centre of mass, the
//! largest of [`ALONE_SHARES`] of it at which it still holds its bar; then the first, likewise,
//! beside it. Both must keep the link clearance on their straight approaches here too: a
//! narrow bar beside a hole leaves a short window
//! (hand_hole_42's left grasp carries the part 28–68 mm down its bar, and 88 mm down its pad
//! meets the hole's end on the approach). The pipeline tries this second way after every
//! hold's grasps slid together (`pipeline::plan`).
//!
//! Frames: grasps and the centre of mass in the object frame; the slide is
//! `grasp · Translation(0, s, 0)`.

use nalgebra::{Isometry3, Matrix3x2, Point3, Translation3, Vector3};
use pregrasp_collision::{ArmModel, ObjectGeometry};
use pregrasp_io::scene::Scene;
use pregrasp_physics::HoldKind;

use crate::closings::each_arm;
use crate::context::PLANNING_MARGIN;
use crate::hold_kind::squeezes;
use crate::open_fingers::OpenFingers;
use crate::seat::{closing, thickness_at};
use pregrasp_model::timeline::CONTACT_ZONE;

/// Shares of the shifts tried, largest first.
pub const SLIDE_SHARES: [f64; 4] = [1.0, 0.75, 0.5, 0.25];
/// Shares of one grasp's shift tried where it slides alone ([`shift_alone`]), largest
/// first: finer than [`SLIDE_SHARES`], as the bar's window is short.
pub const ALONE_SHARES: [f64; 8] = [1.0, 0.875, 0.75, 0.625, 0.5, 0.375, 0.25, 0.125];
/// Longest slide (m) of one grasp: farther, the grasp is on another part of the part.
pub const MAX_SLIDE: f64 = 0.25;
/// Shortest slide (m) worth a second plan.
pub const MIN_SLIDE: f64 = 0.005;

/// The grasps slid by `s`, where the centre of mass `com` projects on the line through them
/// (`t`: 0 at grasp 0, 1 at grasp 1), the residual `r` from that point to `com`, and each
/// grasp's weight `1 − t`, `t` times its `y` axis (how a unit slide of it moves that point);
/// `None` when the grasps coincide.
fn line_residual(
    power: &[Isometry3<f64>; 2],
    com: &Point3<f64>,
    s: [f64; 2],
) -> Option<(Vector3<f64>, [Vector3<f64>; 2])> {
    let slid = slid(power, s);
    let (p0, p1) = (slid[0].translation.vector, slid[1].translation.vector);
    let l = p1 - p0;
    if l.norm_squared() < 1e-12 {
        return None;
    }
    let t = (com.coords - p0).dot(&l) / l.norm_squared();
    let r = com.coords - (p0 + l * t);
    let u = slid.map(|g| g.rotation * Vector3::y());
    Some((r, [u[0] * (1.0 - t), u[1] * t]))
}

/// The shifts (m) of `power[0]` and `power[1]` along their `y` axes that put `com` on the line
/// through them (see the module documentation); `None` when the grasps coincide or the bars
/// run along that line.
pub fn shifts_to_centre(power: &[Isometry3<f64>; 2], com: &Point3<f64>) -> Option<[f64; 2]> {
    let mut s = [0.0; 2];
    for _ in 0..8 {
        let (r, a) = line_residual(power, com, s)?;
        let ds = Matrix3x2::from_columns(&a).pseudo_inverse(1e-9).ok()? * r;
        s = [s[0] + ds[0], s[1] + ds[1]];
        if ds.norm() < 1e-9 {
            break;
        }
    }
    s.iter().all(|x| x.is_finite()).then_some(s)
}

/// The shift (m) of `power[k]` alone along its `y` axis, the other grasp slid by `other`, that
/// brings the line through them nearest the centre of mass `com` (object frame): with `r` and
/// `a_k` (grasp `k`'s column) as in [`shifts_to_centre`], the least-squares step
/// `a_k · r / |a_k|²`, repeated on the moved grasp until it settles (at most 8 times). `None`
/// when the grasps coincide or grasp `k`'s bar runs along the line.
pub fn shift_alone(
    power: &[Isometry3<f64>; 2],
    com: &Point3<f64>,
    k: usize,
    other: f64,
) -> Option<f64> {
    let mut s = [other; 2];
    s[k] = 0.0;
    for _ in 0..8 {
        let (r, a) = line_residual(power, com, s)?;
        if a[k].norm_squared() < 1e-12 {
            return None;
        }
        let ds = a[k].dot(&r) / a[k].norm_squared();
        s[k] += ds;
        if ds.abs() < 1e-9 {
            break;
        }
    }
    s[k].is_finite().then_some(s[k])
}

/// Longest moment arm (m) of the part's weight about the line through the power grasps at
/// which a plan that carries the part is kept as it is. Beyond it the planner also tries the
/// grasps slid towards the centre of mass, and keeps that plan where it carries with a shorter
/// arm. The part tilts in the pads under its weight's moment about that line, and a lift loses
/// the arm times the tilt: the whole-plan replay's carried pinches tilted up to 2.2° at 235 N
/// (panel_15; `crates/physics/data/replay_truth/`), which costs 5 mm — the replay's budget, 45
/// of 50 mm — at an arm of 130 mm. h_frame_25 and h_frame_27 (arms 164 and 160 mm, tilted 1.8
/// and 2.0°) rose 45.0 and 44.4 mm. Of the 234 rows the replay had then, every arm is at
/// most 97 mm (the shelf side) but the H-frames' whose grasps were not slid already: 29, at
/// 125–165 mm.
pub const HANGING_ARM: f64 = 0.10;

/// The moment arm (m) about the line through the power grasps' origins `power` (object frame)
/// of a vertical force at the centre of mass `com` (object frame), the part at `p_obj`:
/// `|((c − p₀) × ẑ) · u|`, `u` the line's unit direction, all in the world frame (`z` up).
/// 0 where the grasps coincide.
pub fn weight_arm(p_obj: &Isometry3<f64>, power: &[Isometry3<f64>; 2], com: &Point3<f64>) -> f64 {
    let [p0, p1] = power.map(|g| p_obj * Point3::from(g.translation.vector));
    let Some(u) = (p1 - p0).try_normalize(1e-12) else {
        return 0.0;
    };
    ((p_obj * com - p0).cross(&Vector3::z())).dot(&u).abs()
}

/// `power` slid by `s` along each grasp's `y` axis.
pub fn slid(power: &[Isometry3<f64>; 2], s: [f64; 2]) -> [Isometry3<f64>; 2] {
    [0, 1].map(|k| slid_one(&power[k], s[k]))
}

/// `grasp` slid by `s` (m) along its `y` axis, its bar.
fn slid_one(grasp: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    grasp * Translation3::new(0.0, s, 0.0)
}

/// How `arm`'s closing ends at the power grasp `grasp` (object frame), if it closes on the part.
fn closing_kind(part: &ObjectGeometry, arm: &ArmModel, grasp: &Isometry3<f64>) -> Option<HoldKind> {
    closing(part, arm, &(grasp * arm.gripper.power_point().inverse())).1
}

/// Whether `arm`'s power grasp still holds its bar slid to `to` (object frame): the approach
/// line crosses material there, and the closing squeezes there where it squeezed before
/// (`squeezed`), else it closes on the part at all.
fn still_holds(part: &ObjectGeometry, arm: &ArmModel, squeezed: bool, to: &Isometry3<f64>) -> bool {
    if thickness_at(part, to).is_none() {
        return false;
    }
    let after = closing_kind(part, arm, to);
    after.is_some() && (!squeezed || squeezes(after))
}

/// [`shifts_to_centre`] of `scene`'s power grasps when they are worth a second plan: the
/// longer at least [`MIN_SLIDE`] and at most [`MAX_SLIDE`].
pub fn shifts_worth_trying(scene: &Scene, com: &Point3<f64>) -> Option<[f64; 2]> {
    let full = shifts_to_centre(&scene.grasps.power, com)?;
    let longest = full[0].abs().max(full[1].abs());
    (MIN_SLIDE..=MAX_SLIDE).contains(&longest).then_some(full)
}

/// The power grasps slid together (see the module documentation): the largest common share
/// of the shifts at which both hold their bars, and where each held alone.
#[derive(Clone, Debug)]
pub struct Together {
    /// The shifts (m) of the largest share at which both hold, if any.
    pub shifts: Option<[f64; 2]>,
    /// The whole shifts (from [`shifts_worth_trying`]).
    full: [f64; 2],
    /// Per share tried above `shifts` (largest first), the shifts where each grasp held (its bar
    /// squeezed, its approach clear).
    held: Vec<[Option<[f64; 2]>; 2]>,
    /// Whether each scene closing squeezed its bar.
    squeezed: [bool; 2],
}

impl Together {
    /// Whether the grasps slid the whole way: the line through them passes the centre of mass.
    pub fn whole(&self) -> bool {
        self.shifts == Some(self.full.map(rounded))
    }

    /// Grasp `k`'s largest shift that held (alone or with the other), or 0.
    fn kept(&self, k: usize) -> f64 {
        self.held
            .iter()
            .find_map(|h| h[k])
            .or(self.shifts)
            .map_or(0.0, |s| s[k])
    }
}

/// The scene's power grasps slid together by the shares of `full` (m, from
/// [`shifts_worth_trying`]), the largest first, until both still hold their bars with their
/// straight approaches clear; `None` when a gripper is not a 2F-85.
pub fn slide_together(
    scene: &Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    full: [f64; 2],
) -> Option<Together> {
    if arms.iter().any(|a| a.gripper.robotiq().is_none()) {
        return None;
    }
    let power = &scene.grasps.power;
    // The scene's closings, once for every share; each arm's beside the other's.
    let squeezed = each_arm(|k| squeezes(closing_kind(part, &arms[k], &power[k])));
    let mut held = Vec::with_capacity(SLIDE_SHARES.len());
    for share in SLIDE_SHARES {
        let s = full.map(|x| rounded(x * share));
        let to = slid(power, s);
        let holds = each_arm(|k| {
            approach_clear(scene, part, &arms[k], &to[k])
                && still_holds(part, &arms[k], squeezed[k], &to[k])
        });
        if holds == [true; 2] {
            return Some(Together {
                shifts: Some(s),
                full,
                held,
                squeezed,
            });
        }
        held.push(holds.map(|h| h.then_some(s)));
    }
    Some(Together {
        shifts: None,
        full,
        held,
        squeezed,
    })
}

/// The power grasps slid one at a time where they do not slide the whole way together (see the
/// module documentation): the shifts (m) that leave the weight the shortest arm about the line
/// through them, both grasps on their bars with their straight approaches clear; `None` where
/// no such slide differs from `together`'s.
pub fn slide_alone(
    scene: &Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    com: &Point3<f64>,
    together: &Together,
) -> Option<[f64; 2]> {
    if together.whole() {
        return None;
    }
    let power = &scene.grasps.power;
    let squeezed = together.squeezed;
    let at = |k: usize, s: f64| slid_one(&power[k], s);
    let clear = |k: usize, s: f64| approach_clear(scene, part, &arms[k], &at(k, s));
    // The approach first: a closing costs more.
    let holds =
        |k: usize, s: f64| clear(k, s) && still_holds(part, &arms[k], squeezed[k], &at(k, s));
    let arm = |s: [f64; 2]| weight_arm(&scene.object.pose, &slid(power, s), com);
    let mut order = [0, 1];
    order.sort_by(|&a, &b| together.kept(b).abs().total_cmp(&together.kept(a).abs()));
    let mut best: Option<(f64, [f64; 2])> = None;
    for k in order {
        // Beside the first grasp's own slide, where it found one; else where the other grasp
        // stays: its largest shift that held (with its approach clear) sliding together.
        let other = best.map_or_else(|| together.kept(1 - k), |(_, s)| s[1 - k]);
        let Some(alone) = shift_alone(power, com, k, other) else {
            continue;
        };
        let alone = alone.clamp(-MAX_SLIDE, MAX_SLIDE);
        let found = ALONE_SHARES.iter().find_map(|share| {
            let mut s = [other; 2];
            s[k] = rounded(alone * share);
            let shorter = best.is_none_or(|(a, _)| arm(s) < a);
            (shorter && s[k].abs() >= MIN_SLIDE && holds(k, s[k])).then_some(s)
        });
        if let Some(s) = found {
            best = Some((arm(s), s));
        }
    }
    best.map(|(_, s)| s)
        .filter(|&s| Some(s) != together.shifts && s.iter().any(|x| x.abs() >= MIN_SLIDE))
}

/// `scene` with its power grasps slid by `s` (m) along their bars.
pub fn slid_scene(scene: &Scene, s: [f64; 2]) -> Scene {
    let mut slid_scene = scene.clone();
    slid_scene.grasps.power = slid(&scene.grasps.power, s);
    slid_scene
}

/// A shift rounded to 0.1 mm: the plan file says how far each grasp moved.
fn rounded(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// Whether `arm`'s open hand keeps the link clearance from the part on the straight approach
/// to the power grasp `grasp` (object frame) outside its contact zone
/// ([`OpenFingers::approach_clear`]).
fn approach_clear(
    scene: &Scene,
    part: &ObjectGeometry,
    arm: &ArmModel,
    grasp: &Isometry3<f64>,
) -> bool {
    let p = &scene.planner;
    let flange = grasp * arm.gripper.power_point().inverse();
    OpenFingers::of(&arm.gripper).approach_clear(
        part.trimesh(),
        &flange,
        [CONTACT_ZONE, p.approach_distance],
        p.link_clearance + PLANNING_MARGIN,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    /// The arm is the horizontal distance of the centre of mass from a level line, whatever
    /// its height; a line rising along itself holds the weight's moment about it, the distance
    /// times the cosine of its slope; none where the centre lies on the line.
    #[test]
    fn the_weight_arm_is_the_moment_of_the_weight_about_the_line() {
        let at = |x: f64, y: f64, z: f64| Isometry3::translation(x, y, z);
        let level = [at(0.0, 0.0, 0.0), at(1.0, 0.0, 0.0)];
        let com = Point3::new(0.5, 0.12, 0.9);
        assert!((weight_arm(&Isometry3::identity(), &level, &com) - 0.12).abs() < 1e-12);
        let power = [at(0.0, 0.0, 0.0), at(1.0, 0.0, 0.5)];
        let cos = 2.0 / 5f64.sqrt();
        assert!((weight_arm(&Isometry3::identity(), &power, &com) - 0.12 * cos).abs() < 1e-12);
        let on = Point3::new(0.3, 0.0, 0.15);
        assert!(weight_arm(&Isometry3::identity(), &power, &on).abs() < 1e-12);
        // Turned 90° about z and moved: the same arm.
        let p_obj = Isometry3::new(
            Vector3::new(0.2, -0.3, 0.0),
            Vector3::z() * std::f64::consts::FRAC_PI_2,
        );
        assert!((weight_arm(&p_obj, &level, &com) - 0.12).abs() < 1e-12);
    }

    /// Two grasps on parallel bars along y, 0.8 m apart along x, the centre of mass 0.05 m
    /// off their line: both slide by about 0.05 m and the line then passes it.
    #[test]
    fn parallel_bars_slide_alike_onto_the_centre() {
        let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        let power = [
            Isometry3::from_parts(Translation3::new(0.02, 0.22, 0.01), down),
            Isometry3::from_parts(Translation3::new(0.82, 0.26, 0.01), down),
        ];
        let com = Point3::new(0.42, 0.19, 0.01);
        let s = shifts_to_centre(&power, &com).unwrap();
        let moved = slid(&power, s);
        let (p0, p1) = (moved[0].translation.vector, moved[1].translation.vector);
        let l = (p1 - p0).normalize();
        let w = com.coords - p0;
        assert!((w - l * w.dot(&l)).norm() < 1e-7, "{s:?}");
        // Least norm: about equal shifts (the centre of mass lies half way along the line),
        // 0.05 m towards it (the grasps' y axes point along the object's −y); the line's slope
        // moves where the centre of mass projects on it.
        assert!(s.iter().all(|x| (x - 0.05).abs() < 1e-3), "{s:?}");
    }

    /// One grasp alone: with the other held (its shift `other`), the line through the grasps
    /// passes the centre of mass halfway between them when `½ s₀ + ½ s₁` is the offset, so
    /// `s₀ = 2 · 0.05 − s₁`; the moved grasp's shift alone, whichever it is.
    #[test]
    fn one_grasp_alone_moves_the_line_by_its_share() {
        let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
        let power = [
            Isometry3::from_parts(Translation3::new(0.0, 0.25, 0.01), down),
            Isometry3::from_parts(Translation3::new(0.8, 0.25, 0.01), down),
        ];
        let com = Point3::new(0.4, 0.20, 0.01);
        for (k, other) in [(0, 0.0), (0, 0.02), (1, 0.0), (1, -0.03)] {
            let s = shift_alone(&power, &com, k, other).unwrap();
            assert!(
                (s - (0.1 - other)).abs() < 1e-9,
                "grasp {k} beside {other}: {s}"
            );
            let mut both = [other; 2];
            both[k] = s;
            let arm = weight_arm(&Isometry3::identity(), &slid(&power, both), &com);
            assert!(arm < 1e-9, "{arm}");
        }
    }

    /// Bars along the line through the grasps cannot move it: no shifts.
    #[test]
    fn bars_along_the_line_give_nothing() {
        let power = [
            Isometry3::translation(0.0, 0.0, 0.0),
            Isometry3::translation(0.0, 0.5, 0.0),
        ];
        let s = shifts_to_centre(&power, &Point3::new(0.1, 0.2, 0.0)).unwrap();
        assert!(s.iter().all(|x| x.abs() < 1e-12), "{s:?}");
    }
}

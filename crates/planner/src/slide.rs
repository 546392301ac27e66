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
//! stops the slide short of it).
//!
//! Frames: grasps and the centre of mass in the object frame; the slide is
//! `grasp · Translation(0, s, 0)`.

use nalgebra::{Isometry3, Matrix3x2, Point3, Translation3, Vector3};
use pregrasp_collision::{ArmModel, ObjectGeometry};
use pregrasp_io::scene::Scene;
use pregrasp_physics::HoldKind;

use crate::closings::each_arm;
use crate::hold_kind::squeezes;
use crate::seat::{closing, thickness_at};

/// Shares of the shifts tried, largest first.
pub const SLIDE_SHARES: [f64; 4] = [1.0, 0.75, 0.5, 0.25];
/// Longest slide (m) of one grasp: farther, the grasp is on another part of the part.
pub const MAX_SLIDE: f64 = 0.25;
/// Shortest slide (m) worth a second plan.
pub const MIN_SLIDE: f64 = 0.005;

/// The shifts (m) of `power[0]` and `power[1]` along their `y` axes that put `com` on the line
/// through them (see the module documentation); `None` when the grasps coincide or the bars
/// run along that line.
pub fn shifts_to_centre(power: &[Isometry3<f64>; 2], com: &Point3<f64>) -> Option<[f64; 2]> {
    let mut s = [0.0; 2];
    for _ in 0..8 {
        let slid = slid(power, s);
        let (p0, p1) = (slid[0].translation.vector, slid[1].translation.vector);
        let l = p1 - p0;
        if l.norm_squared() < 1e-12 {
            return None;
        }
        let t = (com.coords - p0).dot(&l) / l.norm_squared();
        let r = com.coords - (p0 + l * t);
        let u = slid.map(|g| g.rotation * Vector3::y());
        let a = Matrix3x2::from_columns(&[u[0] * (1.0 - t), u[1] * t]);
        let ds = a.pseudo_inverse(1e-9).ok()? * r;
        s = [s[0] + ds[0], s[1] + ds[1]];
        if ds.norm() < 1e-9 {
            break;
        }
    }
    s.iter().all(|x| x.is_finite()).then_some(s)
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
    [0, 1].map(|k| power[k] * Translation3::new(0.0, s[k], 0.0))
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

/// `scene` with its power grasps slid by the largest share of `full` (m, from
/// [`shifts_worth_trying`]) at which both still hold their bars, and the shifts made; `None`
/// when a gripper is not a 2F-85 or no share keeps both grasps on their bars.
pub fn slid_scene(
    scene: &Scene,
    part: &ObjectGeometry,
    arms: &[ArmModel; 2],
    full: [f64; 2],
) -> Option<(Scene, [f64; 2])> {
    if arms.iter().any(|a| a.gripper.robotiq().is_none()) {
        return None;
    }
    let power = &scene.grasps.power;
    // The scene's closings, once for every share; each arm's beside the other's.
    let squeezed = each_arm(|k| squeezes(closing_kind(part, &arms[k], &power[k])));
    SLIDE_SHARES.iter().find_map(|share| {
        // Rounded to 0.1 mm: the plan file says how far each grasp moved.
        let s = full.map(|x| (x * share * 1e4).round() / 1e4);
        let to = slid(power, s);
        let holds = each_arm(|k| still_holds(part, &arms[k], squeezed[k], &to[k])) == [true; 2];
        holds.then(|| {
            let mut slid_scene = scene.clone();
            slid_scene.grasps.power = to;
            (slid_scene, s)
        })
    })
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

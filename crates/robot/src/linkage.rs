//! The Robotiq 2F-85 finger as the real gripper is built: an underactuated linkage of two
//! degrees of freedom, not a one-parameter table.
//!
//! Each finger has four links, named as in the MuJoCo Menagerie model (`robotiq_2f85/2f85.xml`,
//! BSD-3; our `robotiq_2f85.json` names in brackets): the **driver** [outer knuckle], turned
//! by the actuator about pivot `A` on the housing; the **coupler** [outer finger], hinged to
//! the driver; the **spring link** [inner knuckle], turning freely about pivot `S` on the
//! housing, pushed closed by a spring; and the **follower** [finger tip], which carries the
//! pad, hinged to the spring link at `J` and pinned to the coupler at `P` (Menagerie's
//! `connect` equality). Driver, coupler, follower and spring link close a five-bar loop: given
//! the driver angle `q_d` and the spring link's angle `q_s`, the coupler (`q_c`) and the
//! follower (`q_f`) follow ([`FingerLinkage::assemble`]).
//!
//! How the real finger closes: in free air the spring holds the coupler against its stop
//! (`q_c = 0`, rigid with the driver), the loop is a near-parallelogram four-bar and the pad
//! stays parallel to itself ([`FingerLinkage::parallel`]: the 1-DoF closing our table
//! describes). When the spring link meets something, it stops (`q_s` fixed) while the driver
//! turns on, and the follower curls inward about `J` ([`FingerLinkage::assemble`] with the
//! spring link's angle held).
//!
//! Frames: everything is in the plane of the `+x` finger, in gripper-frame coordinates
//! `(x, z)` of G (flange frame: z the approach direction, x the closing axis); the `−x` finger
//! is its mirror image. Joint angles are Menagerie's: positive closes (a rotation about G's
//! `−y`, i.e. counter-clockwise in the `(x, z)` plane as drawn with x right and z up). Lengths
//! in metres, angles in radians.

use nalgebra::{
    Isometry3, Point2, Quaternion, Rotation2, Translation3, UnitQuaternion, Vector2, Vector3,
};

use crate::angle::{rotation2, sin_cos};

/// The links of a finger (the pad rigid on the follower), in [`FingerConfig::link_frames`]
/// order.
pub const FINGER_LINKS: [&str; 5] = ["driver", "coupler", "spring_link", "follower", "pad"];

/// Joint ranges of the Menagerie model (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkageLimits {
    pub driver: (f64, f64),
    pub coupler: (f64, f64),
    pub spring_link: (f64, f64),
    pub follower: (f64, f64),
}

/// The planar geometry of one finger (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerLinkage {
    /// Driver pivot in G `(x, z)`.
    pub a: Point2<f64>,
    /// Spring link pivot in G `(x, z)`.
    pub s: Point2<f64>,
    /// Coupler hinge in the driver frame.
    pub driver_to_coupler: Vector2<f64>,
    /// The follower's pin `P` in the coupler frame (where the loop closes).
    pub coupler_to_pin: Vector2<f64>,
    /// The follower hinge `J` in the spring link frame.
    pub spring_to_hinge: Vector2<f64>,
    /// The follower's frame origin (= the pin `P`) from its hinge `J`, in the follower frame.
    pub hinge_to_pin: Vector2<f64>,
    /// The pad's frame origin in the follower frame (the pad does not move on the follower).
    pub follower_to_pad: Vector2<f64>,
    /// Centre of the pad's contact face, in the pad frame.
    pub pad_center: Vector2<f64>,
    /// Far end of the pad's contact face on its centre line, in the pad frame.
    pub pad_tip: Vector2<f64>,
    pub limits: LinkageLimits,
    /// What [`FingerLinkage::assemble`] and [`FingerLinkage::parallel`] derive from the fields
    /// above at every call otherwise (lengths, fixed angles, the loop's branches), computed by
    /// the constructor: a linkage of other dimensions needs a constructor of its own, not the
    /// fields above changed in place.
    derived: Derived,
}

/// The constants of a [`FingerLinkage`] its solvers need: computed once from its geometry
/// ([`Derived::of`]), the same numbers the solvers would compute at every call.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Derived {
    /// `|coupler_to_pin|`, `|hinge_to_pin|`, `|spring_to_hinge|`.
    coupler_len: f64,
    follower_len: f64,
    spring_len: f64,
    /// Direction angles of `coupler_to_pin`, `hinge_to_pin`, `spring_to_hinge`.
    coupler_angle: f64,
    follower_angle: f64,
    spring_angle: f64,
    /// The assembled branch of the loop for `assemble` (side of `C → J` the pin lies on) and
    /// for `parallel` (side of `S → P` the hinge `J` lies on), both at `qpos0`.
    pin_side: f64,
    hinge_side: f64,
}

impl Derived {
    fn of(l: &FingerLinkage) -> Derived {
        let c = l.a + l.driver_to_coupler;
        let j = l.s + l.spring_to_hinge;
        let p0 = l.a + l.driver_to_coupler + l.coupler_to_pin;
        Derived {
            coupler_len: l.coupler_to_pin.norm(),
            follower_len: l.hinge_to_pin.norm(),
            spring_len: l.spring_to_hinge.norm(),
            coupler_angle: angle_of(&l.coupler_to_pin),
            follower_angle: angle_of(&l.hinge_to_pin),
            spring_angle: angle_of(&l.spring_to_hinge),
            pin_side: side_of(c, j, l.s + l.spring_to_hinge + l.hinge_to_pin),
            hinge_side: side_of(l.s, p0, l.s + l.spring_to_hinge),
        }
    }
}

/// One pose of a finger: its four joint angles (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerConfig {
    pub driver: f64,
    pub coupler: f64,
    pub spring_link: f64,
    pub follower: f64,
}

/// In-plane pose of a link: origin and angle in G's `(x, z)` plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarPose {
    pub origin: Point2<f64>,
    pub angle: f64,
}

impl PlanarPose {
    fn apply(&self, v: &Vector2<f64>) -> Point2<f64> {
        self.origin + rotation2(self.angle) * v
    }

    /// The link frame in G (3-D) for the finger on side `side` (`+1.0`: `+x`, `−1.0`: its
    /// mirror image). The link's own frame has Menagerie's axes mapped into G: its in-plane
    /// `(y, z)` are G's `(x, z)` for the `+x` finger.
    pub fn to_isometry(&self, side: f64) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(side * self.origin.x, 0.0, self.origin.y),
            y_turn(-side * self.angle),
        )
    }
}

/// The turn by `angle` about G's `y` axis: nalgebra's `UnitQuaternion::from_axis_angle` on
/// [`sin_cos`].
fn y_turn(angle: f64) -> UnitQuaternion<f64> {
    let (s, c) = sin_cos(angle / 2.0);
    UnitQuaternion::new_unchecked(Quaternion::from_parts(c, Vector3::y() * s))
}

/// The direction angle of `v` in the `(x, z)` plane, by libm's `atan2` (the same bits on
/// every platform, as [`sin_cos`]; [`crate::atan2`] trades a few ulp for the IK's speed).
fn angle_of(v: &Vector2<f64>) -> f64 {
    libm::atan2(v.y, v.x)
}

/// The intersection of the circle about `c1` of radius `r1` with the circle about `c2` of
/// radius `r2` that lies on side `sign` of the line `c1 → c2` (`+1`: left, counter-clockwise);
/// `None` when they do not meet.
fn circles(c1: Point2<f64>, r1: f64, c2: Point2<f64>, r2: f64, sign: f64) -> Option<Point2<f64>> {
    let d = c2 - c1;
    let dist = d.norm();
    if dist < 1e-12 || dist > r1 + r2 || dist < (r1 - r2).abs() {
        return None;
    }
    let along = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
    let h = (r1 * r1 - along * along).max(0.0).sqrt();
    let u = d / dist;
    let n = Vector2::new(-u.y, u.x);
    Some(c1 + u * along + n * (sign * h))
}

/// Which side of the line `from → to` the point `p` lies on (`±1`).
fn side_of(from: Point2<f64>, to: Point2<f64>, p: Point2<f64>) -> f64 {
    let (a, b) = (to - from, p - from);
    (a.x * b.y - a.y * b.x).signum()
}

impl FingerLinkage {
    /// The 2F-85 of the MuJoCo Menagerie (`robotiq_2f85/2f85.xml`, commit 75df466): `base`
    /// at 0.0108 m on the flange axis (`base_mount` 0.007 + 0.0038), turned −90° about z so the
    /// `right_*` finger lies at `+x`; the follower's joint sits at `(−0.018, 0.0065)` in its
    /// body frame, so its hinge on the spring link is `(0.055, 0.0375) + (−0.018, 0.0065)`; the
    /// pin `P` is the follower's origin, which at `qpos0` (all angles 0) lies at
    /// `(0.0060989, 0.047596)` in the coupler frame. Pad contact face: the inner face of the
    /// two pad boxes, `y = −0.0066` in the pad frame, 37.5 mm long.
    pub fn robotiq_2f85() -> FingerLinkage {
        let base_z = 0.007 + 0.0038;
        let a = Point2::new(0.0306011, 0.054904 + base_z);
        let s = Point2::new(0.0132, 0.0609 + base_z);
        let driver_to_coupler = Vector2::new(0.0315, -0.0041);
        let spring_body = Vector2::new(0.055, 0.0375);
        let follower_joint = Vector2::new(-0.018, 0.0065);
        // At qpos0 every frame is parallel to G: the pin in the coupler frame is the follower's
        // origin minus the coupler's origin.
        let pin = s + spring_body;
        let coupler_origin = a + driver_to_coupler;
        let mut linkage = FingerLinkage {
            a,
            s,
            driver_to_coupler,
            coupler_to_pin: pin - coupler_origin,
            spring_to_hinge: spring_body + follower_joint,
            hinge_to_pin: -follower_joint,
            follower_to_pad: Vector2::new(-0.0189, 0.01352),
            pad_center: Vector2::new(-0.0066, 0.01875),
            pad_tip: Vector2::new(-0.0066, 0.0375),
            limits: LinkageLimits {
                driver: (0.0, 0.8),
                coupler: (-1.57, 0.0),
                spring_link: (-0.29670597283, 0.8),
                follower: (-0.872664, 0.872664),
            },
            derived: Derived {
                coupler_len: 0.0,
                follower_len: 0.0,
                spring_len: 0.0,
                coupler_angle: 0.0,
                follower_angle: 0.0,
                spring_angle: 0.0,
                pin_side: 0.0,
                hinge_side: 0.0,
            },
        };
        linkage.derived = Derived::of(&linkage);
        linkage
    }

    /// The whole finger for driver angle `driver` and spring-link angle `spring_link`: the pin
    /// where the coupler's circle about its hinge `C` meets the follower's circle about `J`,
    /// on the branch the gripper is assembled in. `None` if the loop cannot close there.
    pub fn assemble(&self, driver: f64, spring_link: f64) -> Option<FingerConfig> {
        let c = self.a + rotation2(driver) * self.driver_to_coupler;
        let j = self.s + rotation2(spring_link) * self.spring_to_hinge;
        let d = &self.derived;
        let p = circles(c, d.coupler_len, j, d.follower_len, d.pin_side)?;
        let coupler_abs = angle_of(&(p - c)) - d.coupler_angle;
        let follower_abs = angle_of(&(p - j)) - d.follower_angle;
        Some(FingerConfig {
            driver,
            coupler: wrap(coupler_abs - driver),
            spring_link,
            follower: wrap(follower_abs - spring_link),
        })
    }

    /// The finger in free air at driver angle `driver`: the coupler on its stop (`q_c = 0`),
    /// the spring link where the loop then closes (the parallel mode of the real gripper).
    pub fn parallel(&self, driver: f64) -> Option<FingerConfig> {
        // The pin is fixed to the driver; the hinge J lies on the spring link's circle about S
        // at the follower's length from the pin.
        let p = self.a + rotation2(driver) * (self.driver_to_coupler + self.coupler_to_pin);
        // J lies on the side of the line S → P it lies on at qpos0 (the assembled branch).
        let d = &self.derived;
        let j = circles(self.s, d.spring_len, p, d.follower_len, d.hinge_side)?;
        let spring_link = wrap(angle_of(&(j - self.s)) - d.spring_angle);
        let follower_abs = angle_of(&(p - j)) - d.follower_angle;
        Some(FingerConfig {
            driver,
            coupler: 0.0,
            spring_link,
            follower: wrap(follower_abs - spring_link),
        })
    }

    /// Whether every joint of `config` is within its range (with `slack` rad).
    pub fn within_limits(&self, config: &FingerConfig, slack: f64) -> bool {
        let inside = |x: f64, (lo, hi): (f64, f64)| x >= lo - slack && x <= hi + slack;
        inside(config.driver, self.limits.driver)
            && inside(config.coupler, self.limits.coupler)
            && inside(config.spring_link, self.limits.spring_link)
            && inside(config.follower, self.limits.follower)
    }
}

/// The pad's frame on `follower`, whose rotation is `turn`.
fn pad_of(follower: &PlanarPose, turn: &Rotation2<f64>, linkage: &FingerLinkage) -> PlanarPose {
    PlanarPose {
        origin: follower.origin + turn * linkage.follower_to_pad,
        angle: follower.angle,
    }
}

fn wrap(x: f64) -> f64 {
    crate::wrap_angle(x)
}

impl FingerConfig {
    /// The in-plane pose of each link ([`FINGER_LINKS`] order) for `linkage`.
    pub fn link_frames(&self, linkage: &FingerLinkage) -> [PlanarPose; 5] {
        let [driver, coupler, spring] = self.proximal_frames(linkage);
        let (follower, pad) = self.distal_frames(linkage);
        [driver, coupler, spring, follower, pad]
    }

    /// The driver's, the coupler's and the spring link's frames (the first three of
    /// [`Self::link_frames`]).
    pub fn proximal_frames(&self, linkage: &FingerLinkage) -> [PlanarPose; 3] {
        let driver = PlanarPose {
            origin: linkage.a,
            angle: self.driver,
        };
        let coupler = PlanarPose {
            origin: driver.apply(&linkage.driver_to_coupler),
            angle: self.driver + self.coupler,
        };
        let spring = PlanarPose {
            origin: linkage.s,
            angle: self.spring_link,
        };
        [driver, coupler, spring]
    }

    /// The follower's and the pad's frames (the last two of [`Self::link_frames`]).
    pub fn distal_frames(&self, linkage: &FingerLinkage) -> (PlanarPose, PlanarPose) {
        let (follower, turn) = self.distal_with_turn(linkage);
        (follower, pad_of(&follower, &turn, linkage))
    }

    /// The follower's frame and its rotation (the follower and the pad turn alike).
    fn distal_with_turn(&self, linkage: &FingerLinkage) -> (PlanarPose, Rotation2<f64>) {
        let hinge = linkage.s + rotation2(self.spring_link) * linkage.spring_to_hinge;
        let follower_angle = self.spring_link + self.follower;
        let turn = rotation2(follower_angle);
        let follower = PlanarPose {
            origin: hinge + turn * linkage.hinge_to_pin,
            angle: follower_angle,
        };
        (follower, turn)
    }

    /// The pad's frame and its rotation.
    fn pad_frame(&self, linkage: &FingerLinkage) -> (PlanarPose, Rotation2<f64>) {
        let (follower, turn) = self.distal_with_turn(linkage);
        (pad_of(&follower, &turn, linkage), turn)
    }

    /// Centre of the pad's contact face in G `(x, z)`.
    pub fn pad_center(&self, linkage: &FingerLinkage) -> Point2<f64> {
        self.distal_frames(linkage).1.apply(&linkage.pad_center)
    }

    /// Far end of the pad's contact face in G `(x, z)`.
    pub fn pad_tip(&self, linkage: &FingerLinkage) -> Point2<f64> {
        self.distal_frames(linkage).1.apply(&linkage.pad_tip)
    }

    /// Centre and far end of the pad's contact face in G `(x, z)`: the pad frame's rotation
    /// computed once for both (the same numbers as placing each by the pad frame).
    pub fn pad_face(&self, linkage: &FingerLinkage) -> (Point2<f64>, Point2<f64>) {
        let (pad, turn) = self.pad_frame(linkage);
        (
            pad.origin + turn * linkage.pad_center,
            pad.origin + turn * linkage.pad_tip,
        )
    }

    /// How far the pad is turned from parallel (rad; positive: its tip curled towards the
    /// other finger).
    pub fn distal_pitch(&self) -> f64 {
        -(self.spring_link + self.follower)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_open_finger_is_where_the_menagerie_puts_it() {
        let l = FingerLinkage::robotiq_2f85();
        let open = l.assemble(0.0, 0.0).unwrap();
        assert!(
            open.coupler.abs() < 1e-12 && open.follower.abs() < 1e-12,
            "{open:?}"
        );
        let c = open.pad_center(&l);
        assert!((c - Point2::new(0.0427, 0.14147)).norm() < 1e-6, "{c}");
        let t = open.pad_tip(&l);
        assert!((t - Point2::new(0.0427, 0.16022)).norm() < 1e-6, "{t}");
        let par = l.parallel(0.0).unwrap();
        assert!(
            par.spring_link.abs() < 1e-9 && par.follower.abs() < 1e-9,
            "{par:?}"
        );
    }

    #[test]
    fn the_loop_closes_in_every_assembled_pose() {
        let l = FingerLinkage::robotiq_2f85();
        for i in 0..=40 {
            let qd = 0.8 * i as f64 / 40.0;
            for qs in [-0.2, 0.0, 0.3, 0.6] {
                let Some(cfg) = l.assemble(qd, qs) else {
                    continue;
                };
                let f = cfg.link_frames(&l);
                let pin_coupler = f[1].apply(&l.coupler_to_pin);
                assert!((pin_coupler - f[3].origin).norm() < 1e-12);
                let hinge = f[2].apply(&l.spring_to_hinge);
                assert!(((f[3].origin - hinge).norm() - l.hinge_to_pin.norm()).abs() < 1e-12);
            }
            let par = l.parallel(qd).unwrap();
            assert!(par.coupler == 0.0);
            let again = l.assemble(qd, par.spring_link).unwrap();
            assert!(again.coupler.abs() < 1e-9, "{qd}: {again:?}");
        }
    }
}

//! How a gripper closes on the part at a grasp: the 2F-85's adaptive closing
//! ([`pregrasp_robot::close_fingers`]) against the part's real mesh.
//!
//! With the flange at a grasp, both fingers close from fully open as the linkage closes: in
//! the parallel mode until a link touches the part; a pad touching first makes a pinch, a
//! proximal link (the inner knuckle) touching first lets the finger tip curl around the bar
//! (an encompassing grasp, or the bar caged). The result ([`Grip`]) is where the fingers
//! stopped and every pose they passed through on the way (the finger links' extreme points,
//! per link and plane `y = const`, in the gripper frame G), which is what the support must
//! clear: the closing is a property of the grasp and the part, the support a property of where
//! the part is, so one closing serves every pose of the part ([`Grip::lowest`]).

use std::sync::{Arc, OnceLock};

use nalgebra::{Isometry3, Point3};
use pregrasp_robot::{
    close_fingers_traced, linkage, ClosingKind, FingerConfig, FingerPair, FingerSolids, Gripper,
    GripperState, COUPLER, DRIVER, FINGER_LINKS, FOLLOWER, LINKS_PER_FINGER, PAD, SPRING_LINK,
};

use crate::closing::{FingerShapes, PartClosing};
use crate::object::ObjectGeometry;

mod jaws;
mod patches;

pub use patches::{pad_patches, PadPatch, PATCH_DEPTH, PATCH_STEP};

/// Largest joint turn (rad) between two poses of a closing kept for the support test. Between
/// two kept poses a finger point moves on arcs of at most two stacked rotations (a link and
/// the one carrying it) with levers under 0.15 m, so it strays at most
/// `2 · 0.15 · 0.05² / 8` ≈ 94 µm (the sagittas) from the segment joining its two kept
/// positions; [`SWEEP_SAG`] covers it, so the support test stays on the safe side.
const SWEEP_STEP: f64 = 0.05;
/// Bound (m) on how far a finger point may lie below the kept poses' hull between them.
const SWEEP_SAG: f64 = 1e-4;
/// How far (m) [`Grip::clears`] lowers its sphere and circle bounds so their round-off cannot
/// skip a point below the line.
const BOUND_SLACK: f64 = 1e-9;

/// The largest joint turn between two poses of both fingers.
fn turned(a: &[FingerConfig; 2], b: &[FingerConfig; 2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            (a.driver - b.driver)
                .abs()
                .max((a.coupler - b.coupler).abs())
                .max((a.spring_link - b.spring_link).abs())
                .max((a.follower - b.follower).abs())
        })
        .fold(0.0, f64::max)
}

/// Why a gripper cannot close on the part at a grasp.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum GripFailure {
    /// The fully open fingers already touch the part: it is wider than the stroke there,
    /// or material lies where an open finger must go.
    #[error("the open fingers already touch the part (wider than the stroke, or material where a finger goes)")]
    OpenTouches,
    /// The fingers close fully without touching the part.
    #[error("the pads close on nothing (no part between the fingers)")]
    ClosesOnNothing,
    /// A link that cannot hold the part (the outer knuckle or outer finger) meets it before
    /// the pads or inner knuckles do: the gripper would jam on it.
    #[error("the {link} meets the part before the pads do")]
    Jams { link: &'static str },
}

/// The closing of a gripper at one grasp (see the module documentation).
#[derive(Clone, Debug)]
pub struct Grip {
    /// Where the fingers stopped.
    state: GripperState,
    /// The width held: the pad (jaw) faces' distance (m).
    width: f64,
    /// How each finger's closing ended, `[+x, −x]`.
    pub kinds: [ClosingKind; 2],
    /// The finger links in every pose of the closing, by planes `y = const` (in G); for a
    /// jaw gripper, its jaws open and closed (they translate: their hull holds every pose).
    swept: Arc<Vec<Level>>,
    /// The levels' points `(x, z)`, pose after pose ([`SweptPoints`]).
    points: Arc<SweptPoints>,
    /// Per finger link (both fingers), its levels in `swept` and a sphere holding them.
    links: Arc<Vec<LinkSweep>>,
}

impl PartialEq for Grip {
    fn eq(&self, other: &Grip) -> bool {
        self.state == other.state && self.kinds == other.kinds
    }
}

impl Grip {
    /// The gripper state holding the part.
    pub fn state(&self) -> GripperState {
        self.state
    }

    /// The 2F-85's finger joints where they stopped (a jaw grip: the open pair).
    pub fn fingers(&self) -> FingerPair {
        self.state.fingers()
    }

    /// The width held: distance between the pad faces' centres (m).
    pub fn width(&self) -> f64 {
        self.width
    }

    /// The grasp's kind: a pinch unless a finger wrapped the part.
    pub fn kind(&self) -> ClosingKind {
        self.kinds
            .into_iter()
            .find(|k| matches!(k, ClosingKind::Encompassing | ClosingKind::Caged))
            .unwrap_or(ClosingKind::Pinch)
    }

    /// Lowest world `z` the fingers reach while closing, the flange at `flange_world`.
    pub fn lowest(&self, flange_world: &Isometry3<f64>) -> f64 {
        let up = Heights::of(flange_world);
        let points = &*self.points;
        let scan = |l: &Level, mut best: f64| {
            let base = up.base(l);
            for pose in points.of(l) {
                for p in pose {
                    best = best.min(up.point(base, p));
                }
            }
            best
        };
        // A first answer from the level whose circle reaches lowest, then only the links (a
        // sphere each) and their levels (a circle each) that can reach below it are read.
        let Some(seed) = self
            .swept
            .iter()
            .min_by(|a, b| up.level_bound(a).total_cmp(&up.level_bound(b)))
        else {
            return f64::INFINITY;
        };
        let mut best = scan(seed, f64::INFINITY);
        for g in self.links.iter() {
            if up.link_bound(g) >= best {
                continue;
            }
            for l in &self.swept[g.levels.clone()] {
                if up.level_bound(l) < best {
                    best = scan(l, best);
                }
            }
        }
        best + flange_world.translation.vector.z - SWEEP_SAG
    }

    /// Whether the fingers stay above world height `height` all through the closing, the
    /// flange at `flange_world`: `lowest(flange_world) > height`, the same answer, found
    /// without the minimum (a link or level whose bound clears is not read; the first point
    /// below ends it).
    pub fn clears(&self, flange_world: &Isometry3<f64>, height: f64) -> bool {
        let up = Heights::of(flange_world);
        let z = flange_world.translation.vector.z;
        // As `lowest` rounds: the lowest value `v` passes iff `v + z − SWEEP_SAG > height`, and
        // that is monotone in `v`. Bounds are pushed down by BOUND_SLACK against their own
        // round-off.
        let above = |v: f64| v + z - SWEEP_SAG > height;
        let points = &*self.points;
        for g in self.links.iter() {
            if above(up.link_bound(g) - BOUND_SLACK) {
                continue;
            }
            for l in &self.swept[g.levels.clone()] {
                if above(up.level_bound(l) - BOUND_SLACK) {
                    continue;
                }
                let base = up.base(l);
                if points.of(l).flatten().any(|p| !above(up.point(base, p))) {
                    return false;
                }
            }
        }
        true
    }

    /// The points (in G) that bound the closing fingers: every pose's finger links lie in
    /// their convex hull.
    pub fn swept_points(&self) -> Vec<Point3<f64>> {
        self.swept
            .iter()
            .flat_map(|l| {
                self.points
                    .of(l)
                    .flatten()
                    .map(|p| Point3::new(p[0], l.y, p[1]))
            })
            .collect()
    }
}

/// The finger links' convex pieces for the closing world (the `+x` finger's).
fn finger_shapes() -> &'static FingerShapes {
    static SHAPES: OnceLock<FingerShapes> = OnceLock::new();
    SHAPES.get_or_init(|| {
        let solids = FingerSolids::robotiq_2f85();
        let right = &solids.links[LINKS_PER_FINGER..];
        let links: Vec<Vec<Vec<Point3<f64>>>> =
            right.iter().map(|s| s.pieces.pieces.clone()).collect();
        FingerShapes::new(&links).expect("the built-in finger pieces are solids")
    })
}

/// The points of a link's pieces that can be extreme in some direction (its hull's vertices,
/// link frame of the `+x` finger), grouped by their `y`: the linkage turns links about `y`, so
/// each group stays in its own plane `y = const` as the finger closes.
type Levels = Vec<(f64, Vec<[f64; 2]>)>;

/// [`Levels`] of each link of the `+x` finger.
fn link_levels() -> &'static [Levels] {
    static LEVELS: OnceLock<Vec<Levels>> = OnceLock::new();
    LEVELS.get_or_init(|| {
        let shapes = finger_shapes();
        (0..LINKS_PER_FINGER)
            .map(|link| {
                let mut levels: Levels = Vec::new();
                for p in shapes.hull_points(link) {
                    match levels.iter_mut().find(|(y, _)| *y == p.y) {
                        Some((_, pts)) => pts.push([p.x, p.z]),
                        None => levels.push((p.y, vec![[p.x, p.z]])),
                    }
                }
                levels
            })
            .collect()
    })
}

/// The points of each link's [`Levels`] one after the other: what [`Sweep::add`] places, a link
/// at a time.
type FlatLevels = Vec<[f64; 2]>;

/// The lesser of `a` and `b` (`a` where they are equal), for numbers (no NaN): `f64::min`
/// without its NaN handling, which costs as much as the rest of [`Sweep::add`].
fn least(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// The greater of `a` and `b` (`a` where they are equal), for numbers (no NaN).
fn most(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// [`FlatLevels`] of each link of the `+x` finger.
fn link_points() -> &'static [FlatLevels] {
    static POINTS: OnceLock<Vec<FlatLevels>> = OnceLock::new();
    POINTS.get_or_init(|| {
        link_levels()
            .iter()
            .map(|levels| {
                levels
                    .iter()
                    .flat_map(|(_, pts)| pts.iter().copied())
                    .collect()
            })
            .collect()
    })
}

/// The finger points swept while closing: per kept pose, both fingers' points side by side,
/// link and `y` level after level (`(x, z)` in G), in the order [`Sweep::add`] visits them.
struct Sweep {
    poses: Vec<[f64; 2]>,
    /// [`Sweep::per_pose`].
    per_pose: usize,
    /// Per coordinate of a pose (`x`, `z` of each point in turn), the least and the greatest
    /// of its values so far.
    lo: Vec<f64>,
    hi: Vec<f64>,
}

/// Poses a closing usually keeps (capacity reserved up front).
const SWEEP_POSES: usize = 40;

impl Sweep {
    /// Points per pose of both fingers.
    fn per_pose() -> usize {
        2 * link_levels()
            .iter()
            .flatten()
            .map(|(_, pts)| pts.len())
            .sum::<usize>()
    }

    fn new() -> Sweep {
        let per_pose = Sweep::per_pose();
        Sweep {
            poses: Vec::with_capacity(SWEEP_POSES * per_pose),
            per_pose,
            lo: vec![f64::INFINITY; 2 * per_pose],
            hi: vec![f64::NEG_INFINITY; 2 * per_pose],
        }
    }

    /// The `y` and the point count of each level, in pose order (the `−x` finger's mirror
    /// keeps `y`).
    fn levels() -> impl Iterator<Item = (f64, usize)> {
        [1.0, -1.0].into_iter().flat_map(|_| {
            link_levels()
                .iter()
                .flat_map(|levels| levels.iter().map(|(y, pts)| (*y, pts.len())))
        })
    }

    /// Adds both fingers at `configs` (`[+x, −x]`).
    fn add(&mut self, configs: &[FingerConfig; 2]) {
        let l = linkage();
        let start = self.poses.len();
        self.poses.resize(start + self.per_pose, [0.0; 2]);
        let pose = &mut self.poses[start..];
        let mut at = 0;
        // Fingers in the same configuration (both in free air): the `−x` finger's points are
        // the `+x` finger's mirrored, `−1 · v` being `−v` exactly.
        let alike = configs[0] == configs[1];
        let fingers = if alike { 1 } else { 2 };
        for (cfg, side) in configs.iter().zip([1.0, -1.0]).take(fingers) {
            for (frame, pts) in cfg.link_frames(l).iter().zip(link_points()) {
                // The link frame in the finger's plane: `(x, z) ↦ o + R(angle)·(x, z)`, then
                // mirrored `x → −x` for the `−x` finger (`PlanarPose::to_isometry`, in 2-D: the
                // levels' `y` does not change).
                let (s, c) = frame.angle.sin_cos();
                let (ox, oz) = (frame.origin.x, frame.origin.y);
                let span = at..at + pts.len();
                at = span.end;
                for (p, [x, z]) in pose[span].iter_mut().zip(pts) {
                    *p = [side * (ox + c * x - s * z), oz + s * x + c * z];
                }
            }
        }
        if alike {
            let (right, left) = pose.split_at_mut(at);
            for (q, p) in left.iter_mut().zip(&*right) {
                *q = [-p[0], p[1]];
            }
        }
        // Each point's box grows by its new place, coordinate by coordinate.
        let pose = self.poses[start..].as_flattened();
        for (lo, &v) in self.lo.iter_mut().zip(pose) {
            *lo = least(*lo, v);
        }
        for (hi, &v) in self.hi.iter_mut().zip(pose) {
            *hi = most(*hi, v);
        }
    }

    /// The swept points, and each level with a circle holding its points (its box's
    /// circumcircle: [`Grip::lowest`] scans only the levels whose circle reaches below the best
    /// point so far).
    fn finish(self) -> (Vec<Level>, SweptPoints) {
        let mut offset = 0;
        let levels = Sweep::levels()
            .map(|(y, n)| {
                let pts = offset..offset + n;
                offset += n;
                // The level's box: its points' boxes over all poses (the least and the greatest
                // of the same numbers, whatever the order).
                let coords = 2 * pts.start..2 * pts.end;
                let lo = self.lo[coords.clone()]
                    .chunks_exact(2)
                    .fold([f64::INFINITY; 2], |a, b| {
                        [least(a[0], b[0]), least(a[1], b[1])]
                    });
                let hi = self.hi[coords]
                    .chunks_exact(2)
                    .fold([f64::NEG_INFINITY; 2], |a, b| {
                        [most(a[0], b[0]), most(a[1], b[1])]
                    });
                Level {
                    y,
                    center: [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])],
                    radius: 0.5 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]),
                    pts,
                }
            })
            .collect();
        let points = SweptPoints {
            per_pose: self.per_pose,
            data: self.poses,
        };
        (levels, points)
    }
}

/// The points a closing swept, as [`Sweep::add`] wrote them: pose after pose, each pose's
/// levels side by side (a level's points are the same slice of every pose).
#[derive(Debug)]
struct SweptPoints {
    per_pose: usize,
    data: Vec<[f64; 2]>,
}

impl SweptPoints {
    /// The points of level `l`, pose by pose.
    fn of<'s>(&'s self, l: &Level) -> impl Iterator<Item = &'s [[f64; 2]]> + 's {
        let range = l.pts.clone();
        self.data
            .chunks_exact(self.per_pose)
            .map(move |pose| &pose[range.clone()])
    }
}

/// The swept levels of one finger link: their range in [`Grip`]'s levels and a sphere (in G)
/// holding their points.
#[derive(Clone, Debug)]
struct LinkSweep {
    levels: std::ops::Range<usize>,
    center: Point3<f64>,
    radius: f64,
}

/// The levels of each finger link in `levels` (in [`Sweep::levels`] order), with a sphere each.
fn link_sweeps(levels: &[Level]) -> Vec<LinkSweep> {
    let mut out = Vec::new();
    let mut start = 0;
    for _side in 0..2 {
        for link in link_levels() {
            let range = start..start + link.len();
            start = range.end;
            let group = &levels[range.clone()];
            let (mut lo, mut hi) = (
                Point3::from([f64::INFINITY; 3]),
                Point3::from([f64::NEG_INFINITY; 3]),
            );
            for l in group {
                let r = l.radius;
                lo = lo.inf(&Point3::new(l.center[0] - r, l.y, l.center[1] - r));
                hi = hi.sup(&Point3::new(l.center[0] + r, l.y, l.center[1] + r));
            }
            let center = nalgebra::center(&lo, &hi);
            // Each level's circle lies in the sphere about `center` through its farthest point.
            let radius = group
                .iter()
                .map(|l| (Point3::new(l.center[0], l.y, l.center[1]) - center).norm() + l.radius)
                .fold(0.0, f64::max);
            out.push(LinkSweep {
                levels: range,
                center,
                radius,
            });
        }
    }
    out
}

/// The swept points of one plane `y = const` of one finger link (`(x, z)` in G) and a circle
/// holding them.
#[derive(Clone, Debug)]
struct Level {
    y: f64,
    center: [f64; 2],
    radius: f64,
    /// Its points' place in every pose of [`SweptPoints`].
    pts: std::ops::Range<usize>,
}

/// Heights above the flange (world `z` minus the flange's) of swept points and lower bounds
/// of them, the flange at one world pose: `d` is the world `z` axis in G, so a point `p` of G
/// is `d · p` above the flange. [`Grip::lowest`] and [`Grip::clears`] compute every height here,
/// in the same order, so they agree to the last bit.
struct Heights {
    d: nalgebra::Vector3<f64>,
    /// `|(d.x, d.z)|`: how far a level's circle of radius 1 can reach down.
    planar: f64,
}

impl Heights {
    fn of(flange_world: &Isometry3<f64>) -> Heights {
        let d = flange_world
            .rotation
            .to_rotation_matrix()
            .matrix()
            .row(2)
            .transpose();
        Heights {
            planar: d.x.hypot(d.z),
            d,
        }
    }

    /// The part of a level's points' heights its `y` gives.
    fn base(&self, l: &Level) -> f64 {
        self.d.y * l.y
    }

    /// The height of point `p` (`(x, z)`) of a level whose [`Heights::base`] is `base`.
    fn point(&self, base: f64, p: &[f64; 2]) -> f64 {
        base + self.d.x * p[0] + self.d.z * p[1]
    }

    /// No point of level `l` is lower than this.
    fn level_bound(&self, l: &Level) -> f64 {
        self.point(self.base(l), &l.center) - self.planar * l.radius
    }

    /// No point of link `g`'s levels is lower than this.
    fn link_bound(&self, g: &LinkSweep) -> f64 {
        self.d.dot(&g.center.coords) - g.radius
    }
}

/// The ROS name of finger link `link` ([`FINGER_LINKS`] order).
fn link_name(link: usize) -> &'static str {
    FingerSolids::robotiq_2f85()
        .links
        .get(link)
        .map_or(FINGER_LINKS[link.min(4)], |s| s.name)
}

/// Closes `gripper` on the part with its flange at `flange_in_object` (flange → object
/// frame): the [`Grip`], or why it cannot hold the part there.
pub fn close_on_part(
    object: &ObjectGeometry,
    gripper: &Gripper,
    flange_in_object: &Isometry3<f64>,
) -> Result<Grip, GripFailure> {
    match gripper {
        Gripper::Robotiq2F85(_) => close_2f85(object, flange_in_object),
        Gripper::Jaws(jaws) => jaws::close_jaws(object, jaws, flange_in_object),
    }
}

/// [`close_on_part`] for the 2F-85.
fn close_2f85(
    object: &ObjectGeometry,
    flange_in_object: &Isometry3<f64>,
) -> Result<Grip, GripFailure> {
    let world = PartClosing::new(object, finger_shapes(), *flange_in_object, None);
    let mut sweep = Sweep::new();
    let mut poses = 0usize;
    let mut last: Option<[FingerConfig; 2]> = None;
    let result = close_fingers_traced(&world, linkage(), &mut |configs| {
        poses += 1;
        let moved = last.is_none_or(|l| turned(&l, configs) >= SWEEP_STEP);
        if moved {
            sweep.add(configs);
            last = Some(*configs);
        }
    });
    // Stuck before the first step: a link of the open finger is in the part.
    let opened = poses <= 1 && result.iter().any(|r| r.kind == ClosingKind::Stuck);
    if opened {
        return Err(GripFailure::OpenTouches);
    }
    if let Some(r) = result.iter().find(|r| r.kind == ClosingKind::Stuck) {
        let link = r.first_touch.unwrap_or(DRIVER);
        debug_assert!(matches!(link, DRIVER | COUPLER));
        return Err(GripFailure::Jams {
            link: link_name(link),
        });
    }
    let touched = result
        .iter()
        .any(|r| matches!(r.first_touch, Some(FOLLOWER | PAD | SPRING_LINK)));
    if !touched {
        return Err(GripFailure::ClosesOnNothing);
    }
    let configs = [result[0].config, result[1].config];
    sweep.add(&configs);
    let (swept, points) = sweep.finish();
    let fingers = FingerPair::from_configs(&configs);
    Ok(Grip {
        state: GripperState::Closed(fingers),
        width: fingers.gap(),
        kinds: [result[0].kind, result[1].kind],
        links: Arc::new(link_sweeps(&swept)),
        swept: Arc::new(swept),
        points: Arc::new(points),
    })
}

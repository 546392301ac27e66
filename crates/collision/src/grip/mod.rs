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

use crate::closing::{robotiq_link_hull, FingerShapes, PartClosing};
use crate::object::ObjectGeometry;
use sweep::{Frame, Heights, LinkPoints, Swept};

mod jaws;
mod open;
mod patches;
mod sweep;

pub use open::{
    open_approach_inside, open_inside, OpenHand, OpenInside, OpenMemo, OPEN_APPROACH_STEP,
    OPEN_APPROACH_ZONE, OPEN_CONTACT_DEPTH,
};
pub use patches::{pad_patches, PadPatch, PATCH_DEPTH, PATCH_STEP};

/// Largest joint turn (rad) between two poses of a closing kept for the support test. Between
/// two kept poses a finger point moves on arcs of at most two stacked rotations (a link and
/// the one carrying it) with levers under 0.15 m, so it strays at most
/// `2 · 0.15 · 0.05² / 8` ≈ 94 µm (the sagittas) from the segment joining its two kept
/// positions; [`SWEEP_SAG`] covers it, so the support test stays on the safe side.
const SWEEP_STEP: f64 = 0.05;
/// Bound (m) on how far a finger point may lie below the kept poses' hull between them.
const SWEEP_SAG: f64 = 1e-4;

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
    /// The fully open gripper — a finger link (jaw) or the palm/housing — lies more than
    /// [`OPEN_CONTACT_DEPTH`] inside the part (`depth`, m) at the grasp (`back` = 0) or `back`
    /// (m) before it on the straight approach: a closing must start from a free, fully open
    /// hand (rule 2: contact, never penetration).
    #[error("{}", open_inside_words(link, *depth, *back))]
    OpenInside {
        link: &'static str,
        depth: f64,
        back: f64,
    },
    /// The fingers close fully without touching the part.
    #[error("the pads close on nothing (no part between the fingers)")]
    ClosesOnNothing,
    /// A link that cannot hold the part (the outer knuckle or outer finger) meets it before
    /// the pads or inner knuckles do: the gripper would jam on it.
    #[error("the {link} meets the part before the pads do")]
    Jams { link: &'static str },
}

/// The words of [`GripFailure::OpenInside`].
fn open_inside_words(link: &str, depth: f64, back: f64) -> String {
    let at = if back > 0.0 {
        format!(
            " {:.0} mm before the grasp on the straight approach",
            back * 1e3
        )
    } else {
        String::new()
    };
    format!(
        "the open {link} is {:.1} mm inside the part{at} (at most {:.1} mm)",
        depth * 1e3,
        OPEN_CONTACT_DEPTH * 1e3
    )
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
    /// The finger links in every pose of the closing; for a jaw gripper, its jaws open and
    /// closed (they translate: their hull holds every pose).
    swept: Arc<Swept>,
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
        let best = self.swept.lowest(&Heights::of(flange_world));
        best + flange_world.translation.vector.z - SWEEP_SAG
    }

    /// Whether the fingers stay above world height `height` all through the closing, the
    /// flange at `flange_world`: `lowest(flange_world) > height`, the same answer, found
    /// without the minimum (a link, pose or level whose bound clears is not read; the first
    /// point below ends it).
    pub fn clears(&self, flange_world: &Isometry3<f64>, height: f64) -> bool {
        let z = flange_world.translation.vector.z;
        // As `lowest` rounds: the lowest value `v` passes iff `v + z − SWEEP_SAG > height`, and
        // that is monotone in `v`.
        let above = |v: f64| v + z - SWEEP_SAG > height;
        self.swept.clears(&Heights::of(flange_world), above)
    }

    /// The points (in G) that bound the closing fingers: every pose's finger links lie in
    /// their convex hull.
    pub fn swept_points(&self) -> Vec<Point3<f64>> {
        self.swept.points()
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
        let hulls = (0..LINKS_PER_FINGER)
            .map(|link| robotiq_link_hull(link).clone())
            .collect();
        FingerShapes::with_hulls(&links, hulls).expect("the built-in finger pieces are solids")
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

/// Per finger link (the `+x` finger's five, then the `−x` finger's), its [`Levels`] as the
/// sweep places them.
fn finger_links() -> &'static Arc<Vec<LinkPoints>> {
    static LINKS: OnceLock<Arc<Vec<LinkPoints>>> = OnceLock::new();
    LINKS.get_or_init(|| {
        Arc::new(
            [1.0, -1.0]
                .into_iter()
                .flat_map(|side| {
                    link_levels()
                        .iter()
                        .map(move |levels| LinkPoints::new(side, levels))
                })
                .collect(),
        )
    })
}

/// Poses a closing usually keeps (capacity reserved up front).
const SWEEP_POSES: usize = 40;

/// Both fingers' link frames at `configs` (`[+x, −x]`), in [`finger_links`] order: a pose of
/// the sweep.
fn finger_frames(configs: &[FingerConfig; 2]) -> [Frame; 2 * LINKS_PER_FINGER] {
    let l = linkage();
    let frames = |cfg: &FingerConfig| {
        cfg.link_frames(l).map(|frame| {
            let (s, c) = pregrasp_robot::sin_cos(frame.angle);
            Frame {
                ox: frame.origin.x,
                oz: frame.origin.y,
                c,
                s,
            }
        })
    };
    let right = frames(&configs[0]);
    // Fingers in the same configuration (both in free air): the `−x` finger's frames are the
    // `+x` finger's (mirrored when placed).
    let left = if configs[0] == configs[1] {
        right
    } else {
        frames(&configs[1])
    };
    std::array::from_fn(|k| {
        if k < LINKS_PER_FINGER {
            right[k]
        } else {
            left[k - LINKS_PER_FINGER]
        }
    })
}

/// The ROS name of finger link `link` ([`FINGER_LINKS`] order).
fn link_name(link: usize) -> &'static str {
    FingerSolids::robotiq_2f85()
        .links
        .get(link)
        .map_or(FINGER_LINKS[link.min(4)], |s| s.name)
}

/// Builds, once per process, what closing `gripper` on any part needs and does not depend on
/// the part — the finger links' pieces, hulls and sweep points, the open hand — so that the
/// caller can have it built beside other work: otherwise the first closing builds it while a
/// closing on another thread waits for it. [`close_on_part`] needs no call of this.
pub fn prepare_closing(gripper: &Gripper) {
    OpenHand::of(gripper);
    if let Gripper::Robotiq2F85(_) = gripper {
        finger_shapes();
        finger_links();
    }
}

/// Closes `gripper` on the part with its flange at `flange_in_object` (flange → object
/// frame): the [`Grip`], or why it cannot hold the part there. The closing starts from a free,
/// fully open hand: the open gripper at the grasp and on the last [`OPEN_APPROACH_ZONE`] of its
/// straight approach may touch the part but not lie in it ([`open_approach_inside`]).
pub fn close_on_part(
    object: &ObjectGeometry,
    gripper: &Gripper,
    flange_in_object: &Isometry3<f64>,
) -> Result<Grip, GripFailure> {
    let open_inside = || {
        open_approach_inside(object, gripper, flange_in_object).map(|(inside, back)| {
            GripFailure::OpenInside {
                link: inside.link,
                depth: inside.depth,
                back,
            }
        })
    };
    match gripper {
        // The 2F-85's shapes, open and closing, are built in: whether its open hand lies in
        // the part and how it closes depend on the part and the pose alone.
        Gripper::Robotiq2F85(_) => object.memo().get_or(flange_in_object, || {
            open_inside().map_or_else(|| close_2f85(object, flange_in_object), Err)
        }),
        Gripper::Jaws(jaws) => {
            open_inside().map_or_else(|| jaws::close_jaws(object, jaws, flange_in_object), Err)
        }
    }
}

/// [`close_on_part`] for the 2F-85.
fn close_2f85(
    object: &ObjectGeometry,
    flange_in_object: &Isometry3<f64>,
) -> Result<Grip, GripFailure> {
    let world = PartClosing::new(object, finger_shapes(), *flange_in_object, None);
    let mut sweep = Swept::new(finger_links().clone(), SWEEP_POSES);
    let mut poses = 0usize;
    let mut last: Option<[FingerConfig; 2]> = None;
    let result = close_fingers_traced(&world, linkage(), &mut |configs| {
        poses += 1;
        let moved = last.is_none_or(|l| turned(&l, configs) >= SWEEP_STEP);
        if moved {
            sweep.push(finger_frames(configs));
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
    sweep.push(finger_frames(&configs));
    let fingers = FingerPair::from_configs(&configs);
    Ok(Grip {
        state: GripperState::Closed(fingers),
        width: fingers.gap(),
        kinds: [result[0].kind, result[1].kind],
        swept: Arc::new(sweep.finish()),
    })
}

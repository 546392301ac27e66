//! Both fingers of the 2F-85 as solids: their joint state ([`FingerPair`]) and each finger
//! link's convex pieces ([`FingerSolids`]), placed by the linkage ([`crate::FingerLinkage`]).
//!
//! The pieces come from `data/robotiq_2f85_fingers.json` (`tools/geometry/derive_fingers.py`,
//! fitted to the MuJoCo Menagerie meshes: every mesh vertex inside, largest outward excess
//! 0.11–0.86 mm per link). Each link also has a box in its own frame holding its pieces —
//! the broad phase of the collision model; the pieces are its exact tier.
//!
//! Frames: a link's pieces are given in its link frame ([`crate::PlanarPose::to_isometry`])
//! for the `+x` finger; the `−x` finger's are their mirror images `x → −x`. Shapes are listed
//! left (`−x`) finger first, then right (`+x`), links in [`crate::FINGER_LINKS`] order.

use std::sync::OnceLock;

use nalgebra::{Isometry3, Point3};
use serde::Deserialize;

use crate::finger::BoxJson;
use crate::linkage::{FingerConfig, FingerLinkage};
use crate::links::ConvexPieces;

/// Finger links per finger (driver, coupler, spring link, follower, pad).
pub const LINKS_PER_FINGER: usize = 5;
/// Finger link shapes of both fingers.
pub const FINGER_SHAPES: usize = 2 * LINKS_PER_FINGER;
/// The sides in shape order: the left (`−x`) finger, then the right (`+x`).
pub const SIDES: [f64; 2] = [-1.0, 1.0];

/// The joint state of both fingers: the common driver angle (one actuator turns both) and each
/// finger's spring-link angle, `[+x, −x]` as [`crate::close_fingers`] returns them. In free
/// air the spring holds the coupler on its stop ([`FingerPair::parallel`]); on a part the
/// spring link may have stopped while the driver turned on (the adaptive grasp).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerPair {
    pub driver: f64,
    pub spring_link: [f64; 2],
}

impl FingerPair {
    /// Both fingers in the parallel mode at driver angle `driver` (clamped to its range).
    pub fn parallel(driver: f64) -> FingerPair {
        let l = linkage();
        let driver = driver.clamp(l.limits.driver.0, l.limits.driver.1);
        let spring = l
            .parallel(driver)
            .map_or(l.limits.spring_link.1, |c| c.spring_link);
        FingerPair {
            driver,
            spring_link: [spring; 2],
        }
    }

    /// Fully open (driver at its lower limit).
    pub fn open() -> FingerPair {
        static OPEN: OnceLock<FingerPair> = OnceLock::new();
        *OPEN.get_or_init(|| FingerPair::parallel(linkage().limits.driver.0))
    }

    /// The parallel-mode fingers whose pad faces are `gap` apart (m), clamped to the stroke
    /// (`gap = 0`: the pads touch, or the driver's limit where they cannot).
    pub fn at_gap(gap: f64) -> FingerPair {
        let l = linkage();
        let (mut lo, mut hi) = l.limits.driver;
        let gap_at = |d: f64| FingerPair::parallel(d).gap();
        if gap >= gap_at(lo) {
            return FingerPair::parallel(lo);
        }
        if gap <= gap_at(hi) {
            return FingerPair::parallel(hi);
        }
        // The gap shrinks as the driver turns: bisect to 1e-12 rad.
        while hi - lo > 1e-12 {
            let mid = 0.5 * (lo + hi);
            if gap_at(mid) > gap {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        FingerPair::parallel(0.5 * (lo + hi))
    }

    /// Both fingers' configurations `[+x, −x]` (a spring-link angle at which the loop cannot
    /// close falls back to the parallel mode).
    pub fn configs(&self) -> [FingerConfig; 2] {
        let l = linkage();
        [0, 1].map(|k| {
            l.assemble(self.driver, self.spring_link[k])
                .or_else(|| l.parallel(self.driver))
                .unwrap_or(FingerConfig {
                    driver: self.driver,
                    coupler: 0.0,
                    spring_link: self.spring_link[k],
                    follower: 0.0,
                })
        })
    }

    /// The pair holding two settled finger configurations `[+x, −x]` (their drivers agree).
    pub fn from_configs(configs: &[FingerConfig; 2]) -> FingerPair {
        FingerPair {
            driver: configs[0].driver,
            spring_link: [configs[0].spring_link, configs[1].spring_link],
        }
    }

    /// Distance between the pad faces' centres along the closing axis (m): the width held.
    pub fn gap(&self) -> f64 {
        let l = linkage();
        let [a, b] = self.configs();
        a.pad_center(l).x + b.pad_center(l).x
    }

    /// Every link frame in G, in shape order (left finger's links, then the right's).
    pub fn link_frames(&self) -> [Isometry3<f64>; FINGER_SHAPES] {
        let l = linkage();
        let [right, left] = self.configs();
        let mut out = [Isometry3::identity(); FINGER_SHAPES];
        for (s, (side, cfg)) in SIDES.iter().zip([left, right]).enumerate() {
            for (i, f) in cfg.link_frames(l).iter().enumerate() {
                out[s * LINKS_PER_FINGER + i] = f.to_isometry(*side);
            }
        }
        out
    }

    /// Bits of the three angles, for caches keyed by the state.
    pub fn key(&self) -> [u64; 3] {
        [
            self.driver.to_bits(),
            self.spring_link[0].to_bits(),
            self.spring_link[1].to_bits(),
        ]
    }
}

/// The built-in 2F-85 linkage (Menagerie geometry), built once.
pub fn linkage() -> &'static FingerLinkage {
    static LINKAGE: OnceLock<FingerLinkage> = OnceLock::new();
    LINKAGE.get_or_init(FingerLinkage::robotiq_2f85)
}

/// One finger link as a solid on one side.
#[derive(Debug)]
pub struct FingerSolid {
    /// The ROS name of the link (`outer_knuckle`, `outer_finger`, `inner_knuckle`,
    /// `finger_tip`, `pad`).
    pub name: &'static str,
    /// The box holding the pieces, in the link frame.
    pub bounds: BoxJson,
    /// The convex pieces in the link frame (slack 0: the box holds them).
    pub pieces: ConvexPieces,
}

/// The finger links of both fingers as solids, in shape order.
#[derive(Debug)]
pub struct FingerSolids {
    pub links: Vec<FingerSolid>,
}

#[derive(Deserialize)]
struct FileJson {
    links: Vec<LinkJson>,
}

#[derive(Deserialize)]
struct LinkJson {
    alias: String,
    pieces: Vec<Vec<[f64; 3]>>,
}

const DATA: &str = include_str!("../data/robotiq_2f85_fingers.json");

/// The smallest box about the link frame's axes holding `points`.
fn aabb(points: &[Point3<f64>]) -> BoxJson {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    BoxJson {
        center: [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i])),
        half: [0, 1, 2].map(|i| 0.5 * (hi[i] - lo[i])),
        angle: 0.0,
    }
}

impl FingerSolids {
    /// The built-in 2F-85 fingers (parsed once).
    pub fn robotiq_2f85() -> &'static FingerSolids {
        static SOLIDS: OnceLock<FingerSolids> = OnceLock::new();
        SOLIDS.get_or_init(|| {
            let file: FileJson =
                serde_json::from_str(DATA).expect("built-in robotiq_2f85_fingers.json is valid");
            assert_eq!(file.links.len(), LINKS_PER_FINGER, "five finger links");
            let mut links = Vec::with_capacity(FINGER_SHAPES);
            for side in SIDES {
                for l in &file.links {
                    let name = l.alias.split_whitespace().next().unwrap_or("finger");
                    let name: &'static str = Box::leak(name.to_string().into_boxed_str());
                    let pieces: Vec<Vec<Point3<f64>>> = l
                        .pieces
                        .iter()
                        .map(|p| {
                            p.iter()
                                .map(|v| Point3::new(side * v[0], v[1], v[2]))
                                .collect()
                        })
                        .collect();
                    let all: Vec<Point3<f64>> = pieces.iter().flatten().copied().collect();
                    let coords: Vec<[f64; 3]> = all.iter().map(|p| [p.x, p.y, p.z]).collect();
                    let bounds = crate::finger::tighter_box(aabb(&all), &coords);
                    links.push(FingerSolid {
                        name,
                        bounds,
                        pieces: ConvexPieces { pieces, slack: 0.0 },
                    });
                }
            }
            FingerSolids { links }
        })
    }
}

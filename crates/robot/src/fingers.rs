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

use crate::finger::BoxJson;
use crate::linkage::{FingerConfig, FingerLinkage};
use crate::links::ConvexPieces;
use crate::pieces_blob::Reader;

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

/// The built-in fingers as `build.rs` baked them (format there: `finger_solids`).
const BAKED: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/robotiq_2f85_fingers.bin"));

impl FingerSolids {
    /// The built-in 2F-85 fingers: the pieces of `data/robotiq_2f85_fingers.json`, mirrored to
    /// each side, with their tight boxes (`finger_box::tighter_box`), as `build.rs` baked
    /// them (read once; a test builds them from the JSON and compares, bit for bit).
    pub fn robotiq_2f85() -> &'static FingerSolids {
        static SOLIDS: OnceLock<FingerSolids> = OnceLock::new();
        SOLIDS.get_or_init(|| {
            let mut r = Reader { bytes: BAKED };
            let n = r.count();
            assert_eq!(n, FINGER_SHAPES, "ten finger links");
            let links = (0..n)
                .map(|_| {
                    let name = r.name();
                    let mut three = || [r.number(), r.number(), r.number()];
                    let (center, half) = (three(), three());
                    let angle = r.number();
                    let pieces = (0..r.count())
                        .map(|_| {
                            (0..r.count())
                                .map(|_| Point3::new(r.number(), r.number(), r.number()))
                                .collect()
                        })
                        .collect();
                    FingerSolid {
                        name,
                        bounds: BoxJson {
                            center,
                            half,
                            angle,
                        },
                        pieces: ConvexPieces { pieces, slack: 0.0 },
                    }
                })
                .collect();
            assert!(
                r.bytes.is_empty(),
                "robotiq_2f85_fingers.bin: bytes left over"
            );
            FingerSolids { links }
        })
    }
}

#[cfg(test)]
mod tests {
    use serde::Deserialize;

    use super::*;

    #[derive(Deserialize)]
    struct FileJson {
        links: Vec<LinkJson>,
    }

    #[derive(Deserialize)]
    struct LinkJson {
        alias: String,
        pieces: Vec<Vec<[f64; 3]>>,
    }

    /// The baked fingers are those the JSON gives at run time, bit for bit: the pieces
    /// mirrored to each side (`SIDES` order), named by the alias's first word, and the tight
    /// box of all their points.
    #[test]
    fn the_baked_fingers_are_the_json_s_bit_for_bit() {
        let file: FileJson =
            serde_json::from_str(include_str!("../data/robotiq_2f85_fingers.json")).unwrap();
        let baked = FingerSolids::robotiq_2f85();
        let bits = |v: &[f64]| v.iter().map(|c| c.to_bits()).collect::<Vec<_>>();
        let mut k = 0;
        for side in SIDES {
            for l in &file.links {
                let solid = &baked.links[k];
                k += 1;
                assert_eq!(solid.name, l.alias.split_whitespace().next().unwrap());
                let pieces: Vec<Vec<[f64; 3]>> = l
                    .pieces
                    .iter()
                    .map(|p| p.iter().map(|v| [side * v[0], v[1], v[2]]).collect())
                    .collect();
                assert_eq!(solid.pieces.pieces.len(), pieces.len());
                for (got, want) in solid.pieces.pieces.iter().zip(&pieces) {
                    let got: Vec<f64> = got.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
                    let want: Vec<f64> = want.iter().flatten().copied().collect();
                    assert_eq!(bits(&got), bits(&want), "{} pieces", solid.name);
                }
                let all: Vec<[f64; 3]> = pieces.iter().flatten().copied().collect();
                let want = crate::finger_box::tighter_box(crate::finger_box::aabb(&all), &all);
                let b = &solid.bounds;
                assert_eq!(bits(&b.center), bits(&want.0), "{} box centre", solid.name);
                assert_eq!(bits(&b.half), bits(&want.1), "{} box half", solid.name);
                assert_eq!(
                    b.angle.to_bits(),
                    want.2.to_bits(),
                    "{} box angle",
                    solid.name
                );
            }
        }
        assert_eq!(k, baked.links.len());
    }
}

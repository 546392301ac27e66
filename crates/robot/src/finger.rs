//! Kinematics of the Robotiq 2F-85 fingers as a function of the opening.
//!
//! Each finger is a parallelogram four-bar: the driver (outer knuckle) and the inner knuckle
//! turn about pivots on the housing, the finger tip carrying the pad stays parallel to itself,
//! so the pad centre moves on a circle — it rises about 13 mm from open to closed. The table in
//! `data/robotiq_2f85.json` (derived from the gripper's published description meshes and
//! kinematics by `tools/geometry/derive.py`, aligned to the MuJoCo Menagerie model) gives, for
//! gaps from 0 to 85.2 mm, the pose of every finger link in the gripper frame G; between rows
//! the poses are interpolated linearly in the gap.
//!
//! Frames: G = flange frame, z the approach direction, x the closing axis, y the finger width.
//! The table describes the finger at `+x`; the finger at `−x` is its mirror image `x → −x`.
//! A link pose `[x, z, angle]` is the translation `(x, 0, z)` and the rotation `angle` about
//! G's `+y`. The *gap* is the distance between the two pads' inner (contact) faces.

use std::sync::OnceLock;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::Deserialize;

/// A box in its owning frame: centre, half extents, and a rotation `angle` (rad) about the
/// frame's `y` axis (0 in the data file: axis-aligned).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
pub struct BoxJson {
    pub center: [f64; 3],
    pub half: [f64; 3],
    #[serde(default)]
    pub angle: f64,
}

/// The box about `y` of least area in the `x-z` plane that holds `points`, tried at every
/// degree; replaces `aabb` only where it is at least 15 % smaller (slanted knuckle links).
/// ([`crate::finger_box::tighter_box`], which `build.rs` also runs.)
pub(crate) fn tighter_box(aabb: BoxJson, points: &[[f64; 3]]) -> BoxJson {
    let (center, half, angle) =
        crate::finger_box::tighter_box((aabb.center, aabb.half, aabb.angle), points);
    BoxJson {
        center,
        half,
        angle,
    }
}

#[derive(Deserialize)]
struct StaticJson {
    name: String,
    center: [f64; 3],
    half: [f64; 3],
}

#[derive(Deserialize)]
struct LinkJson {
    name: String,
    #[serde(rename = "box")]
    bounds: BoxJson,
    #[serde(default)]
    hull: Vec<[f64; 3]>,
}

#[derive(Deserialize)]
struct RowJson {
    gap: f64,
    pad_center_z: f64,
    pad_face_x: f64,
    tip_z: f64,
    links: std::collections::BTreeMap<String, [f64; 3]>,
}

#[derive(Deserialize)]
struct FileJson {
    #[serde(rename = "static")]
    statics: Vec<StaticJson>,
    links: Vec<LinkJson>,
    table: Vec<RowJson>,
}

/// The static boxes as [`FingerKinematics::statics`] holds them (not turned).
fn statics_of(statics: Vec<StaticJson>) -> Vec<(String, BoxJson)> {
    statics
        .into_iter()
        .map(|s| {
            (
                s.name,
                BoxJson {
                    center: s.center,
                    half: s.half,
                    angle: 0.0,
                },
            )
        })
        .collect()
}

/// One rigid finger link: its bounding box in its own frame and its mesh hull (for tests).
#[derive(Clone, Debug)]
pub struct FingerLink {
    /// Link name from the data, e.g. `"pad"`, `"finger_tip"`, `"outer_knuckle"`.
    pub name: String,
    /// Box enclosing the link, in the link frame.
    pub bounds: BoxJson,
    /// Convex-hull vertices of the link's mesh, in the link frame.
    pub hull: Vec<[f64; 3]>,
}

/// One row of the opening table.
#[derive(Clone, Debug)]
struct Row {
    gap: f64,
    pad_center_z: f64,
    pad_face_x: f64,
    tip_z: f64,
    /// `[x, z, angle]` per link, in [`FingerKinematics::links`] order.
    poses: Vec<[f64; 3]>,
}

/// The 2F-85 hand: housing boxes and the finger linkage over its whole stroke.
#[derive(Clone, Debug)]
pub struct FingerKinematics {
    /// Boxes of the parts that never move (coupling, housing), in G: `(name, box)`.
    pub statics: Vec<(String, BoxJson)>,
    /// The links of one finger.
    pub links: Vec<FingerLink>,
    rows: Vec<Row>,
}

/// Where a finger is at one gap, interpolated from the table.
#[derive(Clone, Debug, PartialEq)]
pub struct FingerPose {
    /// Gap between the pad faces (m), clamped to the stroke.
    pub gap: f64,
    /// Pad centre on G's z (the precision point of a pinch at this gap).
    pub pad_center_z: f64,
    /// x of the `+x` pad's contact face (≈ gap / 2).
    pub pad_face_x: f64,
    /// Deepest z of the finger (the fingertips).
    pub tip_z: f64,
    /// `[x, z, angle]` in G of each link of the `+x` finger, in [`FingerKinematics::links`]
    /// order.
    pub links: Vec<[f64; 3]>,
}

impl FingerPose {
    /// Pose in G of link `i` of the finger on side `side` (`+1.0`: the `+x` finger, `-1.0`:
    /// its mirror image `(x, z, θ) → (−x, z, −θ)`).
    pub fn link_pose(&self, i: usize, side: f64) -> Isometry3<f64> {
        let [x, z, angle] = self.links[i];
        Isometry3::from_parts(
            Translation3::new(side * x, 0.0, z),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), side * angle),
        )
    }
}

const DATA: &str = include_str!("../data/robotiq_2f85.json");

impl FingerKinematics {
    /// The built-in 2F-85 (parsed once).
    pub fn robotiq_2f85() -> &'static FingerKinematics {
        static MODEL: OnceLock<FingerKinematics> = OnceLock::new();
        MODEL.get_or_init(|| {
            FingerKinematics::from_json(DATA).expect("built-in robotiq_2f85.json is valid")
        })
    }

    /// The built-in 2F-85's static boxes (its body and palm) alone, as
    /// [`robotiq_2f85`](Self::robotiq_2f85)`().statics` holds them: what posing the gripper's
    /// shapes needs. Read without the finger links' hulls and the opening table, which the whole
    /// model parses and tightens: 2.1 M instructions a process, for a table the planner never
    /// reads (the test `statics_alone_are_the_models` compares).
    pub fn robotiq_2f85_statics() -> &'static [(String, BoxJson)] {
        #[derive(Deserialize)]
        struct StaticsOnly {
            #[serde(rename = "static")]
            statics: Vec<StaticJson>,
        }
        static STATICS: OnceLock<Vec<(String, BoxJson)>> = OnceLock::new();
        STATICS.get_or_init(|| {
            let file: StaticsOnly =
                serde_json::from_str(DATA).expect("built-in robotiq_2f85.json is valid");
            statics_of(file.statics)
        })
    }

    fn from_json(text: &str) -> Result<FingerKinematics, String> {
        let file: FileJson = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let links: Vec<FingerLink> = file
            .links
            .into_iter()
            .map(|l| {
                // The contact links keep their axis-aligned boxes: their inner faces are the pad
                // faces the gap is measured between.
                let bounds = if l.name == "pad" || l.name == "finger_tip" {
                    l.bounds
                } else {
                    tighter_box(l.bounds, &l.hull)
                };
                FingerLink {
                    name: l.name,
                    bounds,
                    hull: l.hull,
                }
            })
            .collect();
        let mut rows = Vec::new();
        for r in file.table {
            let poses = links
                .iter()
                .map(|l| {
                    r.links
                        .get(&l.name)
                        .copied()
                        .ok_or_else(|| format!("table row gap {} lacks link {}", r.gap, l.name))
                })
                .collect::<Result<Vec<_>, _>>()?;
            rows.push(Row {
                gap: r.gap,
                pad_center_z: r.pad_center_z,
                pad_face_x: r.pad_face_x,
                tip_z: r.tip_z,
                poses,
            });
        }
        rows.sort_by(|a, b| a.gap.total_cmp(&b.gap));
        if rows.len() < 2 {
            return Err("the opening table needs at least two rows".into());
        }
        Ok(FingerKinematics {
            statics: statics_of(file.statics),
            links,
            rows,
        })
    }

    /// The largest gap (the stroke, fully open), m.
    pub fn stroke(&self) -> f64 {
        self.rows.last().expect("≥ 2 rows").gap
    }

    /// Index of a link by name.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }

    /// The finger at gap `gap` (clamped to `[0, stroke]`), linear between table rows.
    pub fn at(&self, gap: f64) -> FingerPose {
        let gap = gap.clamp(self.rows[0].gap, self.stroke());
        let k = self
            .rows
            .partition_point(|r| r.gap <= gap)
            .clamp(1, self.rows.len() - 1);
        let (r0, r1) = (&self.rows[k - 1], &self.rows[k]);
        let s = if r1.gap > r0.gap {
            (gap - r0.gap) / (r1.gap - r0.gap)
        } else {
            0.0
        };
        let mix = |a: f64, b: f64| a + (b - a) * s;
        let links = r0
            .poses
            .iter()
            .zip(&r1.poses)
            .map(|(p0, p1)| [mix(p0[0], p1[0]), mix(p0[1], p1[1]), mix(p0[2], p1[2])])
            .collect();
        FingerPose {
            gap,
            pad_center_z: mix(r0.pad_center_z, r1.pad_center_z),
            pad_face_x: mix(r0.pad_face_x, r1.pad_face_x),
            tip_z: mix(r0.tip_z, r1.tip_z),
            links,
        }
    }
}

#[cfg(test)]
mod tighter_box_tests {
    use super::*;
    use proptest::prelude::*;

    /// Every point's extent at every degree, as `tighter_box` computed it before the hull.
    fn by_all_points(aabb: BoxJson, points: &[[f64; 3]]) -> BoxJson {
        let mut best = aabb;
        let mut best_area = 0.85 * aabb.half[0] * aabb.half[2];
        for k in 1..180 {
            let beta = (k as f64).to_radians();
            let (s, c) = beta.sin_cos();
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for p in points {
                let local = [c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]];
                for i in 0..3 {
                    lo[i] = lo[i].min(local[i]);
                    hi[i] = hi[i].max(local[i]);
                }
            }
            let half = [0, 1, 2].map(|i| 0.5 * (hi[i] - lo[i]));
            if half[0] * half[2] < best_area {
                best_area = half[0] * half[2];
                let m = [0, 1, 2].map(|i| 0.5 * (hi[i] + lo[i]));
                best = BoxJson {
                    center: [c * m[0] + s * m[2], m[1], -s * m[0] + c * m[2]],
                    half,
                    angle: beta,
                };
            }
        }
        best
    }

    proptest! {
        #[test]
        fn the_planar_hull_gives_the_box_all_points_give(
            pts in proptest::collection::vec(
                (-0.05f64..0.05, -0.02f64..0.02, -0.05f64..0.05), 1..200),
            slant in -1.0f64..1.0,
        ) {
            // Slanted clouds (x and z correlated), where a turned box pays.
            let points: Vec<[f64; 3]> =
                pts.iter().map(|&(x, y, z)| [x, y, 0.3 * z + slant * x]).collect();
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for p in &points {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
            }
            let aabb = BoxJson {
                center: [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i])),
                half: [0, 1, 2].map(|i| 0.5 * (hi[i] - lo[i])),
                angle: 0.0,
            };
            prop_assert_eq!(tighter_box(aabb, &points), by_all_points(aabb, &points));
        }
    }
}

#[cfg(test)]
mod statics_tests {
    use super::*;

    /// The static boxes read alone are the whole model's, bit for bit and in order.
    #[test]
    fn statics_alone_are_the_models() {
        let alone = FingerKinematics::robotiq_2f85_statics();
        let whole = &FingerKinematics::robotiq_2f85().statics;
        assert!(!alone.is_empty());
        assert_eq!(alone, &whole[..]);
    }
}

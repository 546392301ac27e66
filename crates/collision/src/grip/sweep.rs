//! The finger links a closing swept, and how low they reach ([`Grip::lowest`](super::Grip)).
//!
//! A closing keeps, per pose, each finger link's planar frame, not its points: a link of the
//! `+x` finger at frame `(o, θ)` has its point `(x, y, z)` (link frame) at
//! `(ox + cos θ·x − sin θ·z, y, oz + sin θ·x + cos θ·z)` in G, and the `−x` finger's link is
//! that point mirrored (`x` times `side = −1`). The links turn about `y`, so a link's points
//! fall into planes `y = const` (levels) that stay planes as the finger closes.
//!
//! Heights are computed from the points placed this way, the same arithmetic for every query,
//! so [`Swept::lowest`] and [`Swept::clears`] agree to the last bit; three nested bounds cull
//! the points first: a sphere per link over all poses, a circle per link and pose, and a
//! circle per level and pose.

use std::ops::Range;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

/// How far (m) the bounds are lowered so their round-off cannot skip a point below them.
const BOUND_SLACK: f64 = 1e-9;

/// One plane `y = const` of a link's points, in the link frame: their `(x, z)` and a circle
/// holding them.
#[derive(Clone, Debug)]
pub(super) struct Level {
    y: f64,
    center: [f64; 2],
    radius: f64,
    /// Its points in [`LinkPoints::pts`].
    pts: Range<usize>,
}

/// A link's points in its frame (the `+x` finger's), by level, and on which side it is.
#[derive(Clone, Debug)]
pub(super) struct LinkPoints {
    /// `+1.0`: as given; `−1.0`: mirrored `x → −x` once placed.
    side: f64,
    levels: Vec<Level>,
    pts: Vec<[f64; 2]>,
    /// A circle (link frame, `(x, z)`) holding every point, and the range of `y`.
    center: [f64; 2],
    radius: f64,
    y: [f64; 2],
}

impl LinkPoints {
    /// From the link's points grouped by level (`(y, [(x, z)])`), on side `side`.
    pub fn new(side: f64, grouped: &[(f64, Vec<[f64; 2]>)]) -> LinkPoints {
        let mut pts = Vec::new();
        let mut levels = Vec::with_capacity(grouped.len());
        for (y, group) in grouped {
            let start = pts.len();
            pts.extend_from_slice(group);
            let (center, radius) = circle(group);
            levels.push(Level {
                y: *y,
                center,
                radius,
                pts: start..pts.len(),
            });
        }
        let (center, radius) = circle(&pts);
        let y = levels
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |a, l| {
                [a[0].min(l.y), a[1].max(l.y)]
            });
        LinkPoints {
            side,
            levels,
            pts,
            center,
            radius,
            y,
        }
    }
}

/// A circle holding `pts`: their box's circumcircle.
fn circle(pts: &[[f64; 2]]) -> ([f64; 2], f64) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let center = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let radius = pts
        .iter()
        .map(|p| (p[0] - center[0]).hypot(p[1] - center[1]))
        .fold(0.0, f64::max);
    (center, radius)
}

/// A link's planar frame in one pose: its `(x, z)` origin in G and the cosine and sine of its
/// turn about `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Frame {
    pub ox: f64,
    pub oz: f64,
    pub c: f64,
    pub s: f64,
}

impl Frame {
    /// The frame that leaves points where they are.
    pub const IDENTITY: Frame = Frame {
        ox: 0.0,
        oz: 0.0,
        c: 1.0,
        s: 0.0,
    };

    /// Link point `(x, z)` in G (`x`, `z`), on side `side`.
    #[inline]
    fn place(&self, side: f64, p: &[f64; 2]) -> [f64; 2] {
        let [x, z] = *p;
        [
            side * (self.ox + self.c * x - self.s * z),
            self.oz + self.s * x + self.c * z,
        ]
    }
}

/// The links a closing swept: per pose, a frame per link (see the module documentation).
#[derive(Clone, Debug)]
pub(super) struct Swept {
    links: Arc<Vec<LinkPoints>>,
    /// Pose after pose, one frame per link in `links` order.
    frames: Vec<Frame>,
    /// Per link, a sphere (in G) holding its points in every pose.
    spheres: Vec<(Point3<f64>, f64)>,
}

impl Swept {
    /// No pose yet of `links`; room for `poses` poses.
    pub fn new(links: Arc<Vec<LinkPoints>>, poses: usize) -> Swept {
        let n = links.len();
        Swept {
            frames: Vec::with_capacity(poses * n),
            spheres: Vec::new(),
            links,
        }
    }

    /// Adds a pose: a frame per link, in `links` order.
    pub fn push(&mut self, frames: impl IntoIterator<Item = Frame>) {
        let before = self.frames.len();
        self.frames.extend(frames);
        debug_assert_eq!(self.frames.len() - before, self.links.len());
    }

    /// Closes the sweep: each link's sphere over its poses (its box's circumsphere, the box
    /// holding the link's circle at every pose).
    pub fn finish(mut self) -> Swept {
        let n = self.links.len();
        self.spheres = self
            .links
            .iter()
            .enumerate()
            .map(|(k, link)| {
                let mut lo = Point3::from([f64::INFINITY; 3]);
                let mut hi = Point3::from([f64::NEG_INFINITY; 3]);
                for f in self.frames.iter().skip(k).step_by(n) {
                    let [x, z] = f.place(link.side, &link.center);
                    let r = link.radius;
                    lo = lo.inf(&Point3::new(x - r, link.y[0], z - r));
                    hi = hi.sup(&Point3::new(x + r, link.y[1], z + r));
                }
                let center = nalgebra::center(&lo, &hi);
                (center, 0.5 * (hi - lo).norm())
            })
            .collect();
        self
    }

    /// The poses' frames of link `k`.
    fn frames_of(&self, k: usize) -> impl Iterator<Item = &Frame> {
        self.frames.iter().skip(k).step_by(self.links.len())
    }

    /// The lowest height above the flange (see [`Heights`]) of any swept point.
    pub fn lowest(&self, up: &Heights) -> f64 {
        let bound = |k: usize| {
            let (c, r) = &self.spheres[k];
            up.d.dot(&c.coords) - r - BOUND_SLACK
        };
        // The link whose sphere reaches lowest first: its points set a bound that spares most
        // of the others.
        let Some(seed) = (0..self.spheres.len()).min_by(|&a, &b| bound(a).total_cmp(&bound(b)))
        else {
            return f64::INFINITY;
        };
        let mut best = self.scan(up, seed, f64::INFINITY);
        for k in (0..self.spheres.len()).filter(|&k| k != seed) {
            if bound(k) < best {
                best = self.scan(up, k, best);
            }
        }
        best
    }

    /// The least of `best` and the heights of link `k`'s points in every pose, its poses and
    /// levels whose circles cannot reach below `best` skipped.
    fn scan(&self, up: &Heights, k: usize, mut best: f64) -> f64 {
        let link = &self.links[k];
        for f in self.frames_of(k) {
            if up.circle(f, link, &link.center, link.radius, link.y) >= best {
                continue;
            }
            for l in &link.levels {
                if up.circle(f, link, &l.center, l.radius, [l.y, l.y]) >= best {
                    continue;
                }
                let base = up.d.y * l.y;
                for p in &link.pts[l.pts.clone()] {
                    best = best.min(up.point(base, &f.place(link.side, p)));
                }
            }
        }
        best
    }

    /// Whether `above` holds for every swept point's height, for `above` monotone (true above
    /// some height): a bound it holds for spares its points, the first point it fails ends it.
    pub fn clears(&self, up: &Heights, above: impl Fn(f64) -> bool) -> bool {
        for (k, (c, r)) in self.spheres.iter().enumerate() {
            if above(up.d.dot(&c.coords) - r - BOUND_SLACK) {
                continue;
            }
            let link = &self.links[k];
            for f in self.frames_of(k) {
                if above(up.circle(f, link, &link.center, link.radius, link.y)) {
                    continue;
                }
                for l in &link.levels {
                    if above(up.circle(f, link, &l.center, l.radius, [l.y, l.y])) {
                        continue;
                    }
                    let base = up.d.y * l.y;
                    let pts = &link.pts[l.pts.clone()];
                    if pts
                        .iter()
                        .any(|p| !above(up.point(base, &f.place(link.side, p))))
                    {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Every swept point, in G.
    pub fn points(&self) -> Vec<Point3<f64>> {
        let mut out = Vec::new();
        for (k, link) in self.links.iter().enumerate() {
            for f in self.frames_of(k) {
                for l in &link.levels {
                    out.extend(link.pts[l.pts.clone()].iter().map(|p| {
                        let [x, z] = f.place(link.side, p);
                        Point3::new(x, l.y, z)
                    }));
                }
            }
        }
        out
    }
}

/// Heights above the flange (world `z` minus the flange's) of points of G, the flange at one
/// world pose: `d` is the world `z` axis in G, so a point `p` of G is `d · p` above the flange.
pub(super) struct Heights {
    d: Vector3<f64>,
    /// `|(d.x, d.z)|`: how far a circle of radius 1 in a plane `y = const` reaches down.
    planar: f64,
}

impl Heights {
    pub fn of(flange_world: &Isometry3<f64>) -> Heights {
        let d = crate::distance::world_up_in(flange_world);
        Heights {
            planar: d.x.hypot(d.z),
            d,
        }
    }

    /// The height of point `p` (`(x, z)` in G) of a level whose `d.y · y` is `base`.
    #[inline]
    fn point(&self, base: f64, p: &[f64; 2]) -> f64 {
        base + self.d.x * p[0] + self.d.z * p[1]
    }

    /// No point within `radius` of `center` (link frame, `(x, z)`), at a `y` in `y`, of
    /// `link` placed by `f` is lower than this.
    #[inline]
    fn circle(
        &self,
        f: &Frame,
        link: &LinkPoints,
        center: &[f64; 2],
        radius: f64,
        y: [f64; 2],
    ) -> f64 {
        let base = (self.d.y * y[0]).min(self.d.y * y[1]);
        self.point(base, &f.place(link.side, center)) - self.planar * radius - BOUND_SLACK
    }
}

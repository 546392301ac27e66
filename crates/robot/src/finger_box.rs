//! The tight box of a finger link about its frame's `y` axis. Std only, with no paths into
//! the crate: `build.rs` takes this file as its own module to bake the built-in fingers' boxes, so the boxes
//! it writes are the ones this code computes.

/// A box in its link frame: centre, half extents, and its turn (rad) about the frame's `y`.
pub type YBox = ([f64; 3], [f64; 3], f64);

/// The points of `points` on the boundary of their convex hull in the `x-z` plane (Andrew's
/// monotone chain; points on a hull edge are kept, so no extreme value can be lost).
fn planar_hull(points: &[[f64; 3]]) -> Vec<[f64; 2]> {
    let mut pts: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[2]]).collect();
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: &[f64; 2], a: &[f64; 2], b: &[f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let chain = |iter: &mut dyn Iterator<Item = [f64; 2]>| {
        let mut out: Vec<[f64; 2]> = Vec::new();
        for p in iter {
            while out.len() >= 2 && cross(&out[out.len() - 2], &out[out.len() - 1], &p) < 0.0 {
                out.pop();
            }
            out.push(p);
        }
        out
    };
    let mut hull = chain(&mut pts.iter().copied());
    hull.extend(chain(&mut pts.iter().rev().copied()));
    hull
}

/// The box about `y` of least area in the `x-z` plane that holds `points`, tried at every
/// degree; replaces `aabb` only where it is at least 15 % smaller (slanted knuckle links).
pub fn tighter_box(aabb: YBox, points: &[[f64; 3]]) -> YBox {
    if points.is_empty() {
        return aabb;
    }
    let mut best = aabb;
    let mut best_area = 0.85 * aabb.1[0] * aabb.1[2];
    // Extremes along directions in the x-z plane lie on the points' hull in that plane; `y`
    // does not turn.
    let (y_lo, y_hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[1]), hi.max(p[1]))
        });
    let rim: Vec<[f64; 3]> = planar_hull(points)
        .into_iter()
        .map(|[x, z]| [x, y_lo, z])
        .chain([[points[0][0], y_hi, points[0][2]]])
        .collect();
    for k in 1..180 {
        let beta = (k as f64).to_radians();
        let (s, c) = beta.sin_cos();
        // Coordinates along the box axes u = R_y(β)·x̂ = (c, 0, −s), w = R_y(β)·ẑ = (s, 0, c).
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &rim {
            let local = [c * p[0] - s * p[2], p[1], s * p[0] + c * p[2]];
            for i in 0..3 {
                lo[i] = lo[i].min(local[i]);
                hi[i] = hi[i].max(local[i]);
            }
        }
        let half = [
            0.5 * (hi[0] - lo[0]),
            0.5 * (hi[1] - lo[1]),
            0.5 * (hi[2] - lo[2]),
        ];
        if half[0] * half[2] < best_area {
            best_area = half[0] * half[2];
            let m = [
                0.5 * (hi[0] + lo[0]),
                0.5 * (hi[1] + lo[1]),
                0.5 * (hi[2] + lo[2]),
            ];
            // Back to the link frame: p = m_x·u + m_y·ŷ + m_z·w.
            best = (
                [c * m[0] + s * m[2], m[1], -s * m[0] + c * m[2]],
                half,
                beta,
            );
        }
    }
    best
}

/// The smallest box about the frame's axes holding `points` (`build.rs` and the tests ask).
#[cfg_attr(not(test), allow(dead_code))]
pub fn aabb(points: &[[f64; 3]]) -> YBox {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (
        [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i])),
        [0, 1, 2].map(|i| 0.5 * (hi[i] - lo[i])),
        0.0,
    )
}

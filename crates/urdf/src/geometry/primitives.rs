//! URDF primitive solids as polytopes that contain them (circumscribed), in the element
//! frame (the `<collision><origin>` frame).
//!
//! * `<box size="x y z">`: its 8 corners (exact).
//! * `<cylinder radius="r" length="l">` (axis z, centred): two regular `n`-gons at
//!   `z = ±l/2` circumscribed about the circle: vertices at radius `r / cos(π/n)`, so each
//!   side is tangent to the circle. Excess over the solid: `r·(1/cos(π/n) − 1)`
//!   (2.0 % of `r` for `n = 16`).
//! * `<sphere radius="r">`: an icosphere (the icosahedron split twice, 162 vertices on the
//!   unit sphere) scaled by `r / ρ`, `ρ` the smallest distance from the centre to a face
//!   plane of the unit icosphere, so every face plane lies at distance ≥ `r` and the ball is
//!   inside. Excess: `r·(1/ρ − 1)` (1.6 % of `r`).
//! * `<capsule radius="r" length="l">` (axis z, cylinder part of length `l`): the sphere's
//!   polytope centred at `z = ±l/2`; the hull of both contains the hull of the two balls,
//!   which is the capsule.

use nalgebra::{Point3, Vector3};

/// Sides of the polygons circumscribing a cylinder.
pub const CYLINDER_SIDES: usize = 16;

/// The 8 corners of a box of size `s` centred at the origin.
pub fn box_corners(s: [f64; 3]) -> Vec<Point3<f64>> {
    let h = Vector3::new(s[0], s[1], s[2]) / 2.0;
    let mut out = Vec::with_capacity(8);
    for i in 0..8 {
        let sign = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
        out.push(Point3::new(sign(1) * h.x, sign(2) * h.y, sign(4) * h.z));
    }
    out
}

/// Vertices of the prism circumscribing a cylinder of `radius` and `length` along z.
pub fn cylinder_vertices(radius: f64, length: f64) -> Vec<Point3<f64>> {
    let n = CYLINDER_SIDES;
    let rc = radius / (std::f64::consts::PI / n as f64).cos();
    let mut out = Vec::with_capacity(2 * n);
    for z in [-length / 2.0, length / 2.0] {
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            out.push(Point3::new(rc * a.cos(), rc * a.sin(), z));
        }
    }
    out
}

/// Vertices of a polytope containing the ball of `radius` about the origin.
pub fn sphere_vertices(radius: f64) -> Vec<Point3<f64>> {
    let (unit, rho) = icosphere();
    unit.iter()
        .map(|v| Point3::from(v * (radius / rho)))
        .collect()
}

/// Vertices of a polytope containing the capsule of `radius` whose segment runs from
/// `z = −length/2` to `z = +length/2`.
pub fn capsule_vertices(radius: f64, length: f64) -> Vec<Point3<f64>> {
    let ball = sphere_vertices(radius);
    let mut out = Vec::with_capacity(2 * ball.len());
    for dz in [-length / 2.0, length / 2.0] {
        out.extend(ball.iter().map(|p| p + Vector3::new(0.0, 0.0, dz)));
    }
    out
}

/// The unit icosphere (icosahedron split twice: 162 vertices, 320 faces) and its inradius
/// `ρ` (smallest distance from the centre to a face plane).
fn icosphere() -> (Vec<Vector3<f64>>, f64) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<Vector3<f64>> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vector3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..2 {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(f.len() * 4);
        for &[a, b, c] in &f {
            let mut m = |i: usize, j: usize| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    v.push((v[i] + v[j]).normalize());
                    v.len() - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    let rho = f
        .iter()
        .map(|&[a, b, c]| {
            let n = (v[b] - v[a]).cross(&(v[c] - v[a])).normalize();
            n.dot(&v[a]).abs()
        })
        .fold(f64::INFINITY, f64::min);
    (v, rho)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::pieces::{outside_distance, Planes};

    /// Points on the surface of each primitive (dense, deterministic) lie inside its polytope.
    #[test]
    fn polytopes_contain_their_solids() {
        let (r, l) = (0.05, 0.2);
        let dirs: Vec<Vector3<f64>> = (0..2000)
            .map(|i| {
                // Fibonacci sphere.
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / 2000.0;
                let a = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                let s = (1.0 - z * z).sqrt();
                Vector3::new(s * a.cos(), s * a.sin(), z)
            })
            .collect();
        let sphere = Planes::of(&sphere_vertices(r)).unwrap();
        let capsule = Planes::of(&capsule_vertices(r, l)).unwrap();
        let cylinder = Planes::of(&cylinder_vertices(r, l)).unwrap();
        for d in &dirs {
            let p = Point3::from(d * r);
            assert!(outside_distance(&sphere, &p) <= 1e-12);
            let shift = Vector3::new(0.0, 0.0, l / 2.0 * d.z.signum());
            assert!(outside_distance(&capsule, &(p + shift)) <= 1e-12);
            let h = d.x.hypot(d.y).max(1e-300);
            let rim = Point3::new(r * d.x / h, r * d.y / h, d.z * l / 2.0);
            assert!(outside_distance(&cylinder, &rim) <= 1e-12, "{rim}");
        }
        let (_, rho) = icosphere();
        assert!(rho > 0.98 && rho < 1.0, "{rho}");
    }
}

//! Triangle lists for the glTF meshes: the link primitives (cylinders, capsules, boxes)
//! tessellated, the part's mesh as it is.

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_robot::{LinkShape, Primitive};

/// Sides of a tessellated cylinder.
const SIDES: usize = 24;

/// A triangle soup with shared vertices.
#[derive(Default)]
pub(super) struct Tris {
    pub(super) pos: Vec<[f32; 3]>,
    pub(super) idx: Vec<u32>,
}

impl Tris {
    pub(super) fn vertex(&mut self, p: Point3<f64>) -> u32 {
        self.pos.push([p.x as f32, p.y as f32, p.z as f32]);
        (self.pos.len() - 1) as u32
    }

    /// A cylinder (optionally with hemispherical caps) from `a` to `b`.
    pub(super) fn cylinder(&mut self, a: Point3<f64>, b: Point3<f64>, r: f64, caps: bool) {
        let axis = b - a;
        let len = axis.norm();
        let z = if len > 1e-12 {
            axis / len
        } else {
            Vector3::z()
        };
        let helper = if z.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let x = z.cross(&helper).normalize();
        let y = z.cross(&x);
        let ring = |c: Point3<f64>, rr: f64, k: usize| {
            let ang = std::f64::consts::TAU * k as f64 / SIDES as f64;
            c + rr * (ang.cos() * x + ang.sin() * y)
        };
        // Rings: for caps, a few latitudes of each hemisphere; else the two rims.
        let mut rings: Vec<(Point3<f64>, f64)> = Vec::new();
        let lat = 4;
        if caps {
            for i in (1..=lat).rev() {
                let phi = std::f64::consts::FRAC_PI_2 * i as f64 / (lat + 1) as f64;
                rings.push((a - z * (r * phi.sin()), r * phi.cos()));
            }
        }
        rings.push((a, r));
        rings.push((b, r));
        if caps {
            for i in 1..=lat {
                let phi = std::f64::consts::FRAC_PI_2 * i as f64 / (lat + 1) as f64;
                rings.push((b + z * (r * phi.sin()), r * phi.cos()));
            }
        }
        let pole_a = if caps { a - z * r } else { a };
        let pole_b = if caps { b + z * r } else { b };
        let start = self.pos.len() as u32;
        for (c, rr) in &rings {
            for k in 0..SIDES {
                self.vertex(ring(*c, *rr, k));
            }
        }
        let pa = self.vertex(pole_a);
        let pb = self.vertex(pole_b);
        let s = SIDES as u32;
        for (ri, _) in rings.iter().enumerate().skip(1) {
            let r0 = start + (ri as u32 - 1) * s;
            let r1 = start + ri as u32 * s;
            for k in 0..s {
                let k1 = (k + 1) % s;
                self.idx
                    .extend([r0 + k, r0 + k1, r1 + k1, r0 + k, r1 + k1, r1 + k]);
            }
        }
        let last = start + (rings.len() as u32 - 1) * s;
        for k in 0..s {
            let k1 = (k + 1) % s;
            self.idx.extend([pa, start + k1, start + k]);
            self.idx.extend([pb, last + k, last + k1]);
        }
    }

    pub(super) fn cuboid(&mut self, pose: &Isometry3<f64>, h: &Vector3<f64>) {
        let start = self.pos.len() as u32;
        for i in 0..8 {
            let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
            let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
            let sz = if i & 4 == 0 { -1.0 } else { 1.0 };
            self.vertex(pose * Point3::new(sx * h.x, sy * h.y, sz * h.z));
        }
        const F: [[u32; 3]; 12] = [
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        for f in F {
            self.idx.extend(f.map(|i| start + i));
        }
    }

    /// The convex hull of `points` (a link's convex piece); nothing for a degenerate one.
    pub(super) fn convex(&mut self, points: &[Point3<f64>]) {
        let Ok(hull) = pregrasp_geometry::hull::ConvexHull::from_points(points) else {
            return;
        };
        let start = self.pos.len() as u32;
        for v in &hull.vertices {
            self.vertex(*v);
        }
        for t in &hull.triangles {
            self.idx.extend(t.map(|i| start + i));
        }
    }

    /// A link shape as drawn: its exact pieces when `pieces` (a link from a robot description,
    /// whose primitive is only their box) and it has them, else its primitive.
    pub(super) fn link(&mut self, shape: &LinkShape, pieces: bool) {
        match shape.pieces {
            Some(exact) if pieces => {
                for p in &exact.pieces {
                    self.convex(p);
                }
            }
            _ => self.primitive(&shape.primitive),
        }
    }

    pub(super) fn primitive(&mut self, p: &Primitive) {
        match p {
            Primitive::Capsule(c) => self.cylinder(c.a, c.b, c.radius, true),
            Primitive::Cylinder(c) => self.cylinder(c.a, c.b, c.radius, false),
            Primitive::Cuboid { pose, half_extents } => self.cuboid(pose, half_extents),
        }
    }
}

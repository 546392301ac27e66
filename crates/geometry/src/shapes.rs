//! Simple closed meshes built in code: boxes, extruded convex polygons, spheres, and unions of
//! them. Used by tests, benchmarks and the built-in examples. All triangles are wound
//! counter-clockwise seen from outside.

use std::f64::consts::{PI, TAU};

use crate::{Mesh, Point};

/// The axis-aligned box with opposite corners `lo` and `hi` (8 vertices, 12 triangles).
pub fn cuboid(lo: Point, hi: Point) -> Mesh {
    prism(
        &[[lo.x, lo.y], [hi.x, lo.y], [hi.x, hi.y], [lo.x, hi.y]],
        lo.z,
        hi.z,
    )
}

/// The convex polygon `outline` (counter-clockwise in the `xy` plane) extruded from `z0` to
/// `z1 > z0`.
pub fn prism(outline: &[[f64; 2]], z0: f64, z1: f64) -> Mesh {
    let n = outline.len();
    assert!(n >= 3, "a prism needs a polygon with at least 3 corners");
    let mut vertices: Vec<Point> = outline.iter().map(|p| Point::new(p[0], p[1], z0)).collect();
    vertices.extend(outline.iter().map(|p| Point::new(p[0], p[1], z1)));
    let (b, t) = (0u32, n as u32);
    let mut triangles = Vec::with_capacity(4 * n - 4);
    for i in 1..n as u32 - 1 {
        triangles.push([b, b + i + 1, b + i]); // bottom, seen from below
        triangles.push([t, t + i, t + i + 1]); // top
    }
    for i in 0..n as u32 {
        let j = (i + 1) % n as u32;
        triangles.push([b + i, b + j, t + j]);
        triangles.push([b + i, t + j, t + i]);
    }
    Mesh::new(vertices, triangles)
}

/// A UV sphere of `radius` about `center` with `rings` latitude bands (≥ 2) and `segments`
/// longitude slices (≥ 3): `2 · segments · (rings − 1)` triangles.
pub fn uv_sphere(center: Point, radius: f64, rings: u32, segments: u32) -> Mesh {
    assert!(rings >= 2 && segments >= 3);
    let mut vertices = vec![center + nalgebra::Vector3::z() * radius];
    for r in 1..rings {
        let phi = PI * f64::from(r) / f64::from(rings);
        for s in 0..segments {
            let lam = TAU * f64::from(s) / f64::from(segments);
            vertices.push(Point::new(
                center.x + radius * phi.sin() * lam.cos(),
                center.y + radius * phi.sin() * lam.sin(),
                center.z + radius * phi.cos(),
            ));
        }
    }
    let south = vertices.len() as u32;
    vertices.push(center - nalgebra::Vector3::z() * radius);
    let ring = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, ring(1, s), ring(1, s + 1)]);
        triangles.push([south, ring(rings - 1, s + 1), ring(rings - 1, s)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            let (a, b, c, d) = (
                ring(r, s),
                ring(r, s + 1),
                ring(r + 1, s),
                ring(r + 1, s + 1),
            );
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    Mesh::new(vertices, triangles)
}

/// All `parts` in one mesh (vertices are not shared between parts).
pub fn union(parts: &[Mesh]) -> Mesh {
    let mut out = Mesh::default();
    for m in parts {
        let offset = out.vertices.len() as u32;
        out.vertices.extend_from_slice(&m.vertices);
        out.triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + offset)));
    }
    out
}

/// The box with corners `lo`, `hi`, each face cut into an `n × n` grid of quads
/// (`12 n²` triangles). Grid points on shared box edges are computed identically on both faces,
/// so they coincide exactly (an STL of it welds into a closed mesh).
pub fn subdivided_cuboid(lo: Point, hi: Point, n: u32) -> Mesh {
    assert!(n >= 1);
    let at = |axis: usize, i: u32| lo[axis] + (hi[axis] - lo[axis]) * f64::from(i) / f64::from(n);
    let mut mesh = Mesh::default();
    // (normal axis, side, u axis, v axis) with u × v pointing outwards.
    for (k, side, u, v) in [
        (2, 0, 1, 0),
        (2, 1, 0, 1),
        (0, 0, 2, 1),
        (0, 1, 1, 2),
        (1, 0, 0, 2),
        (1, 1, 2, 0),
    ] {
        let base = mesh.vertices.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let mut p = Point::origin();
                p[k] = if side == 0 { lo[k] } else { hi[k] };
                p[u] = at(u, i);
                p[v] = at(v, j);
                mesh.vertices.push(p);
            }
        }
        let id = |i: u32, j: u32| base + i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                mesh.triangles
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                mesh.triangles
                    .push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    mesh
}

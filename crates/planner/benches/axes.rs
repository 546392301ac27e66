//! Algorithm 1 end to end: mesh file load + convex hull + feature edges + candidates + θ_max.
//!
//! Parts (written to a temporary binary STL first, then loaded in every iteration):
//! - `frame_100k`: five bars, each a box with every face cut into a 41 × 41 grid
//!   (100 860 triangles; the hull sees ~50 000 points, most of them on its flat faces);
//! - `lens_100k`: a UV sphere squashed to 5 % height (99 904 triangles, every vertex on the hull);
//! - `frame_1k`: the same frame with 4 × 4 grids (960 triangles).
//!
//! Run: `cargo bench -p pregrasp-planner --bench axes -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Point3};
use pregrasp_geometry::shapes::{subdivided_cuboid, union, uv_sphere};
use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_io::mesh_io::{load_mesh, write_stl};
use pregrasp_io::scene::PlannerParams;
use pregrasp_planner::axes::rotation_axis_candidates;

fn frame(n: u32) -> Mesh {
    let p = Point3::new;
    let (w, h, t, b) = (0.8, 0.6, 0.03, 0.04);
    union(&[
        subdivided_cuboid(p(0.0, 0.0, 0.0), p(w, b, t), n),
        subdivided_cuboid(p(0.0, h - b, 0.0), p(w, h, t), n),
        subdivided_cuboid(p(0.0, b + 0.001, 0.0), p(b, h - b - 0.001, t), n),
        subdivided_cuboid(p(w - b, b + 0.001, 0.0), p(w, h - b - 0.001, t), n),
        subdivided_cuboid(p(0.38, b + 0.001, 0.0), p(0.38 + b, h - b - 0.001, t), n),
    ])
}

fn lens() -> Mesh {
    let mut m = uv_sphere(Point3::new(0.0, 0.0, 0.0), 0.4, 224, 224);
    for v in &mut m.vertices {
        v.z = 0.02 + 0.05 * v.z;
    }
    m
}

/// Algorithm 1 as `pregrasp axes` runs it, from the file on.
fn algorithm1(path: &Path, params: &PlannerParams) -> usize {
    let mesh = load_mesh(path, 1.0).expect("bench mesh loads").mesh;
    let r = rotation_axis_candidates(&mesh, &Isometry3::identity(), 0.0, params);
    r.candidates.len()
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let params = PlannerParams::default();
    for (name, mesh) in [
        ("frame_100k", frame(41)),
        ("lens_100k", lens()),
        ("frame_1k", frame(4)),
    ] {
        let path = dir.path().join(format!("{name}.stl"));
        write_stl(&path, &mesh).expect("write bench mesh");
        let loaded = load_mesh(&path, 1.0).expect("bench mesh loads").mesh;
        eprintln!(
            "{name}: {} triangles, {} welded vertices, {} candidates",
            loaded.triangles.len(),
            loaded.vertices.len(),
            algorithm1(&path, &params)
        );
        c.bench_function(&format!("algorithm1/{name}"), |b| {
            b.iter(|| algorithm1(black_box(&path), &params))
        });
        if name != "frame_1k" {
            c.bench_function(&format!("load/{name}"), |b| {
                b.iter(|| load_mesh(black_box(&path), 1.0).unwrap())
            });
            c.bench_function(&format!("hull/{name}"), |b| {
                b.iter(|| ConvexHull::of_mesh(black_box(&loaded)).unwrap())
            });
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

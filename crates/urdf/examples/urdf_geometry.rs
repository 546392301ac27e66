//! Derives the collision geometry of URDF robots and prints, per link, how far the convex
//! pieces reach outside the geometry (excess), the self-collision pairs, and the first vs
//! cached load time.
//!
//! ```text
//! cargo run --release -p pregrasp-urdf --example urdf_geometry [-- URDF...]
//! ```
//! Default robots: `data/robots/fr3.urdf`, `data/robots/xarm6.urdf`. The cache goes to a
//! fresh temporary folder, so the first load always computes.

use std::path::PathBuf;
use std::time::Instant;

use pregrasp_urdf::geometry::measure_excess;
use pregrasp_urdf::{CacheDir, GeometryOptions, UrdfGeometry, UrdfModel};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    if files.is_empty() {
        files = ["fr3.urdf", "xarm6.urdf"]
            .iter()
            .map(|f| root.join("data/robots").join(f))
            .collect();
    }
    let cache =
        std::env::temp_dir().join(format!("pregrasp-geometry-example-{}", std::process::id()));
    let opts = GeometryOptions {
        cache: CacheDir::At(cache.clone()),
        ..Default::default()
    };
    for file in &files {
        let model = UrdfModel::from_file(file)?;
        let t = Instant::now();
        let first = UrdfGeometry::load(&model, &opts)?;
        let t_first = t.elapsed();
        let t = Instant::now();
        let again = UrdfGeometry::load(&model, &opts)?;
        let t_cached = t.elapsed();
        assert_eq!(first.geometry, again.geometry);
        let g = &first.geometry;
        println!("\n## {} ({})\n", model.name(), file.display());
        println!(
            "load: first {:.1} ms ({:?}), cached {:.1} ms ({:?})\n",
            t_first.as_secs_f64() * 1e3,
            kind(&first.cache),
            t_cached.as_secs_f64() * 1e3,
            kind(&again.cache)
        );
        println!("| link | element | kind | mesh vertices | piece vertices | excess max (mm) | excess mean (mm) | worst vertex outside (m) |");
        println!("|---|---|---|---|---|---|---|---|");
        for e in measure_excess(&model, g, &opts)? {
            let outside = if e.kind == "mesh" {
                format!("{:.1e}", e.vertex_outside)
            } else {
                "–".into()
            };
            println!(
                "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {} |",
                e.link,
                e.element,
                e.kind,
                e.mesh_vertices,
                e.piece_vertices,
                e.max * 1e3,
                e.mean * 1e3,
                outside
            );
        }
        let names = |(a, b)| {
            let (x, y) = g.pair_names((a, b));
            format!("{x}–{y}")
        };
        println!(
            "\nchecked pairs ({}): {}",
            g.self_collision_pairs.len(),
            g.self_collision_pairs
                .iter()
                .map(|&p| names(p))
                .collect::<Vec<_>>()
                .join(", ")
        );
        for why in ["Adjacent", "Always", "Never"] {
            let list: Vec<String> = g
                .excluded_pairs
                .iter()
                .filter(|e| format!("{:?}", e.why) == why)
                .map(|e| format!("{} ({}/{})", names((e.a, e.b)), e.hits, e.samples))
                .collect();
            println!("{why} ({}): {}", list.len(), list.join(", "));
        }
    }
    let _ = std::fs::remove_dir_all(&cache);
    Ok(())
}

fn kind(c: &pregrasp_urdf::CacheOutcome) -> &'static str {
    match c {
        pregrasp_urdf::CacheOutcome::Hit(_) => "hit",
        pregrasp_urdf::CacheOutcome::Written(_) => "computed, written",
        pregrasp_urdf::CacheOutcome::Replaced(..) => "replaced",
        pregrasp_urdf::CacheOutcome::NotCached(_) => "not cached",
    }
}

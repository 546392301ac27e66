//! The whole pipeline (Algorithms 1–3, plan file, check) on the built-in examples, in-process.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::{plan, PlanOptions};

fn bench_plan(c: &mut Criterion) {
    let mut group = c.benchmark_group("plan");
    group.sample_size(20);
    for name in pregrasp_examples::NAMES {
        let ex = pregrasp_examples::by_name(name).expect("example");
        let scene = Scene::from_str(&ex.scene_toml, Path::new(&format!("examples/{name}.toml")))
            .expect("scene");
        group.bench_function(name, |b| {
            b.iter(|| {
                let report = plan(
                    black_box(&scene),
                    &ex.mesh,
                    &PlanOptions::default(),
                    &|_| {},
                    &|| {},
                )
                .expect("plans");
                assert_eq!(report.file.status, "planned");
                report
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_plan);
criterion_main!(benches);

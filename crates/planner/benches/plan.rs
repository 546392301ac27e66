//! The whole pipeline (Algorithms 1–3, plan file, check, grip check) on the built-in examples,
//! in-process: `plan/*` on rayon's default pool (every core), `plan_1thread/*` on one thread
//! (the figure issue 13 sets a goal for).

use pregrasp_io::plan_file::PlanStatus;
use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::{plan, PlanOptions};

fn bench_plan(c: &mut Criterion) {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    for (group_name, pool) in [("plan", None), ("plan_1thread", Some(&one))] {
        let mut group = c.benchmark_group(group_name);
        group.sample_size(20);
        for name in pregrasp_examples::NAMES {
            let ex = pregrasp_examples::by_name(name).expect("example");
            let file = format!("examples/{name}.toml");
            let scene = Scene::from_str(&ex.scene_toml, Path::new(&file)).expect("scene");
            let run = || {
                let report = plan(
                    black_box(&scene),
                    &ex.mesh,
                    &PlanOptions::default(),
                    &|_| {},
                    &|| {},
                )
                .unwrap();
                assert_eq!(report.file.status, PlanStatus::Planned);
                report
            };
            group.bench_function(name, |b| {
                b.iter(|| match pool {
                    Some(pool) => pool.install(run),
                    None => run(),
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench_plan);
criterion_main!(benches);

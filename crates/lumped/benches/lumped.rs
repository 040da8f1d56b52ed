//! Throughput of the lumped engine on `vaujany-site2`, with its forest and without, on one
//! thread and on all cores, in one run so the figures compare as ratios.
//!
//! `cargo bench -p rockfall-lumped --bench lumped`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rockfall_engine::{Plan, RunOptions};
use rockfall_lumped::LumpedModel;
use rockfall_results::Layout;
use std::hint::black_box;
use std::sync::Arc;

const ROCKS: u64 = 4000;

fn site2(c: &mut Criterion) {
    let mut scenario = rockfall_sites::build("vaujany-site2").expect("built-in site");
    scenario.simulation.rocks_per_cell = ROCKS;
    let forest = scenario.build_forest().expect("site forest");
    let layout = Arc::new(Layout {
        trajectories: 0,
        ..Layout::of(&scenario)
    });
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("vaujany-site2");
    group.throughput(Throughput::Elements(ROCKS));
    group.sample_size(10);
    for (label, forest) in [("forest", Some(&forest)), ("bare", None)] {
        let model = LumpedModel::new(&scenario, forest).expect("model");
        let plan = Plan::new(model, &scenario).expect("releases");
        for threads in [1, cores] {
            let opts = RunOptions {
                threads,
                progress: None,
                cancel: None,
            };
            group.bench_function(format!("{label}/{threads}-threads"), |b| {
                b.iter(|| black_box(plan.run_all(&layout, &opts).expect("run")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, site2);
criterion_main!(benches);

//! Throughput of the rigid engine on `forest-slope-40` (seed 001 §3.4) with the built-in
//! cubic1.2 rock (~100 hull vertices) at the scenario's time step of 1 ms: one thread and
//! all cores, with the forest and without, in one run so the figures compare as ratios.
//!
//! Before timing, each case runs once on one thread and prints steps per second, the share
//! of steps in contact, contacts per step and prox sweeps.
//!
//! `cargo bench -p rockfall-rigid --bench rigid`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rockfall_engine::{Plan, RunOptions};
use rockfall_results::{Layout, Tally};
use rockfall_rigid::RigidModel;
use rockfall_rigid::step::StepStats;
use std::hint::black_box;
use std::sync::Arc;

const ROCKS: u64 = 16;

/// Simulates the plan's first [`ROCKS`] rocks one after another on the calling thread: what
/// their steps did and the wall time, s.
fn profile(plan: &Plan<RigidModel<'_>>, layout: &Arc<Layout>) -> (StepStats, f64) {
    let mut tally = Tally::new(layout.clone());
    let mut scratch = rockfall_engine::Engine::scratch(plan.engine());
    let started = std::time::Instant::now();
    for id in 0..ROCKS.min(plan.rocks()) {
        plan.simulate(id, &mut tally, &mut scratch);
    }
    (scratch.stats, started.elapsed().as_secs_f64())
}

fn forest_slope(c: &mut Criterion) {
    let mut scenario = rockfall_sites::build("forest-slope-40").expect("built-in site");
    scenario.simulation.rocks_per_point = ROCKS;
    let forest = scenario.build_forest().expect("site forest");
    let layout = Arc::new(Layout {
        trajectories: 0,
        ..Layout::of(&scenario)
    });
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("forest-slope-40");
    group.throughput(Throughput::Elements(ROCKS));
    group.sample_size(10);
    for (label, forest) in [("forest", Some(&forest)), ("bare", None)] {
        let model = RigidModel::new(&scenario, forest).expect("model");
        let plan = Plan::new(model, &scenario).expect("releases");
        let (st, wall_s) = profile(&plan, &layout);
        let per = |n: u64| n as f64 / st.steps.max(1) as f64;
        eprintln!(
            "{label}: {ROCKS} rocks, {} steps ({:.0} per rock) in {wall_s:.2} s on one thread: \
             {:.0} steps/s, {:.2} µs/step; {:.1} % of steps near the ground, {:.1} % in the \
             scarring layer, {:.1} % in contact, contacts per step \
             {:.2} ground + {:.3} stem, {:.2} prox sweeps per contact step, {} capped",
            st.steps,
            st.steps as f64 / ROCKS as f64,
            st.steps as f64 / wall_s,
            1e6 * wall_s / st.steps.max(1) as f64,
            100.0 * per(st.steps_near_ground),
            100.0 * per(st.steps_in_scar),
            100.0 * per(st.steps_in_contact),
            per(st.ground_contacts),
            per(st.stem_contacts),
            st.iterations as f64 / st.steps_in_contact.max(1) as f64,
            st.unconverged,
        );
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

criterion_group!(benches, forest_slope);
criterion_main!(benches);

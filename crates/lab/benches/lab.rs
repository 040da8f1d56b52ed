//! Throughput of the impact laboratory (seed 001 §2): 500 sampled impacts of the sphere and of
//! flat2.2 at dt = 0.1 ms, on one thread and on all cores, in one run so the figures compare
//! as ratios. Before timing, each shape runs once and prints candidates tried, hit rate and
//! impacts per second.
//!
//! `cargo bench -p rockfall-lab --bench lab`

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rockfall_lab::{Lab, LabSetup, run_lab};
use rockfall_rigid::shape::body_from_spec;
use rockfall_scenario::RockSpec;
use std::hint::black_box;

const SAMPLES: u64 = 500;

fn laboratory(c: &mut Criterion) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut group = c.benchmark_group("impact-lab");
    group.throughput(Throughput::Elements(SAMPLES));
    group.sample_size(10);
    for shape in ["sphere", "flat2.2"] {
        let spec = match shape {
            "sphere" => RockSpec {
                volume_m3: Some(0.02),
                ..RockSpec::sphere(0.34, 2700.0)
            },
            name => RockSpec::named(name, Some(0.02), 2700.0).expect("named shape"),
        };
        let lab = Lab::new(LabSetup::default(), body_from_spec(&spec).expect("rock")).expect("lab");
        let run = run_lab(&lab, 1, SAMPLES, 1, &|_| {}).expect("run");
        eprintln!(
            "{shape}: {SAMPLES} impacts from {} candidates ({:.1} % hits, {} not stepped) in \
             {:.3} s on one thread: {:.0} impacts/s",
            run.tried,
            100.0 * SAMPLES as f64 / run.tried as f64,
            run.misses.wide,
            run.wall_time_s,
            SAMPLES as f64 / run.wall_time_s
        );
        for threads in [1, cores] {
            group.bench_function(format!("{shape}/{threads}-threads"), |b| {
                b.iter(|| black_box(run_lab(&lab, 1, SAMPLES, threads, &|_| {}).expect("run")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, laboratory);
criterion_main!(benches);

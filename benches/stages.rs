//! Criterion benches of each stage's hot path on the paper instances: Bottom-Left, the MILP
//! placement (model build + HiGHS solve), and the A* and paper sequencers.
//!
//! `cargo bench --bench stages -- --warm-up-time 1 --measurement-time 5`

use criterion::{criterion_group, criterion_main, Criterion};
use pushpack::control::TimeLimit;
use pushpack::instance::Instance;
use pushpack::placement::{bl, milp};
use pushpack::sequence::{astar, paper, SequenceOptions};
use std::hint::black_box;

fn load(rel: &str) -> Instance {
    Instance::load(format!("{}/instances/{rel}", env!("CARGO_MANIFEST_DIR"))).expect("bundled instance")
}

fn stages(c: &mut Criterion) {
    let mut g = c.benchmark_group("stages");
    g.sample_size(10);
    for (name, rel) in [
        ("exp1", "paper/exp1_4objects.toml"),
        ("exp2", "paper/exp2_8objects.toml"),
    ] {
        let inst = load(rel);
        g.bench_function(format!("bl_256_orders/{name}"), |b| {
            b.iter(|| bl::solve(black_box(&inst), 1, 256, &TimeLimit::new(60.0)).expect("BL"))
        });
        let warm = bl::solve(&inst, 1, 256, &TimeLimit::new(60.0)).expect("BL");
        g.bench_function(format!("milp_build_and_solve/{name}"), |b| {
            b.iter(|| {
                let s = milp::MilpSettings {
                    time_limit: 60.0,
                    contact_stage: true,
                    seed: 0,
                    ..Default::default()
                };
                milp::solve(black_box(&inst), &warm, &s, &TimeLimit::new(60.0)).expect("MILP")
            })
        });
        let placement = milp::solve(&inst, &warm, &milp::MilpSettings::default(), &TimeLimit::new(60.0))
            .expect("MILP")
            .placement;
        let opts = SequenceOptions {
            no_direct: false,
            no_multi_push: false,
            max_nodes: 5_000_000,
            vetoes: Vec::new(),
        };
        g.bench_function(format!("sequence_paper/{name}"), |b| {
            b.iter(|| paper::solve(black_box(&inst), &placement, &opts, &TimeLimit::new(60.0)).expect("paper"))
        });
        g.bench_function(format!("sequence_astar/{name}"), |b| {
            b.iter(|| {
                astar::solve(
                    black_box(&inst),
                    &placement,
                    &opts,
                    &astar::AstarSettings::default(),
                    &TimeLimit::new(60.0),
                )
                .expect("A*")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);

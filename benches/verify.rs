//! Criterion benches of the checks every benchmark row pays for: `actions::Layout::check` over a
//! whole plan (the feasibility test the sequencers call in their inner loop) and the independent
//! verifier `verify::verify` (packing replay plus joint-trajectory checks).
//!
//! `cargo bench --bench verify -- --warm-up-time 1 --measurement-time 5`

use criterion::{criterion_group, criterion_main, Criterion};
use pushpack::actions::Layout;
use pushpack::instance::Instance;
use pushpack::plan::{optimize, PlacementSolver, PlanOptions, Sequencer};
use std::hint::black_box;

fn checks(c: &mut Criterion) {
    let mut g = c.benchmark_group("checks");
    g.sample_size(10);
    let path = format!("{}/instances/paper/exp2_8objects.toml", env!("CARGO_MANIFEST_DIR"));
    let inst = Instance::load(path).expect("bundled instance");
    // Bottom-Left + paper sequencer: the quickest full plan to set up; the checks do not care.
    let mut o = PlanOptions::from_instance(&inst);
    o.placement = PlacementSolver::Bl;
    o.sequencer = Sequencer::Paper;
    let out = optimize(&inst, &o).expect("plan");
    let placement = out.placement.placement.clone();
    let actions = out.sequence.actions.clone();
    g.bench_function("layout_check_apply_whole_plan/exp2", |b| {
        b.iter(|| {
            let mut l = Layout::new(&inst, &placement);
            for a in &actions {
                black_box(l.check(a).expect("the planner's own plan is feasible"));
                l.apply(a);
            }
        })
    });
    g.bench_function("verify/exp2", |b| {
        b.iter(|| black_box(pushpack::verify::verify(&inst, &out.plan)))
    });
    g.finish();
}

criterion_group!(benches, checks);
criterion_main!(benches);

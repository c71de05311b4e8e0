//! Push-stability check throughput: checks per second for 1-, 2- and 3-box lines, 2-D (LP) and
//! 3-D (SOCP), with clarabel solvers re-used between calls (the production configuration), plus
//! 2-D with a fresh solver per call and the planner's cached path for comparison.
//!
//! `cargo bench --bench push_check -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pushpack::actions::push::{self, convex, parse_scenario, CheckOptions, Dim, LineGeometry, PushModel};
use std::hint::black_box;
use std::sync::atomic::{AtomicU64, Ordering};

static CALLS: AtomicU64 = AtomicU64::new(0);

/// A line of `k` boxes along −x, slightly staggered laterally, each box behind the previous one
/// with a gap (so every phase is checked), pusher centred on the back box, fingertip 5 mm high.
fn model(k: usize) -> PushModel {
    let mut boxes = Vec::new();
    for m in 0..k {
        let x = 0.03 + 0.07 * m as f64;
        let y = 0.05 + 0.004 * m as f64;
        boxes.push(format!(
            r#"{{"id": "b{m}", "size": [0.06, 0.05, 0.04], "mass": {}, "pose": [{x}, {y}, 0.0]}}"#,
            0.05 + 0.01 * m as f64
        ));
    }
    let px = 0.03 + 0.07 * (k - 1) as f64 + 0.035;
    let py = 0.05 + 0.004 * (k - 1) as f64;
    let text = format!(
        r#"{{"mode": "2d", "push_dir": "-x",
            "friction": {{"mu_floor": 0.35, "mu_obj": 0.3, "mu_finger": 0.5}},
            "boxes": [{}],
            "pusher": {{"point": [{px}, {py}], "width": 0.02, "height": 0.005}}}}"#,
        boxes.join(",")
    );
    parse_scenario(&text, "<bench>").expect("valid bench scenario").model
}

fn line(k: usize) -> LineGeometry {
    LineGeometry {
        lateral: (0..k).map(|m| [0.004 * m as f64, 0.05 + 0.004 * m as f64]).collect(),
        weight: (0..k).map(|m| 0.35 * (0.05 + 0.01 * m as f64)).collect(),
        pusher: [0.015 + 0.004 * (k - 1) as f64, 0.035 + 0.004 * (k - 1) as f64],
    }
}

fn bench(c: &mut Criterion) {
    let opts = CheckOptions::default();
    let mut g = c.benchmark_group("push_check");
    g.throughput(Throughput::Elements(1));
    for k in 1..=3 {
        let m = model(k);
        assert!(convex::margin(&m, Dim::D2, &opts).is_some_and(|x| x > 0.0));
        assert!(convex::margin(&m, Dim::D3, &opts).is_some_and(|x| x > 0.0));
        g.bench_with_input(BenchmarkId::new("2d", k), &m, |b, m| {
            b.iter(|| convex::margin(black_box(m), Dim::D2, &opts))
        });
        g.bench_with_input(BenchmarkId::new("3d", k), &m, |b, m| {
            b.iter(|| convex::margin(black_box(m), Dim::D3, &opts))
        });
        g.bench_with_input(BenchmarkId::new("2d_fresh_solver", k), &m, |b, m| {
            convex::set_solver_reuse(false);
            b.iter(|| convex::margin(black_box(m), Dim::D2, &opts));
            convex::set_solver_reuse(true);
        });
        g.bench_with_input(BenchmarkId::new("2d_report", k), &m, |b, m| {
            b.iter(|| convex::check(black_box(m), Dim::D2, &opts))
        });
        let l = line(k);
        let gaps = vec![true; k - 1];
        g.bench_with_input(BenchmarkId::new("2d_planner_uncached", k), &l, |b, l| {
            b.iter(|| {
                // A pusher position never seen before each call defeats the geometry cache.
                let n = CALLS.fetch_add(1, Ordering::Relaxed);
                let mut l = l.clone();
                l.pusher[0] += 1e-12 * (n % 1_000_000_000) as f64;
                push::geometry_margin(black_box(&l), &gaps)
            })
        });
        g.bench_with_input(BenchmarkId::new("2d_planner_cached", k), &l, |b, l| {
            b.iter(|| push::geometry_margin(black_box(l), &gaps))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

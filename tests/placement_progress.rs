//! The exact placement sends progress events: nodes never go down, the proven bound on the
//! occupied area never goes down and never passes the incumbent, and neither passes what the
//! stage finally reports.

use pushpack::control::{Event, Never, Recorder, Stage};
use pushpack::instance::generate::consecutive_squares_toml;
use pushpack::instance::Instance;
use pushpack::plan::{solve_placement_with, PlacementSolver};

#[test]
fn placement_progress_is_monotone_and_bounded() {
    // Squares 1…16: about 0.5 s of exact placement on the 2-core machine (both stages), five
    // times the 0.1 s between events. A search that ends within one interval sends
    // none (`control::Ticker`), so the instance must stay well above it as the search gets
    // faster: squares 1…14 took 2 s when this test was written and 0.1 s on 2026-11-26.
    let inst = Instance::parse(&consecutive_squares_toml(16, None), false, "<squares>", None).unwrap();
    let mut rec = Recorder::default();
    let (r, _) = solve_placement_with(&inst, PlacementSolver::Milp, 1, 5, 120.0, 1, &Never, &mut rec).unwrap();
    let progress: Vec<(u64, Option<f64>, Option<f64>)> = rec
        .0
        .iter()
        .map(|e| match e {
            Event::Progress {
                stage,
                nodes,
                incumbent,
                bound,
            } => {
                assert_eq!(*stage, Stage::Placement);
                (*nodes, *incumbent, *bound)
            }
            other => panic!("only progress events come from the placement: {other:?}"),
        })
        .collect();
    assert!(!progress.is_empty(), "no progress event in {:.2} s", r.time_s);
    let area = r.placement.occupied_area();
    for w in progress.windows(2) {
        let ((n0, _, b0), (n1, _, b1)) = (w[0], w[1]);
        assert!(n1 >= n0, "nodes went down: {n0} -> {n1}");
        if let Some(b0) = b0 {
            let b1 = b1.expect("a bound once known stays known");
            assert!(b1 >= b0, "bound went down: {b0} -> {b1}");
        }
    }
    for &(n, inc, b) in &progress {
        assert!(n <= r.nodes, "{n} nodes reported, {} at the end", r.nodes);
        if let (Some(i), Some(b)) = (inc, b) {
            assert!(b <= i + 1e-12, "bound {b} above incumbent {i}");
        }
        if let Some(b) = b {
            assert!(b <= area + 1e-12, "bound {b} above the final area {area}");
        }
        if let Some(i) = inc {
            assert!(i >= area - 1e-12, "incumbent {i} below the final area {area}");
        }
    }
    // The node count moves while the searches run, not only between them.
    assert!(progress.last().unwrap().0 > progress[0].0 || progress.len() == 1);
}

//! The two sequencers against each other on the committed random set `instances/random/n04`:
//! A*'s action space contains every plan of the paper's Algorithms 1 + 2 (direct places,
//! stacked and staggered releases at offsets `d, 2d, …` up to the line length, line pushes), so
//! its proven optimum is never worse than the paper's plan on any cost component, taken
//! lexicographically. Both plans go through the verifier.

mod common;

use pushpack::instance::Instance;
use pushpack::plan::{optimize, PlacementSolver, PlanOptions, Sequencer};
use pushpack::sequence::SearchStatus;
use pushpack::verify::verify;

fn plan(inst: &Instance, sequencer: Sequencer) -> pushpack::plan::PlanOutcome {
    let mut o = PlanOptions::from_instance(inst);
    o.placement = PlacementSolver::Bl;
    o.sequencer = sequencer;
    let out = optimize(inst, &o).unwrap_or_else(|e| panic!("{}: {e}", inst.name));
    let r = verify(inst, &out.plan);
    assert!(r.is_valid(), "{} {sequencer:?}: {r}", inst.name);
    out
}

#[test]
fn astar_is_never_worse_than_the_paper_sequencer() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("instances/random/n04");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "instances/random/n04 should hold the committed set");
    let mut shorter = 0;
    for f in files.iter().take(10) {
        let inst = Instance::load(f).unwrap();
        let a = plan(&inst, Sequencer::Astar);
        let p = plan(&inst, Sequencer::Paper);
        assert_eq!(a.sequence.status, SearchStatus::Complete, "{}", inst.name);
        let (ma, mp) = (a.plan.metrics, p.plan.metrics);
        let key = |m: &pushpack::sequence::Metrics| (m.seq_len, m.swept_area, m.travel);
        let (ka, kp) = (key(&ma), key(&mp));
        let not_worse = ka.0 < kp.0
            || (ka.0 == kp.0 && ka.1 < kp.1 - 1e-12)
            || (ka.0 == kp.0 && (ka.1 - kp.1).abs() <= 1e-12 && ka.2 <= kp.2 + 1e-9);
        assert!(not_worse, "{}: A* {ka:?} vs paper {kp:?}", inst.name);
        shorter += usize::from(ka.0 < kp.0);
    }
    println!("A* shorter than the paper sequencer on {shorter} of 10");
}

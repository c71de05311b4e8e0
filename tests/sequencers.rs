//! The two sequencers against each other on the committed random set `instances/random/n04`:
//! A*'s action space contains every plan of the paper's Algorithms 1 + 2 (direct places,
//! stacked and staggered releases at offsets `d, 2d, …` up to the line length, line pushes by
//! either arm), so its proven optimum is never worse than the paper's plan, taken
//! lexicographically over (actions, swept area, travel). Both plans go through the verifier.
//! Before A* allowed `k·d` offsets to the k-th object of a line, the paper's sequencer found a
//! shorter plan on 10 of these 20 instances.

mod common;

use pushpack::instance::Instance;
use pushpack::plan::{optimize, PlacementSolver, PlanOptions, Sequencer};
use pushpack::sequence::SearchStatus;
use pushpack::verify::verify;

fn plan(inst: &Instance, sequencer: Sequencer) -> Option<pushpack::plan::PlanOutcome> {
    let mut o = PlanOptions::from_instance(inst);
    o.placement = PlacementSolver::Bl;
    o.sequencer = sequencer;
    o.packing_only = common::packing_study(inst);
    match optimize(inst, &o) {
        Ok(out) => {
            let r = verify(inst, &out.plan);
            assert!(r.is_valid(), "{} {sequencer:?}: {r}", inst.name);
            Some(out)
        }
        // A complete search of its space found no plan; anything else (a stop) fails the test.
        Err(pushpack::error::Error::Infeasible { .. }) => None,
        Err(e) => panic!("{} {sequencer:?}: {e}", inst.name),
    }
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
    assert!(files.len() >= 20, "instances/random/n04 should hold the committed set");
    let (mut shorter, mut only_astar, mut compared) = (0, 0, 0);
    for f in &files {
        let inst = Instance::load(f).unwrap();
        let a = plan(&inst, Sequencer::Astar);
        let p = plan(&inst, Sequencer::Paper);
        let (a, p) = match (a, p) {
            (Some(a), Some(p)) => (a, p),
            (Some(_), None) => {
                only_astar += 1; // the paper's candidate space has no feasible order
                continue;
            }
            (None, None) => continue,
            (None, Some(_)) => panic!("{}: the paper sequencer found a plan, A* proved none exists", inst.name),
        };
        assert_eq!(a.sequence.status, SearchStatus::Complete, "{}", inst.name);
        assert_eq!(p.sequence.status, SearchStatus::Complete, "{}", inst.name);
        let (ma, mp) = (a.plan.metrics, p.plan.metrics);
        let key = |m: &pushpack::sequence::Metrics| (m.seq_len, m.swept_area, m.travel);
        let (ka, kp) = (key(&ma), key(&mp));
        let not_worse = ka.0 < kp.0
            || (ka.0 == kp.0 && ka.1 < kp.1 - 1e-12)
            || (ka.0 == kp.0 && (ka.1 - kp.1).abs() <= 1e-12 && ka.2 <= kp.2 + 1e-9);
        assert!(not_worse, "{}: A* {ka:?} vs paper {kp:?}", inst.name);
        shorter += usize::from(ka.0 < kp.0);
        compared += 1;
    }
    println!(
        "{compared} compared, A* shorter on {shorter}; {only_astar} with a plan from A* only (of {})",
        files.len()
    );
    assert!(
        compared >= 15,
        "only {compared} instances had plans from both sequencers"
    );
}

/// A committed instance, its Bottom-Left placement (seed 0, 8 orders) and sequence options
/// with every action kind allowed and no node limit.
fn bl_setup(
    rel: &str,
) -> (
    Instance,
    pushpack::placement::Placement,
    pushpack::sequence::SequenceOptions,
) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    let inst = Instance::load(&path).unwrap();
    let placement = pushpack::placement::bl::solve(&inst, 0, 8, &pushpack::control::TimeLimit::new(30.0))
        .unwrap()
        .placement;
    let opts = pushpack::sequence::SequenceOptions {
        no_direct: false,
        no_multi_push: false,
        max_nodes: u64::MAX,
        vetoes: Vec::new(),
    };
    (inst, placement, opts)
}

/// A terminator that fires on its first query: deterministic, unlike a short time limit.
struct StopNow;

impl pushpack::control::Terminator for StopNow {
    fn should_stop(&self) -> bool {
        true
    }
}

/// Algorithm 1 enumerates `3^N` assignments (531,441 at twelve objects, minutes of work): it must
/// ask the terminator while it enumerates, and a sequencer stopped before any plan says so with
/// `Error::Stopped`, not `Infeasible` (nothing was proven).
#[test]
fn paper_sequencer_stops_in_algorithm_1_and_says_so() {
    use pushpack::sequence::paper;
    let (inst, placement, opts) = bl_setup("instances/random/n12/n12_k4_s0001.toml");
    match paper::solve(&inst, &placement, &opts, &StopNow) {
        Err(pushpack::error::Error::Stopped {
            stage, limit, nodes, ..
        }) => {
            assert!(stage.contains("Algorithm 1"), "stopped in {stage}");
            assert_eq!(limit, pushpack::status::Limit::Time);
            assert_eq!(nodes, 0);
        }
        Err(e) => panic!("expected Error::Stopped, got {e}"),
        Ok(r) => panic!("a terminator that always fires still gave a plan ({:?})", r.status),
    }
}

/// Algorithm 1 holds every candidate in memory (a 16-object run once filled 22 GB within a
/// minute), so it stops at a cap: exactly when the candidates outnumber it, not before.
#[test]
fn paper_algorithm_1_stops_at_its_candidate_cap_and_not_before() {
    use pushpack::control::TimeLimit;
    use pushpack::sequence::paper::{candidates, CandidatesStop};
    let (inst, placement, opts) = bl_setup("instances/paper/exp2_8objects.toml");
    let stop = TimeLimit::new(600.0);
    let all = candidates(&inst, &placement, &opts, usize::MAX, &stop).expect("the full space fits");
    assert!(all.len() > 1000, "exp2 has {} candidates", all.len());
    let at_cap = candidates(&inst, &placement, &opts, all.len(), &stop).expect("exactly at the cap");
    assert_eq!(at_cap, all, "a cap the space fits in changes nothing");
    assert_eq!(
        candidates(&inst, &placement, &opts, all.len() - 1, &stop),
        Err(CandidatesStop::Candidates)
    );
}

/// A* stopped before any plan still reports what it proved: the fewest actions any plan needs,
/// in the error and its message. Checked against the optimum of a full run on the paper's
/// eight-object instance (the stopped bound may be weaker, never above it), and against the
/// count no bound may fall below (one placement per object).
#[test]
fn astar_stopped_without_a_plan_reports_its_proven_bound() {
    use pushpack::control::TimeLimit;
    use pushpack::sequence::astar::{self, AstarSettings};
    let (inst, placement, opts) = bl_setup("instances/paper/exp2_8objects.toml");
    let full = astar::solve(
        &inst,
        &placement,
        &opts,
        &AstarSettings::default(),
        &TimeLimit::new(120.0),
    )
    .unwrap();
    assert_eq!(full.status, SearchStatus::Complete);
    let optimum = full.metrics.seq_len;
    match astar::solve(&inst, &placement, &opts, &AstarSettings::default(), &StopNow) {
        Err(e @ pushpack::error::Error::Stopped { .. }) => {
            let pushpack::error::Error::Stopped { min_actions, .. } = &e else {
                unreachable!()
            };
            let m = min_actions.expect("A* has a bound from its root");
            assert!(
                m >= inst.n() && m <= optimum,
                "bound {m}, optimum {optimum}, {} objects",
                inst.n()
            );
            assert!(e.to_string().contains(&format!("at least {m} actions")), "{e}");
        }
        Err(e) => panic!("expected Error::Stopped, got {e}"),
        Ok(r) => panic!("a terminator that always fires still gave a plan ({:?})", r.status),
    }
}

/// `n08_k4_s0011` behind 12 cm walls: its Bottom-Left placement has no plan (A* proves it at its
/// root: the hand housing, 10 cm above the fingertips, cannot work next to those walls). With
/// `placement_alternatives` the planner moves on to the next distinct Bottom-Left placements,
/// each skipped one proven to have no plan as well, and returns a valid plan on the first that
/// has one, saying which.
#[test]
fn a_placement_proven_to_have_no_plan_falls_back_to_the_next_bl_placement() {
    use pushpack::control::TimeLimit;
    use pushpack::placement::bl;
    use pushpack::sequence::astar::{self, AstarSettings};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("instances/random/n08/n08_k4_s0011.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("wall_height = 0.1\n"));
    let text = text.replace("wall_height = 0.1\n", "wall_height = 0.12\n");
    let inst = Instance::parse(&text, false, "n08_k4_s0011 with 12 cm walls", None).unwrap();
    let mut o = PlanOptions::from_instance(&inst);
    o.placement = PlacementSolver::Bl;
    o.packing_only = common::packing_study(&inst);
    // Long enough for A*'s first dive on a loaded CI machine (2 s idle); the search then runs
    // to the limit without a proof, which this test does not need.
    o.time_limit = 30.0;
    match optimize(&inst, &o) {
        Err(pushpack::error::Error::Infeasible { .. }) => {}
        other => panic!(
            "the default keeps the placement, which has no plan: {:?}",
            other.map(|x| x.plan.metrics)
        ),
    }
    o.placement_alternatives = 5;
    let out = optimize(&inst, &o).expect("an alternative placement has a plan");
    let r = verify(&inst, &out.plan);
    assert!(r.is_valid(), "{r}");
    let k = out.plan.placement.alternative;
    assert!((1..=5).contains(&k), "alternative {k}");
    assert_eq!(
        out.plan.placement.status,
        pushpack::status::Status::Heuristic,
        "Bottom-Left placements throughout: nothing is proven about the area"
    );

    // The placement used is the k-th distinct Bottom-Left placement after the stage's own, and
    // every one skipped before it is proven to have no plan.
    let stop = TimeLimit::new(60.0);
    let first = bl::solve(&inst, o.seed, o.bl_orders, &stop).unwrap().placement;
    let alts: Vec<_> = bl::alternatives(&inst, o.seed, o.bl_orders, &stop)
        .into_iter()
        .filter(|p| *p != first)
        .collect();
    assert_eq!(out.placement.placement, alts[k - 1]);
    assert!(out.placement.placement.occupied_area() >= first.occupied_area() - 1e-12);
    let opts = pushpack::sequence::SequenceOptions {
        no_direct: false,
        no_multi_push: false,
        max_nodes: o.max_nodes,
        vetoes: Vec::new(),
    };
    for p in std::iter::once(&first).chain(&alts[..k - 1]) {
        match astar::solve(&inst, p, &opts, &AstarSettings::default(), &TimeLimit::new(30.0)) {
            Err(pushpack::error::Error::Infeasible { .. }) => {}
            Err(e) => panic!("a skipped placement: {e}"),
            Ok(r) => panic!("a skipped placement has a plan of {} actions", r.metrics.seq_len),
        }
    }
}

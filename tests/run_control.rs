//! One run control for the whole run: a terminator that fires mid-run stops it with the best
//! plan so far (a status, not an error), the listener hears every stage, and `pushpack plan`
//! stops cleanly on Ctrl+C and writes what it has.

mod common;

use pushpack::control::{Event, Recorder, Stage, Terminator, PROGRESS_INTERVAL};
use pushpack::plan::{optimize_with, PlanOptions, Sequencer};
use pushpack::status::{Limit, Status};
use pushpack::verify::verify;
use std::cell::Cell;

/// Fires from its `n`-th question on: deterministic, unlike a clock.
struct FiresAfter {
    asked: Cell<u64>,
    n: u64,
}

impl Terminator for FiresAfter {
    fn should_stop(&self) -> bool {
        self.asked.set(self.asked.get() + 1);
        self.asked.get() >= self.n
    }
}

/// The `Progress` events of one stage: (nodes, incumbent, bound). Every stage of a run reports,
/// so a test of one search looks at its own stage's events.
fn progress_of(events: &Recorder, of: Stage) -> Vec<(u64, Option<f64>, Option<f64>)> {
    events
        .0
        .iter()
        .filter_map(|e| match e {
            Event::Progress {
                stage,
                nodes,
                incumbent,
                bound,
            } if *stage == of => Some((*nodes, *incumbent, *bound)),
            _ => None,
        })
        .collect()
}

/// A 16-object instance whose A* search runs long enough to be interrupted with a plan in hand.
const LONG: &str = "random/n16/n16_k4_s0001.toml";

/// [`LONG`] planned by A* within `time_limit` seconds, as a packing study (the committed
/// 16-object set allows any orientation).
fn long_astar(time_limit: f64) -> (pushpack::instance::Instance, PlanOptions) {
    let inst = common::load(LONG);
    let mut o = PlanOptions::from_instance(&inst);
    o.sequencer = Sequencer::Astar;
    o.time_limit = time_limit;
    o.packing_only = true;
    (inst, o)
}

#[test]
fn a_terminator_that_fires_mid_search_returns_the_best_plan_so_far_marked_cancelled() {
    let (inst, o) = long_astar(600.0);
    let stop = FiresAfter {
        asked: Cell::new(0),
        n: 300,
    };
    let mut events = Recorder::default();
    let out = optimize_with(&inst, &o, &stop, &mut events).expect("the search has an incumbent when it is stopped");
    let seq = &out.plan.solver.sequence;
    assert_eq!(seq.stopped_by, Some(Limit::Cancel), "{seq:?}");
    assert_eq!(seq.status, Status::Feasible, "stopped early: a bound, not a proof");
    assert!(out.plan.status.has_solution() && out.plan.status != Status::Optimal);
    let r = verify(&inst, &out.plan);
    assert!(r.is_valid(), "{r}");

    // Every stage started and finished, in pipeline order.
    let finished: Vec<Stage> = events
        .0
        .iter()
        .filter_map(|e| match e {
            Event::StageFinished { stage, .. } => Some(*stage),
            _ => None,
        })
        .collect();
    assert_eq!(finished, [Stage::Placement, Stage::Sequence, Stage::Motion]);
}

/// The A* search reports from inside: nodes that only grow, a bound that never passes the best
/// plan, and no more often than the documented interval.
#[test]
fn the_sequence_search_reports_its_progress_at_most_every_interval() {
    let (inst, o) = long_astar(2.0);
    let mut events = Recorder::default();
    let start = std::time::Instant::now();
    let out = optimize_with(&inst, &o, &pushpack::control::Never, &mut events);
    let elapsed = start.elapsed();
    let progress = progress_of(&events, Stage::Sequence);
    let seq_s = out.map(|o| o.plan.solver.sequence.time_s);
    assert!(
        !progress.is_empty(),
        "a search of about a second reports (sequence time {seq_s:?} s)"
    );
    assert!(progress.len() as f64 <= elapsed.as_secs_f64() / PROGRESS_INTERVAL.as_secs_f64() + 1.0);
    let mut last_nodes = 0;
    for (nodes, incumbent, bound) in progress {
        assert!(nodes >= last_nodes);
        last_nodes = nodes;
        if let (Some(i), Some(b)) = (incumbent, bound) {
            assert!(b <= i, "bound {b} above the best plan {i}");
        }
    }
}

#[test]
fn a_terminator_that_fires_at_once_is_a_status_without_a_plan_not_a_crash() {
    let inst = common::load(LONG);
    let o = PlanOptions::from_instance(&inst);
    let stop = FiresAfter {
        asked: Cell::new(0),
        n: 1,
    };
    match optimize_with(&inst, &o, &stop, &mut Recorder::default()) {
        Ok(out) => {
            // Bottom-Left may finish its first order before it asks; then the sequencer stops.
            assert!(out.plan.solver.sequence.stopped_by.is_some());
            let r = verify(&inst, &out.plan);
            assert!(r.is_valid(), "{r}");
        }
        Err(e) => assert!(e.status().is_some(), "a stop is a status, got the error {e}"),
    }
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_pushpack_plan_cleanly_and_writes_the_best_plan_so_far() {
    use std::process::{Command, Stdio};
    let out = tempfile::tempdir().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args([
            "plan",
            &common::bundled(LONG),
            "--packing-only",
            "--time-limit",
            "600",
            "--out",
        ])
        .arg(out.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Long enough for the placement stage and the first incumbent of the sequence search.
    std::thread::sleep(std::time::Duration::from_secs(4));
    let pid = child.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
    let result = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&result.stdout);
    let stderr = String::from_utf8_lossy(&result.stderr);
    let plan = out.path().join("plan.json");
    if plan.exists() {
        let p = pushpack::plan::Plan::load(&plan).unwrap();
        assert_eq!(p.solver.sequence.stopped_by, Some(Limit::Cancel), "{stdout}\n{stderr}");
        let inst = common::load(LONG);
        let r = verify(&inst, &p);
        assert!(r.is_valid(), "{r}");
        assert!(stdout.contains("stopped by the cancel limit"), "{stdout}");
    } else {
        // Stopped before any plan: the placement is written and the status said.
        assert!(out.path().join("placement.json").exists(), "{stdout}\n{stderr}");
        assert!(stderr.contains("status"), "{stderr}");
    }
    assert!(stderr.contains("stopping"), "the user is told what happens: {stderr}");
}

/// The paper sequencer reports too, through both of its algorithms: nodes that only grow (the
/// assignments of Algorithm 1, then Algorithm 2's nodes on top) and never a bound, since it
/// proves none. `n12_k4_s0002`'s Bottom-Left placement keeps Algorithm 2 busy past its node limit.
#[test]
fn the_paper_sequencer_reports_its_progress_and_no_bound() {
    let inst = common::load("random/n12/n12_k4_s0002.toml");
    let mut o = PlanOptions::from_instance(&inst);
    o.sequencer = Sequencer::Paper;
    o.placement = pushpack::plan::PlacementSolver::Bl;
    o.packing_only = true;
    o.max_nodes = 300_000;
    o.time_limit = 60.0;
    let mut events = Recorder::default();
    let start = std::time::Instant::now();
    let out = optimize_with(&inst, &o, &pushpack::control::Never, &mut events);
    let elapsed = start.elapsed();
    let progress = progress_of(&events, Stage::Sequence);
    assert!(
        progress.len() >= 2,
        "a search of {elapsed:?} reports more than once: {progress:?} ({:?})",
        out.err()
    );
    assert!(progress.len() as f64 <= elapsed.as_secs_f64() / PROGRESS_INTERVAL.as_secs_f64() + 1.0);
    let mut last_nodes = 0;
    for (nodes, _, bound) in progress {
        assert!(nodes >= last_nodes, "nodes went from {last_nodes} down to {nodes}");
        last_nodes = nodes;
        assert_eq!(bound, None, "the paper sequencer proves no bound");
    }
}

/// The joint plan reports too: `nodes` counts the actions with trajectories, rising to the
/// plan's length, never past it.
#[test]
fn the_joint_plan_reports_the_actions_it_has_planned() {
    let inst = common::load("paper/exp2_8objects.toml");
    let o = PlanOptions::from_instance(&inst);
    let mut events = Recorder::default();
    let out = optimize_with(&inst, &o, &pushpack::control::Never, &mut events).expect("exp2 plans");
    let actions = out.plan.actions.len() as u64;
    let motion_s = events
        .0
        .iter()
        .find_map(|e| match e {
            Event::StageFinished {
                stage: Stage::Motion,
                time_s,
                ..
            } => Some(*time_s),
            _ => None,
        })
        .expect("the motion stage finishes");
    let planned: Vec<u64> = events
        .0
        .iter()
        .filter_map(|e| match e {
            Event::Progress {
                stage: Stage::Motion,
                nodes,
                incumbent,
                bound,
            } => {
                assert_eq!((incumbent, bound), (&None, &None), "the joint plan optimises nothing");
                Some(*nodes)
            }
            _ => None,
        })
        .collect();
    // The first event is due one interval after the stage starts.
    if motion_s > 2.0 * PROGRESS_INTERVAL.as_secs_f64() {
        assert!(!planned.is_empty(), "{motion_s:.2} s of joint planning without a word");
    }
    assert!(planned.windows(2).all(|w| w[0] <= w[1]), "{planned:?}");
    assert!(
        planned.iter().all(|&k| k <= actions),
        "{planned:?} of {actions} actions"
    );
    let r = verify(&inst, &out.plan);
    assert!(r.is_executable(), "{r}");
}

/// A terminator that fires before the sequence search has any plan ends the run with the
/// error that says it was cancelled, not that it ran out of time (the run's clock had hours
/// left).
#[test]
fn a_terminator_that_fires_before_any_plan_is_a_cancel_not_a_time_limit() {
    let (inst, o) = long_astar(600.0);
    let stop = FiresAfter {
        asked: Cell::new(0),
        n: 20,
    };
    let mut events = Recorder::default();
    match optimize_with(&inst, &o, &stop, &mut events) {
        Err(e @ pushpack::error::Error::Stopped { limit, .. }) => {
            assert_eq!(limit, Limit::Cancel, "{e}");
            assert_eq!(e.status(), Some(Status::Cancelled), "{e}");
        }
        other => panic!(
            "expected a cancelled search without a plan, got {:?}",
            other.map(|o| o.plan.status)
        ),
    }
}

//! plan.json format 2 states every outcome in the one vocabulary of `pushpack::status::Status`,
//! and format 1 files are still read: their sequencer words are restated by what the planner
//! could prove (the paper's sequencer never proves anything).

mod common;

use pushpack::plan::{optimize, Plan, PlanOptions, Sequencer, FORMAT_VERSION};
use pushpack::status::Status;
use pushpack::verify::verify;
use serde_json::{json, Value};

/// A version-2 plan rewritten as version 1 wrote it: no run status, no `stopped_by`, the
/// sequencer's own word for how its search ended and `feasible` for Bottom-Left.
fn as_version_1(plan: &Plan, sequence_word: &str) -> String {
    let mut v = serde_json::to_value(plan).unwrap();
    v["format_version"] = json!(1);
    v.as_object_mut().unwrap().remove("status");
    let p = if plan.placement.status == Status::Optimal {
        "optimal"
    } else {
        "feasible"
    };
    v["placement"]["status"] = json!(p);
    v["solver"]["placement"]["status"] = json!(p);
    v["solver"]["sequence"]["status"] = json!(sequence_word);
    v["solver"]["sequence"].as_object_mut().unwrap().remove("stopped_by");
    serde_json::to_string(&v).unwrap()
}

#[test]
fn a_paper_sequencer_plan_is_heuristic_and_an_astar_plan_on_an_optimal_placement_is_optimal() {
    let inst = common::load("paper/exp1_4objects.toml");
    let mut o = PlanOptions::from_instance(&inst);
    let astar = optimize(&inst, &o).unwrap();
    assert_eq!(astar.plan.format_version, FORMAT_VERSION);
    assert_eq!(astar.plan.placement.status, Status::Optimal);
    assert_eq!(astar.plan.solver.sequence.status, Status::Optimal);
    assert_eq!(astar.plan.status, Status::Optimal);
    o.sequencer = Sequencer::Paper;
    let paper = optimize(&inst, &o).unwrap();
    assert_eq!(paper.plan.solver.sequence.status, Status::Heuristic);
    assert_eq!(
        paper.plan.status,
        Status::Heuristic,
        "the paper's sequencer proves nothing"
    );
    for out in [&astar, &paper] {
        let r = verify(&inst, &out.plan);
        assert!(r.is_valid(), "{r}");
    }
}

#[test]
fn version_1_plans_are_read_with_their_statuses_restated() {
    let inst = common::load("paper/exp1_4objects.toml");
    let mut o = PlanOptions::from_instance(&inst);
    let astar = optimize(&inst, &o).unwrap().plan;
    o.sequencer = Sequencer::Paper;
    let paper = optimize(&inst, &o).unwrap().plan;

    let back = Plan::from_json(&as_version_1(&astar, "complete"), "v1.json").unwrap();
    assert_eq!(back.format_version, 1);
    assert_eq!(back.solver.sequence.status, Status::Optimal);
    assert_eq!(back.status, Status::Optimal);
    let r = verify(&inst, &back);
    assert!(r.is_valid(), "a version-1 plan verifies: {r}");

    // `complete` from the paper's sequencer was never a proof.
    let back = Plan::from_json(&as_version_1(&paper, "complete"), "v1.json").unwrap();
    assert_eq!(back.solver.sequence.status, Status::Heuristic);
    assert_eq!(back.status, Status::Heuristic);

    // An A* search stopped by its time limit with a plan has a bound and a gap: feasible.
    let back = Plan::from_json(&as_version_1(&astar, "time_limit"), "v1.json").unwrap();
    assert_eq!(back.solver.sequence.status, Status::Feasible);
    assert_eq!(back.status, Status::Feasible);
}

#[test]
fn malformed_documents_are_errors_naming_the_file_never_panics() {
    for text in [
        "[]",
        "17",
        r#"{"format_version": 1, "placement": 5}"#,
        r#"{"format_version": 1, "solver": {"sequence": 3}}"#,
        r#"{"format_version": 1, "options": [], "placement": {"status": "feasible"}}"#,
        "{not json",
    ] {
        let e = Plan::from_json(text, "broken.json").expect_err(text);
        assert!(e.to_string().contains("broken.json"), "{text}: {e}");
    }
    let ok: Value = serde_json::from_str(r#"{"a": 1}"#).unwrap();
    assert!(ok.is_object());
}

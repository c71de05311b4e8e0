//! Physics is part of what "executable" means (issue 64; docs/push_stability.md §12–13).
//! `instances/physics/drag_n08.toml` turns the side-contact rule off: its optimal plan then
//! pushes a line past two released boxes and drags one 15 mm along. The verifier must reject
//! that plan for its physics, the planner's replay loop must plan around it, and the side rule
//! alone must avoid it too.

mod common;

use pushpack::plan::{optimize, PlacementSolver, PlanOptions};
use pushpack::verify::{verify, ViolationClass};

fn options(inst: &pushpack::Instance, physics: bool) -> PlanOptions {
    let mut o = PlanOptions::from_instance(inst);
    o.placement = PlacementSolver::Milp;
    o.physics = physics;
    o
}

#[test]
fn a_plan_that_drags_a_neighbour_is_not_executable_and_the_replay_loop_plans_around_it() {
    let inst = common::load("physics/drag_n08.toml");
    assert!(!inst.settings.side_contacts, "the instance turns the side rule off");

    let blind = optimize(&inst, &options(&inst, false)).expect("a plan");
    assert!(blind.plan.solver.sequence.physics_vetoes.is_empty());
    let report = verify(&inst, &blind.plan);
    assert!(
        report.violations.is_empty() && report.robot_issues.is_empty(),
        "{report}"
    );
    assert!(!report.is_executable() && !report.is_valid(), "{report}");
    let drag = report
        .physics_issues
        .iter()
        .find(|v| v.class == ViolationClass::Physics && v.step.is_some())
        .unwrap_or_else(|| panic!("an action out of tolerance: {report}"));
    assert!(drag.message.contains("another box moves"), "{drag}");

    let seen = optimize(&inst, &options(&inst, true)).expect("a plan");
    assert!(
        !seen.plan.solver.sequence.physics_vetoes.is_empty(),
        "the loop vetoed something"
    );
    let report = verify(&inst, &seen.plan);
    assert!(report.is_executable(), "{report}");
}

#[test]
fn the_side_rule_alone_keeps_the_line_from_dragging_a_released_box() {
    let mut inst = common::load("physics/drag_n08.toml");
    inst.settings.side_contacts = true;
    let out = optimize(&inst, &options(&inst, false)).expect("a plan");
    let report = pushpack::verify::verify(&inst, &out.plan);
    assert!(report.is_executable(), "{report}");
}

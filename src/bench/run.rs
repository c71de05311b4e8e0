//! One benchmark run in this process: plan an instance with one planner, verify the plan, and
//! turn everything into a [`ResultRow`]. Errors and panics become `failed` rows, never aborts.

use super::row::{machine, tool_version, ResultRow, RunStatus};
use super::spec::PlannerSpec;
use crate::control::{Never, Silent};
use crate::instance::Instance;
use crate::plan::optimize_stages;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::time::Instant;

/// Set name of an instance path: its parent folder's name (empty for a bare file name).
pub fn set_name(path: &str) -> String {
    Path::new(path)
        .parent()
        .and_then(|p| p.file_name())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// A row with the instance and planner filled in and no results yet (status `failed`).
pub fn base_row(path: &str, inst: &Instance, spec: &PlannerSpec, time_limit: f64) -> ResultRow {
    let (tool_version, git_commit) = tool_version();
    ResultRow {
        instance: path.to_string(),
        instance_digest: inst.digest.clone(),
        set: set_name(path),
        name: inst.name.clone(),
        objects: inst.n(),
        kinds: inst.kinds.len(),
        planner: spec.to_string(),
        seed: inst.settings.seed,
        time_limit_s: time_limit,
        status: RunStatus::Error,
        error: None,
        placement_status: None,
        occupied_area: None,
        placement_bound: None,
        placement_gap: None,
        contact_length: None,
        placement_alternative: None,
        seq_len: None,
        n_place_direct: None,
        n_place_indirect: None,
        n_push: None,
        n_multi_push: None,
        swept_area: None,
        travel: None,
        min_push_margin: None,
        sequence_status: None,
        sequence_bound_len: None,
        sequence_bound_area: None,
        sequence_bound_travel: None,
        sequence_gap: None,
        placement_nodes: None,
        sequence_nodes: None,
        sequence_assignments: None,
        placement_time_s: None,
        sequence_time_s: None,
        plan_time_s: None,
        verify_time_s: None,
        wall_time_s: 0.0,
        verify: None,
        violations: None,
        robot_issues: None,
        robot_time_s: None,
        sim_ok: None,
        sim_position_error_mm: None,
        sim_rotation_deg: None,
        sim_time_s: None,
        host: machine().0,
        cpu_model: machine().1,
        jobs: None,
        tool_version,
        git_commit,
    }
}

/// Text of a panic payload.
fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-text payload".into()
    }
}

/// The `sim_*` columns. A replay that cannot run (the plan does not match its instance, which
/// the verifier has reported already) leaves them empty and says why in `error`.
fn simulate_row(row: &mut ResultRow, inst: &Instance, plan: &crate::plan::Plan) {
    let opts = crate::simulate::SimOptions::from_instance(inst);
    match catch_unwind(AssertUnwindSafe(|| crate::simulate::simulate(inst, plan, &opts))) {
        Ok(Ok(s)) => {
            let (pos, rot) = s.worst();
            row.sim_ok = Some(s.ok);
            row.sim_position_error_mm = Some(pos);
            row.sim_rotation_deg = Some(rot);
            row.sim_time_s = Some(s.wall_s);
        }
        Ok(Err(e)) => row.error = Some(format!("simulate: {e}")),
        Err(p) => row.error = Some(format!("simulate: panic: {}", panic_message(p.as_ref()))),
    }
}

/// Plan `inst` with `spec` (the run's `time_limit`), verify, and fill the row. When a later
/// stage ends without a plan, the placement's fields are kept.
pub fn run_in_process(path: &str, inst: &Instance, spec: &PlannerSpec, time_limit: f64) -> ResultRow {
    let start = Instant::now();
    let mut row = base_row(path, inst, spec, time_limit);
    let opts = spec.options(inst, time_limit);
    let result = catch_unwind(AssertUnwindSafe(|| {
        let t = Instant::now();
        let (placed, out) = optimize_stages(inst, &opts, &Never, &mut Silent);
        let out = out.map_err(|e| (e, placed.map(Box::new)))?;
        let plan_time = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let report =
            crate::verify::verify_with(inst, &out.plan, &crate::verify::VerifyOptions { physics: opts.physics });
        Ok::<_, (crate::error::Error, Option<Box<crate::placement::PlacementResult>>)>((
            out,
            plan_time,
            report,
            t.elapsed().as_secs_f64(),
        ))
    }));
    match result {
        Err(p) => {
            row.status = RunStatus::Crashed;
            row.error = Some(format!("panic: {}", panic_message(p.as_ref())));
        }
        Ok(Err((e, placed))) => {
            if let Some(p) = placed {
                let status = crate::plan::placement_status(&p);
                row.placement_status = Some(status.as_str().to_string());
                row.occupied_area = Some(p.placement.occupied_area());
                row.placement_bound = Some(p.lower_bound);
                row.placement_gap = Some(p.gap());
                row.contact_length = Some(p.placement.contact_length(inst));
                row.placement_nodes = Some(p.nodes);
                row.placement_time_s = Some(p.time_s);
            }
            // A run stopped by a limit, or proven to have no plan, ended with a status; any
            // other error stays an error.
            if let Some(status) = e.status() {
                row.status = status.into();
            }
            if let crate::error::Error::Stopped { min_actions, .. } = &e {
                row.sequence_bound_len = *min_actions;
            }
            row.error = Some(e.to_string());
        }
        Ok(Ok((out, plan_time, report, verify_time))) => {
            let plan = &out.plan;
            let m = plan.metrics;
            let (ps, ss) = (&plan.solver.placement, &plan.solver.sequence);
            row.status = plan.status.into();
            row.placement_status = Some(ps.status.as_str().to_string());
            row.occupied_area = Some(plan.placement.occupied_area);
            row.placement_bound = Some(plan.placement.lower_bound);
            row.placement_gap = Some(plan.placement.gap);
            row.contact_length = Some(plan.placement.contact_length);
            row.placement_alternative = Some(plan.placement.alternative);
            row.seq_len = Some(m.seq_len);
            row.n_place_direct = Some(m.n_place_direct);
            row.n_place_indirect = Some(m.n_place_indirect);
            row.n_push = Some(m.n_push);
            row.n_multi_push = Some(m.n_multi_push);
            row.swept_area = Some(m.swept_area);
            row.travel = Some(m.travel);
            row.min_push_margin = plan.actions.iter().filter_map(|a| a.margin).reduce(f64::min);
            row.sequence_status = Some(ss.status.as_str().to_string());
            row.sequence_bound_len = ss.cost_bound.map(|c| c.len);
            row.sequence_bound_area = ss.cost_bound.map(|c| c.area);
            row.sequence_bound_travel = ss.cost_bound.map(|c| c.travel);
            row.sequence_gap = ss.gap;
            row.placement_nodes = Some(ps.nodes);
            row.sequence_nodes = Some(ss.nodes);
            row.sequence_assignments = ss.assignments;
            row.placement_time_s = Some(ps.time_s);
            row.sequence_time_s = Some(ss.time_s);
            row.plan_time_s = Some(plan_time);
            row.verify_time_s = Some(verify_time);
            row.verify = Some(if report.is_valid() { "valid" } else { "invalid" }.into());
            row.violations = Some(report.violations.len());
            row.robot_issues = Some(report.robot_issues.len());
            row.robot_time_s = plan.trajectories.iter().map(|t| t.t_end).reduce(f64::max);
            // The verifier's replay, when it ran, is the one the `sim_*` columns show; a
            // packing-only plan is replayed only when the spec asks (`+simulate`).
            if let crate::verify::PhysicsCheck::Replayed {
                ok,
                worst_mm,
                worst_deg,
                wall_s,
            } = report.physics
            {
                row.sim_ok = Some(ok);
                row.sim_position_error_mm = Some(worst_mm);
                row.sim_rotation_deg = Some(worst_deg);
                row.sim_time_s = Some(wall_s);
            } else if spec.simulate {
                simulate_row(&mut row, inst, plan);
            }
        }
    }
    row.wall_time_s = start.elapsed().as_secs_f64();
    row
}

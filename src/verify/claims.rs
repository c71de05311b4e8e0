//! What a plan claims about itself, checked against its own numbers and the instance: statuses,
//! bounds and gaps (docs/formats.md), and the robot records that the joint replay does not
//! cover (velocity limits, gripper openings, the grasp axis of every release).

use crate::geometry::{Arm, Axis2};
use crate::instance::Instance;
use crate::plan::{Plan, Sequencer};
use crate::status::Status;

/// Relative tolerance of recomputed figures (gaps, bounds against objectives).
const REL: f64 = 1e-6;
/// Largest angle between a release's closing axis and its grasp axis (rad): 1°.
const AXIS_TOL: f64 = 0.0175;

/// Contradictions between a plan's claimed statuses, bounds and gaps and its own numbers.
pub(super) fn status_claims(plan: &Plan) -> Vec<String> {
    let mut out = Vec::new();
    let p = &plan.placement;
    let area = p.occupied_area;
    if !(p.lower_bound.is_finite() && p.gap.is_finite()) {
        out.push("placement lower_bound and gap must be finite".into());
        return out;
    }
    if p.lower_bound > area * (1.0 + REL) {
        out.push(format!(
            "placement lower_bound {:.6e} m² is above the occupied area {area:.6e} m²: a bound cannot exceed what is achieved",
            p.lower_bound
        ));
    }
    let gap = if area > 0.0 {
        ((area - p.lower_bound) / area).max(0.0)
    } else {
        0.0
    };
    if p.gap < 0.0 || (p.gap - gap).abs() > REL {
        out.push(format!(
            "placement gap {} is not (area − bound) / area = {gap:.9}",
            p.gap
        ));
    }
    if p.status == Status::Optimal && gap > REL {
        out.push(format!("placement claimed optimal with a gap of {gap:.4}"));
    }
    if p.solver == "bl" && p.status != Status::Heuristic {
        out.push(format!(
            "a Bottom-Left placement proves nothing, yet its status is {}",
            p.status
        ));
    }
    if !p.status.has_solution() {
        out.push(format!("placement status {} for a plan that has a placement", p.status));
    }
    let sp = &plan.solver.placement;
    if sp.status != p.status {
        out.push(format!(
            "solver.placement.status {} differs from placement.status {}",
            sp.status, p.status
        ));
    }
    if let Some(g) = sp.gap.filter(|g| (g - p.gap).abs() > REL) {
        out.push(format!("solver.placement.gap {g} differs from placement.gap {}", p.gap));
    }
    if let Some(b) = sp.bound.filter(|b| (b - p.lower_bound).abs() > REL * area.max(1e-12)) {
        out.push(format!(
            "solver.placement.bound {b} differs from placement.lower_bound {}",
            p.lower_bound
        ));
    }

    let s = &plan.solver.sequence;
    let m = &plan.metrics;
    if plan.options.sequencer == Sequencer::Paper && s.status != Status::Heuristic {
        out.push(format!(
            "the paper's sequencer proves nothing, yet the sequence status is {}",
            s.status
        ));
    }
    if !s.status.has_solution() {
        out.push(format!("sequence status {} for a plan that has actions", s.status));
    }
    if s.status == Status::Optimal && s.stopped_by.is_some() {
        out.push("sequence claimed optimal though a limit stopped its search".into());
    }
    if s.status == Status::Optimal && s.cost_bound.is_none() {
        out.push("sequence claimed optimal without a bound".into());
    }
    if let Some(b) = &s.cost_bound {
        if b.len > m.seq_len || b.area > m.swept_area * (1.0 + REL) + 1e-12 {
            out.push(format!(
                "sequence bound ({} actions, {:.6e} m²) above the plan's ({} actions, {:.6e} m²)",
                b.len, b.area, m.seq_len, m.swept_area
            ));
        }
        let met = b.len == m.seq_len
            && (b.area - m.swept_area).abs() <= REL * m.swept_area.max(1e-12)
            && (b.travel - m.travel).abs() <= REL * m.travel.max(1e-12);
        if s.status == Status::Optimal && !met {
            out.push("sequence claimed optimal, but its bound does not meet the plan's cost".into());
        }
    }
    if let Some(g) = s.gap.filter(|g| !(0.0..=1.0).contains(g)) {
        out.push(format!("sequence gap {g} outside [0, 1]"));
    }
    let run = Status::combine(&[p.status, s.status]);
    if plan.status != run {
        out.push(format!(
            "run status {} is not what its stages prove ({} placement, {} sequence: {run})",
            plan.status, p.status, s.status
        ));
    }
    out
}

/// Robot records the joint replay takes on trust otherwise: the velocity limits the plan was
/// timed with, recorded velocities, gripper openings, and the closing axis at every release.
/// Each finding is `(action index, message)`.
pub(super) fn robot_records(inst: &Instance, plan: &Plan) -> Vec<(Option<usize>, String)> {
    let mut out = Vec::new();
    let Some(robot) = &plan.robot else {
        out.push((None, "joint trajectories without the robot section".into()));
        return out;
    };
    let scale = robot.timing.velocity_scale;
    if !(scale.is_finite() && scale > 0.0 && scale <= 1.0) {
        out.push((None, format!("velocity_scale {scale} must be in (0, 1]")));
        return out;
    }
    if let Some(claimed) = robot.execution_time_s {
        let end = plan.robot_time_s().unwrap_or(0.0);
        if !(claimed - end).abs().le(&1e-9) {
            out.push((
                None,
                format!("execution time recorded as {claimed} s, the trajectories end at {end} s"),
            ));
        }
    }
    let model = &inst.robot.model;
    for arm in [Arm::Left, Arm::Right] {
        for (j, spec) in model.arms[arm.index()].iter().enumerate() {
            let want = spec.velocity * scale;
            match robot.velocity_limits.get(j) {
                Some(v) if (v - want).abs() <= 1e-9 * want.max(1.0) => {}
                other => out.push((
                    None,
                    format!(
                        "velocity limit of {} joint {j} recorded as {other:?} rad/s, the model gives {want} rad/s",
                        arm.name()
                    ),
                )),
            }
        }
    }
    for t in &plan.trajectories {
        let limits: Vec<f64> = model.arms[t.arm.index()].iter().map(|j| j.velocity * scale).collect();
        for p in &t.points {
            for (j, v) in p.velocities.iter().enumerate() {
                let lim = limits.get(j).copied().unwrap_or(0.0);
                if !v.is_finite() || v.abs() > lim * (1.0 + 1e-6) + 1e-9 {
                    out.push((
                        t.action,
                        format!(
                            "{}: recorded velocity of joint {j} is {v} rad/s at t = {:.3} s, above the limit {lim} rad/s",
                            t.label, p.t
                        ),
                    ));
                    break;
                }
            }
        }
        for kp in &t.key_poses {
            if !(kp.opening.is_finite() && kp.opening >= 0.0 && kp.opening <= inst.gripper.max_opening + 1e-9) {
                out.push((
                    t.action,
                    format!(
                        "{} / {}: gripper opening {} m outside [0, {}] m",
                        t.label, kp.label, kp.opening, inst.gripper.max_opening
                    ),
                ));
            }
        }
        // The closing axis (the TCP frame's y) at the release must lie along the grasp axis.
        let Some(k) = t.action else { continue };
        let Some(axis) = plan.actions.get(k).and_then(|a| a.grasp_axis) else {
            continue;
        };
        let yaw = inst.container.yaw
            + match axis {
                Axis2::X => 0.0,
                Axis2::Y => std::f64::consts::FRAC_PI_2,
            };
        for kp in t.key_poses.iter().filter(|kp| kp.label == "release") {
            let r = &kp.rotation;
            let along = (r[0][1] * yaw.cos() + r[1][1] * yaw.sin()).abs();
            if along < AXIS_TOL.cos() {
                out.push((
                    Some(k),
                    format!(
                        "{}: the fingers close {:.1}° away from grasp axis {axis:?} at the release",
                        t.label,
                        along.clamp(0.0, 1.0).acos().to_degrees()
                    ),
                ));
            }
        }
    }
    out
}

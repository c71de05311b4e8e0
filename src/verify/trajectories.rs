//! Checks of the recorded joint trajectories of a plan, for the verifier.
//!
//! Everything is re-derived from the instance and the plan file: joint names and limits, FK of
//! every key pose against its recorded TCP pose and against the planner's key points, continuity
//! (joint steps; speeds and accelerations by finite differences between consecutive points within
//! the scaled limits; recorded velocities continuous and consistent with the positions), the
//! straight-line pushes, the arms' start and end at home, and collisions at every point and
//! between consecutive points.

use crate::actions::Action;
use crate::geometry::Arm;
use crate::instance::Instance;
use crate::motion::joint_plan::{apply_action, collision_at, idle_arm, line_distance, segment_hand, ObjAt, LINE_LIMIT};
use crate::motion::keypoints::action_keypoints;
use crate::motion::trajectory::{ActionTrajectory, TrajPoint};
use crate::placement::Placement;
use crate::plan::Plan;
use crate::robot::ik::{max_abs_diff, pose_residual};
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// Largest joint step between two consecutive trajectory points (rad).
pub const MAX_JOINT_STEP: f64 = 0.1;
/// Tolerance of recorded TCP positions against FK (m).
pub const FK_POSITION_TOL: f64 = 1e-6;
/// Tolerance of recorded TCP rotations against FK (rad).
pub const FK_ROTATION_TOL: f64 = 1e-6;

fn fmt_q(q: &[f64]) -> String {
    let v: Vec<String> = q.iter().map(|x| format!("{x:.4}")).collect();
    format!("[{}]", v.join(", "))
}

fn as6(v: &[f64]) -> Option<[f64; 6]> {
    (v.len() == 6 && v.iter().all(|x| x.is_finite())).then(|| std::array::from_fn(|k| v[k]))
}

/// Every violated condition of the plan's joint trajectories: (index of the action in
/// `plan.actions` or `None` for plan-level and park/home moves, message).
pub fn check_trajectories(inst: &Instance, plan: &Plan) -> Vec<(Option<usize>, String)> {
    let mut out: Vec<(Option<usize>, String)> = Vec::new();
    let actions = match plan.actions(inst) {
        Ok(a) => a,
        Err(e) => return vec![(None, format!("cannot read the actions: {e}"))],
    };
    let placement = match plan.placement(inst) {
        Ok(p) => p,
        Err(e) => return vec![(None, format!("cannot read the placement: {e}"))],
    };
    if plan.trajectories.is_empty() {
        if !actions.is_empty() {
            out.push((None, "plan has no joint trajectories".into()));
        }
        return out;
    }
    let model = &inst.robot.model;
    let Some((scale, acceleration)) = check_robot_section(inst, plan, &actions, &placement, &mut out) else {
        return out;
    };
    let mut q_cur = inst.robot.home;
    let mut opening = [0.0f64; 2];
    let mut at = vec![ObjAt::Table; inst.n()];
    let mut t_prev = f64::NEG_INFINITY;
    for tr in &plan.trajectories {
        let idx = tr.action;
        let mut issue = |m: String| out.push((idx, format!("{}: {m}", tr.label)));
        if let Some(k) = idx {
            if k >= actions.len() {
                issue(format!("refers to action {k}, but the plan has {}", actions.len()));
                continue;
            }
        }
        let action = idx.map(|k| &actions[k]);
        if let Some(e) = &tr.error {
            issue(format!("no joint trajectory: {e}"));
            if let Some(a) = action {
                apply_action(&mut at, &placement, a);
            }
            continue;
        }
        let arm = tr.arm;
        if let Some(a) = action {
            if a.arm() != arm {
                issue(format!(
                    "executed by the {} arm, but the action names the {} arm",
                    arm.name(),
                    a.arm().name()
                ));
            }
        }
        if tr.joint_names != model.joint_names(arm) {
            issue(format!(
                "joint names {:?} are not the {} arm's {:?}",
                tr.joint_names,
                arm.name(),
                model.joint_names(arm)
            ));
            continue;
        }
        if tr.points.is_empty() {
            issue("no points".into());
            continue;
        }
        if tr.t_start < t_prev - 1e-9 {
            issue(format!(
                "starts at t = {:.4} s before the previous move ended ({t_prev:.4} s)",
                tr.t_start
            ));
        }
        t_prev = tr.t_end;
        // Points: finite, within limits, continuous, within velocity limits.
        let mut qs: Vec<[f64; 6]> = Vec::new();
        for (i, p) in tr.points.iter().enumerate() {
            let Some(q) = as6(&p.positions) else {
                issue(format!("point {i}: positions must be 6 finite numbers"));
                qs.clear();
                break;
            };
            if let Some(e) = model.limit_error(arm, &q) {
                issue(format!("point {i} (t = {:.3} s): joint limit: {e}", p.t));
            }
            qs.push(q);
        }
        if qs.len() != tr.points.len() {
            continue;
        }
        let limits = Limits {
            velocity: std::array::from_fn(|j| model.arms[arm.index()][j].velocity * scale),
            acceleration,
        };
        let start_gap = max_abs_diff(&qs[0], &q_cur[arm.index()]);
        if start_gap > 1e-9 {
            issue(format!(
                "starts at {} but the {} arm is at {} (jump {start_gap:.4} rad)",
                fmt_q(&qs[0]),
                arm.name(),
                fmt_q(&q_cur[arm.index()])
            ));
        }
        for m in check_motion(&tr.joint_names, &tr.points, &qs, &limits) {
            issue(m);
        }
        // Key poses.
        if let Some(a) = action {
            for m in check_key_poses(inst, &placement, a, tr, &qs) {
                issue(m);
            }
        }
        // Collisions at every point and half-way between points.
        let other = arm.other();
        for m in check_collisions(
            inst,
            &placement,
            &at,
            action,
            tr,
            &qs,
            &q_cur[other.index()],
            opening[other.index()],
            opening[arm.index()],
        ) {
            issue(m);
        }
        q_cur[arm.index()] = *qs.last().expect("non-empty");
        if let Some(last) = tr.key_poses.last() {
            opening[arm.index()] = last.opening;
        }
        if let Some(a) = action {
            apply_action(&mut at, &placement, a);
        }
    }
    for arm in [Arm::Left, Arm::Right] {
        let gap = max_abs_diff(&q_cur[arm.index()], &inst.robot.home[arm.index()]);
        if gap > 1e-9 {
            out.push((
                None,
                format!(
                    "the {} arm does not end at its home pose (off by {gap:.4} rad)",
                    arm.name()
                ),
            ));
        }
    }
    out
}

/// The plan-level checks of the robot part: the `robot` section against the instance, turns a
/// top-down pick cannot make, one trajectory per action, and the timing limits against what the
/// instance allows. Returns the velocity scale and the scaled acceleration limit to check the
/// points against, or `None` when the recorded ones are unusable.
fn check_robot_section(
    inst: &Instance,
    plan: &Plan,
    actions: &[Action],
    placement: &Placement,
    out: &mut Vec<(Option<usize>, String)>,
) -> Option<(f64, f64)> {
    match &plan.robot {
        None => out.push((None, "plan has trajectories but no `robot` section".into())),
        Some(r) => {
            if r.tcp_offset
                .iter()
                .zip(&inst.robot.tcp_offset)
                .any(|(a, b)| (a - b).abs() > 1e-12)
            {
                out.push((
                    None,
                    format!(
                        "robot.tcp_offset {:?} differs from the instance's {:?}",
                        r.tcp_offset, inst.robot.tcp_offset
                    ),
                ));
            }
        }
    }
    // A top-down pick keeps the object's up axis; turning it over needs the cell's regrasp.
    if !inst.robot.regrasp {
        for (k, a) in actions.iter().enumerate() {
            if let Action::Place { object, .. } = a {
                let (o, t) = (&inst.objects[*object], &placement.targets[*object]);
                if t.orientation.up != o.table.up {
                    out.push((
                        Some(k),
                        format!(
                            "object {} stands on its {}-face on the table and on its {}-face in the container: a \
                             top-down pick cannot turn it over (set robot.regrasp = true if the cell can, or \
                             allow only `upright` orientations)",
                            o.id,
                            o.table.up.name(),
                            t.orientation.up.name()
                        ),
                    ));
                }
            }
        }
    }
    // One trajectory per action.
    for k in 0..actions.len() {
        let n = plan.trajectories.iter().filter(|t| t.action == Some(k)).count();
        if n != 1 {
            out.push((Some(k), format!("{n} joint trajectories for this action (expected 1)")));
        }
    }
    // The limits the plan was timed with (`verify::claims` checks that the scale is in (0, 1]
    // and that the recorded velocity limits are the model's times it).
    let timing = plan.robot.as_ref().map(|r| r.timing).unwrap_or_default();
    let scale = timing.velocity_scale;
    let acceleration = timing.acceleration * scale * scale;
    if !(scale.is_finite() && scale > 0.0 && scale <= 1.0 && acceleration.is_finite() && acceleration > 0.0) {
        out.push((
            None,
            format!(
                "robot.timing: velocity scale {scale} and acceleration {} rad/s² must be in (0, 1] and positive",
                timing.acceleration
            ),
        ));
        return None;
    }
    // The instance, not the plan, says how fast the cell may run: a plan that records faster
    // limits than its instance allows would be checked against its own word otherwise.
    let cell_scale = inst.robot.speed_scale;
    let cell_acceleration = inst
        .settings
        .joint_acceleration
        .unwrap_or(crate::motion::trajectory::DEFAULT_ACCELERATION);
    if scale > cell_scale * (1.0 + 1e-12) {
        out.push((
            None,
            format!("robot.timing: velocity scale {scale} is above the instance's robot.speed_scale {cell_scale}"),
        ));
    }
    if timing.acceleration > cell_acceleration * (1.0 + 1e-12) {
        out.push((
            None,
            format!(
                "robot.timing: acceleration {} rad/s² is above the instance's limit {cell_acceleration} rad/s² \
                 ([planner] joint_acceleration, default {})",
                timing.acceleration,
                crate::motion::trajectory::DEFAULT_ACCELERATION
            ),
        ));
    }
    Some((scale, acceleration))
}

/// The key poses of one action's trajectory against the action's key points (labels, joint
/// limits, forward kinematics, a top-down tool, a trajectory point at each), and its push along
/// a straight line.
fn check_key_poses(
    inst: &Instance,
    placement: &Placement,
    a: &Action,
    tr: &ActionTrajectory,
    qs: &[[f64; 6]],
) -> Vec<String> {
    let model = &inst.robot.model;
    let arm = tr.arm;
    let mut out = Vec::new();
    let mut issue = |m: String| out.push(m);
    let kps = action_keypoints(inst, placement, a);
    if kps.len() != tr.key_poses.len() {
        issue(format!(
            "{} key poses recorded, the action has {}",
            tr.key_poses.len(),
            kps.len()
        ));
    }
    for (kp, want) in tr.key_poses.iter().zip(&kps) {
        let mut kissue = |m: String| issue(format!("key pose {}: {m}", kp.label));
        if kp.label != want.label {
            kissue(format!("label should be {}", want.label));
        }
        let Some(q) = as6(&kp.joints) else {
            kissue("joints must be 6 finite numbers".into());
            continue;
        };
        if let Some(e) = model.limit_error(arm, &q) {
            kissue(format!("joint limit: {e}"));
        }
        let fk = model.tcp_pose(arm, &q, &inst.robot.tcp_offset);
        let rot = match recorded_rotation(&kp.rotation) {
            Ok(r) => r,
            Err(e) => {
                kissue(e);
                continue;
            }
        };
        let rec = Isometry3::from_parts(Translation3::from(Vector3::from(kp.position)), rot);
        let (dp, dr) = pose_residual(&fk, &rec);
        if dp > FK_POSITION_TOL || dr > FK_ROTATION_TOL {
            kissue(format!(
                "FK of the recorded joints is {dp:.3e} m / {dr:.3e} rad away from the recorded TCP pose \
                 (tolerance {FK_POSITION_TOL:e} m / {FK_ROTATION_TOL:e} rad)"
            ));
        }
        let dw = (Vector3::from(kp.position) - Vector3::from(want.position)).norm();
        if dw > FK_POSITION_TOL {
            kissue(format!(
                "recorded TCP position is {dw:.3e} m from the planned key point"
            ));
        }
        let down = fk.rotation * Vector3::z();
        let tilt = down.angle(&-Vector3::z());
        if tilt > FK_ROTATION_TOL {
            kissue(format!("tool is tilted {tilt:.3e} rad from top-down"));
        }
        match tr.points.iter().position(|p| (p.t - kp.t).abs() <= 1e-9) {
            Some(i) if max_abs_diff(&qs[i], &q) <= 1e-9 => {}
            Some(i) => kissue(format!(
                "the point at t = {:.3} s is not at the key pose's joints",
                tr.points[i].t
            )),
            None => kissue(format!("no trajectory point at its time t = {:.3} s", kp.t)),
        }
    }
    // Straight-line push.
    let find = |l: &str| tr.key_poses.iter().find(|k| k.label == l);
    if let (Some(s), Some(e)) = (find("push-start"), find("push-end")) {
        let (a3, b3) = (Vector3::from(s.position), Vector3::from(e.position));
        let mut worst: f64 = 0.0;
        let idx: Vec<usize> = (0..qs.len())
            .filter(|&i| tr.points[i].t >= s.t - 1e-9 && tr.points[i].t <= e.t + 1e-9)
            .collect();
        for w in idx.windows(2) {
            for u in [0.0, 0.5] {
                let q: [f64; 6] = std::array::from_fn(|j| qs[w[0]][j] + u * (qs[w[1]][j] - qs[w[0]][j]));
                let p = model.tcp_position(arm, &q, &inst.robot.tcp_offset);
                worst = worst.max(line_distance(&p, &a3, &b3));
            }
        }
        if worst > LINE_LIMIT {
            issue(format!(
                "push leaves the straight line by {worst:.4e} m (limit {LINE_LIMIT:e} m)"
            ));
        }
    }
    out
}

/// Collisions of one trajectory at every point and half-way between points, with the objects
/// where `at` has them and the other arm idle at `q_other` with its fingers at `opening_other`;
/// `opening` is the arm's own opening when the move starts.
#[allow(clippy::too_many_arguments)]
fn check_collisions(
    inst: &Instance,
    placement: &Placement,
    at: &[ObjAt],
    action: Option<&Action>,
    tr: &ActionTrajectory,
    qs: &[[f64; 6]],
    q_other: &[f64; 6],
    opening_other: f64,
    opening_self: f64,
) -> Vec<String> {
    let arm = tr.arm;
    let mut out = Vec::new();
    let mut issue = |m: String| out.push(m);
    let other = arm.other();
    let other_obs = idle_arm(inst, other, q_other, opening_other);
    let openings: Vec<f64> = tr.key_poses.iter().map(|k| k.opening).collect();
    let mut reported = 0;
    for i in 0..qs.len() {
        for u in [0.0, 0.5] {
            if i + 1 == qs.len() && u > 0.0 {
                continue;
            }
            let q: [f64; 6] = if u == 0.0 {
                qs[i]
            } else {
                std::array::from_fn(|j| 0.5 * (qs[i][j] + qs[i + 1][j]))
            };
            let t = tr.points[i].t + u * tr.points.get(i + 1).map(|p| p.t - tr.points[i].t).unwrap_or(0.0);
            let seg = tr
                .key_poses
                .iter()
                .position(|k| k.t >= t - 1e-9)
                .unwrap_or(tr.key_poses.len().saturating_sub(1));
            let hand = match action {
                Some(a) => segment_hand(inst, placement, a, seg, &openings, opening_self),
                None => crate::motion::collision::Hand {
                    opening: opening_self,
                    held: None,
                },
            };
            if let Some((part, obs)) = collision_at(inst, placement, at, action, seg, &hand, arm, &q, &other_obs) {
                if reported < 3 {
                    issue(format!("collision at t = {t:.3} s: {part} hits {obs}"));
                }
                reported += 1;
            }
        }
    }
    if reported > 3 {
        issue(format!("{} more colliding samples", reported - 3));
    }
    out
}

/// Joint limits a trajectory's points must keep: `velocity_scale ×` the model's velocity limits
/// (rad/s) and `acceleration × velocity_scale²` (rad/s²), both as recorded in `robot.timing`.
struct Limits {
    velocity: [f64; 6],
    acceleration: f64,
}

/// Relative slack of the velocity and acceleration checks, for rounding only: the smoothed time
/// law (`motion::profile`) keeps its bounds exactly for finite differences over any samples.
pub const RATE_REL_TOL: f64 = 1e-6;
/// Absolute slack of the same checks (rad/s, rad/s²; rad for the velocity–position consistency).
pub const RATE_ABS_TOL: f64 = 1e-9;

/// Timing of one trajectory's points, by finite differences over consecutive points: time
/// increases, no joint steps more than [`MAX_JOINT_STEP`], the speed over every interval is
/// within the scaled velocity limit, and the change of speed between adjacent intervals, over the
/// distance of their midpoints, within the scaled acceleration limit. Recorded velocities (when
/// the points carry any) must be continuous, |v(i) − v(i−1)| ≤ a·Δt, and consistent with the
/// positions: |Δq − Δt·(v(i−1) + v(i))/2| ≤ a·Δt²/4, which every motion whose acceleration stays
/// within a satisfies (trapezoid rule). At most three findings per kind.
fn check_motion(names: &[String], points: &[TrajPoint], qs: &[[f64; 6]], lim: &Limits) -> Vec<String> {
    let mut out = Vec::new();
    let mut count = [0usize; 5];
    let mut report = |kind: usize, m: String, out: &mut Vec<String>| {
        count[kind] += 1;
        if count[kind] <= 3 {
            out.push(m);
        }
    };
    let slack = |x: f64| x * (1.0 + RATE_REL_TOL) + RATE_ABS_TOL;
    let a = lim.acceleration;
    let with_v = points.iter().any(|p| !p.velocities.is_empty());
    let vs: Vec<[f64; 6]> = if with_v {
        match points.iter().map(|p| as6(&p.velocities)).collect::<Option<Vec<_>>>() {
            Some(v) => v,
            None => {
                out.push("recorded velocities must be 6 finite numbers at every point (or at none)".into());
                Vec::new()
            }
        }
    } else {
        Vec::new()
    };
    let mut prev: Option<([f64; 6], f64)> = None;
    for i in 1..qs.len() {
        let (t0, t1) = (points[i - 1].t, points[i].t);
        let dt = t1 - t0;
        // Written so that a NaN time fails too.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(dt > 0.0) {
            report(
                0,
                format!("point {i}: time does not increase ({t1:.6} s after {t0:.6} s)"),
                &mut out,
            );
            prev = None;
            continue;
        }
        let fd: [f64; 6] = std::array::from_fn(|j| (qs[i][j] - qs[i - 1][j]) / dt);
        for j in 0..6 {
            let d = (qs[i][j] - qs[i - 1][j]).abs();
            if d > MAX_JOINT_STEP {
                let m = format!(
                    "point {i} (t = {t1:.3} s): {} jumps {d:.4} rad (continuity threshold {MAX_JOINT_STEP} rad)",
                    names[j]
                );
                report(1, m, &mut out);
            } else if fd[j].abs() > slack(lim.velocity[j]) {
                let m = format!(
                    "point {i} (t = {t1:.3} s): {} moves at {:.4} rad/s, above its scaled limit {:.4} rad/s",
                    names[j],
                    fd[j].abs(),
                    lim.velocity[j]
                );
                report(2, m, &mut out);
            }
        }
        if let Some((fp, dp)) = prev {
            let mid = 0.5 * (dp + dt);
            if let Some(j) = (0..6).find(|&j| (fd[j] - fp[j]).abs() / mid > slack(a)) {
                let m = format!(
                    "point {i} (t = {t0:.3} s): {} accelerates at {:.4} rad/s² (finite differences), above the \
                     scaled limit {a:.4} rad/s²",
                    names[j],
                    (fd[j] - fp[j]).abs() / mid
                );
                report(3, m, &mut out);
            }
        }
        prev = Some((fd, dt));
        if vs.len() == qs.len() {
            let (v0, v1) = (&vs[i - 1], &vs[i]);
            let bad = (0..6).find(|&j| {
                let jump = (v1[j] - v0[j]).abs();
                let off = (qs[i][j] - qs[i - 1][j] - 0.5 * dt * (v0[j] + v1[j])).abs();
                jump > slack(a * dt) || off > slack(a * dt * dt / 4.0)
            });
            if let Some(j) = bad {
                let m = format!(
                    "point {i} (t = {t1:.3} s): the recorded velocity of {} goes from {:.4} to {:.4} rad/s while it \
                     moves {:.5} rad in {dt:.4} s: not a motion within {a:.4} rad/s²",
                    names[j],
                    v0[j],
                    v1[j],
                    qs[i][j] - qs[i - 1][j]
                );
                report(4, m, &mut out);
            }
        }
    }
    let more: usize = count.iter().map(|c| c.saturating_sub(3)).sum();
    if more > 0 {
        out.push(format!("{more} more timing findings"));
    }
    out
}

/// A recorded rotation matrix as a rotation, or why it is not one. Taken as it is once it is
/// orthonormal with determinant +1: `Rotation3::from_matrix` re-orthonormalises iteratively
/// from the identity and lands on the wrong rotation for a hand turned by π (a correct record
/// was reported 3.14 rad away from its own joints' forward kinematics).
fn recorded_rotation(r: &[[f64; 3]; 3]) -> Result<UnitQuaternion<f64>, String> {
    let m = Matrix3::from_fn(|i, j| r[i][j]);
    let orth = (m.transpose() * m - Matrix3::identity()).amax();
    let det = m.determinant();
    if !(orth <= 1e-6 && det > 0.0) {
        return Err(format!(
            "rotation is not a rotation matrix (|RᵀR − I| = {orth:.1e}, det = {det:.3})"
        ));
    }
    Ok(UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
        m,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
    }

    #[test]
    fn a_tool_turned_by_pi_reads_back_exactly() {
        // Top-down tool (tool z along world −z) at yaws near π: a half-turn from the identity.
        for yaw in [std::f64::consts::PI, std::f64::consts::PI - 1e-3, 3.0] {
            let truth = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, yaw);
            let back = recorded_rotation(&rows(truth.to_rotation_matrix().matrix())).unwrap();
            assert!(back.angle_to(&truth) < 1e-12, "yaw {yaw}: {}", back.angle_to(&truth));
        }
    }

    fn names() -> Vec<String> {
        (0..6).map(|j| format!("J{j}")).collect()
    }

    const LIM: Limits = Limits {
        velocity: [0.45; 6],
        acceleration: 0.81,
    };

    /// Points of a smoothed leg at scale 0.9, as the joint plan records them.
    fn leg() -> Vec<TrajPoint> {
        let opts = crate::motion::TrajectoryOptions::default();
        let (a, b) = ([0.0; 6], [0.6, -0.3, 0.2, 0.0, 0.4, 1.0]);
        let mid = [0.35, -0.1, 0.15, 0.05, 0.2, 0.5];
        crate::motion::trajectory::time_segment(&[a, mid, b], &[0.5; 6], &opts, 0.0).0
    }

    fn qs(points: &[TrajPoint]) -> Vec<[f64; 6]> {
        points.iter().map(|p| as6(&p.positions).unwrap()).collect()
    }

    #[test]
    fn a_smoothed_leg_keeps_the_scaled_limits() {
        let p = leg();
        assert_eq!(check_motion(&names(), &p, &qs(&p), &LIM), Vec::<String>::new());
    }

    #[test]
    fn a_point_too_fast_for_the_scaled_limit_but_not_for_the_urdf_is_refused() {
        // Two points 0.047 rad apart in 0.1 s: 0.47 rad/s, under the URDF's 0.5, over 0.45.
        let at = |t: f64, q: f64| TrajPoint {
            t,
            positions: vec![q, 0.0, 0.0, 0.0, 0.0, 0.0],
            velocities: Vec::new(),
        };
        let p = vec![at(0.0, 0.0), at(0.1, 0.047)];
        let found = check_motion(&names(), &p, &qs(&p), &LIM);
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(found[0].contains("above its scaled limit"), "{found:?}");
    }

    #[test]
    fn a_velocity_jump_and_an_acceleration_spike_are_refused() {
        let mut p = leg();
        let i = p.len() / 2;
        p[i].velocities[1] += 0.1;
        let found = check_motion(&names(), &p, &qs(&p), &LIM);
        assert!(found.iter().any(|m| m.contains("recorded velocity of J1")), "{found:?}");
        assert!(!found.iter().any(|m| m.contains("finite differences")), "{found:?}");
        let mut p = leg();
        p[i].positions[2] += 0.002;
        let found = check_motion(&names(), &p, &qs(&p), &LIM);
        assert!(found.iter().any(|m| m.contains("J2 accelerates")), "{found:?}");
    }

    #[test]
    fn a_non_rotation_is_refused() {
        let mut m = rows(&Matrix3::identity());
        m[0][0] = 1.1;
        assert!(recorded_rotation(&m).unwrap_err().contains("not a rotation"));
        let mirror = rows(&Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)));
        assert!(recorded_rotation(&mirror).is_err());
    }
}

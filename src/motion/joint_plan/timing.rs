//! The joint trajectories of a whole plan: home moves, timing, key-pose records.

use super::*;

/// The `robot` section for an instance.
pub fn robot_info(inst: &Instance, opts: &TrajectoryOptions) -> RobotInfo {
    let m = &inst.robot.model;
    RobotInfo {
        model: inst.robot.model_path.clone(),
        tcp_offset: inst.robot.tcp_offset,
        base_frame: "WAIST".into(),
        tcp_frame: "TCP at tcp_offset in *ARM_JOINT5_Link; rotation columns: x = JOINT5_Link z \
                    (the hand housing's narrow side), y = finger closing axis (JOINT5_Link y), z = approach (JOINT5_Link -x)"
            .into(),
        joint_names_left: m.joint_names(Arm::Left),
        joint_names_right: m.joint_names(Arm::Right),
        timing: *opts,
        velocity_limits: m.arms[0].iter().map(|j| j.velocity * opts.velocity_scale).collect(),
        execution_time_s: None,
    }
}

pub(super) fn vmax(inst: &Instance, arm: Arm) -> [f64; 6] {
    std::array::from_fn(|k| inst.robot.model.arms[arm.index()][k].velocity)
}

/// A move of an arm back to its home pose (to park it out of the other arm's way, or at the end):
/// up to transfer height above the home TCP, then down to home; each leg a joint move, or a
/// straight line where the joint move collides. Returns the legs (each timed from rest to rest)
/// and the smallest clearance.
#[allow(clippy::too_many_arguments)]
pub(super) fn home_move(
    inst: &Instance,
    placement: &Placement,
    at: &[ObjAt],
    arm: Arm,
    from: &[f64; 6],
    hand: Hand,
    other: Vec<Obstacle>,
    memo: &RefCell<IkMemo>,
) -> Result<(Legs, f64), RobotError> {
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: at.to_vec(),
        other,
        scope: Scope::Full,
        fast_ik: false,
        memo: Some(memo),
    };
    let solver = IkSolver::new(&inst.robot.model, arm, &inst.robot.tcp_offset);
    // Obstacles of an idle move = every object where it is (an empty push sees them so).
    let idle = Action::Push {
        objects: vec![],
        push_dir: PushDir::MinusX,
        distance: 0.0,
        pusher_at: 0.0,
        arm,
    };
    let home = inst.robot.home[arm.index()];
    let home_pose = solver.fk(&home);
    let mut above = home_pose;
    above.translation.vector.z = above
        .translation
        .vector
        .z
        .max(crate::motion::keypoints::transfer_z(inst));
    let via = near_memo(&ctx, &solver, &above, &home)?;
    let what = format!("{} arm back home", arm.name());
    let mut clear = f64::INFINITY;
    let mut legs = Vec::new();
    let mut q = *from;
    for (target_q, target_pose) in [(via, above), (home, home_pose)] {
        let joint = vec![q, target_q];
        let leg = match check_samples(
            &ctx,
            &solver,
            &idle,
            0,
            &hand,
            &densify(&joint),
            &what,
            &mut clear,
            JOINT_MOVE_MARGIN,
        ) {
            Ok(()) => joint,
            Err(e) => {
                let mut line = line_memo(&ctx, &solver, &q, &solver.fk(&q), &target_pose, &what, LINE_TOLERANCE)
                    .map_err(|_| e.clone())?;
                if max_abs_diff(line.last().expect("non-empty"), &target_q) > 1e-6 {
                    return Err(e);
                }
                *line.last_mut().expect("non-empty") = target_q;
                check_samples(&ctx, &solver, &idle, 0, &hand, &densify(&line), &what, &mut clear, 0.0)
                    .map_err(|_| e)?;
                line
            }
        };
        q = target_q;
        legs.push(leg);
    }
    Ok((legs, clear))
}

/// Time several rest-to-rest legs one after the other.
pub(super) fn time_legs(
    legs: &[Vec<[f64; 6]>],
    v: &[f64; 6],
    opts: &TrajectoryOptions,
    t0: f64,
) -> (Vec<TrajPoint>, f64) {
    let mut points = Vec::new();
    let mut t = t0;
    for leg in legs {
        let (pts, t1) = time_segment(leg, v, opts, t);
        append(&mut points, pts);
        t = t1;
    }
    (points, t)
}

/// Key pose records of a motion, timed.
pub(super) fn key_pose_records(inst: &Instance, arm: Arm, m: &Motion, times: &[f64]) -> Vec<KeyPose> {
    m.specs
        .iter()
        .zip(&m.key_q)
        .zip(times)
        .map(|((sp, q), t)| {
            let pose = inst.robot.model.tcp_pose(arm, q, &inst.robot.tcp_offset);
            let r = pose.rotation.to_rotation_matrix();
            let r = r.matrix();
            let p = pose.translation.vector;
            KeyPose {
                label: sp.label.clone(),
                position: [p.x, p.y, p.z],
                rotation: std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)])),
                joints: q.to_vec(),
                t: *t,
                opening: sp.opening,
            }
        })
        .collect()
}

pub(super) fn append(points: &mut Vec<TrajPoint>, mut seg: Vec<TrajPoint>) {
    if !points.is_empty() && !seg.is_empty() {
        seg.remove(0);
    }
    points.extend(seg);
}

pub(super) fn hold(points: &mut Vec<TrajPoint>, dt: f64) -> f64 {
    let last = points.last().expect("non-empty").clone();
    let t = last.t + dt;
    points.push(TrajPoint { t, ..last });
    t
}

/// Joint trajectories of a whole plan: the `robot` section and one record per action, plus park
/// moves of an idle arm that is in the way and the final moves back home. Never fails: an action
/// without a feasible motion gets a record with `error` set (and the verifier reports it).
pub fn plan_trajectories(
    inst: &Instance,
    placement: &Placement,
    actions: &[Action],
    opts: &TrajectoryOptions,
) -> (RobotInfo, Vec<ActionTrajectory>) {
    plan_trajectories_with(inst, placement, actions, opts, &mut |_| {})
}

/// [`plan_trajectories`], calling `planned(k)` once the first `k` actions have their
/// trajectories (a live display's pulse: a 20-object plan takes seconds here).
///
/// Long on purpose: the arms' state (configurations, hands, where every object is, the clock)
/// threads through every action in order, with the park-and-retry of an idle arm in the way and
/// the final moves home. Each motion is a call (`plan_action`, `home_move`, `time_legs`); what
/// stays here is that state.
pub fn plan_trajectories_with(
    inst: &Instance,
    placement: &Placement,
    actions: &[Action],
    opts: &TrajectoryOptions,
    planned: &mut dyn FnMut(usize),
) -> (RobotInfo, Vec<ActionTrajectory>) {
    let model = &inst.robot.model;
    let mut q_cur = inst.robot.home;
    let mut hand_cur = [Hand {
        opening: 0.0,
        held: None,
    }; 2];
    let mut at = vec![ObjAt::Table; inst.n()];
    let mut t = 0.0;
    let mut out = Vec::new();
    let statics = static_obstacles(inst);
    let solvers = [Arm::Left, Arm::Right].map(|a| IkSolver::new(model, a, &inst.robot.tcp_offset));
    // IK answers by their exact inputs, shared by every action: the kinematic pass that ranks an
    // action's hand variants solves the poses its full pass solves again, variants share their
    // table half, and parking and going home solve the same pose above home.
    let memo = RefCell::new(IkMemo::default());
    let idle_obstacles =
        |arm: Arm, q: &[f64; 6], hand: &Hand| arm_as_obstacles(robot_parts(model, inst, arm, q, hand), arm);
    let simple_record = |label: String, arm: Arm, pts: Vec<TrajPoint>, t0: f64, t1: f64, clear: f64| ActionTrajectory {
        action: None,
        label,
        arm,
        joint_names: model.joint_names(arm),
        t_start: t0,
        t_end: t1,
        points: pts,
        key_poses: Vec::new(),
        clearance: clear.is_finite().then_some(clear),
        notes: Vec::new(),
        error: None,
    };
    for (k, action) in actions.iter().enumerate() {
        planned(k);
        let arm = action.arm();
        let other = arm.other();
        let label = action_label(inst, action);
        let mut notes = Vec::new();
        let record_err = |e: String, notes: Vec<String>, t: f64| ActionTrajectory {
            action: Some(k),
            label: label.clone(),
            arm,
            joint_names: model.joint_names(arm),
            t_start: t,
            t_end: t,
            points: Vec::new(),
            key_poses: Vec::new(),
            clearance: None,
            notes,
            error: Some(e),
        };
        if !inst.robot.arms.contains(&arm) {
            out.push(record_err(
                format!("the {} arm is not allowed by the instance", arm.name()),
                notes,
                t,
            ));
            apply(&mut at, placement, action);
            continue;
        }
        let mut ctx = Ctx {
            inst,
            placement,
            statics: statics.clone(),
            at: at.clone(),
            other: idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]),
            scope: Scope::Full,
            fast_ik: false,
            memo: Some(&memo),
        };
        let solver = &solvers[arm.index()];
        // An idle arm whose hand hangs over the container is in the way of every action there:
        // park it at once (saves a failing first attempt); otherwise only when the action fails.
        let over_container = q_cur[other.index()] != inst.robot.home[other.index()] && {
            let p = model.tcp_position(other, &q_cur[other.index()], &inst.robot.tcp_offset);
            let c = to_container(inst, &p);
            let m = 0.05 + inst.container.wall_thickness;
            c[0] > -m && c[0] < inst.container.width + m && c[1] > -m && c[1] < inst.container.depth + m
        };
        let mut result = if over_container {
            Err(RobotError::Other("idle arm over the container".into()))
        } else {
            plan_action(
                &ctx,
                solver,
                action,
                &q_cur[arm.index()],
                hand_cur[arm.index()],
                &mut notes,
            )
        };
        // The idle arm in the way: park it at home first.
        if result.is_err() && q_cur[other.index()] != inst.robot.home[other.index()] {
            let park = home_move(
                inst,
                placement,
                &at,
                other,
                &q_cur[other.index()],
                hand_cur[other.index()],
                idle_obstacles(arm, &q_cur[arm.index()], &hand_cur[arm.index()]),
                &memo,
            );
            if let Ok((legs, clear)) = park {
                let (pts, t1) = time_legs(&legs, &vmax(inst, other), opts, t);
                out.push(simple_record(
                    format!("park {}", other.name()),
                    other,
                    pts,
                    t,
                    t1,
                    clear,
                ));
                t = t1;
                q_cur[other.index()] = inst.robot.home[other.index()];
                ctx.other = idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]);
                notes.clear();
                result = plan_action(
                    &ctx,
                    solver,
                    action,
                    &q_cur[arm.index()],
                    hand_cur[arm.index()],
                    &mut notes,
                );
            }
        }
        match result {
            Ok(m) => {
                let t0 = t;
                let mut points: Vec<TrajPoint> = Vec::new();
                let mut times = Vec::new();
                let v = vmax(inst, arm);
                for (s, legs) in m.segments.iter().enumerate() {
                    let (pts, t1) = time_legs(legs, &v, opts, t);
                    append(&mut points, pts);
                    t = t1;
                    // The gripper closes at the grasp and opens at the release.
                    if matches!(action, Action::Place { .. }) && (s == 1 || s == 4) {
                        times.push(t);
                        t = hold(&mut points, GRIPPER_DWELL);
                    } else {
                        times.push(t);
                    }
                }
                let key_poses = key_pose_records(inst, arm, &m, &times);
                q_cur[arm.index()] = *m.key_q.last().expect("key poses");
                hand_cur[arm.index()] = Hand {
                    opening: m.specs.last().map(|s| s.opening).unwrap_or(0.0),
                    held: None,
                };
                out.push(ActionTrajectory {
                    action: Some(k),
                    label: label.clone(),
                    arm,
                    joint_names: model.joint_names(arm),
                    t_start: t0,
                    t_end: t,
                    points,
                    key_poses,
                    clearance: m.clearance.is_finite().then_some(m.clearance),
                    notes,
                    error: None,
                });
            }
            Err(e) => out.push(record_err(e.to_string(), notes, t)),
        }
        apply(&mut at, placement, action);
    }
    // Back home.
    for arm in [Arm::Left, Arm::Right] {
        let home = inst.robot.home[arm.index()];
        if q_cur[arm.index()] == home {
            continue;
        }
        let other = arm.other();
        let res = home_move(
            inst,
            placement,
            &at,
            arm,
            &q_cur[arm.index()],
            hand_cur[arm.index()],
            idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]),
            &memo,
        );
        match res {
            Ok((legs, clear)) => {
                let (pts, t1) = time_legs(&legs, &vmax(inst, arm), opts, t);
                out.push(simple_record(format!("home {}", arm.name()), arm, pts, t, t1, clear));
                t = t1;
                q_cur[arm.index()] = home;
            }
            Err(e) => {
                let mut r = simple_record(format!("home {}", arm.name()), arm, Vec::new(), t, t, f64::INFINITY);
                r.error = Some(e.to_string());
                out.push(r);
            }
        }
    }
    planned(actions.len());
    let mut info = robot_info(inst, opts);
    info.execution_time_s = out.iter().map(|r| r.t_end).reduce(f64::max);
    (info, out)
}

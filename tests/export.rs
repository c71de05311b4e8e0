//! `pushpack export`: ROS `trajectory_msgs/JointTrajectory` YAML and JSON and CSV per arm, parsed
//! back and compared with the plan's trajectories.

mod common;

use pushpack::plan::export::{export, to_yaml, ExportFormat, RosJointTrajectory};
use pushpack::plan::{optimize, PlanOptions};
use pushpack::robot::Arm;

fn plan() -> pushpack::plan::Plan {
    let inst = common::load("paper/exp1_4objects.toml");
    optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan
}

/// Finite differences over exported points `(time, positions, velocities)`: every joint's speed
/// over every interval within `vlim` (its scaled velocity limit), the change of speed between
/// adjacent intervals over the distance of their midpoints within `alim` (the scaled acceleration
/// limit), and the recorded velocities continuous: they change by at most `alim · dt`. The only
/// slack is for time stamps rounded to the nanosecond (each off by ≤ 0.5 ns).
fn assert_finite_difference_limits(points: &[(f64, &[f64], &[f64])], vlim: &[f64], alim: f64) {
    let n = vlim.len();
    let mut prev: Option<(Vec<f64>, f64)> = None;
    for w in points.windows(2) {
        let dt = w[1].0 - w[0].0;
        assert!(dt > 0.0, "time runs forward");
        let fd: Vec<f64> = (0..n).map(|j| (w[1].1[j] - w[0].1[j]) / dt).collect();
        for j in 0..n {
            assert!(
                fd[j].abs() <= vlim[j] * (1.0 + 1e-9 / dt) + 1e-12,
                "joint {j}: {} rad/s over {} (dt {dt})",
                fd[j],
                vlim[j]
            );
            let jump = (w[1].2[j] - w[0].2[j]).abs();
            assert!(
                jump <= alim * (dt + 1e-9) * (1.0 + 1e-9) + 1e-12,
                "joint {j}: recorded velocity jumps {jump} rad/s in {dt} s at t = {}",
                w[1].0
            );
        }
        if let Some((fp, dp)) = &prev {
            let mid = 0.5 * (dp + dt);
            for j in 0..n {
                let acc = (fd[j] - fp[j]).abs() / mid;
                let rounding = 1e-9 * (fd[j].abs() / dt + fp[j].abs() / dp) / mid;
                assert!(
                    acc <= alim * (1.0 + 1e-9) + rounding + 1e-9,
                    "joint {j}: {acc} rad/s² over {alim} at t = {}",
                    w[0].0
                );
            }
        }
        prev = Some((fd, dt));
    }
}

/// The scaled limits of a plan: velocity limits per joint and `acceleration × scale²`.
fn scaled_limits(plan: &pushpack::plan::Plan) -> (Vec<f64>, f64) {
    let r = plan.robot.as_ref().unwrap();
    let s = r.timing.velocity_scale;
    (r.velocity_limits.clone(), r.timing.acceleration * s * s)
}

fn check_message(m: &RosJointTrajectory, arm: Arm, plan: &pushpack::plan::Plan) {
    let prefix = match arm {
        Arm::Left => "LARM",
        Arm::Right => "RARM",
    };
    assert_eq!(m.joint_names.len(), 6);
    assert!(
        m.joint_names.iter().all(|n| n.starts_with(prefix)),
        "{:?}",
        m.joint_names
    );
    assert_eq!(m.header.frame_id, "WAIST");
    assert!(m.points.len() > 10);
    assert_eq!(m.points[0].time_from_start.as_secs(), 0.0);
    for w in m.points.windows(2) {
        assert!(w[1].time_from_start.as_secs() > w[0].time_from_start.as_secs());
    }
    for p in &m.points {
        assert_eq!(p.positions.len(), 6);
        assert_eq!(p.velocities.len(), 6);
        assert!(p.time_from_start.nsecs >= 0 && p.time_from_start.nsecs < 1_000_000_000);
    }
    let (vlim, alim) = scaled_limits(plan);
    let pts: Vec<(f64, &[f64], &[f64])> = m
        .points
        .iter()
        .map(|p| (p.time_from_start.as_secs(), &p.positions[..], &p.velocities[..]))
        .collect();
    assert_finite_difference_limits(&pts, &vlim, alim);
    // Every point of the arm's trajectories is in the message (bar duplicates at the joins).
    let pts: Vec<_> = plan
        .trajectories
        .iter()
        .filter(|t| t.arm == arm)
        .flat_map(|t| t.points.iter())
        .collect();
    for p in pts {
        let found = m
            .points
            .iter()
            .find(|q| (q.time_from_start.as_secs() - p.t).abs() < 1e-6)
            .unwrap_or_else(|| panic!("no point at t = {}", p.t));
        for j in 0..6 {
            assert!((found.positions[j] - p.positions[j]).abs() < 1e-12);
        }
    }
}

#[test]
fn export_writes_ros_yaml_json_and_csv_per_arm_that_parse_back() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    let mut seen = 0;
    for (fmt, name) in [
        (ExportFormat::RosYaml, "ros-yaml"),
        (ExportFormat::RosJson, "ros-json"),
        (ExportFormat::Csv, "csv"),
    ] {
        assert_eq!(name.parse::<ExportFormat>().unwrap(), fmt);
        assert_eq!(fmt.name(), name);
        let out = dir.path().join(name);
        let files = export(&plan, fmt, &out).expect("exports");
        assert_eq!(files.len(), 2, "both arms move in exp1: {files:?}");
        for f in &files {
            let arm = if f.file_name().unwrap().to_str().unwrap().starts_with("left") {
                Arm::Left
            } else {
                Arm::Right
            };
            let text = std::fs::read_to_string(f).unwrap();
            match fmt {
                ExportFormat::RosYaml => {
                    let m: RosJointTrajectory =
                        serde_norway::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                    check_message(&m, arm, &plan);
                    // Generic YAML view: the ROS field names are there.
                    let v: serde_norway::Value = serde_norway::from_str(&text).unwrap();
                    assert!(v["points"][0]["time_from_start"]["secs"].is_i64());
                    assert!(v["header"]["stamp"]["nsecs"].is_i64());
                }
                ExportFormat::RosJson => {
                    let m: RosJointTrajectory = serde_json::from_str(&text).unwrap();
                    check_message(&m, arm, &plan);
                }
                ExportFormat::Csv => {
                    let mut lines = text.lines();
                    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
                    assert_eq!(header.len(), 7);
                    assert_eq!(header[0], "t");
                    let mut last = -1.0;
                    let mut rows = 0;
                    for l in lines {
                        let v: Vec<f64> = l.split(',').map(|x| x.parse().expect("a number")).collect();
                        assert_eq!(v.len(), 7);
                        assert!(v[0] > last);
                        last = v[0];
                        rows += 1;
                    }
                    // Same rows as the JSON message of that arm.
                    let json = dir.path().join("ros-json").join(format!("{}_arm.json", arm.name()));
                    let m: RosJointTrajectory = serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
                    assert_eq!(rows, m.points.len());
                }
                _ => unreachable!("not in this loop: ros2-goal has its own test below"),
            }
            seen += 1;
        }
    }
    assert_eq!(seen, 6);
}

#[test]
fn yaml_of_an_empty_message_parses_and_bad_plans_are_refused() {
    let m = RosJointTrajectory {
        header: pushpack::plan::export::RosHeader {
            seq: 0,
            stamp: pushpack::plan::export::RosTime { secs: 0, nsecs: 0 },
            frame_id: "WAIST".into(),
        },
        joint_names: vec!["A".into()],
        points: vec![],
    };
    let back: RosJointTrajectory = serde_norway::from_str(&to_yaml(&m)).unwrap();
    assert_eq!(back, m);
    assert!("ros".parse::<ExportFormat>().is_err());
    let mut plan = plan();
    plan.trajectories.clear();
    let dir = tempfile::tempdir().unwrap();
    let e = export(&plan, ExportFormat::Csv, dir.path()).unwrap_err();
    assert!(e.to_string().contains("no joint trajectories"), "{e}");
}

/// ROS 2 `builtin_interfaces/Duration`, as the message definition has it.
#[derive(serde::Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct Duration {
    sec: i32,
    nanosec: u32,
}

/// The goal's points as (time, positions, velocities).
fn goal_points(t: &JointTrajectory) -> Vec<(f64, &[f64], &[f64])> {
    t.points
        .iter()
        .map(|p| (p.time_from_start.secs(), &p.positions[..], &p.velocities[..]))
        .collect()
}

impl Duration {
    fn secs(&self) -> f64 {
        self.sec as f64 + self.nanosec as f64 * 1e-9
    }
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Header {
    stamp: Duration,
    frame_id: String,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct JointTrajectoryPoint {
    positions: Vec<f64>,
    velocities: Vec<f64>,
    accelerations: Vec<f64>,
    effort: Vec<f64>,
    time_from_start: Duration,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct JointTrajectory {
    header: Header,
    joint_names: Vec<String>,
    points: Vec<JointTrajectoryPoint>,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct MultiDofJointTrajectory {
    header: Header,
    joint_names: Vec<String>,
    points: Vec<serde_norway::Value>,
}

/// `control_msgs/action/FollowJointTrajectory` goal (ROS 2 Humble and later), field for field.
#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct FollowJointTrajectoryGoal {
    trajectory: JointTrajectory,
    multi_dof_trajectory: MultiDofJointTrajectory,
    path_tolerance: Vec<serde_norway::Value>,
    component_path_tolerance: Vec<serde_norway::Value>,
    goal_tolerance: Vec<serde_norway::Value>,
    component_goal_tolerance: Vec<serde_norway::Value>,
    goal_time_tolerance: Duration,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct GripperCommand {
    position: f64,
    max_effort: f64,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct GripperStep {
    time_from_start: Duration,
    arm: String,
    command: GripperCommand,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct GripperSteps {
    steps: Vec<GripperStep>,
}

/// The ROS 2 goal parses as the real message definitions; both arms' points are on it with
/// their own positions, joint speeds by finite differences stay within the plan's limits, and
/// the gripper commands close on every object the plan picks and open again.
#[test]
fn ros2_goal_for_both_arms_with_gripper_commands_parses_as_the_message_definitions() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    let files = export(&plan, ExportFormat::Ros2Goal, dir.path()).unwrap();
    assert_eq!(files.len(), 3);
    let goal: FollowJointTrajectoryGoal =
        serde_norway::from_str(&std::fs::read_to_string(dir.path().join("both_arms_goal.yaml")).unwrap()).unwrap();
    let t = &goal.trajectory;
    assert_eq!(t.header.frame_id, "WAIST");
    assert_eq!(t.header.stamp.secs(), 0.0);
    assert!(goal.multi_dof_trajectory.joint_names.is_empty() && goal.multi_dof_trajectory.points.is_empty());
    assert!(goal.multi_dof_trajectory.header.frame_id.is_empty());
    assert!(goal.path_tolerance.is_empty() && goal.goal_tolerance.is_empty());
    assert!(goal.component_path_tolerance.is_empty() && goal.component_goal_tolerance.is_empty());
    assert_eq!(goal.goal_time_tolerance.secs(), 0.0);
    let moving: Vec<Arm> = [Arm::Left, Arm::Right]
        .into_iter()
        .filter(|&a| plan.trajectories.iter().any(|tr| tr.arm == a))
        .collect();
    assert_eq!(t.joint_names.len(), 6 * moving.len());
    assert_eq!(t.points[0].time_from_start.secs(), 0.0);
    for p in &t.points {
        assert_eq!(p.positions.len(), t.joint_names.len());
        assert_eq!(p.velocities.len(), t.joint_names.len());
        assert!(p.accelerations.is_empty() && p.effort.is_empty());
        assert!(p.time_from_start.nanosec < 1_000_000_000);
    }
    // Speeds and accelerations by finite differences within the scaled limits, velocities
    // continuous, on the goal as a controller receives it (both arms' columns).
    let (vlim, alim) = scaled_limits(&plan);
    let vlim: Vec<f64> = (0..t.joint_names.len()).map(|j| vlim[j % 6]).collect();
    assert_finite_difference_limits(&goal_points(t), &vlim, alim);
    // Each arm's own points are on the goal, in its six columns.
    for (k, &arm) in moving.iter().enumerate() {
        for tr in plan.trajectories.iter().filter(|tr| tr.arm == arm) {
            for p in &tr.points {
                let q = t
                    .points
                    .iter()
                    .find(|q| (q.time_from_start.secs() - p.t).abs() < 1e-6)
                    .unwrap_or_else(|| panic!("no goal point at t = {}", p.t));
                for j in 0..6 {
                    assert!((q.positions[6 * k + j] - p.positions[j]).abs() < 1e-12);
                }
            }
        }
    }
    let g: GripperSteps =
        serde_norway::from_str(&std::fs::read_to_string(dir.path().join("gripper_commands.yaml")).unwrap()).unwrap();
    assert!(g
        .steps
        .windows(2)
        .all(|w| w[0].time_from_start.secs() <= w[1].time_from_start.secs()));
    let end = t.points.last().unwrap().time_from_start.secs();
    let mut closes = 0;
    for arm in ["left", "right"] {
        let steps: Vec<&GripperStep> = g.steps.iter().filter(|s| s.arm == arm).collect();
        for w in steps.windows(2) {
            assert!(
                (w[0].command.position - w[1].command.position).abs() > 1e-9,
                "a command changes the opening"
            );
            closes += (w[1].command.position < w[0].command.position) as usize;
        }
    }
    for s in &g.steps {
        assert!(s.command.position >= 0.0 && s.command.max_effort == 0.0);
        assert!(s.time_from_start.secs() <= end + 1e-9);
    }
    let picks = plan.actions.iter().filter(|a| a.kind == "place").count();
    assert!(closes >= picks, "{closes} closing commands for {picks} placed objects");
}

/// `robot.speed_scale` slows the trajectories to that fraction of the joint limits; the plan
/// records it, the verifier accepts the plan against the scaled limits, and the exported goal's
/// finite-difference speeds stay below them.
#[test]
fn speed_scale_keeps_trajectories_and_the_export_below_the_scaled_limits() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/instances/paper/exp1_4objects.toml"
    ))
    .unwrap()
    .replacen("[[kinds]]", "[robot]\nspeed_scale = 0.5\n\n[[kinds]]", 1);
    let inst = common::parse(&text);
    assert_eq!(inst.robot.speed_scale, 0.5);
    let plan = optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan;
    let report = pushpack::verify::verify(&inst, &plan);
    assert!(report.is_valid(), "{report:?}");
    let robot = plan.robot.as_ref().unwrap();
    assert_eq!(robot.timing.velocity_scale, 0.5);
    let urdf = [0.5f64; 6]; // the NEXTAGE Open URDF's arm joint limit, rad/s
    for (v, u) in robot.velocity_limits.iter().zip(urdf) {
        assert!((v - 0.5 * u).abs() < 1e-12, "{v}");
    }
    let dir = tempfile::tempdir().unwrap();
    export(&plan, ExportFormat::Ros2Goal, dir.path()).unwrap();
    let goal: FollowJointTrajectoryGoal =
        serde_norway::from_str(&std::fs::read_to_string(dir.path().join("both_arms_goal.yaml")).unwrap()).unwrap();
    // 0.5 × 0.5 rad/s and 0.5² × 1 rad/s², by finite differences over the goal's points.
    let t = &goal.trajectory;
    let vlim = vec![0.25; t.joint_names.len()];
    assert_eq!(robot.timing.acceleration, 1.0);
    assert_finite_difference_limits(&goal_points(t), &vlim, 0.25);
    // The default plan of the same instance is faster: the scale is not ignored. (The speed
    // scale is one of the run's options, `trajectory.velocity_scale`, which `from_instance`
    // takes from `robot.speed_scale`: the default plan needs the default instance's options.)
    let default_inst = common::load("paper/exp1_4objects.toml");
    let base = optimize(&default_inst, &PlanOptions::from_instance(&default_inst))
        .unwrap()
        .plan;
    assert!(plan.robot_time_s().unwrap() > base.robot_time_s().unwrap() * 1.5);
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ListPoint {
    positions: Vec<f64>,
    velocities: Vec<f64>,
    time_from_start: Duration,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ListTrajectory {
    joint_names: Vec<String>,
    points: Vec<ListPoint>,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ListGripper {
    arm: String,
    command: GripperCommand,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ListStep {
    trajectory: Option<ListTrajectory>,
    gripper: Option<ListGripper>,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ActionList {
    steps: Vec<ListStep>,
}

/// The blocking action list holds the whole goal, cut where the gripper acts, with every
/// gripper command at its place: run in order, it reproduces the goal point for point, and each
/// trajectory piece starts and ends at rest (so waiting for a gripper is safe).
#[test]
fn the_action_list_interleaves_the_goal_and_the_gripper_commands() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    export(&plan, ExportFormat::Ros2Goal, dir.path()).unwrap();
    let read = |f: &str| std::fs::read_to_string(dir.path().join(f)).unwrap();
    let goal: FollowJointTrajectoryGoal = serde_norway::from_str(&read("both_arms_goal.yaml")).unwrap();
    let grip: GripperSteps = serde_norway::from_str(&read("gripper_commands.yaml")).unwrap();
    let list: ActionList = serde_norway::from_str(&read("action_list.yaml")).unwrap();
    let (mut offset, mut replay, mut commands) = (0.0, Vec::<(f64, Vec<f64>)>::new(), Vec::new());
    for step in &list.steps {
        match (&step.trajectory, &step.gripper) {
            (Some(t), None) => {
                assert_eq!(t.joint_names, goal.trajectory.joint_names);
                assert!(t.points.len() >= 2);
                assert_eq!(t.points[0].time_from_start.secs(), 0.0);
                for end in [&t.points[0], t.points.last().unwrap()] {
                    assert!(
                        end.velocities.iter().all(|v| v.abs() < 1e-9),
                        "a piece starts and ends at rest"
                    );
                }
                for p in &t.points {
                    let at = offset + p.time_from_start.secs();
                    if replay.last().is_none_or(|(t0, _)| at > t0 + 1e-6) {
                        replay.push((at, p.positions.clone()));
                    }
                }
                offset += t.points.last().unwrap().time_from_start.secs();
            }
            (None, Some(g)) => commands.push((offset, g.arm.clone(), g.command.position)),
            other => panic!("a step is a trajectory or a gripper command: {other:?}"),
        }
    }
    let want = &goal.trajectory.points;
    assert_eq!(replay.len(), want.len(), "every goal point once");
    for ((t, q), p) in replay.iter().zip(want) {
        assert!(
            (t - p.time_from_start.secs()).abs() < 1e-6,
            "{t} vs {}",
            p.time_from_start.secs()
        );
        assert!(q.iter().zip(&p.positions).all(|(a, b)| (a - b).abs() < 1e-9));
    }
    assert_eq!(commands.len(), grip.steps.len());
    for ((t, arm, pos), g) in commands.iter().zip(&grip.steps) {
        assert!((t - g.time_from_start.secs()).abs() < 1e-6 && *arm == g.arm && *pos == g.command.position);
    }
}

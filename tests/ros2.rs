//! `pushpack export --format ros2-goal`: one FollowJointTrajectory goal per arm, the gripper
//! commands and the blocking list, parsed back into structs that mirror the ROS 2 message
//! definitions field for field (unknown fields rejected); the sender script's dry run checked
//! against the same structs; and the command line's refusal of a plan the robot cannot run.

mod common;

use common::limits::{assert_finite_difference_limits, scaled_limits};
use pushpack::plan::export::{export, export_with, ExportFormat, ExportOptions};
use pushpack::plan::{optimize, Plan, PlanOptions};
use pushpack::robot::Arm;
use std::path::Path;

fn plan() -> Plan {
    let inst = common::load("paper/exp1_4objects.toml");
    optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan
}

fn read(dir: &Path, file: &str) -> String {
    std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn read_goal(dir: &Path, file: &str) -> FollowJointTrajectoryGoal {
    serde_norway::from_str(&read(dir, file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// ROS 2 `builtin_interfaces/Duration`, as the message definition has it.
#[derive(serde::Deserialize, Debug, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct Duration {
    sec: i32,
    nanosec: u32,
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

/// `control_msgs/action/GripperCommand` goal.
#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct GripperGoal {
    command: GripperCommand,
}

/// `ros2_goals.yaml`.
#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Manifest {
    frame_id: String,
    arms: Vec<ManifestArm>,
    gripper_commands: String,
    action_list: String,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ManifestArm {
    arm: String,
    controller: String,
    action: String,
    joint_names: Vec<String>,
    goal: String,
    gripper_action: String,
}

/// The goal's points as (time, positions, velocities).
fn goal_points(t: &JointTrajectory) -> Vec<(f64, &[f64], &[f64])> {
    t.points
        .iter()
        .map(|p| (p.time_from_start.secs(), &p.positions[..], &p.velocities[..]))
        .collect()
}

/// One goal per arm, six joints each with that arm's names, every field of the goal as the
/// message definition has it; time runs forward from 0, speeds within the plan's limits, each
/// arm's own points on it; the manifest names the controllers asked for, and no goal for both
/// arms is left behind for a controller to reject.
#[test]
fn each_arm_gets_its_own_six_joint_goal_for_its_named_controller() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    let opts = ExportOptions {
        left_controller: "cell/left_arm".into(),
        right_controller: "right_jtc".into(),
        ..ExportOptions::default()
    };
    let files = export_with(&plan, ExportFormat::Ros2Goal, dir.path(), &opts).unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "left_arm_goal.yaml",
            "right_arm_goal.yaml",
            "gripper_commands.yaml",
            "action_list.yaml",
            "ros2_goals.yaml"
        ]
    );
    let m: Manifest = serde_norway::from_str(&read(dir.path(), "ros2_goals.yaml")).unwrap();
    assert_eq!(m.frame_id, "WAIST");
    assert_eq!(
        (m.gripper_commands.as_str(), m.action_list.as_str()),
        ("gripper_commands.yaml", "action_list.yaml")
    );
    let want = [
        (
            "left",
            "cell/left_arm",
            "/cell/left_arm/follow_joint_trajectory",
            "LARM_JOINT",
            "/lhand_controller/gripper_cmd",
        ),
        (
            "right",
            "right_jtc",
            "/right_jtc/follow_joint_trajectory",
            "RARM_JOINT",
            "/rhand_controller/gripper_cmd",
        ),
    ];
    assert_eq!(m.arms.len(), 2);
    let (vlim, alim) = scaled_limits(&plan);
    for (a, (arm, controller, action, prefix, gripper)) in m.arms.iter().zip(want) {
        assert_eq!(
            (a.arm.as_str(), a.controller.as_str(), a.action.as_str()),
            (arm, controller, action)
        );
        assert_eq!(a.gripper_action, gripper);
        let goal = read_goal(dir.path(), &a.goal);
        let t = &goal.trajectory;
        let joints: Vec<String> = (0..6).map(|j| format!("{prefix}{j}")).collect();
        assert_eq!(t.joint_names, joints);
        assert_eq!(a.joint_names, joints);
        assert_eq!(t.header.frame_id, "WAIST");
        assert_eq!(t.header.stamp.secs(), 0.0);
        assert!(goal.multi_dof_trajectory.joint_names.is_empty() && goal.multi_dof_trajectory.points.is_empty());
        assert!(goal.multi_dof_trajectory.header.frame_id.is_empty());
        assert!(goal.path_tolerance.is_empty() && goal.goal_tolerance.is_empty());
        assert!(goal.component_path_tolerance.is_empty() && goal.component_goal_tolerance.is_empty());
        assert_eq!(goal.goal_time_tolerance.secs(), 0.0);
        assert_eq!(t.points[0].time_from_start.secs(), 0.0);
        for p in &t.points {
            assert_eq!((p.positions.len(), p.velocities.len()), (6, 6));
            assert!(p.accelerations.is_empty() && p.effort.is_empty());
            assert!(p.time_from_start.nanosec < 1_000_000_000);
        }
        for w in t.points.windows(2) {
            assert!(
                w[1].time_from_start.secs() > w[0].time_from_start.secs(),
                "time runs forward"
            );
        }
        assert_finite_difference_limits(&goal_points(t), &vlim, alim);
        let own = if arm == "left" { Arm::Left } else { Arm::Right };
        for tr in plan.trajectories.iter().filter(|tr| tr.arm == own) {
            for p in &tr.points {
                let q = t
                    .points
                    .iter()
                    .find(|q| (q.time_from_start.secs() - p.t).abs() < 1e-6)
                    .unwrap_or_else(|| panic!("{arm}: no goal point at t = {}", p.t));
                assert!(q.positions.iter().zip(&p.positions).all(|(a, b)| (a - b).abs() < 1e-12));
            }
        }
    }
    assert!(!dir.path().join("both_arms_goal.yaml").exists());
    let bad = ExportOptions {
        right_controller: "2nd controller".into(),
        ..ExportOptions::default()
    };
    let e = export_with(&plan, ExportFormat::Ros2Goal, dir.path(), &bad).unwrap_err();
    assert!(
        e.to_string().contains("--right-controller") && e.to_string().contains("ROS 2 name"),
        "{e}"
    );
}

/// A grasp command closes to the object's width less the instance's squeeze (in the
/// instance's units), every command carries the instance's effort, and the numbers print as
/// the lengths they mean: no digits of arithmetic noise.
#[test]
fn gripper_commands_squeeze_each_grasp_with_the_instances_effort() {
    let text = std::fs::read_to_string(common::bundled("paper/exp1_4objects.toml"))
        .unwrap()
        .replacen("[gripper]\n", "[gripper]\nsqueeze = 0.3\nmax_effort = 15\n", 1);
    let inst = common::parse(&text);
    assert_eq!((inst.gripper.squeeze, inst.gripper.max_effort), (0.003, 15.0));
    let plain = common::load("paper/exp1_4objects.toml");
    assert_eq!(
        (plain.gripper.squeeze, plain.gripper.max_effort),
        (0.002, 20.0),
        "the defaults"
    );
    for (bad, field) in [
        ("squeeze = -0.1", "gripper.squeeze"),
        ("max_effort = 0", "gripper.max_effort"),
        ("max_effort = nan", "gripper.max_effort"),
    ] {
        let t = text.replacen("[gripper]\n", &format!("[gripper]\n{bad}\n"), 1);
        let t = t.replacen("squeeze = 0.3\nmax_effort = 15\n", "", 1);
        let e = pushpack::Instance::parse(&t, false, "bad.toml", None)
            .expect_err(bad)
            .to_string();
        assert!(e.contains("bad.toml") && e.contains(field), "{bad}: {e}");
    }
    let plan = optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan;
    let dir = tempfile::tempdir().unwrap();
    export_with(
        &plan,
        ExportFormat::Ros2Goal,
        dir.path(),
        &ExportOptions::from_instance(&inst),
    )
    .unwrap();
    let file = read(dir.path(), "gripper_commands.yaml");
    let g: GripperSteps = serde_norway::from_str(&file).unwrap();
    let mut grasps = 0;
    for arm in [Arm::Left, Arm::Right] {
        let key: Vec<_> = plan
            .arm_trajectories(arm)
            .into_iter()
            .flat_map(|t| t.key_poses.iter())
            .collect();
        let steps: Vec<&GripperStep> = g.steps.iter().filter(|s| s.arm == arm.name()).collect();
        let mut last = f64::NAN; // the first command opens: no grasp
        for s in steps {
            assert_eq!(s.command.max_effort, 15.0);
            let k = key
                .iter()
                .find(|k| (k.t - s.time_from_start.secs()).abs() < 1e-6)
                .expect("a command at a key pose");
            // Rounded to the nanometre: an opening of 0.09 m that the arithmetic left as
            // 0.08999999999999998 is printed as 0.09.
            let want = if k.opening > 0.0 && k.opening < last {
                grasps += 1;
                ((k.opening - 0.003) * 1e9).round() / 1e9
            } else {
                (k.opening * 1e9).round() / 1e9
            };
            assert_eq!(s.command.position, want, "{} at {}", arm.name(), k.t);
            last = k.opening;
        }
    }
    let picks = plan.actions.iter().filter(|a| a.kind == "place").count();
    assert!(grasps >= picks, "{grasps} grasps for {picks} placed objects");
    for line in file.lines().filter(|l| l.contains("position:")) {
        let pos = line.split("position: ").nth(1).unwrap().split(',').next().unwrap();
        let decimals = pos.split('.').nth(1).map_or(0, str::len);
        assert!(decimals <= 9, "{pos} has digits below the nanometre");
    }
}

/// The sender's dry run (no ROS needed) prints what it would send; every goal reads back into
/// the message definitions' structs, trajectory goals have six joints each and go to the
/// manifest's action servers, and the timed mode sends exactly the goal files and each gripper
/// command at its time.
#[test]
fn the_senders_dry_run_sends_goals_the_message_definitions_accept() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    export(&plan, ExportFormat::Ros2Goal, dir.path()).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/ros2_send.py");
    let grip: GripperSteps = serde_norway::from_str(&read(dir.path(), "gripper_commands.yaml")).unwrap();
    for mode in ["blocking", "timed"] {
        let out = std::process::Command::new("python3")
            .arg(script)
            .arg(dir.path())
            .args(["--mode", mode, "--dry-run"])
            .output()
            .expect("python3 runs (scripts/ros2_send.py needs it and PyYAML)");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{mode}: {stderr}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["mode"], mode);
        let batches = v["batches"].as_array().unwrap();
        let (mut trajectories, mut grippers) = (0, Vec::new());
        for b in batches {
            for g in b["goals"].as_array().unwrap() {
                let (action, ty) = (g["action"].as_str().unwrap(), g["type"].as_str().unwrap());
                match ty {
                    "control_msgs/action/FollowJointTrajectory" => {
                        let goal: FollowJointTrajectoryGoal =
                            serde_json::from_value(g["goal"].clone()).unwrap_or_else(|e| panic!("{mode}: {e}"));
                        let t = &goal.trajectory;
                        let prefix = match action {
                            "/larm_controller/follow_joint_trajectory" => "LARM_JOINT",
                            "/rarm_controller/follow_joint_trajectory" => "RARM_JOINT",
                            other => panic!("{mode}: unexpected action server {other}"),
                        };
                        assert_eq!(t.joint_names.len(), 6);
                        assert!(t.joint_names.iter().all(|n| n.starts_with(prefix)));
                        assert!(t.points.iter().all(|p| p.positions.len() == 6));
                        assert_eq!(t.points[0].time_from_start.secs(), 0.0);
                        for w in t.points.windows(2) {
                            assert!(w[1].time_from_start.secs() > w[0].time_from_start.secs());
                        }
                        if mode == "timed" {
                            let file = format!(
                                "{}_arm_goal.yaml",
                                if prefix == "LARM_JOINT" { "left" } else { "right" }
                            );
                            let sent = goal_points(t);
                            let want = read_goal(dir.path(), &file);
                            assert_eq!(sent, goal_points(&want.trajectory), "{file} is sent as it is");
                        }
                        trajectories += 1;
                    }
                    "control_msgs/action/GripperCommand" => {
                        let goal: GripperGoal = serde_json::from_value(g["goal"].clone()).unwrap();
                        assert!(action.ends_with("hand_controller/gripper_cmd"), "{action}");
                        grippers.push((b["at"].as_f64(), goal.command.position));
                    }
                    other => panic!("{mode}: unexpected action type {other}"),
                }
            }
        }
        assert_eq!(grippers.len(), grip.steps.len(), "{mode}: every gripper command once");
        if mode == "timed" {
            assert_eq!(trajectories, 2, "one goal per arm");
            for ((at, pos), s) in grippers.iter().zip(&grip.steps) {
                assert!((at.unwrap() - s.time_from_start.secs()).abs() < 1e-9);
                assert_eq!(*pos, s.command.position);
            }
        } else {
            assert!(trajectories > 2 && trajectories % 2 == 0, "both arms in each piece");
        }
    }
    // A directory that is not an export is an error with exit code 2, not a traceback.
    let out = std::process::Command::new("python3")
        .args([script, "/nonexistent", "--dry-run"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a complete ros2-goal export"));
}

fn cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args(args)
        .output()
        .unwrap()
}

/// `pushpack export` verifies the plan: a packing-only plan is refused with exit 1 and a
/// message naming `--packing-only`, nothing written; with the flag it is exported with a
/// warning. A controller name ROS 2 rejects is an input error (exit 2) naming the flag.
#[test]
fn export_refuses_a_plan_the_robot_cannot_run_unless_packing_only() {
    let file = common::bundled("paper/exp1_4objects.toml");
    let inst = common::load("paper/exp1_4objects.toml");
    let opts = PlanOptions {
        packing_only: true,
        ..PlanOptions::from_instance(&inst)
    };
    let plan = optimize(&inst, &opts).expect("plans").plan;
    assert!(!pushpack::verify(&inst, &plan).is_executable());
    let dir = tempfile::tempdir().unwrap();
    let plan_file = dir.path().join("plan.json");
    plan.save(&plan_file).unwrap();
    let p = plan_file.to_str().unwrap();
    let out_dir = dir.path().join("goals");
    let o = out_dir.to_str().unwrap();
    let r = cli(&["export", p, "--format", "ros2-goal", "--out", o, "--instance", &file]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("not executable") && stderr.contains("--packing-only"),
        "{stderr}"
    );
    assert!(!out_dir.exists(), "nothing is written");
    let r = cli(&[
        "export",
        p,
        "--format",
        "ros2-goal",
        "--out",
        o,
        "--instance",
        &file,
        "--packing-only",
    ]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("do not send it to a robot"),
        "{stderr}"
    );
    assert!(out_dir.join("left_arm_goal.yaml").exists());
    let r = cli(&[
        "export",
        p,
        "--format",
        "ros2-goal",
        "--out",
        o,
        "--instance",
        &file,
        "--packing-only",
        "--left-controller",
        "larm controller",
    ]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--left-controller"), "{stderr}");
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
    arm: String,
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
    trajectories: Option<Vec<ListTrajectory>>,
    gripper: Option<ListGripper>,
}

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ActionList {
    steps: Vec<ListStep>,
}

/// The blocking action list holds both arms' goals, cut where the gripper acts, one six-joint
/// piece per arm in each step, with every gripper command at its place: run in order, it passes
/// through every point of each arm's goal, and each piece starts and ends at rest (so waiting
/// for a gripper is safe).
#[test]
fn the_action_list_interleaves_per_arm_pieces_and_the_gripper_commands() {
    let plan = plan();
    let dir = tempfile::tempdir().unwrap();
    export(&plan, ExportFormat::Ros2Goal, dir.path()).unwrap();
    let grip: GripperSteps = serde_norway::from_str(&read(dir.path(), "gripper_commands.yaml")).unwrap();
    let list: ActionList = serde_norway::from_str(&read(dir.path(), "action_list.yaml")).unwrap();
    let goals = [
        read_goal(dir.path(), "left_arm_goal.yaml"),
        read_goal(dir.path(), "right_arm_goal.yaml"),
    ];
    let mut offset = 0.0;
    let mut replay: [Vec<(f64, Vec<f64>)>; 2] = Default::default();
    let mut commands = Vec::new();
    for step in &list.steps {
        match (&step.trajectories, &step.gripper) {
            (Some(pieces), None) => {
                assert_eq!(pieces.len(), 2, "both arms in every piece");
                let mut dur = None;
                for (k, (piece, arm)) in pieces.iter().zip(["left", "right"]).enumerate() {
                    assert_eq!(piece.arm, arm);
                    assert_eq!(piece.joint_names, goals[k].trajectory.joint_names);
                    assert!(piece.points.len() >= 2);
                    assert_eq!(piece.points[0].time_from_start.secs(), 0.0);
                    for end in [&piece.points[0], piece.points.last().unwrap()] {
                        assert!(
                            end.velocities.iter().all(|v| v.abs() < 1e-9),
                            "a piece starts and ends at rest"
                        );
                    }
                    for p in &piece.points {
                        assert_eq!(p.positions.len(), 6);
                        replay[k].push((offset + p.time_from_start.secs(), p.positions.clone()));
                    }
                    let d = piece.points.last().unwrap().time_from_start.secs();
                    assert!(
                        dur.is_none_or(|x: f64| (x - d).abs() < 1e-9),
                        "the arms' pieces end together"
                    );
                    dur = Some(d);
                }
                offset += dur.unwrap();
            }
            (None, Some(g)) => commands.push((offset, g.arm.clone(), g.command.position)),
            other => panic!("a step is trajectories or a gripper command: {other:?}"),
        }
    }
    for (k, goal) in goals.iter().enumerate() {
        for p in &goal.trajectory.points {
            let t = p.time_from_start.secs();
            let q = replay[k]
                .iter()
                .find(|(s, _)| (s - t).abs() < 1e-6)
                .unwrap_or_else(|| panic!("arm {k}: no point at {t} in the list"));
            assert!(q.1.iter().zip(&p.positions).all(|(a, b)| (a - b).abs() < 1e-9));
        }
    }
    assert_eq!(commands.len(), grip.steps.len());
    for ((t, arm, pos), g) in commands.iter().zip(&grip.steps) {
        assert!((t - g.time_from_start.secs()).abs() < 1e-6 && *arm == g.arm && *pos == g.command.position);
    }
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
    // 0.5 × 0.5 rad/s and 0.5² × 1 rad/s², by finite differences over each goal's points.
    assert_eq!(robot.timing.acceleration, 1.0);
    for arm in ["left", "right"] {
        let goal = read_goal(dir.path(), &format!("{arm}_arm_goal.yaml"));
        assert_finite_difference_limits(&goal_points(&goal.trajectory), &[0.25; 6], 0.25);
    }
    // The default plan of the same instance is faster: the scale is not ignored. (The speed
    // scale is one of the run's options, `trajectory.velocity_scale`, which `from_instance`
    // takes from `robot.speed_scale`: the default plan needs the default instance's options.)
    let default_inst = common::load("paper/exp1_4objects.toml");
    let base = optimize(&default_inst, &PlanOptions::from_instance(&default_inst))
        .unwrap()
        .plan;
    assert!(plan.robot_time_s().unwrap() > base.robot_time_s().unwrap() * 1.5);
}

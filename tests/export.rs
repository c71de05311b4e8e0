//! `pushpack export`: ROS `trajectory_msgs/JointTrajectory` YAML and JSON and CSV per arm, parsed
//! back and compared with the plan's trajectories (ROS 2 goals: tests/ros2.rs).

mod common;

use pushpack::plan::export::{export, to_yaml, ExportFormat, RosJointTrajectory};
use pushpack::plan::{optimize, PlanOptions};
use pushpack::robot::Arm;

fn plan() -> pushpack::plan::Plan {
    let inst = common::load("paper/exp1_4objects.toml");
    optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan
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
    let (vlim, alim) = common::limits::scaled_limits(plan);
    let pts: Vec<(f64, &[f64], &[f64])> = m
        .points
        .iter()
        .map(|p| (p.time_from_start.as_secs(), &p.positions[..], &p.velocities[..]))
        .collect();
    common::limits::assert_finite_difference_limits(&pts, &vlim, alim);
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

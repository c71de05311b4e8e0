//! Export of a plan's joint trajectories for a robot controller: one ROS 1
//! `trajectory_msgs/JointTrajectory`-shaped message per arm (YAML or JSON) or one CSV per arm;
//! or, for ROS 2, one goal per arm with the gripper commands ([`super::ros2`]).
//!
//! Each arm's message holds every point of its moves in plan time (`time_from_start` from the
//! start of the plan); while the other arm works, the arm holds still (two points with the same
//! positions). Field names follow ROS 1 (`header.seq`, `stamp.secs/nsecs`,
//! `time_from_start.secs/nsecs`), as used by the NEXTAGE Open's ROS 1 stack (rtmros_nextage).
//! The YAML is written by hand (no YAML serialiser dependency); the tests parse it back.

use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::plan::Plan;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Export format (more may come: match with a wildcard arm).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum ExportFormat {
    /// `trajectory_msgs/JointTrajectory` as YAML (`<arm>_arm.yaml`).
    RosYaml,
    /// `trajectory_msgs/JointTrajectory` as JSON (`<arm>_arm.json`).
    RosJson,
    /// CSV: `t` then one column per joint (`<arm>_arm.csv`).
    Csv,
    /// ROS 2: one `control_msgs/action/FollowJointTrajectory` goal per arm
    /// (`left_arm_goal.yaml`, `right_arm_goal.yaml`), the gripper commands on their clock
    /// (`gripper_commands.yaml`), all as one blocking action list (`action_list.yaml`), and the
    /// action servers to send them to (`ros2_goals.yaml`); see [`super::ros2`].
    Ros2Goal,
}

impl ExportFormat {
    /// Command-line names: `ros-yaml`, `ros-json`, `csv`, `ros2-goal`.
    pub const NAMES: [&'static str; 4] = ["ros-yaml", "ros-json", "csv", "ros2-goal"];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::RosYaml => "ros-yaml",
            ExportFormat::RosJson => "ros-json",
            ExportFormat::Csv => "csv",
            ExportFormat::Ros2Goal => "ros2-goal",
        }
    }

    fn extension(self) -> &'static str {
        match self {
            ExportFormat::RosYaml => "yaml",
            ExportFormat::RosJson => "json",
            ExportFormat::Csv => "csv",
            ExportFormat::Ros2Goal => "yaml",
        }
    }
}

impl std::str::FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "ros-yaml" => Ok(ExportFormat::RosYaml),
            "ros-json" => Ok(ExportFormat::RosJson),
            "csv" => Ok(ExportFormat::Csv),
            "ros2-goal" => Ok(ExportFormat::Ros2Goal),
            other => Err(format!(
                "unknown export format {other:?}: expected one of ros-yaml, ros-json, csv, ros2-goal"
            )),
        }
    }
}

/// What the ROS 2 export needs beyond the plan: the controllers' names and the gripper's
/// squeeze and effort. [`Default`] is NEXTAGE's controllers and the instance defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// Trajectory controller of the left arm (NEXTAGE: `larm_controller`).
    pub left_controller: String,
    /// Trajectory controller of the right arm (NEXTAGE: `rarm_controller`).
    pub right_controller: String,
    /// `GripperCommand` action server of the left hand, as a controller name
    /// (`<name>/gripper_cmd`, as ros2_control's gripper action controller names it).
    pub left_gripper_controller: String,
    /// `GripperCommand` action server of the right hand.
    pub right_gripper_controller: String,
    /// How much narrower than the object a grasp command closes (m): the instance's
    /// `gripper.squeeze`.
    pub squeeze: f64,
    /// `max_effort` of every gripper command (N): the instance's `gripper.max_effort`.
    pub max_effort: f64,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            left_controller: "larm_controller".into(),
            right_controller: "rarm_controller".into(),
            left_gripper_controller: "lhand_controller".into(),
            right_gripper_controller: "rhand_controller".into(),
            squeeze: crate::instance::Gripper::DEFAULT_SQUEEZE,
            max_effort: crate::instance::Gripper::DEFAULT_MAX_EFFORT,
        }
    }
}

impl ExportOptions {
    /// The defaults with the instance's gripper squeeze and effort.
    pub fn from_instance(inst: &crate::instance::Instance) -> Self {
        ExportOptions {
            squeeze: inst.gripper.squeeze,
            max_effort: inst.gripper.max_effort,
            ..Default::default()
        }
    }

    /// Refuses a controller name ROS 2 would reject (the sender would fail on the robot, after
    /// the files were written and checked) and a squeeze or effort that is not a finite number
    /// ≥ 0. `file` names where the options came from in the error.
    pub fn check(&self, file: &str) -> Result<()> {
        let names = [
            ("--left-controller", &self.left_controller),
            ("--right-controller", &self.right_controller),
            ("--left-gripper-controller", &self.left_gripper_controller),
            ("--right-gripper-controller", &self.right_gripper_controller),
        ];
        for (field, name) in names {
            // A ROS 2 name: tokens of letters, digits and `_`, not starting with a digit,
            // separated by single `/`.
            let ok = !name.is_empty()
                && name.split('/').all(|t| {
                    !t.is_empty()
                        && !t.starts_with(|c: char| c.is_ascii_digit())
                        && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                });
            if !ok {
                return Err(Error::input(
                    file,
                    field,
                    format!(
                        "{name:?} is not a ROS 2 name: use letters, digits and `_` (not starting with a digit), tokens separated by `/`"
                    ),
                ));
            }
        }
        for (field, v) in [("squeeze", self.squeeze), ("max_effort", self.max_effort)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::input(
                    file,
                    field,
                    format!("must be a finite number >= 0, got {v}"),
                ));
            }
        }
        Ok(())
    }

    /// The trajectory controller of `arm`.
    pub fn controller(&self, arm: Arm) -> &str {
        match arm {
            Arm::Left => &self.left_controller,
            Arm::Right => &self.right_controller,
        }
    }

    /// The gripper controller of `arm`'s hand.
    pub fn gripper_controller(&self, arm: Arm) -> &str {
        match arm {
            Arm::Left => &self.left_gripper_controller,
            Arm::Right => &self.right_gripper_controller,
        }
    }
}

/// ROS 1 `time` / `duration`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct RosTime {
    /// Whole seconds.
    pub secs: i64,
    /// Nanoseconds (0 ≤ nsecs < 1e9).
    pub nsecs: i64,
}

impl RosTime {
    /// From seconds (rounded to the nanosecond).
    pub fn from_secs(t: f64) -> RosTime {
        let ns = (t * 1e9).round() as i64;
        RosTime {
            secs: ns.div_euclid(1_000_000_000),
            nsecs: ns.rem_euclid(1_000_000_000),
        }
    }
    /// As seconds.
    pub fn as_secs(&self) -> f64 {
        self.secs as f64 + self.nsecs as f64 * 1e-9
    }
}

/// `std_msgs/Header`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct RosHeader {
    /// Sequence number (0).
    pub seq: u32,
    /// Stamp (0 = start when received).
    pub stamp: RosTime,
    /// Frame of the message (`WAIST`).
    pub frame_id: String,
}

/// `trajectory_msgs/JointTrajectoryPoint`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct RosPoint {
    /// Positions (rad).
    pub positions: Vec<f64>,
    /// Velocities (rad/s).
    pub velocities: Vec<f64>,
    /// Accelerations (empty).
    pub accelerations: Vec<f64>,
    /// Efforts (empty).
    pub effort: Vec<f64>,
    /// Time from the start of the plan.
    pub time_from_start: RosTime,
}

/// `trajectory_msgs/JointTrajectory`.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct RosJointTrajectory {
    /// Header.
    pub header: RosHeader,
    /// Joint names.
    pub joint_names: Vec<String>,
    /// Points.
    pub points: Vec<RosPoint>,
}

/// The message of one arm (`None` when the arm never moves).
pub fn arm_message(plan: &Plan, arm: Arm) -> Option<RosJointTrajectory> {
    let trs: Vec<_> = plan
        .arm_trajectories(arm)
        .into_iter()
        .filter(|t| !t.points.is_empty())
        .collect();
    let first = trs.first()?;
    let frame = plan
        .robot
        .as_ref()
        .map(|r| r.base_frame.clone())
        .unwrap_or_else(|| "WAIST".into());
    let mut points: Vec<RosPoint> = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    let mk = |p: &crate::motion::TrajPoint| RosPoint {
        positions: p.positions.clone(),
        velocities: if p.velocities.len() == p.positions.len() {
            p.velocities.clone()
        } else {
            vec![0.0; p.positions.len()]
        },
        accelerations: Vec::new(),
        effort: Vec::new(),
        time_from_start: RosTime::from_secs(p.t),
    };
    if first.points[0].t > 0.0 {
        let mut p = mk(&first.points[0]);
        p.time_from_start = RosTime::from_secs(0.0);
        points.push(p);
        last_t = 0.0;
    }
    for tr in &trs {
        for p in &tr.points {
            if p.t <= last_t + 1e-9 {
                continue;
            }
            points.push(mk(p));
            last_t = p.t;
        }
    }
    Some(RosJointTrajectory {
        header: RosHeader {
            seq: 0,
            stamp: RosTime { secs: 0, nsecs: 0 },
            frame_id: frame,
        },
        joint_names: first.joint_names.clone(),
        points,
    })
}

/// `x` in the shortest digits that read back as exactly `x` (Rust's `{:?}`, as ryu prints),
/// in a form YAML 1.1 reads as a float: PyYAML, which `ros2` and rclpy scripts use, takes
/// `1e-7` and `1.0e16` for strings and needs `1.0e-7` and `1.0e+16`.
pub(super) fn num(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains("inf") || s.contains("NaN") {
        return s;
    }
    match s.split_once('e') {
        Some((m, e)) => {
            let m = if m.contains('.') {
                m.to_string()
            } else {
                format!("{m}.0")
            };
            let e = if e.starts_with('-') {
                e.to_string()
            } else {
                format!("+{e}")
            };
            format!("{m}e{e}")
        }
        None if s.contains('.') => s,
        None => format!("{s}.0"),
    }
}

pub(super) fn list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| num(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// The message as YAML (block style, flow lists for vectors).
pub fn to_yaml(m: &RosJointTrajectory) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "header:");
    let _ = writeln!(s, "  seq: {}", m.header.seq);
    let _ = writeln!(s, "  stamp:");
    let _ = writeln!(s, "    secs: {}", m.header.stamp.secs);
    let _ = writeln!(s, "    nsecs: {}", m.header.stamp.nsecs);
    let _ = writeln!(
        s,
        "  frame_id: \"{}\"",
        m.header.frame_id.replace('\\', "\\\\").replace('"', "\\\"")
    );
    let names: Vec<String> = m.joint_names.iter().map(|n| format!("\"{n}\"")).collect();
    let _ = writeln!(s, "joint_names: [{}]", names.join(", "));
    if m.points.is_empty() {
        let _ = writeln!(s, "points: []");
    } else {
        let _ = writeln!(s, "points:");
    }
    for p in &m.points {
        let _ = writeln!(s, "  - positions: {}", list(&p.positions));
        let _ = writeln!(s, "    velocities: {}", list(&p.velocities));
        let _ = writeln!(s, "    accelerations: {}", list(&p.accelerations));
        let _ = writeln!(s, "    effort: {}", list(&p.effort));
        let _ = writeln!(s, "    time_from_start:");
        let _ = writeln!(s, "      secs: {}", p.time_from_start.secs);
        let _ = writeln!(s, "      nsecs: {}", p.time_from_start.nsecs);
    }
    s
}

/// The message as CSV: `t,<joint names…>`, one row per point.
pub fn to_csv(m: &RosJointTrajectory) -> String {
    let mut s = String::from("t");
    for n in &m.joint_names {
        s.push(',');
        s.push_str(n);
    }
    s.push('\n');
    for p in &m.points {
        s.push_str(&num(p.time_from_start.as_secs()));
        for x in &p.positions {
            s.push(',');
            s.push_str(&num(*x));
        }
        s.push('\n');
    }
    s
}

/// [`export_with`] with the default [`ExportOptions`].
pub fn export(plan: &Plan, format: ExportFormat, out_dir: &Path) -> Result<Vec<PathBuf>> {
    export_with(plan, format, out_dir, &ExportOptions::default())
}

/// Write the plan's joint trajectories in `format` into `out_dir` (created if needed): one file
/// per arm that moves (`left_arm.yaml`, `right_arm.csv`, …), or the ROS 2 files. Returns the
/// paths written. Fails when the plan has no trajectories or a trajectory of it has an error.
/// It does not judge whether the robot can run the plan: call [`crate::verify::verify`] first.
pub fn export_with(plan: &Plan, format: ExportFormat, out_dir: &Path, opts: &ExportOptions) -> Result<Vec<PathBuf>> {
    let file = "plan.json";
    if plan.trajectories.is_empty() {
        return Err(Error::input(
            file,
            "trajectories",
            "the plan has no joint trajectories to export",
        ));
    }
    if let Some((k, t)) = plan.trajectories.iter().enumerate().find(|(_, t)| t.error.is_some()) {
        return Err(Error::input(
            file,
            format!("trajectories[{k}]"),
            format!(
                "{} has no joint trajectory: {}",
                t.label,
                t.error.as_deref().unwrap_or("")
            ),
        ));
    }
    exportable(plan, file)?;
    opts.check("<export options>")?;
    std::fs::create_dir_all(out_dir).map_err(|e| Error::Io {
        path: out_dir.to_path_buf(),
        source: e,
    })?;
    let mut written = Vec::new();
    let write = |name: &str, text: String, written: &mut Vec<PathBuf>| -> Result<()> {
        let path = out_dir.join(name);
        std::fs::write(&path, text).map_err(|e| Error::Io {
            path: path.clone(),
            source: e,
        })?;
        written.push(path);
        Ok(())
    };
    if format == ExportFormat::Ros2Goal {
        if let Some(e) = super::ros2::ros2_export(plan, opts) {
            for g in &e.arms {
                let text = super::ros2::arm_goal_yaml(&e.frame_id, g);
                write(&super::ros2::arm_goal_file(g.arm), text, &mut written)?;
            }
            write("gripper_commands.yaml", super::ros2::gripper_yaml(&e), &mut written)?;
            write("action_list.yaml", super::ros2::action_list_yaml(&e), &mut written)?;
            write("ros2_goals.yaml", super::ros2::manifest_yaml(&e), &mut written)?;
        }
        return Ok(written);
    }
    for arm in [Arm::Left, Arm::Right] {
        let Some(m) = arm_message(plan, arm) else {
            continue;
        };
        let text = match format {
            ExportFormat::RosYaml => to_yaml(&m),
            ExportFormat::RosJson => serde_json::to_string_pretty(&m).expect("messages serialise") + "\n",
            ExportFormat::Csv => to_csv(&m),
            ExportFormat::Ros2Goal => continue, // written above
        };
        write(
            &format!("{}_arm.{}", arm.name(), format.extension()),
            text,
            &mut written,
        )?;
    }
    Ok(written)
}

/// The checks a controller's input needs and that need no instance: every number finite, time
/// running forward inside each trajectory and across one arm's trajectories, one value per
/// joint, and recorded velocities within the plan's own limits. A plan that fails is refused,
/// never exported in part (a point at t = 1e300 once dropped most of a trajectory silently).
fn exportable(plan: &Plan, file: &str) -> Result<()> {
    let bad = |field: String, reason: String| Err(Error::input(file, field, reason));
    let limits = plan
        .robot
        .as_ref()
        .map(|r| r.velocity_limits.clone())
        .unwrap_or_default();
    for (k, t) in plan.trajectories.iter().enumerate() {
        let f = |s: &str| format!("trajectories[{k}].{s}");
        if !(t.t_start.is_finite() && t.t_end.is_finite() && t.t_start <= t.t_end) {
            return bad(
                f("t_end"),
                format!("{}: times {} to {} do not run forward", t.label, t.t_start, t.t_end),
            );
        }
        let n = t.joint_names.len();
        let mut prev = t.t_start;
        for (i, p) in t.points.iter().enumerate() {
            let fp = |s: &str| f(&format!("points[{i}].{s}"));
            if !p.t.is_finite() || p.t < prev - 1e-9 || p.t > t.t_end + 1e-9 {
                return bad(
                    fp("t"),
                    format!(
                        "{}: t = {} is not between the previous point ({prev}) and t_end ({})",
                        t.label, p.t, t.t_end
                    ),
                );
            }
            if p.positions.len() != n || p.positions.iter().any(|q| !q.is_finite()) {
                return bad(
                    fp("positions"),
                    format!(
                        "{}: {} finite values needed for {n} joints, got {:?}",
                        t.label, n, p.positions
                    ),
                );
            }
            // Finite differences, with 1 % for time stamps rounded to the sampling step.
            if let Some(q) = i.checked_sub(1).map(|h| &t.points[h]) {
                let dt = p.t - q.t;
                for (j, (a, b)) in q.positions.iter().zip(&p.positions).enumerate() {
                    let lim = limits.get(j).copied().unwrap_or(f64::INFINITY);
                    if (b - a).abs() > (lim * 1.01) * dt + 1e-6 {
                        return bad(
                            fp("positions"),
                            format!(
                                "{}: joint {j} moves {:.4} rad in {dt:.4} s before t = {:.3} s, faster than {lim} rad/s",
                                t.label,
                                (b - a).abs(),
                                p.t
                            ),
                        );
                    }
                }
            }
            prev = p.t;
            if !p.velocities.is_empty() && p.velocities.len() != n {
                return bad(
                    fp("velocities"),
                    format!("{}: {} values for {n} joints", t.label, p.velocities.len()),
                );
            }
            for (j, v) in p.velocities.iter().enumerate() {
                let lim = limits.get(j).copied().unwrap_or(f64::INFINITY);
                if !v.is_finite() || v.abs() > lim * (1.0 + 1e-6) + 1e-9 {
                    return bad(
                        fp(&format!("velocities[{j}]")),
                        format!(
                            "{}: {v} rad/s at t = {:.3} s exceeds the limit {lim} rad/s",
                            t.label, p.t
                        ),
                    );
                }
            }
        }
    }
    for arm in [Arm::Left, Arm::Right] {
        let mut end = f64::NEG_INFINITY;
        for t in plan.arm_trajectories(arm) {
            if t.t_start < end - 1e-9 {
                return bad(
                    "trajectories".into(),
                    format!(
                        "{}: the {} arm's trajectories overlap in time ({} starts before {end})",
                        t.label,
                        arm.name(),
                        t.t_start
                    ),
                );
            }
            end = t.t_end;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn numbers_print_shortest_and_as_yaml_1_1_floats() {
        assert_eq!(num(0.05), "0.05");
        // The noise of arithmetic stays (rounding is the caller's choice, see `ros2::round_nm`).
        assert_eq!(num(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(num(1.0), "1.0");
        assert_eq!(num(-2.5e-7), "-2.5e-7");
        assert_eq!(num(1e-7), "1.0e-7");
        assert_eq!(num(1e16), "1.0e+16");
        for x in [0.1, 1e-7, 3.4e-17, 1e16, -123.456, 1e300] {
            assert_eq!(num(x).parse::<f64>().unwrap(), x);
        }
    }
}

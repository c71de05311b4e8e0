//! Export for a ROS 2 cell: one `control_msgs/action/FollowJointTrajectory` goal per arm (six
//! joints each, for that arm's own trajectory controller), the gripper commands
//! (`control_msgs/action/GripperCommand` goals) with the times at which to send them, on the
//! goals' common clock, a blocking action list, and a manifest that names the action server of
//! every file (`ros2_goals.yaml`, read by `scripts/ros2_send.py`).
//!
//! One goal per arm because a ros2_control trajectory controller rejects a goal with joints it
//! does not own, and NEXTAGE's controllers (`larm_controller`, `rarm_controller`) own six
//! joints each. Durations are ROS 2 `builtin_interfaces/Duration` (`sec`, `nanosec`). The
//! blocking list runs both arms on one time line: at a time only one arm has a point, the other
//! arm's position and velocity are interpolated linearly between its own points, which is exact
//! while it holds still (the per-arm messages hold an arm with two equal points while the other
//! works). The YAML is written by hand, as for the ROS 1 messages; the tests parse it back into
//! structs that mirror the message definitions field for field.

use super::export::{arm_message, list, num, ExportOptions, RosJointTrajectory};
use crate::geometry::Arm;
use crate::plan::Plan;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// `builtin_interfaces/Duration` (and `Time`): whole seconds and nanoseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, `0 ≤ nanosec < 1e9`.
    pub nanosec: u32,
}

impl Duration {
    /// From seconds, rounded to the nanosecond.
    pub fn from_secs(t: f64) -> Duration {
        let ns = (t * 1e9).round() as i64;
        Duration {
            sec: ns.div_euclid(1_000_000_000) as i32,
            nanosec: ns.rem_euclid(1_000_000_000) as u32,
        }
    }

    /// As seconds.
    pub fn as_secs(&self) -> f64 {
        self.sec as f64 + self.nanosec as f64 * 1e-9
    }
}

/// `trajectory_msgs/JointTrajectoryPoint` (ROS 2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// Joint positions (rad), in `joint_names` order.
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s).
    pub velocities: Vec<f64>,
    /// Empty: the controller interpolates.
    pub accelerations: Vec<f64>,
    /// Empty.
    pub effort: Vec<f64>,
    /// Time from the start of the goal.
    pub time_from_start: Duration,
}

/// The ROS 2 export of a plan: one goal per arm that moves, both arms on one time line for the
/// blocking list, and the gripper commands.
#[derive(Debug, Clone, PartialEq)]
pub struct Ros2Export {
    /// Frame of the trajectory headers (the model's root link).
    pub frame_id: String,
    /// One goal per arm that moves (left first).
    pub arms: Vec<ArmGoal>,
    /// Joint names of [`Self::points`]: the left arm's, then the right arm's.
    pub joint_names: Vec<String>,
    /// Points of both arms on one time line (the blocking list cuts these per arm).
    pub points: Vec<Point>,
    /// Gripper commands in time order.
    pub gripper: Vec<GripperStep>,
}

/// The `control_msgs/action/FollowJointTrajectory` goal of one arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmGoal {
    /// The arm.
    pub arm: Arm,
    /// The trajectory controller that owns its joints (`larm_controller`, …).
    pub controller: String,
    /// The gripper controller of its hand (a `GripperCommand` action server).
    pub gripper_controller: String,
    /// Its six joint names.
    pub joint_names: Vec<String>,
    /// Its own points, on the plan's clock.
    pub points: Vec<Point>,
}

/// One gripper command: send a `control_msgs/action/GripperCommand` goal to the arm's gripper
/// when the trajectory reaches `time_from_start`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GripperStep {
    /// Time on the trajectory goals' clock.
    pub time_from_start: Duration,
    /// `left` or `right`.
    pub arm: String,
    /// The `control_msgs/GripperCommand`.
    pub command: GripperCommand,
}

/// `control_msgs/GripperCommand`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GripperCommand {
    /// Finger opening (m; 0 = closed). On a grasp, the object's width less the squeeze margin.
    pub position: f64,
    /// Largest effort (N), the instance's `gripper.max_effort`.
    pub max_effort: f64,
}

/// A length rounded to the nanometre, so that a width less a margin prints as the number it
/// means (`0.05`, not `0.049999999999999996` from the subtraction's rounding); far below any
/// gripper's resolution.
pub fn round_nm(x: f64) -> f64 {
    (x * 1e9).round() / 1e9
}

fn ros2_points(m: &RosJointTrajectory) -> Vec<Point> {
    m.points
        .iter()
        .map(|p| Point {
            positions: p.positions.clone(),
            velocities: p.velocities.clone(),
            accelerations: Vec::new(),
            effort: Vec::new(),
            time_from_start: Duration::from_secs(p.time_from_start.as_secs()),
        })
        .collect()
}

/// Position and velocity of `m` at `t` (`ts`: its point times): linear between its points, held
/// before the first and after the last.
fn sample(m: &RosJointTrajectory, ts: &[f64], t: f64) -> (Vec<f64>, Vec<f64>) {
    let k = ts.partition_point(|&x| x <= t + 1e-9);
    if k == 0 {
        let p = &m.points[0];
        return (p.positions.clone(), vec![0.0; p.positions.len()]);
    }
    let a = &m.points[k - 1];
    if k == m.points.len() || (ts[k - 1] - t).abs() <= 1e-9 {
        let v = if k == m.points.len() && t > ts[k - 1] + 1e-9 {
            vec![0.0; a.positions.len()]
        } else {
            a.velocities.clone()
        };
        return (a.positions.clone(), v);
    }
    let b = &m.points[k];
    let s = (t - ts[k - 1]) / (ts[k] - ts[k - 1]);
    let lerp = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p + s * (q - p)).collect();
    (lerp(&a.positions, &b.positions), lerp(&a.velocities, &b.velocities))
}

/// The ROS 2 export of `plan` (`None` when no arm moves). Call it only on a plan that passed
/// the export checks ([`super::export::export_with`] does).
pub fn ros2_export(plan: &Plan, opts: &ExportOptions) -> Option<Ros2Export> {
    let arms: Vec<(Arm, RosJointTrajectory, Vec<f64>)> = [Arm::Left, Arm::Right]
        .into_iter()
        .filter_map(|a| {
            let m = arm_message(plan, a)?;
            let ts = m.points.iter().map(|p| p.time_from_start.as_secs()).collect();
            Some((a, m, ts))
        })
        .collect();
    let frame_id = arms.first()?.1.header.frame_id.clone();
    let mut times: Vec<f64> = arms.iter().flat_map(|(_, _, ts)| ts.iter().copied()).collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
    let points = times
        .iter()
        .map(|&t| {
            let (mut positions, mut velocities) = (Vec::new(), Vec::new());
            for (_, m, ts) in &arms {
                let (p, v) = sample(m, ts, t);
                positions.extend(p);
                velocities.extend(v);
            }
            Point {
                positions,
                velocities,
                accelerations: Vec::new(),
                effort: Vec::new(),
                time_from_start: Duration::from_secs(t),
            }
        })
        .collect();
    let joint_names = arms.iter().flat_map(|(_, m, _)| m.joint_names.clone()).collect();
    // A command wherever an arm's opening changes (and its first opening), at the key pose
    // after which it holds. A closing onto a width > 0 is a grasp: the command asks for the
    // width less the squeeze margin, or a position-controlled gripper would stop on contact
    // and hold the box by no force at all.
    let mut gripper = Vec::new();
    for (arm, _, _) in &arms {
        let mut last: Option<f64> = None;
        for tr in plan.arm_trajectories(*arm) {
            for k in &tr.key_poses {
                if last.is_none_or(|o| (o - k.opening).abs() > 1e-9) {
                    let grasp = k.opening > 1e-9 && last.is_some_and(|o| k.opening < o);
                    let position = if grasp {
                        (k.opening - opts.squeeze).max(0.0)
                    } else {
                        k.opening
                    };
                    gripper.push(GripperStep {
                        time_from_start: Duration::from_secs(k.t),
                        arm: arm.name().to_string(),
                        command: GripperCommand {
                            position: round_nm(position),
                            max_effort: opts.max_effort,
                        },
                    });
                    last = Some(k.opening);
                }
            }
        }
    }
    gripper.sort_by(|a: &GripperStep, b: &GripperStep| {
        a.time_from_start.as_secs().total_cmp(&b.time_from_start.as_secs())
    });
    let goals = arms
        .iter()
        .map(|(arm, m, _)| ArmGoal {
            arm: *arm,
            controller: opts.controller(*arm).to_string(),
            gripper_controller: opts.gripper_controller(*arm).to_string(),
            joint_names: m.joint_names.clone(),
            points: ros2_points(m),
        })
        .collect();
    Some(Ros2Export {
        frame_id,
        arms: goals,
        joint_names,
        points,
        gripper,
    })
}

fn duration(d: Duration) -> String {
    format!("{{sec: {}, nanosec: {}}}", d.sec, d.nanosec)
}

fn quoted(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

fn names(v: &[String]) -> String {
    let q: Vec<String> = v.iter().map(|n| quoted(n)).collect();
    format!("[{}]", q.join(", "))
}

/// One arm's `control_msgs/action/FollowJointTrajectory` goal as YAML (every field of the goal,
/// Humble and later). It is large (0.7 MB for exp2), beyond what one shell argument may
/// hold: send it with `scripts/ros2_send.py`, which reads it from the file.
pub fn arm_goal_yaml(frame_id: &str, g: &ArmGoal) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "trajectory:");
    let _ = writeln!(s, "  header:");
    let _ = writeln!(s, "    stamp: {{sec: 0, nanosec: 0}}");
    let _ = writeln!(s, "    frame_id: {}", quoted(frame_id));
    let _ = writeln!(s, "  joint_names: {}", names(&g.joint_names));
    let _ = writeln!(s, "  points:{}", if g.points.is_empty() { " []" } else { "" });
    for p in &g.points {
        let _ = writeln!(s, "    - positions: {}", list(&p.positions));
        let _ = writeln!(s, "      velocities: {}", list(&p.velocities));
        let _ = writeln!(s, "      accelerations: []");
        let _ = writeln!(s, "      effort: []");
        let _ = writeln!(s, "      time_from_start: {}", duration(p.time_from_start));
    }
    // The rest of the goal: no path or goal tolerances beyond the controller's own.
    let _ = writeln!(s, "multi_dof_trajectory:");
    let _ = writeln!(s, "  header: {{stamp: {{sec: 0, nanosec: 0}}, frame_id: \"\"}}");
    let _ = writeln!(s, "  joint_names: []");
    let _ = writeln!(s, "  points: []");
    let _ = writeln!(s, "path_tolerance: []");
    let _ = writeln!(s, "component_path_tolerance: []");
    let _ = writeln!(s, "goal_tolerance: []");
    let _ = writeln!(s, "component_goal_tolerance: []");
    let _ = writeln!(s, "goal_time_tolerance: {{sec: 0, nanosec: 0}}");
    s
}

/// The file name of an arm's goal: `left_arm_goal.yaml`, `right_arm_goal.yaml`.
pub fn arm_goal_file(arm: Arm) -> String {
    format!("{}_arm_goal.yaml", arm.name())
}

/// The manifest (`ros2_goals.yaml`): for each arm that moves, its controller, the action server
/// of its goal and of its gripper, and the goal's file; then the gripper commands' and the
/// blocking list's files. The sender reads only this file's names, so controller names chosen
/// at export time reach the robot without retyping.
pub fn manifest_yaml(e: &Ros2Export) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Written by `pushpack export --format ros2-goal`; scripts/ros2_send.py reads it.\n\
         # `action`: control_msgs/action/FollowJointTrajectory server of the arm's controller;\n\
         # `gripper_action`: control_msgs/action/GripperCommand server of its hand."
    );
    let _ = writeln!(s, "frame_id: {}", quoted(&e.frame_id));
    let _ = writeln!(s, "arms:{}", if e.arms.is_empty() { " []" } else { "" });
    for g in &e.arms {
        let _ = writeln!(s, "  - arm: {}", g.arm.name());
        let _ = writeln!(s, "    controller: {}", quoted(&g.controller));
        let _ = writeln!(
            s,
            "    action: {}",
            quoted(&format!("/{}/follow_joint_trajectory", g.controller))
        );
        let _ = writeln!(s, "    joint_names: {}", names(&g.joint_names));
        let _ = writeln!(s, "    goal: {}", arm_goal_file(g.arm));
        let _ = writeln!(
            s,
            "    gripper_action: {}",
            quoted(&format!("/{}/gripper_cmd", g.gripper_controller))
        );
    }
    let _ = writeln!(s, "gripper_commands: gripper_commands.yaml");
    let _ = writeln!(s, "action_list: action_list.yaml");
    s
}

/// The gripper commands as YAML: a list of `{time_from_start, arm, command}`.
pub fn gripper_yaml(e: &Ros2Export) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# control_msgs/action/GripperCommand goals, to send when the arms' goals reach time_from_start"
    );
    let _ = writeln!(s, "steps:{}", if e.gripper.is_empty() { " []" } else { "" });
    for g in &e.gripper {
        let _ = writeln!(s, "  - time_from_start: {}", duration(g.time_from_start));
        let _ = writeln!(s, "    arm: {}", g.arm);
        let _ = writeln!(
            s,
            "    command: {{position: {}, max_effort: {}}}",
            num(g.command.position),
            num(g.command.max_effort)
        );
    }
    s
}

/// The plan as a blocking action list: trajectory goals and gripper commands in the order an
/// executor runs them, each to completion before the next. The arms' time line is cut at every
/// gripper command's time; the arms are at rest there (commands fall on key poses, where every
/// leg ends at rest), so waiting for the gripper costs no jerk. A `trajectories` step holds one
/// goal per arm (its six joints, for its own controller), to be sent together and awaited
/// together; each piece's `time_from_start` starts at 0.
pub fn action_list_yaml(e: &Ros2Export) -> String {
    let mut cuts: Vec<f64> = e.gripper.iter().map(|g| g.time_from_start.as_secs()).collect();
    cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Run in order, each step to completion: `trajectories` holds one control_msgs/action/\n\
         # FollowJointTrajectory goal's trajectory per arm (send them together, the rest of each goal\n\
         # as in <arm>_arm_goal.yaml), `gripper` a control_msgs/action/GripperCommand goal for that\n\
         # arm's gripper. Controllers and action servers are named in ros2_goals.yaml."
    );
    let _ = writeln!(s, "steps:{}", if e.points.is_empty() { " []" } else { "" });
    let mut from = 0.0;
    let trajectory = |s: &mut String, a: f64, b: f64| {
        let pts: Vec<&Point> = e
            .points
            .iter()
            .filter(|p| {
                let t = p.time_from_start.as_secs();
                t >= a - 1e-9 && t <= b + 1e-9
            })
            .collect();
        if pts.len() < 2 {
            return;
        }
        let _ = writeln!(s, "  - trajectories:");
        let t0 = pts[0].time_from_start.as_secs();
        let mut end = 0;
        for g in &e.arms {
            let cols = end..end + g.joint_names.len();
            end = cols.end;
            let _ = writeln!(s, "      - arm: {}", g.arm.name());
            let _ = writeln!(s, "        joint_names: {}", names(&g.joint_names));
            let _ = writeln!(s, "        points:");
            for p in &pts {
                let _ = writeln!(s, "          - positions: {}", list(&p.positions[cols.clone()]));
                let _ = writeln!(s, "            velocities: {}", list(&p.velocities[cols.clone()]));
                let rel = Duration::from_secs(p.time_from_start.as_secs() - t0);
                let _ = writeln!(s, "            time_from_start: {}", duration(rel));
            }
        }
    };
    for &cut in &cuts {
        trajectory(&mut s, from, cut);
        for g in e
            .gripper
            .iter()
            .filter(|g| (g.time_from_start.as_secs() - cut).abs() <= 1e-9)
        {
            let _ = writeln!(
                s,
                "  - gripper: {{arm: {}, command: {{position: {}, max_effort: {}}}}}",
                g.arm,
                num(g.command.position),
                num(g.command.max_effort)
            );
        }
        from = cut;
    }
    let end = e.points.last().map(|p| p.time_from_start.as_secs()).unwrap_or(0.0);
    trajectory(&mut s, from, end);
    s
}

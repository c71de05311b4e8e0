//! Time parameterisation of joint paths and the trajectory records of `plan.json`.
//!
//! A motion segment is a joint path from rest to rest (a polyline through joint waypoints). It is
//! timed with a trapezoidal profile on the path parameter τ = time the path would take at full
//! speed (every piece between two waypoints is run so that its fastest joint moves at its velocity
//! limit): τ̇ ≤ 1 keeps every joint within `velocity_scale × v_max`, τ̈ ≤ α with
//! α = a_max·velocity_scale² / max_j(v_j·velocity_scale) keeps every joint's tangential
//! acceleration within `velocity_scale² × a_max`. That law's velocity jumps at every bend of the
//! polyline, so what is recorded is its moving average ([`super::profile`]): continuous velocity,
//! every joint's acceleration within `velocity_scale² × a_max`, straight joint moves exactly on
//! their segment. The segment is sampled every ≤ `sample_dt` seconds and where the averaging
//! window is centred on a waypoint, with positions and velocities of the smoothed law.

use super::profile::Smoothed;
use crate::geometry::Arm;
use serde::{Deserialize, Serialize};

/// Default joint acceleration limit (rad/s²) — the URDF has none; MoveIt's nextage_moveit_config
/// uses 1.5 rad/s², we stay below it.
pub const DEFAULT_ACCELERATION: f64 = 1.0;
/// Default time between trajectory points (s).
pub const DEFAULT_SAMPLE_DT: f64 = 0.1;
/// Time the gripper is given to close or open at a grasp or release (s).
pub const GRIPPER_DWELL: f64 = 0.5;

/// Options of the joint plan and its timing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryOptions {
    /// Fraction of the model's velocity limits used (0 < s ≤ 1); accelerations scale with s².
    pub velocity_scale: f64,
    /// Joint acceleration limit at full scale (rad/s²).
    pub acceleration: f64,
    /// Largest time between two output points (s).
    pub sample_dt: f64,
}

impl Default for TrajectoryOptions {
    fn default() -> Self {
        TrajectoryOptions {
            velocity_scale: crate::instance::DEFAULT_SPEED_SCALE,
            acceleration: DEFAULT_ACCELERATION,
            sample_dt: DEFAULT_SAMPLE_DT,
        }
    }
}

/// `robot` section of `plan.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotInfo {
    /// Model file (`<bundled>` = the compiled-in `models/nextage_open.urdf`).
    pub model: String,
    /// TCP offset in `*ARM_JOINT5_Link` (m).
    pub tcp_offset: [f64; 3],
    /// Frame of every pose: the model's root link.
    pub base_frame: String,
    /// Convention of the TCP rotation matrices.
    pub tcp_frame: String,
    /// Joint names per arm.
    pub joint_names_left: Vec<String>,
    /// Joint names per arm.
    pub joint_names_right: Vec<String>,
    /// Timing options used.
    pub timing: TrajectoryOptions,
    /// Joint velocity limits used (rad/s, after scaling), per arm joint (left order = right order).
    pub velocity_limits: Vec<f64>,
    /// How long the robot takes to run the plan (s): the end of the last trajectory, both arms
    /// in turn. Absent in plans written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub execution_time_s: Option<f64>,
}

/// One timed point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajPoint {
    /// Time from the start of the plan (s).
    pub t: f64,
    /// Joint positions (rad), in `joint_names` order.
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub velocities: Vec<f64>,
}

/// One key pose of an action.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeyPose {
    /// `pre-grasp`, `grasp`, … (the labels of [`super::keypoints::action_keypoints`]).
    pub label: String,
    /// TCP position (world, m).
    pub position: [f64; 3],
    /// TCP rotation matrix (world; rows), see [`RobotInfo::tcp_frame`].
    pub rotation: [[f64; 3]; 3],
    /// Joint vector (rad).
    pub joints: Vec<f64>,
    /// Time at which it is reached (s from plan start).
    pub t: f64,
    /// Finger opening after the key pose (m; 0 = closed).
    pub opening: f64,
}

/// The joint trajectory of one action (or of a parking / homing move of an arm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ActionTrajectory {
    /// Index of the action in `actions` (0-based), none for a park or return-home move.
    pub action: Option<usize>,
    /// `place 1a`, `push 2a+4a`, `park left`, `home right`.
    pub label: String,
    /// Executing arm.
    pub arm: Arm,
    /// Joint names of `points[].positions`.
    pub joint_names: Vec<String>,
    /// Start time (s from plan start).
    pub t_start: f64,
    /// End time.
    pub t_end: f64,
    /// Timed points; the first is the arm's configuration when the move starts.
    pub points: Vec<TrajPoint>,
    /// Key poses.
    pub key_poses: Vec<KeyPose>,
    /// Smallest distance between the robot and any obstacle along the motion (m; contacts the
    /// action intends, such as fingers on the grasped or pushed object, excluded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clearance: Option<f64>,
    /// Remarks (assumptions the joint plan had to make).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// Why no trajectory could be produced (then `points` is empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// Time a rest-to-rest path through `waypoints` starting at `t0`; returns the points (the first
/// at `t0`) and the end time. `vmax` are the (unscaled) joint velocity limits.
///
/// The path parameter τ runs each piece between two waypoints with its fastest joint at
/// `velocity_scale × vmax`; a trapezoid on τ with tangential acceleration α =
/// a·s² / max_j(v_j·s) times it, and [`super::profile`] smooths that law so that the velocity is
/// continuous and every joint's acceleration stays within a·s² (slowing the leg down where the
/// bends of a sampled line need it). Points carry positions and velocities of the smoothed law.
pub fn time_segment(
    waypoints: &[[f64; 6]],
    vmax: &[f64; 6],
    opts: &TrajectoryOptions,
    t0: f64,
) -> (Vec<TrajPoint>, f64) {
    let s = opts.velocity_scale;
    let vm: [f64; 6] = std::array::from_fn(|j| vmax[j] * s);
    let amax = opts.acceleration * s * s;
    let alpha = amax / vm.iter().cloned().fold(0.0, f64::max);
    // τ at every waypoint.
    let mut tau = vec![0.0];
    for w in waypoints.windows(2) {
        let d = (0..6).map(|j| (w[1][j] - w[0][j]).abs() / vm[j]).fold(0.0, f64::max);
        tau.push(tau.last().unwrap() + d);
    }
    let rest = |t: f64, q: &[f64; 6]| TrajPoint {
        t,
        positions: q.to_vec(),
        velocities: vec![0.0; 6],
    };
    if *tau.last().unwrap() <= 1e-12 {
        return (vec![rest(t0, &waypoints[0])], t0);
    }
    let law = Smoothed::new(waypoints, &tau, alpha, amax);
    let times = law.sample_times(opts.sample_dt);
    let last = times.len() - 1;
    let out = times
        .iter()
        .enumerate()
        .map(|(i, &t)| match i {
            // Exact ends, at rest.
            0 => rest(t0, &waypoints[0]),
            _ if i == last => rest(t0 + t, waypoints.last().unwrap()),
            _ => TrajPoint {
                t: t0 + t,
                positions: law.pos(t).to_vec(),
                velocities: law.vel(t).to_vec(),
            },
        })
        .collect();
    (out, t0 + law.duration())
}

//! Time parameterisation of joint paths and the trajectory records of `plan.json`.
//!
//! A motion segment is a joint path from rest to rest (a polyline through joint waypoints). It is
//! timed with a trapezoidal profile on the path parameter τ = time the path would take at full
//! speed (every piece between two waypoints is run so that its fastest joint moves at its velocity
//! limit): τ̇ ≤ 1 keeps every joint within `velocity_scale × v_max`, τ̈ ≤ α with
//! α = a_max·velocity_scale² / max_j(v_j·velocity_scale) keeps every joint's tangential
//! acceleration within `velocity_scale² × a_max`. The segment is then sampled every ≤ `sample_dt`
//! seconds (positions interpolated linearly between the waypoints, velocities from the profile).

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
/// at `t0`) and the end time. `vmax` are the (scaled) joint velocity limits.
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
    let l = *tau.last().unwrap();
    let rest = |t: f64| TrajPoint {
        t,
        positions: waypoints[0].to_vec(),
        velocities: vec![0.0; 6],
    };
    if l <= 1e-12 {
        return (vec![rest(t0)], t0);
    }
    // Trapezoid on τ with rate ≤ 1, acceleration ≤ alpha.
    let (peak, ta, dur) = if l * alpha >= 1.0 {
        (1.0, 1.0 / alpha, l + 1.0 / alpha)
    } else {
        let p = (alpha * l).sqrt();
        (p, p / alpha, 2.0 * p / alpha)
    };
    let profile = |t: f64| -> (f64, f64) {
        if t <= ta {
            (0.5 * alpha * t * t, alpha * t)
        } else if t >= dur - ta {
            let r = (dur - t).max(0.0);
            (l - 0.5 * alpha * r * r, alpha * r)
        } else {
            (0.5 * alpha * ta * ta + peak * (t - ta), peak)
        }
    };
    // Time at which the path parameter reaches x (inverse of the profile).
    let xa = 0.5 * alpha * ta * ta;
    let time_at = |x: f64| -> f64 {
        if x <= xa {
            (2.0 * x / alpha).sqrt()
        } else if x >= l - xa {
            dur - (2.0 * (l - x).max(0.0) / alpha).sqrt()
        } else {
            ta + (x - xa) / peak
        }
    };
    // Samples every ≤ sample_dt, plus one at every waypoint: a controller interpolates between
    // points, and without the waypoints it would cut the corners of the planned (collision-checked)
    // path.
    let n = (dur / opts.sample_dt).ceil().max(1.0) as usize;
    let mut times: Vec<f64> = (0..=n).map(|i| dur * i as f64 / n as f64).collect();
    times.extend(tau[1..tau.len() - 1].iter().map(|&x| time_at(x).clamp(0.0, dur)));
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let mut out = Vec::with_capacity(times.len());
    let mut k = 0;
    let last = times.len() - 1;
    for (i, &t) in times.iter().enumerate() {
        let (x, rate) = if i == last { (l, 0.0) } else { profile(t) };
        while k + 2 < tau.len() && x > tau[k + 1] {
            k += 1;
        }
        let span = (tau[k + 1] - tau[k]).max(1e-300);
        let u = ((x - tau[k]) / span).clamp(0.0, 1.0);
        let (a, b) = (&waypoints[k], &waypoints[k + 1]);
        let positions: Vec<f64> = (0..6).map(|j| a[j] + u * (b[j] - a[j])).collect();
        let velocities: Vec<f64> = (0..6)
            .map(|j| if span > 1e-12 { (b[j] - a[j]) / span * rate } else { 0.0 })
            .collect();
        out.push(TrajPoint {
            t: t0 + t,
            positions,
            velocities,
        });
    }
    // Exact end.
    if let Some(last) = out.last_mut() {
        last.positions = waypoints.last().unwrap().to_vec();
        last.velocities = vec![0.0; 6];
    }
    (out, t0 + dur)
}

//! Joint plans of actions: key poses with orientation and finger opening, inverse kinematics
//! along them, straight Cartesian lines and joint-space moves, collision checks along the motion,
//! arm selection and the reachability predicate of the action planner.
//!
//! Per action (docs/robot.md, "Key poses and joint plans"): place = pre-grasp → grasp → lift → pre-place → release → retreat;
//! push = above-push → push-start → push-end → push-retreat. The positions are exactly those of
//! [`super::keypoints::action_keypoints`] (so travel and verifier agree). Every vertical move and
//! the push itself are straight lines in Cartesian space, sampled adaptively until the TCP stays
//! within [`LINE_TOLERANCE`] of the line between consecutive samples (the spec's bound, checked by
//! the verifier, is [`LINE_LIMIT`]); the transfer (lift → pre-place) and the approach from the
//! arm's previous configuration are joint-space moves, replaced by a Cartesian line when the joint
//! move collides. The gripper is symmetric about its closing axis, so every grasp or push can be
//! done with the hand turned by π: each action is planned in every such variant and the feasible
//! one with the least joint motion (and the larger joint margin) wins.

use super::collision::{
    arm_as_obstacles, clearance, first_collision, grown, object_in_container, object_on_table, robot_parts,
    static_obstacles, Hand, Held, Obstacle, ObstacleKind, Part, PartKind,
};
use super::keypoints::action_keypoints;
use super::trajectory::{
    time_segment, ActionTrajectory, KeyPose, RobotInfo, TrajPoint, TrajectoryOptions, GRIPPER_DWELL,
};
use crate::actions::{Action, PlaceMode};
use crate::geometry::Arm;
use crate::geometry::{Axis2, BodyAxis, PushDir, Rect};
use crate::instance::Instance;
use crate::placement::Placement;
use crate::robot::ik::{max_abs_diff, top_down_pose, IkSolver};
use crate::robot::RobotError;
use nalgebra::{Isometry3, Vector3};
use std::cell::RefCell;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};

mod ctx;
mod keyposes;
mod path;
mod reach;
mod replay;
mod timing;
mod variants;

pub use ctx::*;
use keyposes::*;
pub use path::*;
pub use reach::*;
pub(crate) use replay::*;
pub use timing::*;
use variants::*;

/// Joint-space legs of a move: each a polyline of configurations of one arm.
pub(super) type Legs = Vec<Vec<[f64; 6]>>;
/// Planning tolerance of straight lines: largest TCP distance from the line between two samples (m).
pub const LINE_TOLERANCE: f64 = 5e-5;
/// The spec's bound on the deviation of a straight-line push (m), checked by the verifier.
pub const LINE_LIMIT: f64 = 1e-3;
/// Line tolerance of the reachability predicate (m): it needs to know that a line can be
/// followed and roughly where the arm is, not the joint plan's fine waypoints.
pub const PREDICATE_LINE_TOLERANCE: f64 = 1e-3;
/// Planning tolerance of straight lines: largest turn of the tool from its interpolated
/// orientation between two samples (rad).
pub const ROT_TOLERANCE: f64 = 5e-4;
/// Largest joint step between two waypoints of a straight line (rad).
pub const MAX_LINE_STEP: f64 = 0.05;
/// Joint step between collision samples of a joint-space move (rad).
pub const COLLISION_STEP: f64 = 0.01;

/// Clearance a joint-space move keeps from every obstacle (m). Its samples are
/// [`COLLISION_STEP`] apart and the verifier samples the timed trajectory elsewhere; between
/// samples a part can move a few millimetres, so a move that only grazes an obstacle at the
/// samples may cut into it between them. Straight lines keep no margin: they touch on purpose
/// (zero-gap packing) and are sampled to 0.05 mm.
pub const JOINT_MOVE_MARGIN: f64 = 0.005;

/// How a segment is moved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Move {
    /// Joint-space interpolation (a Cartesian line if that collides).
    Joint,
    /// Straight Cartesian line.
    Line,
}

/// Where an object is when an action starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjAt {
    /// At its start pose on the table.
    Table,
    /// On the container floor with this footprint (C), at its target height.
    Floor(Rect),
}

/// A key pose to reach, with the gripper state after it.
#[derive(Debug, Clone)]
pub(super) struct Spec {
    pub(super) label: String,
    pub(super) target: Isometry3<f64>,
    pub(super) opening: f64,
    pub(super) held: Option<Held>,
    pub(super) mv: Move,
}

//! The robot model: the NEXTAGE Open kinematic chains loaded from URDF, forward and inverse
//! kinematics. Nothing here knows about boxes, actions or plans.
//!
//! The model is read with urdf-rs and converted into one serial chain per arm (WAIST → chest →
//! `*ARM_JOINT0..5`). The chest joint is held at 0. The TCP sits at a fixed offset in the
//! `*ARM_JOINT5_Link` frame, whose −x axis is the fingertip direction. The TCP *frame* has z along
//! the approach (−x of `JOINT5_Link`), y along the finger closing axis (y of `JOINT5_Link`) and x
//! along z of `JOINT5_Link` (the stock hand housing bulges 5.4 cm toward −x of the TCP frame and
//! 3.6 cm toward +x); see `docs/robot.md`.
//!
//! * [`ik`] — inverse kinematics (damped least squares with a closed-form wrist-roll step).
//!
//! What the robot does with the model (key points, joint plans, cell collisions, time
//! parameterisation) is the [`crate::motion`] stage.

mod cholesky;
pub mod ik;

pub use crate::geometry::Arm;
pub use ik::{top_down_rotation, IkSolver};

use crate::geometry::parry_bridge::Solid;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};

/// Default standard initial pose of the NEXTAGE Open arms, degrees (left, right).
pub const NEXTAGE_INITIAL_POSE_DEG: [[f64; 6]; 2] = [
    [0.6, 0.0, -100.0, -15.2, 9.4, -3.2],
    [-0.6, 0.0, -100.0, 15.2, 9.4, 3.2],
];

/// Default TCP offset in the `*ARM_JOINT5_Link` frame: the fingertip centre of the bundled
/// gripper, whose 0.10 m finger plates hang below the stock hand housing (which itself reaches
/// 0.20 m below the flange). At the standard initial pose the fingertips hang 0.068 m above the
/// default table (`robot.table_z` = −0.30). Why 0.10 m: docs/robot.md, "The work cell".
pub const DEFAULT_TCP_OFFSET: [f64; 3] = [-0.30, 0.0, 0.0];

/// Default world z of the table top (`robot.table_z`), 0.10 m lower than the paper-era cell's
/// −0.20 so that the wrist poses stay where they were with the 0.10 m longer TCP.
pub const DEFAULT_TABLE_Z: f64 = -0.30;

/// One revolute joint of an arm chain.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpec {
    /// URDF joint name.
    pub name: String,
    /// Fixed transform parent link → joint frame.
    pub origin: Isometry3<f64>,
    /// Rotation axis in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Lower position limit (rad).
    pub lower: f64,
    /// Upper position limit (rad).
    pub upper: f64,
    /// Velocity limit (rad/s).
    pub velocity: f64,
}

/// A collision primitive attached to one link of an arm.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkShape {
    /// Name for messages (`LARM_JOINT3_Link`, `LARM_gripper_Link`, …).
    pub name: String,
    /// Which frame of the chain carries it: 0..=5 = `*ARM_JOINTk_Link`.
    pub link: usize,
    /// Pose of the solid in that link frame.
    pub origin: Isometry3<f64>,
    /// The solid.
    pub solid: Solid,
}

/// Errors of the robot stage: every one carries the numbers that explain it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RobotError {
    /// No configuration within the joint limits reaches the pose.
    #[error(
        "{arm} arm cannot reach TCP ({:.4}, {:.4}, {:.4}) m: best residual {pos_residual:.3e} m / {rot_residual:.3e} rad \
         after {attempts} seeds{}",
        target[0], target[1], target[2],
        at_limit.as_ref().map(|(j, v)| format!(", {j} held at its limit {v:.4} rad")).unwrap_or_default()
    )]
    Unreachable {
        /// Arm name.
        arm: String,
        /// Target TCP position (world).
        target: [f64; 3],
        /// Best position residual reached (m).
        pos_residual: f64,
        /// Best rotation residual reached (rad).
        rot_residual: f64,
        /// A joint pinned at a limit in the best attempt (name, value).
        at_limit: Option<(String, f64)>,
        /// Number of seeds tried.
        attempts: usize,
    },
    /// A configuration violates a joint limit.
    #[error("{joint} = {value:.6} rad is outside [{lower:.6}, {upper:.6}]")]
    JointLimit {
        /// Joint name.
        joint: String,
        /// Value.
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// A straight-line move cannot be followed within its tolerance.
    #[error("{what}: TCP leaves the straight line by {deviation:.4e} m (limit {limit:.1e} m) or jumps {jump:.4} rad")]
    Path {
        /// Which segment.
        what: String,
        /// Largest deviation found (m).
        deviation: f64,
        /// Allowed deviation (m).
        limit: f64,
        /// Largest joint step (rad).
        jump: f64,
    },
    /// A part of the robot (or the carried object) hits something.
    #[error("{what}: {part} hits {obstacle} (penetration at TCP ({:.4}, {:.4}, {:.4}))", tcp[0], tcp[1], tcp[2])]
    Collision {
        /// Which segment.
        what: String,
        /// Robot part.
        part: String,
        /// Obstacle.
        obstacle: String,
        /// TCP position at the colliding sample.
        tcp: [f64; 3],
    },
    /// The arm is not usable (not allowed by the instance).
    #[error("{0}")]
    Other(String),
}

/// Kinematic model of both arms.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotModel {
    /// Fixed transform WAIST → arm base (chest joint at 0, chest origin included).
    pub base: [Isometry3<f64>; 2],
    /// Six joints per arm (left, right).
    pub arms: [Vec<JointSpec>; 2],
    /// Collision primitives per arm (box, cylinder, sphere or capsule geometry of the arm links
    /// and of links fixed to `*ARM_JOINT5_Link`; meshes are skipped).
    pub shapes: [Vec<LinkShape>; 2],
}

/// Rotation of the TCP frame in the `*ARM_JOINT5_Link` frame: z = −x (approach), y = y (closing
/// axis), x = z.
pub fn tcp_rotation_in_wrist() -> Rotation3<f64> {
    Rotation3::from_matrix_unchecked(Matrix3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0))
}

const BUNDLED_URDF: &str = include_str!("../../models/nextage_open.urdf");

impl RobotModel {
    /// The bundled NEXTAGE Open model (`models/nextage_open.urdf`, compiled in).
    pub fn bundled() -> RobotModel {
        RobotModel::from_urdf_str(BUNDLED_URDF).expect("the bundled model parses (tested)")
    }

    /// Parse a URDF text and extract both arm chains.
    pub fn from_urdf_str(text: &str) -> Result<RobotModel, String> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| format!("URDF does not parse: {e}"))?;
        let find = |name: &str| robot.joints.iter().find(|j| j.name == name);
        let iso = |j: &urdf_rs::Joint| {
            let [x, y, z] = *j.origin.xyz;
            let [r, p, yw] = *j.origin.rpy;
            Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, p, yw))
        };
        let mut base = [Isometry3::identity(); 2];
        let mut arms: [Vec<JointSpec>; 2] = [Vec::new(), Vec::new()];
        let mut shapes: [Vec<LinkShape>; 2] = [Vec::new(), Vec::new()];
        for arm in [Arm::Left, Arm::Right] {
            // Walk up from JOINT0 to the root, collecting fixed transforms (chest held at 0).
            let j0name = format!("{}_JOINT0", arm.prefix());
            let j0 = find(&j0name).ok_or_else(|| format!("joint {j0name} missing"))?;
            let mut b = Isometry3::identity();
            let mut parent = j0.parent.link.clone();
            let mut guard = 0;
            while let Some(pj) = robot.joints.iter().find(|j| j.child.link == parent) {
                b = iso(pj) * b;
                parent = pj.parent.link.clone();
                guard += 1;
                if guard > 64 {
                    return Err("joint tree has a cycle".into());
                }
            }
            base[arm.index()] = b;
            let mut prev_child: Option<String> = None;
            for k in 0..6 {
                let name = format!("{}_JOINT{k}", arm.prefix());
                let j = find(&name).ok_or_else(|| format!("joint {name} missing"))?;
                if let Some(pc) = &prev_child {
                    if &j.parent.link != pc {
                        return Err(format!(
                            "joint {name}: parent {} is not the previous joint's child {pc}",
                            j.parent.link
                        ));
                    }
                }
                if !matches!(j.joint_type, urdf_rs::JointType::Revolute) {
                    return Err(format!("joint {name} must be revolute"));
                }
                let a = Vector3::from(*j.axis.xyz);
                if a.norm() < 1e-9 {
                    return Err(format!("joint {name} has a zero axis"));
                }
                // Written so that NaN limits fail too.
                #[allow(clippy::neg_cmp_op_on_partial_ord)]
                if !(j.limit.lower < j.limit.upper) {
                    return Err(format!(
                        "joint {name}: lower limit {} not below upper {}",
                        j.limit.lower, j.limit.upper
                    ));
                }
                arms[arm.index()].push(JointSpec {
                    name: name.clone(),
                    origin: iso(j),
                    axis: Unit::new_normalize(a),
                    lower: j.limit.lower,
                    upper: j.limit.upper,
                    velocity: j.limit.velocity,
                });
                prev_child = Some(j.child.link.clone());
                collect_shapes(
                    &robot,
                    &j.child.link,
                    k,
                    Isometry3::identity(),
                    k == 5,
                    &mut shapes[arm.index()],
                );
            }
        }
        Ok(RobotModel { base, arms, shapes })
    }

    /// How far the hand reaches below the wrist flange (m): the largest extent along −x of
    /// `*ARM_JOINT5_Link` (the approach direction) of the collision primitives fixed to the
    /// wrist. Fingers hang between there and the TCP. 0 when the model has no hand primitives.
    pub fn hand_bottom(&self, arm: Arm) -> f64 {
        self.shapes[arm.index()]
            .iter()
            .filter(|s| s.link == 5)
            .map(|s| s.solid.support_extent(&s.origin, &-Vector3::x()))
            .fold(0.0, f64::max)
    }

    /// Joint names of an arm, in chain order.
    pub fn joint_names(&self, arm: Arm) -> Vec<String> {
        self.arms[arm.index()].iter().map(|j| j.name.clone()).collect()
    }

    /// Frames of `*ARM_JOINT0_Link` … `*ARM_JOINT5_Link` in the WAIST frame.
    pub fn link_frames(&self, arm: Arm, q: &[f64; 6]) -> [Isometry3<f64>; 6] {
        let mut t = self.base[arm.index()];
        let mut out = [Isometry3::identity(); 6];
        for (k, (j, qi)) in self.arms[arm.index()].iter().zip(q).enumerate() {
            t = t * j.origin * UnitQuaternion::from_axis_angle(&j.axis, *qi);
            out[k] = t;
        }
        out
    }

    /// Full TCP pose (position and TCP-frame rotation) in the WAIST frame.
    pub fn tcp_pose(&self, arm: Arm, q: &[f64; 6], tcp_offset: &[f64; 3]) -> Isometry3<f64> {
        tcp_from_wrist(&self.wrist_pose(arm, q), tcp_offset)
    }

    /// Smallest distance of any joint to its nearest limit (rad); negative when outside.
    pub fn joint_margin(&self, arm: Arm, q: &[f64; 6]) -> f64 {
        self.arms[arm.index()]
            .iter()
            .zip(q)
            .map(|(j, v)| (v - j.lower).min(j.upper - v))
            .fold(f64::INFINITY, f64::min)
    }

    /// Typed joint-limit check (tolerance 1e-9 rad).
    pub fn limit_error(&self, arm: Arm, q: &[f64; 6]) -> Option<RobotError> {
        self.arms[arm.index()].iter().zip(q).find_map(|(j, v)| {
            (!(*v >= j.lower - 1e-9 && *v <= j.upper + 1e-9)).then(|| RobotError::JointLimit {
                joint: j.name.clone(),
                value: *v,
                lower: j.lower,
                upper: j.upper,
            })
        })
    }

    /// Pose of `*ARM_JOINT5_Link` in the WAIST frame (the same numbers as the last of
    /// [`Self::link_frames`]: the same products in the same order).
    pub fn wrist_pose(&self, arm: Arm, q: &[f64; 6]) -> Isometry3<f64> {
        let mut t = self.base[arm.index()];
        for (j, qi) in self.arms[arm.index()].iter().zip(q) {
            t = t * j.origin * UnitQuaternion::from_axis_angle(&j.axis, *qi);
        }
        t
    }

    /// TCP position in the WAIST frame.
    pub fn tcp_position(&self, arm: Arm, q: &[f64; 6], tcp_offset: &[f64; 3]) -> Vector3<f64> {
        let w = self.wrist_pose(arm, q);
        (w * nalgebra::Point3::from(Vector3::from(*tcp_offset))).coords
    }

    /// Error text when a configuration violates a joint limit.
    pub fn check_joint_limits(&self, arm: Arm, q: &[f64; 6]) -> Result<(), String> {
        for (j, qi) in self.arms[arm.index()].iter().zip(q) {
            if *qi < j.lower - 1e-9 || *qi > j.upper + 1e-9 {
                return Err(format!(
                    "{} = {:.4} rad is outside [{:.4}, {:.4}]",
                    j.name, qi, j.lower, j.upper
                ));
            }
        }
        Ok(())
    }

    /// Conservative reach test for a top-down TCP position: false only when the point is
    /// certainly out of reach (farther from the shoulder than the fully stretched arm).
    /// Exact reachability needs inverse kinematics.
    pub fn reachable_top_down(&self, arm: Arm, tcp: &Vector3<f64>, tcp_offset: &[f64; 3]) -> bool {
        let chain = &self.arms[arm.index()];
        let shoulder = (self.base[arm.index()] * chain[0].origin * chain[1].origin)
            .translation
            .vector;
        let reach: f64 = chain[2..]
            .iter()
            .map(|j| j.origin.translation.vector.norm())
            .sum::<f64>()
            + Vector3::from(*tcp_offset).norm();
        (tcp - shoulder).norm() <= reach
    }
}

/// Pose of a URDF `<origin>`.
fn urdf_iso(p: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = *p.xyz;
    let [r, pi, yw] = *p.rpy;
    Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, pi, yw))
}

/// Collision primitives of `link` (frame `k` of the chain, at `offset` in that frame); with
/// `descend`, also of every link fixed to it (recursively). Meshes are skipped; links behind
/// movable joints (the fingers) are skipped: pushpack builds the fingers from the instance.
fn collect_shapes(
    robot: &urdf_rs::Robot,
    link: &str,
    k: usize,
    offset: Isometry3<f64>,
    descend: bool,
    out: &mut Vec<LinkShape>,
) {
    if let Some(l) = robot.links.iter().find(|l| l.name == link) {
        for c in &l.collision {
            let solid = match &c.geometry {
                urdf_rs::Geometry::Box { size } => Solid::Cuboid {
                    half: Vector3::new(size[0], size[1], size[2]) / 2.0,
                },
                urdf_rs::Geometry::Cylinder { radius, length } => Solid::Cylinder {
                    radius: *radius,
                    half_length: length / 2.0,
                },
                urdf_rs::Geometry::Capsule { radius, length } => Solid::Capsule {
                    a: Vector3::new(0.0, 0.0, -length / 2.0),
                    b: Vector3::new(0.0, 0.0, length / 2.0),
                    radius: *radius,
                },
                urdf_rs::Geometry::Sphere { radius } => Solid::Ball { radius: *radius },
                urdf_rs::Geometry::Mesh { .. } => continue,
            };
            let ok = match solid {
                Solid::Cuboid { half } => half.iter().all(|h| h.is_finite() && *h > 0.0),
                Solid::Cylinder { radius, half_length } => radius > 0.0 && half_length > 0.0,
                Solid::Capsule { radius, a, .. } => radius > 0.0 && a.z.is_finite(),
                Solid::Ball { radius } => radius > 0.0,
            };
            if ok {
                out.push(LinkShape {
                    name: link.to_string(),
                    link: k,
                    origin: offset * urdf_iso(&c.origin),
                    solid,
                });
            }
        }
    }
    if descend {
        for j in robot.joints.iter().filter(|j| j.parent.link == link) {
            if matches!(j.joint_type, urdf_rs::JointType::Fixed) {
                collect_shapes(robot, &j.child.link, k, offset * urdf_iso(&j.origin), true, out);
            }
        }
    }
}

/// The TCP pose of a wrist (`*ARM_JOINT5_Link`) pose: [`RobotModel::tcp_pose`] from a wrist
/// pose already at hand.
pub fn tcp_from_wrist(wrist: &Isometry3<f64>, tcp_offset: &[f64; 3]) -> Isometry3<f64> {
    wrist
        * Isometry3::from_parts(
            Translation3::from(Vector3::from(*tcp_offset)),
            UnitQuaternion::from_rotation_matrix(&tcp_rotation_in_wrist()),
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bundled_model_loads_and_has_six_joints_per_arm() {
        let m = RobotModel::bundled();
        assert_eq!(m.arms[0].len(), 6);
        assert_eq!(m.arms[1].len(), 6);
    }

    #[test]
    fn home_tcp_hangs_above_the_table() {
        let m = RobotModel::bundled();
        let q = NEXTAGE_INITIAL_POSE_DEG.map(|a| a.map(f64::to_radians));
        let l = m.tcp_position(Arm::Left, &q[0], &DEFAULT_TCP_OFFSET);
        let r = m.tcp_position(Arm::Right, &q[1], &DEFAULT_TCP_OFFSET);
        // At the standard initial pose the fingertips hang about 0.07 m above the default table.
        let t = DEFAULT_TABLE_Z;
        assert!(l.z > t + 0.03 && l.z < t + 0.12, "left TCP z = {}", l.z);
        assert!(l.y > 0.0 && r.y < 0.0);
        assert!(
            (l.y + r.y).abs() < 1e-9 && (l.x - r.x).abs() < 1e-9 && (l.z - r.z).abs() < 1e-9,
            "mirror symmetric"
        );
    }
}

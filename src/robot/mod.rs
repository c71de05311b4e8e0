//! Stage 4: the robot — NEXTAGE Open kinematic model loaded from URDF, forward kinematics,
//! reachability, and the TCP key points of every action.
//!
//! The model is read with urdf-rs and converted into one serial chain per arm (WAIST → chest →
//! `*ARM_JOINT0..5`). The chest joint is held at 0. The TCP sits at a fixed offset in the
//! `*ARM_JOINT5_Link` frame, whose −x axis is the fingertip direction.

pub mod keypoints;

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// One of the two arms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Arm {
    /// The left arm (`LARM_*`, y > 0 side).
    Left,
    /// The right arm (`RARM_*`, y < 0 side).
    Right,
}

impl Arm {
    /// 0 for left, 1 for right.
    pub fn index(self) -> usize {
        match self {
            Arm::Left => 0,
            Arm::Right => 1,
        }
    }
    /// `left` or `right`.
    pub fn name(self) -> &'static str {
        match self {
            Arm::Left => "left",
            Arm::Right => "right",
        }
    }
    /// URDF joint-name prefix.
    pub fn prefix(self) -> &'static str {
        match self {
            Arm::Left => "LARM",
            Arm::Right => "RARM",
        }
    }
}

/// Default TCP offset in the `*ARM_JOINT5_Link` frame: the fingertip centre of the bundled gripper,
/// 0.20 m along −x of the wrist flange: at the standard initial pose the fingertips then hang
/// 0.068 m above the default table (z = −0.20), as SPEC §3 describes.
pub const DEFAULT_TCP_OFFSET: [f64; 3] = [-0.20, 0.0, 0.0];

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

/// Kinematic model of both arms.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotModel {
    /// Fixed transform WAIST → arm base (chest joint at 0, chest origin included).
    pub base: [Isometry3<f64>; 2],
    /// Six joints per arm (left, right).
    pub arms: [Vec<JointSpec>; 2],
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
            }
        }
        Ok(RobotModel { base, arms })
    }

    /// Pose of `*ARM_JOINT5_Link` in the WAIST frame.
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
        let q = crate::instance::NEXTAGE_INITIAL_POSE_DEG.map(|a| a.map(f64::to_radians));
        let l = m.tcp_position(Arm::Left, &q[0], &DEFAULT_TCP_OFFSET);
        let r = m.tcp_position(Arm::Right, &q[1], &DEFAULT_TCP_OFFSET);
        // SPEC §3: at the standard initial pose the hands hang about 0.07 m above the table (z = -0.20).
        assert!(l.z > -0.20 + 0.03 && l.z < -0.20 + 0.12, "left TCP z = {}", l.z);
        assert!(l.y > 0.0 && r.y < 0.0);
        assert!(
            (l.y + r.y).abs() < 1e-9 && (l.x - r.x).abs() < 1e-9 && (l.z - r.z).abs() < 1e-9,
            "mirror symmetric"
        );
    }
}

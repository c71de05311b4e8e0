//! The two arms of the robot, as every stage names them.

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
    /// The other arm.
    pub fn other(self) -> Arm {
        match self {
            Arm::Left => Arm::Right,
            Arm::Right => Arm::Left,
        }
    }

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

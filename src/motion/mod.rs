//! Stage 5: motion — what the robot does for each action: TCP key points, reachability as a
//! planner predicate, joint plans with cell collisions, and their time parameterisation.
//!
//! * [`keypoints`] — the TCP key points of an action and the travel metric they define;
//! * [`collision`] — the work cell and the robot's collision primitives (parry3d);
//! * [`joint_plan`] — key poses of an action, joint plans, arm selection, reachability;
//! * [`profile`] — the smoothed time law of one rest-to-rest leg;
//! * [`reach_cache`] — reachability memoised for the sequencers;
//! * [`trajectory`] — time parameterisation and the `plan.json` trajectory records.

pub mod collision;
pub mod joint_plan;
pub mod keypoints;
pub mod profile;
pub mod reach_cache;
pub mod trajectory;

pub use joint_plan::{action_reachable, arms_reaching, plan_trajectories, plan_trajectories_with, select_arm};
pub use trajectory::{ActionTrajectory, KeyPose, RobotInfo, TrajPoint, TrajectoryOptions};

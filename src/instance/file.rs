//! Serde-only external types of the instance file (TOML or JSON, one schema).
//!
//! These types mirror the file one to one and carry no invariants; [`super::Instance::load`] converts them
//! into a validated [`super::Instance`]. Every field, its unit and default is in `docs/formats.md`.

use serde::{Deserialize, Serialize};

/// The whole instance file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceFile {
    /// Schema version; only 1 exists.
    #[serde(default = "one")]
    pub format_version: u32,
    /// Human-readable name.
    #[serde(default)]
    pub name: Option<String>,
    /// Free text (provenance, assumptions).
    #[serde(default)]
    pub description: Option<String>,
    /// Length unit of every length in the file: `m` (default), `cm` or `mm`.
    #[serde(default)]
    pub units: Option<String>,
    /// The container.
    pub container: ContainerFile,
    /// Friction coefficients.
    pub friction: FrictionFile,
    /// Gripper geometry.
    pub gripper: GripperFile,
    /// Robot and work cell; every field has a default.
    #[serde(default)]
    pub robot: RobotFile,
    /// Planner settings; every field has a default.
    #[serde(default)]
    pub planner: PlannerFile,
    /// Object kinds (size and mass shared by all objects of a kind).
    pub kinds: Vec<KindFile>,
    /// The objects on the table.
    pub objects: Vec<ObjectFile>,
}

fn one() -> u32 {
    1
}

/// Container geometry and pose.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContainerFile {
    /// Inner extent along the container's x axis.
    pub width: f64,
    /// Inner extent along the container's y axis.
    pub depth: f64,
    /// Wall height above the inner floor.
    pub wall_height: f64,
    /// Wall thickness.
    pub wall_thickness: f64,
    /// World (x, y) of the centre of the inner floor.
    pub center: [f64; 2],
    /// Yaw of the container frame in the world, radians.
    #[serde(default)]
    pub yaw: f64,
    /// World z of the inner floor; defaults to the table height.
    #[serde(default)]
    pub floor_z: Option<f64>,
}

/// Friction coefficients (dimensionless).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionFile {
    /// Object–floor (and object–table) friction.
    pub mu_floor: f64,
    /// Object–object friction.
    pub mu_obj: f64,
    /// Finger–object friction.
    pub mu_finger: f64,
}

/// Gripper geometry.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GripperFile {
    /// Thickness of one finger plate (along the grasp axis); the closed pair pushes with this.
    pub finger_thickness: f64,
    /// Width of a finger plate (across the grasp axis).
    pub finger_width: f64,
    /// How far the fingers reach down beside a box (vertical). The plates hang from the hand
    /// housing to the TCP, so the TCP must be at least this far below the housing.
    pub finger_length: f64,
    /// Maximum opening between the fingers.
    pub max_opening: f64,
    /// How far below an object's top face the fingertips grasp it.
    pub grasp_depth: f64,
    /// Extra opening per side when releasing.
    pub release_clearance: f64,
    /// Minimum indirect offset `d`; at least `finger_thickness + release_clearance`.
    #[serde(default)]
    pub min_offset: Option<f64>,
    /// Height of the fingertips above the floor while pushing; default 0.005 m.
    #[serde(default)]
    pub push_height: Option<f64>,
    /// How much narrower than the object a grasp command closes (length); default 2 mm.
    #[serde(default)]
    pub squeeze: Option<f64>,
    /// Largest grip force of a gripper command, in newtons whatever `units` says; default 20.
    #[serde(default)]
    pub max_effort: Option<f64>,
}

/// Robot and work cell.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotFile {
    /// URDF model path (relative to the instance file, then to the working directory);
    /// omitted = the bundled `models/nextage_open.urdf`.
    #[serde(default)]
    pub model: Option<String>,
    /// TCP offset in the wrist (`*ARM_JOINT5_Link`) frame; omitted = the bundled gripper's.
    #[serde(default)]
    pub tcp_offset: Option<[f64; 3]>,
    /// Arms that may be used: any of `left`, `right`; default both.
    #[serde(default)]
    pub arms: Option<Vec<String>>,
    /// Home joint angles (radians), 6 per arm; default the standard initial pose.
    #[serde(default)]
    pub home: Option<HomeFile>,
    /// World z of the table top; default -0.20 m.
    #[serde(default)]
    pub table_z: Option<f64>,
    /// Clearance of transfer moves above the container wall top; default 0.08 m.
    #[serde(default)]
    pub transfer_clearance: Option<f64>,
    /// Whether the cell can turn an object onto another face between pick and place (a regrasp
    /// station, a second gripper, an operator); default false.
    #[serde(default)]
    pub regrasp: Option<bool>,
    /// Fraction of the model's joint velocity limits the trajectories use, in (0, 1]; default
    /// [`crate::instance::DEFAULT_SPEED_SCALE`].
    #[serde(default)]
    pub speed_scale: Option<f64>,
}

/// Home configuration per arm (radians).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HomeFile {
    /// Left arm, LARM_JOINT0..5.
    pub left: [f64; 6],
    /// Right arm, RARM_JOINT0..5.
    pub right: [f64; 6],
}

/// Planner settings.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlannerFile {
    /// Seed of every random choice; default 0.
    #[serde(default)]
    pub seed: Option<u64>,
    /// Number of random orders tried by Bottom-Left; default 256.
    #[serde(default)]
    pub bl_orders: Option<usize>,
    /// Wall-clock limit of the whole run in seconds; default 60.
    #[serde(default)]
    pub time_limit: Option<f64>,
    /// Node limit of the sequence search; default 2,000,000.
    #[serde(default)]
    pub max_nodes: Option<u64>,
    /// Minimum push-stability margin (metres of contact segment); default 0.002.
    #[serde(default)]
    pub min_push_margin: Option<f64>,
    /// Largest rotation (degrees) a box may make over a push phase judged by its travel
    /// (`docs/push_stability.md` §5.4); default 1.
    #[serde(default)]
    pub max_push_rotation_deg: Option<f64>,
    /// Largest lateral drift (length) of a box over such a phase; default 0.001 m.
    #[serde(default)]
    pub max_push_drift: Option<f64>,
    /// Lateral gap (length) below which a pushed box slides along a face it passes; default
    /// 0.001 m.
    #[serde(default)]
    pub side_clearance: Option<f64>,
    /// Judge side contacts in pushes; default true.
    #[serde(default)]
    pub side_contacts: Option<bool>,
    /// Also reject pushes into slots (side contacts on both sides); default false.
    #[serde(default)]
    pub forbid_slots: Option<bool>,
    /// Forbid direct placing (ablation).
    #[serde(default)]
    pub no_direct: Option<bool>,
    /// Forbid multi-object pushes (ablation).
    #[serde(default)]
    pub no_multi_push: Option<bool>,
    /// A packing-only study: robot issues do not make the plan invalid; default false.
    #[serde(default)]
    pub packing_only: Option<bool>,
    /// A* sequencer: largest indirect offset in multiples of the minimum offset; default 3.
    #[serde(default)]
    pub max_offset_steps: Option<usize>,
    /// A* sequencer: node budget of the greedy dive for a first plan; default 20,000.
    #[serde(default)]
    pub dive_nodes: Option<u64>,
    /// Joint acceleration limit of the trajectories at full speed (rad/s²); default 1.
    #[serde(default)]
    pub joint_acceleration: Option<f64>,
    /// Largest time between two trajectory points (s); default 0.1.
    #[serde(default)]
    pub sample_dt: Option<f64>,
}

/// One object kind.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KindFile {
    /// Kind name, referenced by objects.
    pub name: String,
    /// Edge lengths along the body x, y, z axes.
    pub size: [f64; 3],
    /// Mass in kilograms.
    pub mass: f64,
    /// Per-kind object–floor friction, overriding `friction.mu_floor`.
    #[serde(default)]
    pub mu_floor: Option<f64>,
    /// Per-kind object–object friction, overriding `friction.mu_obj`.
    #[serde(default)]
    pub mu_obj: Option<f64>,
    /// Per-kind finger–object friction, overriding `friction.mu_finger`.
    #[serde(default)]
    pub mu_finger: Option<f64>,
}

/// One object on the table.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectFile {
    /// Unique id.
    pub id: String,
    /// Name of its kind.
    pub kind: String,
    /// World x of its centre on the table.
    pub x: f64,
    /// World y of its centre on the table.
    pub y: f64,
    /// Yaw on the table, radians.
    #[serde(default)]
    pub yaw: f64,
    /// Body axis pointing up on the table: `x`, `y` or `z` (default `z`).
    #[serde(default)]
    pub up: Option<String>,
    /// `any` (default) or `upright` (keep the table's up axis).
    #[serde(default)]
    pub orientations: Option<String>,
}

//! Stage 0: the validated, immutable problem instance, and its loader from TOML/JSON files.
//!
//! [`file`](mod@file) holds the serde-only mirror of the file; [`Instance::load`] parses, converts units
//! and validates it, failing with an [`Error::Input`] that names the file, the field and the
//! reason. After loading, every invariant the later stages rely on holds (positive finite sizes,
//! at least one orientation that fits, no overlap on the table, reachable start poses, …).

mod builder;
pub mod file;
pub mod generate;

pub use builder::{GripperSpec, InstanceBuilder, Orientations, Units};

mod validation;

use validation::*;

use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::geometry::{convex_overlap, oriented_corners, BodyAxis, Box3, Orientation, Rect};
use crate::robot::{RobotModel, NEXTAGE_INITIAL_POSE_DEG};
use file::InstanceFile;
use nalgebra::Vector3;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// Standard gravity (m/s²).
pub const GRAVITY: f64 = 9.81;

/// The validated problem instance. Immutable once loaded.
#[derive(Debug, Clone)]
pub struct Instance {
    /// Name (from the file, else its stem).
    pub name: String,
    /// Where it was loaded from (`<memory>` otherwise); used in messages.
    pub source: String,
    /// SHA-256 of the file text.
    pub digest: String,
    /// The container.
    pub container: Container,
    /// Object kinds.
    pub kinds: Vec<Kind>,
    /// Objects, in file order; the index is the object's number everywhere in pushpack.
    pub objects: Vec<Object>,
    /// Gripper geometry.
    pub gripper: Gripper,
    /// Robot and work cell.
    pub robot: RobotCell,
    /// Planner settings from the file (the CLI may override them).
    pub settings: Settings,
    /// The parsed file, kept for writing it back into plan files and tools.
    pub file: InstanceFile,
}

/// Container geometry and pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Container {
    /// Inner width (C's x).
    pub width: f64,
    /// Inner depth (C's y).
    pub depth: f64,
    /// Wall height above the floor.
    pub wall_height: f64,
    /// Wall thickness.
    pub wall_thickness: f64,
    /// World (x, y) of the floor centre.
    pub center: [f64; 2],
    /// Yaw of C in the world.
    pub yaw: f64,
    /// World z of the inner floor.
    pub floor_z: f64,
}

impl Container {
    /// The inner floor `[0, width] × [0, depth]` in C.
    pub fn floor(&self) -> Rect {
        Rect::new(0.0, 0.0, self.width, self.depth)
    }

    /// A point of C in world coordinates.
    pub fn to_world(&self, p: [f64; 3]) -> Vector3<f64> {
        let (s, c) = self.yaw.sin_cos();
        let u = p[0] - self.width / 2.0;
        let v = p[1] - self.depth / 2.0;
        Vector3::new(
            self.center[0] + c * u - s * v,
            self.center[1] + s * u + c * v,
            self.floor_z + p[2],
        )
    }

    /// A world point in C (the inverse of [`Container::to_world`]).
    pub fn from_world(&self, p: &Vector3<f64>) -> [f64; 3] {
        let (s, c) = self.yaw.sin_cos();
        let (x, y) = (p.x - self.center[0], p.y - self.center[1]);
        [
            c * x + s * y + self.width / 2.0,
            -s * x + c * y + self.depth / 2.0,
            p.z - self.floor_z,
        ]
    }

    /// The four walls as boxes in C (they stand outside the floor rectangle).
    pub fn walls(&self) -> [Box3; 4] {
        let t = self.wall_thickness;
        let (w, d, h) = (self.width, self.depth, self.wall_height);
        [
            Box3 {
                min: [-t, -t, 0.0],
                max: [0.0, d + t, h],
            },
            Box3 {
                min: [w, -t, 0.0],
                max: [w + t, d + t, h],
            },
            Box3 {
                min: [-t, -t, 0.0],
                max: [w + t, 0.0, h],
            },
            Box3 {
                min: [-t, d, 0.0],
                max: [w + t, d + t, h],
            },
        ]
    }

    /// World-frame outer footprint corners (walls included).
    pub fn outer_corners_world(&self) -> [[f64; 2]; 4] {
        let t = self.wall_thickness;
        oriented_corners(
            self.center[0],
            self.center[1],
            self.yaw,
            self.width + 2.0 * t,
            self.depth + 2.0 * t,
        )
    }
}

/// An object kind.
#[derive(Debug, Clone, PartialEq)]
pub struct Kind {
    /// Kind name.
    pub name: String,
    /// Edge lengths along body x, y, z.
    pub size: [f64; 3],
    /// Mass (kg).
    pub mass: f64,
}

/// Pose of an object on the table (world frame).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TablePose {
    /// World x of the centre.
    pub x: f64,
    /// World y of the centre.
    pub y: f64,
    /// Yaw (radians).
    pub yaw: f64,
    /// Body axis pointing up.
    pub up: BodyAxis,
}

/// One object.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    /// Unique id.
    pub id: String,
    /// Index into [`Instance::kinds`].
    pub kind: usize,
    /// Edge lengths along body x, y, z (the kind's).
    pub size: [f64; 3],
    /// Mass (kg).
    pub mass: f64,
    /// Object–floor friction.
    pub mu_floor: f64,
    /// Object–object friction.
    pub mu_obj: f64,
    /// Finger–object friction.
    pub mu_finger: f64,
    /// Start pose on the table.
    pub table: TablePose,
    /// Allowed orientations in the container (non-empty, heights fit).
    pub orientations: Vec<Orientation>,
}

impl Object {
    /// Footprint corners and height on the table, world frame.
    pub fn table_footprint(&self) -> ([[f64; 2]; 4], f64) {
        let (fp, h) = Orientation {
            up: self.table.up,
            yaw90: false,
        }
        .dims(self.size);
        (
            oriented_corners(self.table.x, self.table.y, self.table.yaw, fp[0], fp[1]),
            h,
        )
    }
}

/// Gripper geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gripper {
    /// Thickness of a finger plate (and of the closed pair used as a pusher).
    pub finger_thickness: f64,
    /// Width of a finger plate.
    pub finger_width: f64,
    /// How far the fingers reach down beside a box; the plates hang from the hand housing to the
    /// TCP, and must be at least this long (validated).
    pub finger_length: f64,
    /// Maximum opening.
    pub max_opening: f64,
    /// Grasp depth below an object's top.
    pub grasp_depth: f64,
    /// Release clearance per side.
    pub release_clearance: f64,
    /// Minimum indirect offset `d`.
    pub min_offset: f64,
    /// Fingertip height above the floor while pushing.
    pub push_height: f64,
    /// How much narrower than the object a grasp command asks the fingers to close (m), so
    /// that a position-controlled gripper presses on the object instead of stopping at it.
    pub squeeze: f64,
    /// Largest grip force of a gripper command (N).
    pub max_effort: f64,
}

impl Gripper {
    /// Default `squeeze`: 2 mm.
    pub const DEFAULT_SQUEEZE: f64 = 0.002;
    /// Default `max_effort`: 20 N, which holds 2.4 kg between two fingers at a finger friction
    /// of 0.6 (the bundled instances' objects weigh under 0.1 kg).
    pub const DEFAULT_MAX_EFFORT: f64 = 20.0;
}

/// Robot model and work cell.
#[derive(Debug, Clone)]
pub struct RobotCell {
    /// Kinematic model.
    pub model: RobotModel,
    /// Where the model came from (`<bundled>` for the built-in copy).
    pub model_path: String,
    /// TCP offset in the wrist frame.
    pub tcp_offset: [f64; 3],
    /// Arms that may be used.
    pub arms: Vec<Arm>,
    /// Home joint angles per arm (left, right).
    pub home: [[f64; 6]; 2],
    /// World z of the table top.
    pub table_z: f64,
    /// Clearance of transfer moves above the container wall top.
    pub transfer_clearance: f64,
    /// The cell can turn objects over between pick and place (else a place that changes an
    /// object's up axis is not executable by a top-down pick).
    pub regrasp: bool,
    /// Fraction of the model's joint velocity limits the trajectories use, in (0, 1].
    pub speed_scale: f64,
}

/// Default of `robot.speed_scale`: trajectories use 90 % of the joint velocity limits (and 81 %
/// of the acceleration limit), a margin a controller's tracking error and time-stamp rounding
/// stay within (at 100 % the exported points exceeded the URDF limit by 1e-9 rad/s).
pub const DEFAULT_SPEED_SCALE: f64 = 0.9;

impl RobotCell {
    /// TCP position of an arm at its home configuration (world frame).
    pub fn home_tcp(&self, arm: Arm) -> Vector3<f64> {
        self.model.tcp_position(arm, &self.home[arm.index()], &self.tcp_offset)
    }
}

/// Planner settings with their defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Seed of every random choice (default 0).
    pub seed: u64,
    /// Random orders tried by Bottom-Left (default 256).
    pub bl_orders: usize,
    /// Time limit of the whole run in seconds (default 60).
    pub time_limit: f64,
    /// Node limit of a sequence search (default 2,000,000).
    pub max_nodes: u64,
    /// Minimum push-stability margin in metres (default 0.002).
    pub min_push_margin: f64,
    /// Largest rotation (rad) of a box over a push phase judged by its travel (default 1°,
    /// [`DEFAULT_MAX_PUSH_ROTATION`]; `docs/push_stability.md` §5.4).
    pub max_push_rotation: f64,
    /// Largest lateral drift (m) of a box over such a phase (default 1 mm,
    /// [`DEFAULT_MAX_PUSH_DRIFT`]).
    pub max_push_drift: f64,
    /// Lateral gap (m) below which a pushed box slides along a parallel face it passes: a *side
    /// contact* (default 1 mm, [`DEFAULT_SIDE_CLEARANCE`]; `docs/push_stability.md` §12).
    pub side_clearance: f64,
    /// Judge side contacts (default true): a push whose box slides along a neighbour that nothing
    /// holds against the push, or between faces on both of its sides, is rejected.
    pub side_contacts: bool,
    /// Also reject a pushed box with side contacts on both sides, a slot (default false:
    /// measured, it costs plans and buys no replay that passes; `docs/push_stability.md` §12).
    pub forbid_slots: bool,
    /// Forbid direct placing.
    pub no_direct: bool,
    /// Forbid multi-object pushes.
    pub no_multi_push: bool,
    /// A packing-only study (default false; `PlanOptions::packing_only`).
    pub packing_only: bool,
    /// The A* sequencer's largest indirect offset in multiples of the minimum offset (`None`:
    /// the sequencer's default, `AstarSettings::max_offset_steps`).
    pub max_offset_steps: Option<usize>,
    /// Node budget of the A* sequencer's first dive (`None`: `AstarSettings::dive_nodes`).
    pub dive_nodes: Option<u64>,
    /// Joint acceleration limit at full speed, rad/s² (`None`: `TrajectoryOptions::acceleration`).
    pub joint_acceleration: Option<f64>,
    /// Largest time between two trajectory points, s (`None`: `TrajectoryOptions::sample_dt`).
    pub sample_dt: Option<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            seed: 0,
            bl_orders: 256,
            time_limit: 60.0,
            max_nodes: 2_000_000,
            min_push_margin: 0.002,
            max_push_rotation: DEFAULT_MAX_PUSH_ROTATION,
            max_push_drift: DEFAULT_MAX_PUSH_DRIFT,
            side_clearance: DEFAULT_SIDE_CLEARANCE,
            side_contacts: true,
            forbid_slots: false,
            no_direct: false,
            no_multi_push: false,
            packing_only: false,
            max_offset_steps: None,
            dive_nodes: None,
            joint_acceleration: None,
            sample_dt: None,
        }
    }
}

/// Default of `planner.max_push_rotation_deg`, in rad: 1°. The planner's release and target
/// tolerances are a few tenths of a millimetre over a box's half width, which a degree already
/// uses (docs/push_stability.md §5.4).
pub const DEFAULT_MAX_PUSH_ROTATION: f64 = std::f64::consts::PI / 180.0;

/// Default of `planner.side_clearance`: 1 mm, twice the half-millimetre release error a real
/// cell sees; a box turned 0.5° comes 0.26 mm closer over a 6 cm face on top of it.
pub const DEFAULT_SIDE_CLEARANCE: f64 = 1e-3;

/// Largest accepted `planner.side_clearance` (m): a gap the size of a finger's thickness is no
/// longer a clearance but room, which the slab checks already judge.
pub const MAX_SIDE_CLEARANCE: f64 = 0.01;

/// Default of `planner.max_push_drift`: 1 mm.
pub const DEFAULT_MAX_PUSH_DRIFT: f64 = 1e-3;

/// Largest accepted `planner.max_push_rotation_deg`. The travel rule uses the rotation and drift
/// rates at the start of a phase (`docs/push_stability.md` §5.4); within a few degrees the
/// pivot's lever arms change by a few per cent, beyond that the estimate no longer describes the
/// motion, so a larger tolerance would accept what the model cannot judge.
pub const MAX_PUSH_ROTATION_DEG: f64 = 5.0;

/// Largest accepted `planner.max_push_drift` (m): a box that ends a push 5 mm beside its target
/// would press that far into a touching neighbour's target in a dense packing; a larger
/// tolerance would only hide a misplacement.
pub const MAX_PUSH_DRIFT: f64 = 0.005;

/// Largest accepted `planner.max_offset_steps`: the A* sequencer's compact state key stores an
/// offset step in a byte beside the push direction (`sequence::astar`).
pub const MAX_OFFSET_STEPS: usize = 100;

/// Largest accepted `planner.sample_dt` (s): a controller interpolates joint values linearly
/// between trajectory points, and the further apart they are, the further that line leaves the
/// planned path (a push leaves its straight line; the verifier checks collisions only at the
/// points and half-way between them).
pub const MAX_SAMPLE_DT: f64 = 1.0;

/// Largest accepted `planner.time_limit` in seconds (larger values cannot be represented as a
/// `std::time::Duration` deadline in every solver).
pub const MAX_TIME_LIMIT: f64 = 1e9;

/// Smallest accepted box edge in metres: 100 × [`crate::geometry::EPS`], so that the geometric
/// tolerance stays negligible against every object.
pub const MIN_EDGE: f64 = 1e-4;

impl Instance {
    /// Load and validate an instance file (`.toml` or `.json`; other extensions are tried as TOML).
    pub fn load(path: impl AsRef<Path>) -> Result<Instance> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        let json = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.eq_ignore_ascii_case("json"))
            .unwrap_or(false);
        Self::parse(&text, json, &path.display().to_string(), path.parent())
    }

    /// Parse and validate instance text. `base_dir` resolves a relative robot model path.
    pub fn parse(text: &str, json: bool, source: &str, base_dir: Option<&Path>) -> Result<Instance> {
        let file: InstanceFile = if json {
            let mut de = serde_json::Deserializer::from_str(text);
            serde_path_to_error::deserialize(&mut de).map_err(|e| {
                let path = e.path().to_string();
                let inner = e.into_inner();
                let syntax = inner.is_syntax() || inner.is_eof();
                let reason = inner.to_string();
                Error::input(source, serde_field(&path, &reason, syntax), reason)
            })?
        } else {
            let de = toml::Deserializer::parse(text)
                .map_err(|e| Error::input(source, "<syntax>", e.to_string().trim().to_string()))?;
            serde_path_to_error::deserialize(de).map_err(|e| {
                let path = e.path().to_string();
                let inner = e.into_inner();
                let mut reason = inner.message().to_string();
                if let Some(line) = inner
                    .span()
                    .and_then(|s| text.get(..s.start))
                    .map(|t| t.matches('\n').count() + 1)
                {
                    reason = format!("{reason} (line {line})");
                }
                Error::input(source, serde_field(&path, &reason, false), reason)
            })?
        };
        let digest: String = Sha256::digest(text.as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        validate(file, source, base_dir, digest)
    }

    /// Number of objects.
    pub fn n(&self) -> usize {
        self.objects.len()
    }
}

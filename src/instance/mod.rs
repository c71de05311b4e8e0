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
    /// Length of a finger plate.
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
}

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
    /// Time limit per stage in seconds (default 60).
    pub time_limit: f64,
    /// Node limit of a sequence search (default 2,000,000).
    pub max_nodes: u64,
    /// Minimum push-stability margin in metres (default 0.002).
    pub min_push_margin: f64,
    /// Forbid direct placing.
    pub no_direct: bool,
    /// Forbid multi-object pushes.
    pub no_multi_push: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            seed: 0,
            bl_orders: 256,
            time_limit: 60.0,
            max_nodes: 2_000_000,
            min_push_margin: 0.002,
            no_direct: false,
            no_multi_push: false,
        }
    }
}

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

/// The dotted field path of a deserialisation error: the serde path, completed with the name of a
/// missing field (serde reports those at the enclosing table); `<syntax>` for JSON syntax errors
/// that have no meaningful path, `<root>` for errors about the document as a whole. Blank or
/// odd keys (an unknown key `"  "`) are quoted so that the path is never empty.
fn serde_field(path: &str, reason: &str, syntax: bool) -> String {
    let root = path == ".";
    if syntax && (root || path.contains('?')) {
        return "<syntax>".to_string();
    }
    let base = (!root).then(|| tidy_path(path));
    if let Some(rest) = reason.strip_prefix("missing field `") {
        if let Some(name) = rest.split('`').next().filter(|n| !n.is_empty()) {
            return match base {
                Some(b) => format!("{b}.{name}"),
                None => name.to_string(),
            };
        }
    }
    base.unwrap_or_else(|| "<root>".to_string())
}

/// Quote the segments of a dotted path that are empty or contain blanks or control characters.
fn tidy_path(path: &str) -> String {
    path.split('.')
        .map(|s| {
            if s.is_empty() || s.chars().any(|c| c.is_whitespace() || c.is_control()) {
                format!("{s:?}")
            } else {
                s.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Field-error helper bound to one source file.
struct Check<'a> {
    file: &'a str,
}

impl Check<'_> {
    fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> Error {
        Error::input(self.file, field, reason)
    }
    fn finite(&self, field: &str, v: f64) -> Result<f64> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be a finite number, got {v}")))
        }
    }
    fn positive(&self, field: &str, v: f64) -> Result<f64> {
        self.finite(field, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be > 0, got {v}")))
        }
    }
    fn non_negative(&self, field: &str, v: f64) -> Result<f64> {
        self.finite(field, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be >= 0, got {v}")))
        }
    }
}

/// A length for messages: six decimals without trailing zeros, or scientific when very large or small.
fn num(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}

/// `[a, b, c]` as `a x b x c`.
fn fmt3(v: [f64; 3]) -> String {
    format!("{} x {} x {}", num(v[0]), num(v[1]), num(v[2]))
}

/// Distance from a point to a convex quadrilateral (0 inside).
fn point_polygon_distance(p: [f64; 2], poly: &[[f64; 2]; 4]) -> f64 {
    let mut inside = true;
    let mut sign = 0.0;
    let mut best = f64::INFINITY;
    for k in 0..4 {
        let a = poly[k];
        let b = poly[(k + 1) % 4];
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let (px, py) = (p[0] - a[0], p[1] - a[1]);
        let cross = ex * py - ey * px;
        if cross != 0.0 {
            if sign == 0.0 {
                sign = cross.signum();
            } else if cross.signum() != sign {
                inside = false;
            }
        }
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 {
            ((px * ex + py * ey) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (dx, dy) = (px - t * ex, py - t * ey);
        best = best.min((dx * dx + dy * dy).sqrt());
    }
    if inside {
        0.0
    } else {
        best
    }
}

fn parse_axis(c: &Check, field: &str, s: Option<&str>) -> Result<BodyAxis> {
    match s.unwrap_or("z") {
        "x" | "+x" | "-x" => Ok(BodyAxis::X),
        "y" | "+y" | "-y" => Ok(BodyAxis::Y),
        "z" | "+z" | "-z" => Ok(BodyAxis::Z),
        other => Err(c.err(field, format!("must be one of x, y, z, got {other:?}"))),
    }
}

fn resolve_model(c: &Check, rel: &str, base_dir: Option<&Path>) -> Result<PathBuf> {
    let p = Path::new(rel);
    let mut tried = Vec::new();
    if p.is_absolute() {
        tried.push(p.to_path_buf());
    } else {
        if let Some(b) = base_dir {
            tried.push(b.join(p));
        }
        tried.push(p.to_path_buf());
    }
    tried.iter().find(|t| t.is_file()).cloned().ok_or_else(|| {
        let list: Vec<String> = tried.iter().map(|t| t.display().to_string()).collect();
        c.err(
            "robot.model",
            format!("model file not found (looked at {})", list.join(", ")),
        )
    })
}

fn validate(f: InstanceFile, source: &str, base_dir: Option<&Path>, digest: String) -> Result<Instance> {
    let c = Check { file: source };
    if f.format_version != 1 {
        return Err(c.err(
            "format_version",
            format!("only version 1 exists, got {}", f.format_version),
        ));
    }
    let scale = match f.units.as_deref().unwrap_or("m") {
        "m" => 1.0,
        "cm" => 0.01,
        "mm" => 0.001,
        other => return Err(c.err("units", format!("must be \"m\", \"cm\" or \"mm\", got {other:?}"))),
    };
    let l = |v: f64| v * scale;

    // Container.
    let cf = &f.container;
    let container = Container {
        width: l(c.positive("container.width", cf.width)?),
        depth: l(c.positive("container.depth", cf.depth)?),
        wall_height: l(c.positive("container.wall_height", cf.wall_height)?),
        wall_thickness: l(c.positive("container.wall_thickness", cf.wall_thickness)?),
        center: [
            l(c.finite("container.center[0]", cf.center[0])?),
            l(c.finite("container.center[1]", cf.center[1])?),
        ],
        yaw: c.finite("container.yaw", cf.yaw)?,
        floor_z: 0.0,
    };

    // Friction.
    let fr = &f.friction;
    let mu_floor = c.non_negative("friction.mu_floor", fr.mu_floor)?;
    let mu_obj = c.non_negative("friction.mu_obj", fr.mu_obj)?;
    let mu_finger = c.non_negative("friction.mu_finger", fr.mu_finger)?;

    // Gripper.
    let g = &f.gripper;
    let finger_thickness = l(c.positive("gripper.finger_thickness", g.finger_thickness)?);
    let release_clearance = l(c.non_negative("gripper.release_clearance", g.release_clearance)?);
    let min_offset_floor = finger_thickness + release_clearance;
    let min_offset = match g.min_offset {
        Some(v) => {
            let v = l(c.positive("gripper.min_offset", v)?);
            if v < min_offset_floor - 1e-12 {
                return Err(c.err(
                    "gripper.min_offset",
                    format!("must be >= finger_thickness + release_clearance = {min_offset_floor:.4} m, got {v:.4} m"),
                ));
            }
            v
        }
        None => min_offset_floor,
    };
    let gripper = Gripper {
        finger_thickness,
        finger_width: l(c.positive("gripper.finger_width", g.finger_width)?),
        finger_length: l(c.positive("gripper.finger_length", g.finger_length)?),
        max_opening: l(c.positive("gripper.max_opening", g.max_opening)?),
        grasp_depth: l(c.positive("gripper.grasp_depth", g.grasp_depth)?),
        release_clearance,
        min_offset,
        push_height: match g.push_height {
            Some(v) => l(c.non_negative("gripper.push_height", v)?),
            None => 0.005,
        },
    };

    if gripper.grasp_depth > gripper.finger_length + 1e-9 {
        return Err(c.err(
            "gripper.grasp_depth",
            format!(
                "must be at most finger_length = {:.4} m (the fingers cannot reach deeper), got {:.4} m",
                gripper.finger_length, gripper.grasp_depth
            ),
        ));
    }

    // Robot.
    let r = &f.robot;
    let table_z = match r.table_z {
        Some(v) => l(c.finite("robot.table_z", v)?),
        None => -0.20,
    };
    let mut container = container;
    container.floor_z = match cf.floor_z {
        Some(v) => l(c.finite("container.floor_z", v)?),
        None => table_z,
    };
    let (model, model_path) = match &r.model {
        None => (RobotModel::bundled(), "<bundled>".to_string()),
        Some(rel) => {
            let path = resolve_model(&c, rel, base_dir)?;
            let text =
                std::fs::read_to_string(&path).map_err(|e| c.err("robot.model", format!("{}: {e}", path.display())))?;
            let m = RobotModel::from_urdf_str(&text)
                .map_err(|e| c.err("robot.model", format!("{}: {e}", path.display())))?;
            (m, path.display().to_string())
        }
    };
    let tcp_offset = match r.tcp_offset {
        Some(t) => {
            for (i, v) in t.iter().enumerate() {
                c.finite(&format!("robot.tcp_offset[{i}]"), *v)?;
            }
            t.map(l)
        }
        None => crate::robot::DEFAULT_TCP_OFFSET,
    };
    let arms = match &r.arms {
        None => vec![Arm::Left, Arm::Right],
        Some(list) => {
            let mut arms = Vec::new();
            for (i, a) in list.iter().enumerate() {
                let arm = match a.as_str() {
                    "left" => Arm::Left,
                    "right" => Arm::Right,
                    other => {
                        return Err(c.err(
                            format!("robot.arms[{i}]"),
                            format!("must be \"left\" or \"right\", got {other:?}"),
                        ))
                    }
                };
                if !arms.contains(&arm) {
                    arms.push(arm);
                }
            }
            if arms.is_empty() {
                return Err(c.err("robot.arms", "at least one arm is needed"));
            }
            arms
        }
    };
    let home = match &r.home {
        None => NEXTAGE_INITIAL_POSE_DEG.map(|a| a.map(f64::to_radians)),
        Some(h) => {
            for (name, q) in [("left", &h.left), ("right", &h.right)] {
                for (i, v) in q.iter().enumerate() {
                    c.finite(&format!("robot.home.{name}[{i}]"), *v)?;
                }
            }
            [h.left, h.right]
        }
    };
    for arm in [Arm::Left, Arm::Right] {
        if let Err(e) = model.check_joint_limits(arm, &home[arm.index()]) {
            return Err(c.err(format!("robot.home.{}", arm.name()), e));
        }
    }
    let transfer_clearance = match r.transfer_clearance {
        Some(v) => l(c.non_negative("robot.transfer_clearance", v)?),
        None => 0.08,
    };
    let robot = RobotCell {
        model,
        model_path,
        tcp_offset,
        arms,
        home,
        table_z,
        transfer_clearance,
        regrasp: r.regrasp.unwrap_or(false),
    };

    // Planner settings.
    let p = &f.planner;
    let d = Settings::default();
    let settings = Settings {
        seed: p.seed.unwrap_or(d.seed),
        bl_orders: match p.bl_orders {
            Some(0) => return Err(c.err("planner.bl_orders", "must be >= 1")),
            Some(v) => v,
            None => d.bl_orders,
        },
        time_limit: match p.time_limit {
            Some(v) => {
                let v = c.positive("planner.time_limit", v)?;
                if v > MAX_TIME_LIMIT {
                    return Err(c.err(
                        "planner.time_limit",
                        format!("must be at most {MAX_TIME_LIMIT:e} s, got {v:e} s"),
                    ));
                }
                v
            }
            None => d.time_limit,
        },
        max_nodes: match p.max_nodes {
            Some(0) => return Err(c.err("planner.max_nodes", "must be >= 1")),
            Some(v) => v,
            None => d.max_nodes,
        },
        min_push_margin: match p.min_push_margin {
            Some(v) => l(c.non_negative("planner.min_push_margin", v)?),
            None => d.min_push_margin,
        },
        no_direct: p.no_direct.unwrap_or(false),
        no_multi_push: p.no_multi_push.unwrap_or(false),
    };

    // Kinds.
    if f.kinds.is_empty() {
        return Err(c.err("kinds", "at least one kind is needed"));
    }
    let mut kinds = Vec::new();
    let mut kind_mu = Vec::new();
    for (i, k) in f.kinds.iter().enumerate() {
        let fld = |s: &str| format!("kinds[{i}].{s}");
        if k.name.trim().is_empty() {
            return Err(c.err(fld("name"), "must not be empty"));
        }
        if kinds.iter().any(|o: &Kind| o.name == k.name) {
            return Err(c.err(fld("name"), format!("duplicate kind name {:?}", k.name)));
        }
        let mut size = [0.0; 3];
        for (j, s) in size.iter_mut().enumerate() {
            let field = fld(&format!("size[{j}]"));
            *s = l(c.positive(&field, k.size[j])?);
            if *s < MIN_EDGE {
                return Err(c.err(
                    field,
                    format!(
                        "must be at least {MIN_EDGE} m (100 x the geometric tolerance), got {:e} m",
                        *s
                    ),
                ));
            }
        }
        let mass = c.positive(&fld("mass"), k.mass)?;
        let mf = match k.mu_floor {
            Some(v) => c.non_negative(&fld("mu_floor"), v)?,
            None => mu_floor,
        };
        let mo = match k.mu_obj {
            Some(v) => c.non_negative(&fld("mu_obj"), v)?,
            None => mu_obj,
        };
        let mg = match k.mu_finger {
            Some(v) => c.non_negative(&fld("mu_finger"), v)?,
            None => mu_finger,
        };
        kinds.push(Kind {
            name: k.name.clone(),
            size,
            mass,
        });
        kind_mu.push([mf, mo, mg]);
    }

    // Objects.
    if f.objects.is_empty() {
        return Err(c.err("objects", "at least one object is needed"));
    }
    let floor_area = container.width * container.depth;
    let mut objects: Vec<Object> = Vec::new();
    let mut min_area_sum = 0.0;
    for (i, o) in f.objects.iter().enumerate() {
        let fld = |s: &str| format!("objects[{i}].{s}");
        if o.id.trim().is_empty() {
            return Err(c.err(fld("id"), "must not be empty"));
        }
        if objects.iter().any(|p| p.id == o.id) {
            return Err(c.err(fld("id"), format!("duplicate object id {:?}", o.id)));
        }
        let kind = kinds
            .iter()
            .position(|k| k.name == o.kind)
            .ok_or_else(|| c.err(fld("kind"), format!("unknown kind {:?}", o.kind)))?;
        let up = parse_axis(&c, &fld("up"), o.up.as_deref())?;
        let table = TablePose {
            x: l(c.finite(&fld("x"), o.x)?),
            y: l(c.finite(&fld("y"), o.y)?),
            yaw: c.finite(&fld("yaw"), o.yaw)?,
            up,
        };
        let size = kinds[kind].size;
        // The default follows the gripper: a top-down two-finger pick cannot turn a box over,
        // so without a regrasp the face it stands on stays down and every plan stays
        // executable. `any` remains for packing-only studies (docs/formats.md).
        let default_rule = if robot.regrasp { "any" } else { "upright" };
        let candidates: Vec<Orientation> = match o.orientations.as_deref().unwrap_or(default_rule) {
            "any" => Orientation::all().to_vec(),
            "upright" => vec![Orientation { up, yaw90: false }, Orientation { up, yaw90: true }],
            other => {
                return Err(c.err(
                    fld("orientations"),
                    format!("must be \"any\" or \"upright\", got {other:?}"),
                ))
            }
        };
        let mut orientations: Vec<Orientation> = Vec::new();
        for ori in candidates {
            let (fp, h) = ori.dims(size);
            let fits =
                h <= container.wall_height + 1e-9 && fp[0] <= container.width + 1e-9 && fp[1] <= container.depth + 1e-9;
            let graspable = (fp[0] + 2.0 * gripper.release_clearance <= gripper.max_opening + 1e-9
                || fp[1] + 2.0 * gripper.release_clearance <= gripper.max_opening + 1e-9)
                && h > gripper.grasp_depth + 1e-9;
            let pushable = h > gripper.push_height + 1e-9;
            if fits && graspable && pushable && !orientations.iter().any(|q| q.dims(size) == ori.dims(size)) {
                orientations.push(ori);
            }
        }
        if orientations.is_empty() {
            return Err(c.err(
                fld("kind"),
                format!(
                    "object {:?} (size {} m) fits in none of its allowed orientations: it must fit the container \
                     ({} m), leave release_clearance on both sides within max_opening ({} m), and stand taller \
                     than grasp_depth ({} m) and push_height ({} m)",
                    o.id,
                    fmt3(size),
                    fmt3([container.width, container.depth, container.wall_height]),
                    num(gripper.max_opening),
                    num(gripper.grasp_depth),
                    num(gripper.push_height)
                ),
            ));
        }
        min_area_sum += orientations
            .iter()
            .map(|q| q.dims(size).0[0] * q.dims(size).0[1])
            .fold(f64::INFINITY, f64::min);
        let [mf, mo, mg] = kind_mu[kind];
        objects.push(Object {
            id: o.id.clone(),
            kind,
            size,
            mass: kinds[kind].mass,
            mu_floor: mf,
            mu_obj: mo,
            mu_finger: mg,
            table,
            orientations,
        });
    }
    if min_area_sum > floor_area + 1e-12 {
        return Err(c.err(
            "objects",
            format!("total footprint area {min_area_sum:.5} m² exceeds the container floor {floor_area:.5} m²"),
        ));
    }
    // Table poses: no overlap with each other or with the container, and reachable.
    let walls = container.outer_corners_world();
    for i in 0..objects.len() {
        let (fi, hi) = objects[i].table_footprint();
        for j in 0..i {
            let (fj, _) = objects[j].table_footprint();
            if convex_overlap(&fi, &fj) {
                return Err(c.err(
                    format!("objects[{i}]"),
                    format!(
                        "object {:?} overlaps object {:?} on the table",
                        objects[i].id, objects[j].id
                    ),
                ));
            }
        }
        if convex_overlap(&fi, &walls) {
            return Err(c.err(
                format!("objects[{i}]"),
                format!("object {:?} starts on top of the container", objects[i].id),
            ));
        }
        if hi <= gripper.grasp_depth + 1e-9 {
            return Err(c.err(
                format!("objects[{i}]"),
                format!(
                    "object {:?} is {:.4} m tall on the table, not taller than grasp_depth = {:.4} m: it cannot be picked up",
                    objects[i].id, hi, gripper.grasp_depth
                ),
            ));
        }
        // The hands hang at their home pose over the table: nothing may reach up into them.
        let hand_radius = gripper.max_opening / 2.0 + gripper.finger_thickness;
        for arm in [Arm::Left, Arm::Right] {
            let tcp = robot.home_tcp(arm);
            if table_z + hi > tcp.z && point_polygon_distance([tcp.x, tcp.y], &fi) < hand_radius {
                return Err(c.err(
                    format!("objects[{i}]"),
                    format!(
                        "object {:?} is {:.4} m tall but lies under the {} hand, whose fingertips hang {:.4} m above \
                         the table at the home pose: lower it or move it away from ({:.3}, {:.3})",
                        objects[i].id,
                        hi,
                        arm.name(),
                        tcp.z - table_z,
                        tcp.x,
                        tcp.y
                    ),
                ));
            }
        }
        let grasp = Vector3::new(
            objects[i].table.x,
            objects[i].table.y,
            table_z + hi - gripper.grasp_depth,
        );
        if !robot
            .arms
            .iter()
            .any(|a| robot.model.reachable_top_down(*a, &grasp, &robot.tcp_offset))
        {
            return Err(c.err(
                format!("objects[{i}]"),
                format!(
                    "object {:?} at ({:.3}, {:.3}) is out of reach of every allowed arm for a top-down grasp",
                    objects[i].id, objects[i].table.x, objects[i].table.y
                ),
            ));
        }
    }
    let name = f.name.clone().unwrap_or_else(|| {
        Path::new(source)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("instance")
            .to_string()
    });
    Ok(Instance {
        name,
        source: source.to_string(),
        digest,
        container,
        kinds,
        objects,
        gripper,
        robot,
        settings,
        file: f,
    })
}

//! `push-check` scenarios: one push described in a small JSON file, decided by the convex check,
//! reported with a verdict, a margin and a certificate.
//!
//! Format (lengths in metres unless `units` says `cm`/`mm`; angles in radians):
//!
//! ```json
//! {
//!   "name": "two boxes, lateral offset",
//!   "mode": "2d",                      // "2d" | "3d" | "robust" (2-D) | "robust3d"
//!   "push_dir": "-x",                  // "-x" | "+x" | "-y" | "+y" | [ux, uy]
//!   "friction": { "mu_floor": 0.35, "mu_obj": 0.3, "mu_finger": 0.5 },
//!   "boxes": [                         // front (nearest the destination) to back
//!     { "id": "b1", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.03, 0.02, 0.0] },
//!     { "id": "b2", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.09, 0.02, 0.0],
//!       "mu_floor": 0.4 }              // optional per-box mu_floor / mu_obj / mu_finger
//!   ],
//!   "pusher": { "point": [0.12, 0.02], "width": 0.02, "height": 0.005 },
//!   "robust": { "mu_floor": [0.3, 0.4], "mu_obj": [0.25, 0.35], "mu_finger": [0.4, 0.6],
//!               "cof_region": [0.003, 0.003] }
//! }
//! ```
//!
//! `size` is the box's extent along its own x and y (turned by the pose's yaw) and its height;
//! `pose` the footprint centre and yaw. Boxes may start apart along the push direction: the back
//! ones then move first (one phase per gap). The pusher is the flat back of the closed fingers:
//! a face `width` wide centred at `point`, perpendicular to `normal` (default: the push
//! direction), fingertip `height` above the floor; its contact patch reaches from the fingertip
//! to the top of the back box. Optional: `units`, `gravity`, `cone_shrink`, `name`.

use std::fmt;
use std::path::Path;

mod contact;
mod parse;
mod report;

use contact::*;
pub use parse::*;
pub use report::*;

use serde::{Deserialize, Serialize};

use super::convex::{self, Binding, CheckOptions, CheckResult, ContactForce, Dim, FloorForce, PhaseStatus};
use super::model::{cross, dot, Body, Contact, ContactKind, PushModel, V2};
use super::robust::{self, RobustCase, UncertaintySet};
use super::travel::TravelCheck;
use crate::error::{Error, Result};

/// Which check a scenario asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Mode {
    /// Planar LP.
    #[serde(rename = "2d")]
    D2,
    /// Spatial SOCP with patches, floor pressure and toppling.
    #[serde(rename = "3d")]
    D3,
    /// 2-D over the uncertainty set.
    #[serde(rename = "robust")]
    Robust,
    /// 3-D over the uncertainty set.
    #[serde(rename = "robust3d")]
    Robust3d,
}

impl Mode {
    /// Model dimension of the mode.
    pub fn dim(self) -> Dim {
        match self {
            Mode::D2 | Mode::Robust => Dim::D2,
            Mode::D3 | Mode::Robust3d => Dim::D3,
        }
    }
    /// Whether the mode is robust.
    pub fn robust(self) -> bool {
        matches!(self, Mode::Robust | Mode::Robust3d)
    }
    /// File spelling.
    pub fn name(self) -> &'static str {
        match self {
            Mode::D2 => "2d",
            Mode::D3 => "3d",
            Mode::Robust => "robust",
            Mode::Robust3d => "robust3d",
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    units: Option<String>,
    mode: Mode,
    push_dir: DirSpec,
    #[serde(default)]
    gravity: Option<f64>,
    friction: FrictionFile,
    #[serde(default)]
    robust: Option<RobustFile>,
    boxes: Vec<BoxFile>,
    pusher: PusherFile,
    #[serde(default)]
    cone_shrink: Option<f64>,
    #[serde(default)]
    max_rotation: Option<f64>,
    #[serde(default)]
    max_drift: Option<f64>,
    #[serde(default)]
    min_margin: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum DirSpec {
    Named(String),
    Vector([f64; 2]),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FrictionFile {
    mu_floor: f64,
    mu_obj: f64,
    mu_finger: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobustFile {
    #[serde(default)]
    mu_floor: Option<[f64; 2]>,
    #[serde(default)]
    mu_obj: Option<[f64; 2]>,
    #[serde(default)]
    mu_finger: Option<[f64; 2]>,
    #[serde(default)]
    cof_region: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxFile {
    id: String,
    size: [f64; 3],
    mass: f64,
    pose: [f64; 3],
    #[serde(default)]
    mu_floor: Option<f64>,
    #[serde(default)]
    mu_obj: Option<f64>,
    #[serde(default)]
    mu_finger: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PusherFile {
    point: [f64; 2],
    width: f64,
    height: f64,
    #[serde(default)]
    normal: Option<[f64; 2]>,
}

/// A validated scenario: the push model plus what to check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scenario {
    /// File the scenario came from (or `<memory>`).
    pub source: String,
    /// Display name.
    pub name: String,
    /// Requested check.
    pub mode: Mode,
    /// The push model with every gap closed (boxes at the moment they touch).
    pub model: PushModel,
    /// Gap closed before each box (m), front to back, the pusher's last.
    pub gaps: Vec<f64>,
    /// Uncertainty set (robust modes).
    pub uncertainty: Option<UncertaintySet>,
    /// Cone shrink and tolerance.
    pub options: CheckOptions,
}

/// Read and validate a scenario file.
pub fn load_scenario(path: impl AsRef<Path>) -> Result<Scenario> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    parse_scenario(&text, &path.display().to_string())
}

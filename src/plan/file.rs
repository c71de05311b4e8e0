//! The `plan.json` document: what a plan is on disk, reading it back (version 1 and 2) and
//! converting it into the instance's actions and placement.

use super::{sequence_status, PlanOptions, Sequencer};
use crate::actions::{Action, PlaceMode};
use crate::error::{Error, Result};
use crate::geometry::{Arm, Axis2, Orientation, PushDir, Rect};
use crate::instance::Instance;
use crate::motion::keypoints::KeyPoint;
use crate::placement::{Placement, Target};
use crate::sequence::{self, Metrics, SearchStatus};
use crate::status::{Limit, Status};
use serde::{Deserialize, Serialize};

/// Version of the `plan.json` schema. Version 2 states every outcome in the one vocabulary of
/// [`Status`]; version 1 files are still read ([`Plan::load`] upgrades them).
pub const FORMAT_VERSION: u32 = 2;

/// Tool name and version.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToolInfo {
    /// `pushpack`.
    pub name: String,
    /// Crate version.
    pub version: String,
}

/// Which instance the plan is for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstanceRef {
    /// Instance name.
    pub name: String,
    /// Path it was loaded from.
    pub source: String,
    /// SHA-256 of the instance file.
    pub digest: String,
}

/// Summary of the placement stage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacementSummary {
    /// What the placement stage proved (`optimal`, `feasible` or `heuristic`).
    pub status: Status,
    /// Occupied area (m²).
    pub occupied_area: f64,
    /// Proven lower bound on the occupied area (m²).
    pub lower_bound: f64,
    /// Relative gap.
    pub gap: f64,
    /// Contact length (m).
    pub contact_length: f64,
    /// Solver name.
    pub solver: String,
    /// 0 for the placement stage's own result; k when the sequencer proved that the first k
    /// placements tried admit no plan and this is the next distinct Bottom-Left placement
    /// ([`PlanOptions::placement_alternatives`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub alternative: usize,
}

fn is_zero(k: &usize) -> bool {
    *k == 0
}

/// One object's target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacementEntry {
    /// Object id.
    pub object: String,
    /// Kind name.
    pub kind: String,
    /// Orientation (vertical body axis, 90° turn).
    pub orientation: Orientation,
    /// Minimum corner x of the footprint in C (m).
    pub x: f64,
    /// Minimum corner y of the footprint in C (m).
    pub y: f64,
    /// Footprint extent along C's x (m).
    pub size_x: f64,
    /// Footprint extent along C's y (m).
    pub size_y: f64,
    /// Height (m).
    pub height: f64,
}

/// One action in execution order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ActionEntry {
    /// 1-based step number.
    pub step: usize,
    /// `place` or `push`.
    pub kind: String,
    /// Object ids (a push lists its line front to back).
    pub objects: Vec<String>,
    /// `direct` or `indirect` (places only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mode: Option<String>,
    /// Push direction (`-x` or `-y`) of an indirect place or a push.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub push_dir: Option<PushDir>,
    /// Offset from the target of an indirect place (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<f64>,
    /// Push distance (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<f64>,
    /// Grasp axis of a place (`x` or `y` of C).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grasp_axis: Option<Axis2>,
    /// Lateral coordinate of the pusher centre (m, C frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pusher_at: Option<f64>,
    /// Release footprint of a place (C frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub release: Option<Rect>,
    /// Push stability margin (m); pushes only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Mechanical model that decided the push (`2d`: clarabel LP, docs/push_stability.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub push_model: Option<String>,
    /// The push's phase judged by its travel, when it has one (docs/push_stability.md §5.4):
    /// the back object closing its gap alone while it turns about the finger's edge. `margin`
    /// is then the smallest margin of the other phases.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub travel_phase: Option<TravelPhase>,
    /// Executing arm.
    pub arm: Arm,
    /// TCP travel of this action from the arm's previous position (m).
    pub cost: f64,
    /// TCP key points (world frame).
    pub key_poses: Vec<KeyPoint>,
}

/// How far the back object of a push turns and drifts while it closes its gap alone, against
/// the instance's `planner.max_push_rotation_deg` and `planner.max_push_drift`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TravelPhase {
    /// The object that moves alone (the line's back object).
    pub object: String,
    /// The gap it closes (m).
    pub gap: f64,
    /// Its rotation over the gap (rad).
    pub rotation: f64,
    /// The lateral drift of its centre over the gap (m).
    pub drift: f64,
    /// `max(rotation / max_push_rotation, drift / max_push_drift)`: the share of the
    /// tolerances the phase uses; it passes iff ≤ 1.
    pub usage: f64,
}

/// Statistics of one stage.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageStats {
    /// What the stage proved ([`Status`]).
    pub status: Status,
    /// What stopped the stage before it finished its proof, if anything did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stopped_by: Option<Limit>,
    /// Wall-clock seconds.
    pub time_s: f64,
    /// Nodes (or orders) explored.
    pub nodes: u64,
    /// Proven lower bound, when the stage has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
    /// Relative gap, when the stage has a bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// Assignments evaluated (sequencing).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub assignments: Option<u64>,
    /// Proven lexicographic lower bound (actions, swept area, travel) of the sequence stage.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cost_bound: Option<sequence::astar::Cost>,
    /// Sequence stage: the actions the physics replay rejected, each in its neighbourhood, that
    /// the search then avoided (`docs/push_stability.md` §13); absent when none was.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub physics_vetoes: Vec<String>,
}

/// Per-stage statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolverStats {
    /// Placement stage.
    pub placement: StageStats,
    /// Sequence stage.
    pub sequence: StageStats,
}

/// The `plan.json` document.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Schema version ([`FORMAT_VERSION`]).
    pub format_version: u32,
    /// Producing tool.
    pub tool: ToolInfo,
    /// Instance reference.
    pub instance: InstanceRef,
    /// What the whole run proved: [`Status::combine`] of the placement and sequence stages.
    pub status: Status,
    /// Options used.
    pub options: PlanOptions,
    /// Placement summary.
    pub placement: PlacementSummary,
    /// Per-object targets, in instance order.
    pub placements: Vec<PlacementEntry>,
    /// Actions in execution order.
    pub actions: Vec<ActionEntry>,
    /// Plan metrics.
    pub metrics: Metrics,
    /// Solver statistics.
    pub solver: SolverStats,
    /// Robot model, TCP and frames of the joint trajectories (SPEC §8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robot: Option<crate::motion::RobotInfo>,
    /// Joint trajectories: one per action in order, plus park and return-home moves.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub trajectories: Vec<crate::motion::ActionTrajectory>,
}

impl Plan {
    /// The robot's execution time: the end of the last joint trajectory (s), when the plan has
    /// trajectories. The arms move in turn, so this is the sum of every action's motion.
    pub fn robot_time_s(&self) -> Option<f64> {
        self.trajectories.iter().map(|t| t.t_end).reduce(f64::max)
    }

    /// The trajectories of one arm, in time order.
    pub fn arm_trajectories(&self, arm: Arm) -> Vec<&crate::motion::ActionTrajectory> {
        let mut v: Vec<&crate::motion::ActionTrajectory> = self.trajectories.iter().filter(|t| t.arm == arm).collect();
        v.sort_by(|a, b| a.t_start.total_cmp(&b.t_start));
        v
    }
}

fn object_index(inst: &Instance, id: &str, field: &str, file: &str) -> Result<usize> {
    inst.objects
        .iter()
        .position(|o| o.id == id)
        .ok_or_else(|| Error::input(file, field, format!("unknown object id {id:?}")))
}

impl Plan {
    /// Read a plan file.
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Plan> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        Plan::from_json(&text, &path.display().to_string())
    }

    /// Parse a plan document (version 1 or 2); `file` names it in errors.
    pub fn from_json(text: &str, file: &str) -> Result<Plan> {
        let bad = |field: String, reason: String| Error::input(file, field, reason);
        let mut doc: serde_json::Value = serde_json::from_str(text).map_err(|e| bad(String::new(), e.to_string()))?;
        if doc["format_version"].as_u64() == Some(1) {
            upgrade_v1(&mut doc);
        }
        serde_path_to_error::deserialize(doc)
            .map_err(|e| Error::input(file, e.path().to_string(), e.into_inner().to_string()))
    }

    /// Write as pretty JSON.
    pub fn save(&self, path: impl AsRef<std::path::Path>) -> Result<()> {
        let path = path.as_ref();
        let text = serde_json::to_string_pretty(self).expect("plans serialise");
        std::fs::write(path, text + "\n").map_err(|e| Error::Io {
            path: path.to_path_buf(),
            source: e,
        })
    }

    /// The placement as targets of the instance's objects (validating ids and sizes).
    pub fn placement(&self, inst: &Instance) -> Result<Placement> {
        let file = "plan.json";
        if self.placements.len() != inst.n() {
            return Err(Error::input(
                file,
                "placements",
                format!("{} entries for {} objects", self.placements.len(), inst.n()),
            ));
        }
        let mut targets: Vec<Option<Target>> = vec![None; inst.n()];
        for (k, e) in self.placements.iter().enumerate() {
            let i = object_index(inst, &e.object, &format!("placements[{k}].object"), file)?;
            if targets[i].is_some() {
                return Err(Error::input(
                    file,
                    format!("placements[{k}].object"),
                    format!("object {:?} placed twice", e.object),
                ));
            }
            for (name, v) in [
                ("x", e.x),
                ("y", e.y),
                ("size_x", e.size_x),
                ("size_y", e.size_y),
                ("height", e.height),
            ] {
                if !v.is_finite() {
                    return Err(Error::input(file, format!("placements[{k}].{name}"), "must be finite"));
                }
            }
            targets[i] = Some(Target {
                orientation: e.orientation,
                rect: Rect::new(e.x, e.y, e.size_x, e.size_y),
                height: e.height,
            });
        }
        Ok(Placement {
            targets: targets
                .into_iter()
                .map(|t| t.expect("all set: counts match and no duplicates"))
                .collect(),
        })
    }

    /// The actions as [`Action`]s of the instance (validating ids and fields).
    pub fn actions(&self, inst: &Instance) -> Result<Vec<Action>> {
        let file = "plan.json";
        let mut out = Vec::new();
        for (k, e) in self.actions.iter().enumerate() {
            let f = |s: &str| format!("actions[{k}].{s}");
            let missing = |s: &str| Error::input(file, f(s), "missing");
            let ids: Vec<usize> = e
                .objects
                .iter()
                .enumerate()
                .map(|(j, id)| object_index(inst, id, &f(&format!("objects[{j}]")), file))
                .collect::<Result<_>>()?;
            match e.kind.as_str() {
                "place" => {
                    if ids.len() != 1 {
                        return Err(Error::input(file, f("objects"), "a place moves exactly one object"));
                    }
                    let mode = match e.mode.as_deref() {
                        Some("direct") => PlaceMode::Direct,
                        Some("indirect") => {
                            let offset = e.offset.ok_or_else(|| missing("offset"))?;
                            if !(offset.is_finite() && offset > 0.0) {
                                return Err(Error::input(file, f("offset"), "must be finite and > 0"));
                            }
                            PlaceMode::Indirect {
                                push_dir: e.push_dir.ok_or_else(|| missing("push_dir"))?,
                                offset,
                            }
                        }
                        Some(other) => {
                            return Err(Error::input(
                                file,
                                f("mode"),
                                format!("must be direct or indirect, got {other:?}"),
                            ))
                        }
                        None => return Err(missing("mode")),
                    };
                    out.push(Action::Place {
                        object: ids[0],
                        mode,
                        grasp_axis: e.grasp_axis.ok_or_else(|| missing("grasp_axis"))?,
                        arm: e.arm,
                    });
                }
                "push" => {
                    if ids.is_empty() {
                        return Err(Error::input(file, f("objects"), "a push moves at least one object"));
                    }
                    let distance = e.distance.ok_or_else(|| missing("distance"))?;
                    let pusher_at = e.pusher_at.ok_or_else(|| missing("pusher_at"))?;
                    if !distance.is_finite() || !pusher_at.is_finite() {
                        return Err(Error::input(
                            file,
                            f("distance"),
                            "distance and pusher_at must be finite",
                        ));
                    }
                    out.push(Action::Push {
                        objects: ids,
                        push_dir: e.push_dir.ok_or_else(|| missing("push_dir"))?,
                        distance,
                        pusher_at,
                        arm: e.arm,
                    });
                }
                other => {
                    return Err(Error::input(
                        file,
                        f("kind"),
                        format!("must be place or push, got {other:?}"),
                    ))
                }
            }
        }
        Ok(out)
    }
}

/// Rewrite a version-1 `plan.json` document in place as version 2. Version 1 wrote the
/// sequencer's own words (`complete`, `node_limit`, `time_limit`) and called every Bottom-Left
/// placement `feasible`; the options echo says which methods ran, which decides what was proven.
fn upgrade_v1(doc: &mut serde_json::Value) {
    use serde_json::Value;
    let sequencer = match doc["options"]["sequencer"].as_str() {
        Some("paper") => Sequencer::Paper,
        _ => Sequencer::Astar,
    };
    let mut stages = Vec::new();
    let placement_solver = doc["placement"]["solver"].as_str().unwrap_or("").to_string();
    let p = match doc["placement"]["status"].as_str() {
        Some("optimal") => Status::Optimal,
        _ if placement_solver == "bl" => Status::Heuristic,
        _ => Status::Feasible,
    };
    stages.push(p);
    // A malformed document is left for the deserialiser to reject with its path; writing into
    // a field that is not an object would panic.
    if !doc.is_object() || !doc["placement"].is_object() {
        return;
    }
    doc["placement"]["status"] = Value::from(p.as_str());
    if doc["solver"]["placement"].is_object() {
        doc["solver"]["placement"]["status"] = Value::from(p.as_str());
    }
    if let Some(word) = doc["solver"]["sequence"]["status"].as_str().map(str::to_string) {
        // `as_str` succeeded, so `solver` and `sequence` are objects.
        let search = match word.as_str() {
            "node_limit" => SearchStatus::NodeLimit,
            "time_limit" => SearchStatus::TimeLimit,
            _ => SearchStatus::Complete,
        };
        let (s, stop) = sequence_status(sequencer, search);
        stages.push(s);
        doc["solver"]["sequence"]["status"] = Value::from(s.as_str());
        if let Some(l) = stop {
            doc["solver"]["sequence"]["stopped_by"] = serde_json::to_value(l).expect("limits serialise");
        }
    }
    doc["status"] = Value::from(Status::combine(&stages).as_str());
}

impl crate::simulate::Replayable for Plan {
    fn replay_placement(&self, inst: &Instance) -> Result<Placement> {
        self.placement(inst)
    }
    fn replay_actions(&self, inst: &Instance) -> Result<Vec<Action>> {
        self.actions(inst)
    }
}

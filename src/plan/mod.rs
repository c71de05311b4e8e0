//! The plan: the one composer that runs every stage ([`optimize`]) and the `plan.json` file.
//!
//! [`Plan`] is the immutable solution snapshot written to disk; it refers to objects by id so that
//! outside tools can read it without the instance. [`Plan::actions`] converts it back into
//! [`Action`]s against an instance, rejecting unknown ids and malformed entries.

use crate::actions::{Action, PlaceMode};
use crate::control::{Either, Event, Listener, Never, Silent, Stage, Terminator, TimeLimit};
use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::geometry::{Axis2, Orientation, PushDir, Rect};
use crate::instance::Instance;
use crate::motion::keypoints::{action_keypoints, path_length, KeyPoint};
use crate::placement::{self, Placement, PlacementResult, PlacementStatus, Target};
use crate::sequence::{self, Metrics, SearchStatus, SequenceOptions, SequenceResult};
use crate::status::{Limit, Status};
use serde::{Deserialize, Serialize};

pub mod export;

/// Version of the `plan.json` schema. Version 2 states every outcome in the one vocabulary of
/// [`Status`]; version 1 files are still read ([`Plan::load`] upgrades them).
pub const FORMAT_VERSION: u32 = 2;

/// Which placement solver to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlacementSolver {
    /// The paper's extended Bottom-Left.
    Bl,
    /// Exact MILP (HiGHS), warm-started by Bottom-Left.
    Milp,
}

/// Largest instance for which `plan` uses the MILP placement by default (see docs/algorithms.md).
pub const MILP_DEFAULT_MAX_OBJECTS: usize = 10;

/// Run the chosen placement solver (MILP runs Bottom-Left first as its warm start).
pub fn solve_placement(
    inst: &Instance,
    solver: PlacementSolver,
    seed: u64,
    bl_orders: usize,
    time_limit: f64,
) -> Result<PlacementResult> {
    solve_placement_report(inst, solver, seed, bl_orders, time_limit).map(|(r, _)| r)
}

/// [`solve_placement`], with the exact solver's report (bound over time, stage costs).
pub fn solve_placement_report(
    inst: &Instance,
    solver: PlacementSolver,
    seed: u64,
    bl_orders: usize,
    time_limit: f64,
) -> Result<(PlacementResult, Option<placement::milp::MilpReport>)> {
    solve_placement_with(inst, solver, seed, bl_orders, time_limit, &Never)
}

/// [`solve_placement_report`] that also stops when `stop` says so (a cancel flag).
pub fn solve_placement_with(
    inst: &Instance,
    solver: PlacementSolver,
    seed: u64,
    bl_orders: usize,
    time_limit: f64,
    stop: &dyn Terminator,
) -> Result<(PlacementResult, Option<placement::milp::MilpReport>)> {
    let clock = TimeLimit::new(time_limit);
    let limit = Either(&clock, stop);
    let bl = placement::bl::solve(inst, seed, bl_orders, &limit);
    match solver {
        PlacementSolver::Bl => bl.map(|r| (r, None)),
        PlacementSolver::Milp => {
            let settings = placement::milp::MilpSettings {
                time_limit: (time_limit - clock.elapsed()).max(0.0),
                contact_stage: true,
                seed,
            };
            // Bottom-Left finding nothing proves nothing: the exact search starts without it.
            let warm = bl.unwrap_or_else(|_| PlacementResult::empty("bl", clock.elapsed()));
            placement::milp::solve_report(inst, &warm, &settings, &limit).map(|(r, rep)| (r, Some(rep)))
        }
    }
}

/// Which sequencer to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Sequencer {
    /// The paper's Algorithms 1 + 2.
    Paper,
    /// Best-first search over assignment and order together, with admissible bounds.
    Astar,
}

/// Options of one planning run (defaults from the instance's `[planner]` table).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanOptions {
    /// Seed of every random choice.
    pub seed: u64,
    /// Forbid direct placing.
    pub no_direct: bool,
    /// Forbid multi-object pushes.
    pub no_multi_push: bool,
    /// Placement solver.
    pub placement: PlacementSolver,
    /// Sequencer.
    pub sequencer: Sequencer,
    /// Time limit of the whole run (s): placement, sequence and joint trajectories together
    /// ([`RunBudget`] divides it).
    pub time_limit: f64,
    /// Node limit of the sequence search.
    pub max_nodes: u64,
    /// Bottom-Left orders.
    pub bl_orders: usize,
    /// When the sequencer proves that the placement admits no plan, try up to this many further
    /// Bottom-Left placements, best first, within the same sequence time limit. 0 (the default)
    /// keeps the placement stage's result whatever happens, as comparisons between sequencers
    /// need.
    #[serde(default)]
    pub placement_alternatives: usize,
}

impl PlanOptions {
    /// The instance's own settings.
    pub fn from_instance(inst: &Instance) -> PlanOptions {
        let s = &inst.settings;
        PlanOptions {
            seed: s.seed,
            no_direct: s.no_direct,
            no_multi_push: s.no_multi_push,
            placement: if inst.n() <= MILP_DEFAULT_MAX_OBJECTS {
                PlacementSolver::Milp
            } else {
                PlacementSolver::Bl
            },
            sequencer: Sequencer::Astar,
            time_limit: s.time_limit,
            max_nodes: s.max_nodes,
            bl_orders: s.bl_orders,
            placement_alternatives: 0,
        }
    }
}

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
    /// Executing arm.
    pub arm: Arm,
    /// TCP travel of this action from the arm's previous position (m).
    pub cost: f64,
    /// TCP key points (world frame).
    pub key_poses: Vec<KeyPoint>,
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

/// Everything one planning run produced.
#[derive(Debug, Clone)]
pub struct PlanOutcome {
    /// The plan file.
    pub plan: Plan,
    /// Placement stage result.
    pub placement: PlacementResult,
    /// Sequence stage result.
    pub sequence: SequenceResult,
}

/// How a run's one time limit is shared between its stages.
///
/// The placement stage may use up to half of it (it usually needs far less, and then leaves
/// the rest to the sequence). The joint trajectories and the verifier cannot be interrupted
/// without losing the plan, so the sequence search stops early enough to leave them their
/// expected time: 0.1 s per object (measured: 1.4 s for 28 actions of a 20-object plan on the
/// reference machine, docs/benchmarks.md), at most 30 % of the limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunBudget {
    /// The whole run's limit (s).
    pub total_s: f64,
    /// Most the placement stage may use (s).
    pub placement_s: f64,
    /// Time kept back at the end for joint trajectories and verification (s).
    pub motion_reserve_s: f64,
}

impl RunBudget {
    /// The budget of a run of `inst` within `time_limit` seconds.
    pub fn new(inst: &Instance, time_limit: f64) -> RunBudget {
        RunBudget {
            total_s: time_limit,
            placement_s: 0.5 * time_limit,
            motion_reserve_s: (0.1 * inst.n() as f64).min(0.3 * time_limit),
        }
    }

    /// The sequence stage's limit once the placement took `placement_s`.
    pub fn sequence_s(&self, placement_s: f64) -> f64 {
        (self.total_s - placement_s - self.motion_reserve_s).max(0.0)
    }
}

/// Run every stage: placement, then actions and their order, then joint trajectories; return
/// the plan. [`PlanOptions::time_limit`] bounds the whole run ([`RunBudget`]).
pub fn optimize(inst: &Instance, opts: &PlanOptions) -> Result<PlanOutcome> {
    optimize_with(inst, opts, &Never, &mut Silent)
}

/// [`optimize`] under the caller's control: `stop` ends the run early (a [`CancelFlag`],
/// another deadline) and `listener` hears every stage start and finish. A run stopped during
/// the sequence search still returns its best plan so far, with the limit that stopped it in
/// [`StageStats::stopped_by`].
///
/// [`CancelFlag`]: crate::control::CancelFlag
pub fn optimize_with(
    inst: &Instance,
    opts: &PlanOptions,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> Result<PlanOutcome> {
    optimize_stages(inst, opts, stop, listener).1
}

/// [`optimize_with`], also returning the placement when a later stage fails (the CLI draws it).
pub fn optimize_stages(
    inst: &Instance,
    opts: &PlanOptions,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> (Option<PlacementResult>, Result<PlanOutcome>) {
    let budget = RunBudget::new(inst, opts.time_limit);
    listener.event(&Event::StageStarted {
        stage: Stage::Placement,
        budget_s: budget.placement_s,
    });
    let placement = match solve_placement_with(
        inst,
        opts.placement,
        opts.seed,
        opts.bl_orders,
        budget.placement_s,
        stop,
    ) {
        Ok((p, _)) => p,
        Err(e) => return (None, Err(e)),
    };
    listener.event(&Event::StageFinished {
        stage: Stage::Placement,
        status: placement_status(&placement),
        time_s: placement.time_s,
        nodes: placement.nodes,
        objective: Some(placement.placement.occupied_area()),
        bound: Some(placement.lower_bound),
    });
    let seq_s = budget.sequence_s(placement.time_s);
    let out = sequence_placement_with(inst, opts, placement.clone(), seq_s, stop, listener);
    (Some(placement), out)
}

/// The stages after placement: choose actions and their order for `placement`, then assemble
/// the plan. Callers that want the placement even when no sequence is found (the CLI draws it)
/// run [`solve_placement`] and this themselves; [`optimize`] is the two in one.
///
/// With [`PlanOptions::placement_alternatives`] > 0, a placement the sequencer proves to have no
/// plan ([`Error::Infeasible`]) is replaced by the next distinct Bottom-Left placement
/// ([`placement::bl::alternatives`]), until one has a plan, the alternatives are used up or the
/// sequence time limit runs out. The plan then records which alternative it used; its placement
/// is `feasible`, with the first placement's lower bound (a bound on every placement).
pub fn sequence_placement(inst: &Instance, opts: &PlanOptions, placement: PlacementResult) -> Result<PlanOutcome> {
    let budget = RunBudget::new(inst, opts.time_limit);
    sequence_placement_with(inst, opts, placement, budget.sequence_s(0.0), &Never, &mut Silent)
}

/// [`sequence_placement`] within `time_limit` seconds and under the caller's `stop` and
/// `listener` ([`optimize_with`]).
pub fn sequence_placement_with(
    inst: &Instance,
    opts: &PlanOptions,
    placement: PlacementResult,
    time_limit: f64,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> Result<PlanOutcome> {
    listener.event(&Event::StageStarted {
        stage: Stage::Sequence,
        budget_s: time_limit,
    });
    let clock = TimeLimit::new(time_limit);
    let limit = Either(&clock, stop);
    let first = sequence_one(inst, opts, &placement.placement, &limit);
    let reason = match first {
        Ok(sequence) => return Ok(outcome(inst, opts, placement, sequence, 0, stop, listener)),
        Err(Error::Infeasible { reason }) if opts.placement_alternatives > 0 => reason,
        Err(e) => return Err(e),
    };
    let start = std::time::Instant::now();
    let others = placement::bl::alternatives(inst, opts.seed, opts.bl_orders, &limit);
    // The placement stage's time includes finding the alternatives, not sequencing them.
    let alternatives_s = start.elapsed().as_secs_f64();
    let mut tried = 0;
    for alt in others
        .into_iter()
        .filter(|p| *p != placement.placement)
        .take(opts.placement_alternatives)
    {
        if limit.should_stop() {
            break;
        }
        tried += 1;
        match sequence_one(inst, opts, &alt, &limit) {
            Ok(sequence) => {
                let pr = PlacementResult {
                    placement: alt,
                    status: PlacementStatus::Feasible,
                    lower_bound: placement.lower_bound,
                    // With the exact stage's bound the alternative is `feasible`, not a
                    // heuristic's: its gap is measured against a proven bound.
                    solver: if placement.solver == "bl" {
                        "bl"
                    } else {
                        "bl-alternative"
                    }
                    .into(),
                    time_s: placement.time_s + alternatives_s,
                    nodes: placement.nodes,
                    subproblems: placement.subproblems,
                };
                return Ok(outcome(inst, opts, pr, sequence, tried, stop, listener));
            }
            Err(Error::Infeasible { .. }) => continue,
            Err(e) => return Err(e),
        }
    }
    Err(Error::Infeasible {
        reason: format!("{reason}; {tried} alternative Bottom-Left placements tried, none has a plan either"),
    })
}

/// One run of the chosen sequencer on `placement`.
fn sequence_one(
    inst: &Instance,
    opts: &PlanOptions,
    placement: &Placement,
    limit: &dyn Terminator,
) -> Result<SequenceResult> {
    let seq_opts = SequenceOptions {
        no_direct: opts.no_direct,
        no_multi_push: opts.no_multi_push,
        max_nodes: opts.max_nodes,
    };
    match opts.sequencer {
        Sequencer::Paper => sequence::paper::solve(inst, placement, &seq_opts, limit),
        Sequencer::Astar => sequence::astar::solve(
            inst,
            placement,
            &seq_opts,
            &sequence::astar::AstarSettings::default(),
            limit,
        ),
    }
}

fn outcome(
    inst: &Instance,
    opts: &PlanOptions,
    placement: PlacementResult,
    sequence: SequenceResult,
    alternative: usize,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> PlanOutcome {
    let (status, _) = sequence_status(opts.sequencer, sequence.status);
    listener.event(&Event::StageFinished {
        stage: Stage::Sequence,
        status,
        time_s: sequence.time_s,
        nodes: sequence.nodes,
        objective: Some(sequence.metrics.seq_len as f64),
        bound: sequence.bound.map(|b| b.len as f64),
    });
    listener.event(&Event::StageStarted {
        stage: Stage::Motion,
        budget_s: 0.0,
    });
    let start = std::time::Instant::now();
    let mut plan = build_plan(inst, opts, &placement, &sequence);
    plan.placement.alternative = alternative;
    // A search the caller cancelled says so, not "time limit": the run did not run out of time.
    if sequence.status != SearchStatus::Complete && stop.should_stop() {
        plan.solver.sequence.stopped_by = Some(Limit::Cancel);
    }
    listener.event(&Event::StageFinished {
        stage: Stage::Motion,
        // Joint trajectories are planned, not optimised: a solution that proves nothing.
        status: Status::Heuristic,
        time_s: start.elapsed().as_secs_f64(),
        nodes: plan.trajectories.len() as u64,
        objective: None,
        bound: None,
    });
    PlanOutcome {
        plan,
        placement,
        sequence,
    }
}

/// Assemble the plan file from stage results.
pub fn build_plan(inst: &Instance, opts: &PlanOptions, pr: &PlacementResult, sr: &SequenceResult) -> Plan {
    let p = &pr.placement;
    let placements = p
        .targets
        .iter()
        .enumerate()
        .map(|(i, t)| PlacementEntry {
            object: inst.objects[i].id.clone(),
            kind: inst.kinds[inst.objects[i].kind].name.clone(),
            orientation: t.orientation,
            x: t.rect.x0,
            y: t.rect.y0,
            size_x: t.rect.width(),
            size_y: t.rect.depth(),
            height: t.height,
        })
        .collect();
    let mut pos = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    let layout = crate::actions::Layout::new(inst, p);
    let actions = sr
        .actions
        .iter()
        .zip(&sr.margins)
        .enumerate()
        .map(|(k, (a, m))| {
            let kps = action_keypoints(inst, p, a);
            let (cost, end) = path_length(&pos[a.arm().index()], &kps);
            pos[a.arm().index()] = end;
            let ids = a.objects().iter().map(|&i| inst.objects[i].id.clone()).collect();
            match a {
                Action::Place {
                    object,
                    mode,
                    grasp_axis,
                    arm,
                } => {
                    let (mode_s, dir, off) = match mode {
                        PlaceMode::Direct => ("direct", None, None),
                        PlaceMode::Indirect { push_dir, offset } => ("indirect", Some(*push_dir), Some(*offset)),
                    };
                    ActionEntry {
                        step: k + 1,
                        kind: "place".into(),
                        objects: ids,
                        mode: Some(mode_s.into()),
                        push_dir: dir,
                        offset: off,
                        distance: None,
                        grasp_axis: Some(*grasp_axis),
                        pusher_at: None,
                        release: Some(layout.release_rect(*object, mode)),
                        margin: None,
                        push_model: None,
                        arm: *arm,
                        cost,
                        key_poses: kps,
                    }
                }
                Action::Push {
                    push_dir,
                    distance,
                    pusher_at,
                    arm,
                    ..
                } => ActionEntry {
                    step: k + 1,
                    kind: "push".into(),
                    objects: ids,
                    mode: None,
                    push_dir: Some(*push_dir),
                    offset: None,
                    distance: Some(*distance),
                    grasp_axis: None,
                    pusher_at: Some(*pusher_at),
                    release: None,
                    margin: *m,
                    push_model: Some("2d".into()),
                    arm: *arm,
                    cost,
                    key_poses: kps,
                },
            }
        })
        .collect();
    let (robot, trajectories) =
        crate::motion::plan_trajectories(inst, p, &sr.actions, &crate::motion::TrajectoryOptions::default());
    let placement_status = placement_status(pr);
    let (sequence_status, sequence_stop) = sequence_status(opts.sequencer, sr.status);
    Plan {
        format_version: FORMAT_VERSION,
        tool: ToolInfo {
            name: "pushpack".into(),
            version: env!("CARGO_PKG_VERSION").into(),
        },
        instance: InstanceRef {
            name: inst.name.clone(),
            source: inst.source.clone(),
            digest: inst.digest.clone(),
        },
        status: Status::combine(&[placement_status, sequence_status]),
        options: opts.clone(),
        placement: PlacementSummary {
            status: placement_status,
            occupied_area: p.occupied_area(),
            lower_bound: pr.lower_bound,
            gap: pr.gap(),
            contact_length: p.contact_length(inst),
            solver: pr.solver.clone(),
            alternative: 0,
        },
        placements,
        actions,
        metrics: sr.metrics,
        solver: SolverStats {
            placement: StageStats {
                status: placement_status,
                stopped_by: None,
                time_s: pr.time_s,
                nodes: pr.nodes,
                bound: Some(pr.lower_bound),
                gap: Some(pr.gap()),
                assignments: None,
                cost_bound: None,
            },
            sequence: StageStats {
                status: sequence_status,
                stopped_by: sequence_stop,
                time_s: sr.time_s,
                nodes: sr.nodes,
                bound: sr.bound.map(|b| b.travel),
                gap: sr.bound.map(|b| {
                    if b.len == sr.metrics.seq_len
                        && (b.area - sr.metrics.swept_area).abs() <= 1e-12
                        && sr.metrics.travel > 0.0
                    {
                        ((sr.metrics.travel - b.travel) / sr.metrics.travel).max(0.0)
                    } else {
                        1.0
                    }
                }),
                assignments: Some(sr.assignments),
                cost_bound: sr.bound,
            },
        },
        robot: Some(robot),
        trajectories,
    }
}

/// The placement stage's result in the vocabulary of [`Status`]: Bottom-Left proves no bound
/// beyond the trivial sum of areas, so its placements are `heuristic` even when they happen to
/// meet that bound.
pub fn placement_status(pr: &PlacementResult) -> Status {
    match pr.status {
        PlacementStatus::Optimal => Status::Optimal,
        PlacementStatus::Feasible if pr.solver == "bl" => Status::Heuristic,
        PlacementStatus::Feasible => Status::Feasible,
    }
}

/// The sequence stage's result in the vocabulary of [`Status`], with what stopped it early.
/// Only A* proves anything: a `complete` A* search is optimal within its action space
/// (docs/algorithms.md); the paper's sequencer is a heuristic however its search ends.
pub fn sequence_status(sequencer: Sequencer, search: SearchStatus) -> (Status, Option<Limit>) {
    let stop = match search {
        SearchStatus::Complete => None,
        SearchStatus::NodeLimit => Some(Limit::Nodes),
        SearchStatus::TimeLimit => Some(Limit::Time),
    };
    let status = match (sequencer, stop) {
        (Sequencer::Paper, _) => Status::Heuristic,
        (Sequencer::Astar, None) => Status::Optimal,
        (Sequencer::Astar, Some(_)) => Status::Feasible,
    };
    (status, stop)
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

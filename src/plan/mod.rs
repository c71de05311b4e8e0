//! The plan: the one composer that runs every stage ([`optimize`]) and the `plan.json` file.
//!
//! [`Plan`] is the immutable solution snapshot written to disk; it refers to objects by id so that
//! outside tools can read it without the instance. [`Plan::actions`] converts it back into
//! [`crate::actions::Action`]s against an instance, rejecting unknown ids and malformed entries.

use crate::actions::veto::Veto;
use crate::control::{Either, Event, Listener, Never, Silent, Stage, Terminator, TimeLimit};
use crate::error::{Error, Result};
use crate::instance::Instance;
use crate::motion::TrajectoryOptions;
use crate::placement::{self, Placement, PlacementResult, PlacementStatus};
use crate::sequence::{self, SearchStatus, SequenceOptions, SequenceResult};
use crate::simulate;
use crate::status::{Limit, Status};
use serde::{Deserialize, Serialize};

mod build;
pub mod export;
mod file;
pub mod ros2;

pub use build::{build_plan, build_plan_with};
pub use file::*;

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
    solve_placement_with(inst, solver, seed, bl_orders, time_limit, 1, &Never, &mut Silent)
}

/// [`solve_placement_report`] with the exact search's boxes on `threads` threads (the same
/// answer on any number), that also stops when `stop` says so (a cancel flag) and tells
/// `listener` how the exact search goes ([`Event::Progress`]).
#[allow(clippy::too_many_arguments)] // the run's settings, then its control
pub fn solve_placement_with(
    inst: &Instance,
    solver: PlacementSolver,
    seed: u64,
    bl_orders: usize,
    time_limit: f64,
    threads: usize,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
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
                threads: threads.max(1),
                ..Default::default()
            };
            // Bottom-Left finding nothing proves nothing: the exact search starts without it.
            let warm = bl.unwrap_or_else(|_| PlacementResult::empty("bl", clock.elapsed()));
            placement::milp::solve_listen(inst, &warm, &settings, &limit, listener).map(|(r, rep)| (r, Some(rep)))
        }
    }
}

/// The exact placement with explicit settings (the area stage's master, the contact budget):
/// Bottom-Left with `bl_orders` orders for the warm start, then the exact search, both within
/// `settings.time_limit` and seeded by `settings.seed`.
pub fn solve_placement_exact(
    inst: &Instance,
    bl_orders: usize,
    settings: &placement::milp::MilpSettings,
    stop: &dyn Terminator,
) -> Result<(PlacementResult, placement::milp::MilpReport)> {
    let clock = TimeLimit::new(settings.time_limit);
    let limit = Either(&clock, stop);
    let bl = placement::bl::solve(inst, settings.seed, bl_orders, &limit);
    let warm = bl.unwrap_or_else(|_| PlacementResult::empty("bl", clock.elapsed()));
    let rest = placement::milp::MilpSettings {
        time_limit: (settings.time_limit - clock.elapsed()).max(0.0),
        ..settings.clone()
    };
    placement::milp::solve_report(inst, &warm, &rest, &limit)
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

/// Every setting of one planning run: [`PlanOptions::from_instance`] fills it from the
/// instance's `[planner]` and `[robot]` tables and their documented defaults (docs/formats.md),
/// and the CLI's flags override it. `plan.json` records it as `options`.
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
    /// ([`RunBudget`] divides it). A search checks its clock between steps, so a run can end
    /// up to one step late: 0.25 s at most on the committed 20-object set (docs/benchmarks.md).
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
    /// A packing-only study: the plan does not claim that the robot can run it, so robot
    /// issues (a box turned over, a pose out of reach) are reported but do not make it invalid
    /// (default false: plans are meant to be executable).
    #[serde(default)]
    pub packing_only: bool,
    /// Settings of the A* sequencer (absent in older plan files: the defaults).
    #[serde(default)]
    pub astar: sequence::astar::AstarSettings,
    /// Timing of the joint trajectories (absent in older plan files: the defaults).
    /// `velocity_scale` comes from the instance's `robot.speed_scale`.
    #[serde(default)]
    pub trajectory: TrajectoryOptions,
    /// Threads of the exact placement's box searches and of the inverse kinematics' descents
    /// from their seeds (default 1; `plan --threads`). The plan is the same on any number, only
    /// the wall time changes (absent in older plan files: 1).
    #[serde(default = "one_thread")]
    pub threads: usize,
    /// Replay each plan the sequencer finds in the physics engine, and search again without
    /// the first action the replay rejects, in its neighbourhood (default true;
    /// `plan --no-physics` turns it off, and the verifier's replay with it). Packing-only runs
    /// replay inside the search too; their verifier does not (they are never executable).
    #[serde(default = "yes")]
    pub physics: bool,
}

fn yes() -> bool {
    true
}

fn one_thread() -> usize {
    1
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
            packing_only: s.packing_only,
            physics: true,
            astar: {
                let d = sequence::astar::AstarSettings::default();
                sequence::astar::AstarSettings {
                    max_offset_steps: s.max_offset_steps.unwrap_or(d.max_offset_steps),
                    dive_nodes: s.dive_nodes.unwrap_or(d.dive_nodes),
                    ..d
                }
            },
            trajectory: {
                let d = TrajectoryOptions::default();
                TrajectoryOptions {
                    velocity_scale: inst.robot.speed_scale,
                    acceleration: s.joint_acceleration.unwrap_or(d.acceleration),
                    sample_dt: s.sample_dt.unwrap_or(d.sample_dt),
                }
            },
            threads: 1,
        }
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
        opts.threads,
        stop,
        listener,
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
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs_f64(time_limit.max(0.0));
    let first = sequence_physical(inst, opts, &placement.placement, &limit, deadline, listener);
    let reason = match first {
        Ok((sequence, vetoes)) => {
            let mut out = outcome(inst, opts, placement, sequence, 0, stop, listener);
            out.plan.solver.sequence.physics_vetoes = vetoes;
            return Ok(out);
        }
        Err(Error::Infeasible { reason }) if opts.placement_alternatives > 0 => reason,
        Err(e) => return Err(cancelled(e, stop)),
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
        match sequence_physical(inst, opts, &alt, &limit, deadline, listener) {
            Ok((sequence, vetoes)) => {
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
                let mut out = outcome(inst, opts, pr, sequence, tried, stop, listener);
                out.plan.solver.sequence.physics_vetoes = vetoes;
                return Ok(out);
            }
            Err(Error::Infeasible { .. }) => continue,
            Err(e) => return Err(cancelled(e, stop)),
        }
    }
    Err(Error::Infeasible {
        reason: format!("{reason}; {tried} alternative Bottom-Left placements tried, none has a plan either"),
    })
}

/// A search the caller cancelled before it had any plan says so, not "time limit": the run
/// did not run out of time (as [`outcome`] marks one cancelled with a plan in hand). The
/// searches see the caller's stop and the run's clock as one limit.
fn cancelled(e: Error, stop: &dyn Terminator) -> Error {
    match e {
        Error::Stopped {
            stage,
            limit: Limit::Time,
            nodes,
            elapsed_s,
            min_actions,
        } if stop.should_stop() => Error::Stopped {
            stage,
            limit: Limit::Cancel,
            nodes,
            elapsed_s,
            min_actions,
        },
        e => e,
    }
}

/// The chosen sequencer on `placement`, with the physics replay in the loop: each plan found is
/// replayed (up to its first action out of tolerance); that action is vetoed in its
/// neighbourhood and the search runs again, until a plan passes, the search finds none, or the
/// limit strikes. The last plan found is returned either way, with the vetoes' reasons: a plan
/// that still fails is the verifier's to reject, not this loop's to hide.
///
/// With the replay on, each search gets [`PHYSICS_SHARE`] of the time left, so that a plan the
/// replay rejects leaves time to search again; a first search that finds nothing in its share
/// runs again with all of it.
fn sequence_physical(
    inst: &Instance,
    opts: &PlanOptions,
    placement: &Placement,
    limit: &dyn Terminator,
    deadline: std::time::Instant,
    listener: &mut dyn Listener,
) -> Result<(SequenceResult, Vec<String>)> {
    let mut vetoes: Vec<Veto> = Vec::new();
    let mut last: Option<SequenceResult> = None;
    // Packing-only studies replay too: the boxes' mechanics do not depend on the robot.
    let replay = opts.physics;
    let started = std::time::Instant::now();
    // The stage's time and nodes are those of every search and replay it ran.
    let mut nodes = 0;
    let total = |mut s: SequenceResult, nodes: u64| {
        s.time_s = started.elapsed().as_secs_f64();
        s.nodes = nodes;
        s
    };
    loop {
        let left = deadline
            .saturating_duration_since(std::time::Instant::now())
            .as_secs_f64();
        let share = TimeLimit::new(if replay { left * PHYSICS_SHARE } else { left });
        let attempt = sequence_one(inst, opts, placement, &Either(limit, &share), listener, &vetoes);
        let attempt = match attempt {
            Err(Error::Stopped { .. }) if last.is_none() && share.should_stop() && !limit.should_stop() => {
                sequence_one(inst, opts, placement, limit, listener, &vetoes)
            }
            a => a,
        };
        let found = match attempt {
            Ok(s) => s,
            // With vetoes in force, a failed search still leaves the last plan in hand.
            // It was found under every veto but the last, which it breaks.
            Err(e) => match last {
                Some(s) if !vetoes.is_empty() => return Ok((total(s, nodes), reasons(&vetoes[..vetoes.len() - 1]))),
                _ => return Err(e),
            },
        };
        nodes += found.nodes;
        if !replay || limit.should_stop() || vetoes.len() >= MAX_PHYSICS_VETOES {
            return Ok((total(found, nodes), reasons(&vetoes)));
        }
        match physics_veto(inst, placement, &found.actions, limit) {
            Some(v) => {
                // A veto the search already had would mean it ignored one: never loop on it.
                debug_assert!(!vetoes.contains(&v), "the search chose a vetoed action: {}", v.reason);
                if vetoes.contains(&v) {
                    return Ok((total(found, nodes), reasons(&vetoes)));
                }
                vetoes.push(v)
            }
            None => return Ok((total(found, nodes), reasons(&vetoes))),
        }
        last = Some(found);
    }
}

/// Share of the time left that one search of the planner's physics loop (`docs/push_stability.md` §13) may use: the rest is kept
/// for searching again around the actions the replay rejects.
pub const PHYSICS_SHARE: f64 = 2.0 / 3.0;

/// Most physics vetoes one placement's search takes before it gives up and returns its plan:
/// each costs a search and a replay.
pub const MAX_PHYSICS_VETOES: usize = 32;

fn reasons(vetoes: &[Veto]) -> Vec<String> {
    vetoes.iter().map(|v| v.reason.clone()).collect()
}

/// The first action of `actions` that the physics replay moves a box out of tolerance in, as a
/// veto in the state it ran in; `None` when the replay passes (or cannot tell which action).
///
/// The replay runs with the instance's settings first, then under the sweep's other settings
/// (`simulate::sweep::variants`: half the step, slower pushes, softer and stiffer contacts),
/// each until its first failure: a push that passes one setting and fails the next is fragile,
/// and a plan found again around it is one the sweep accepts. A plan that passes the first
/// replay costs five more; one that fails it, one.
fn physics_veto(
    inst: &Instance,
    placement: &Placement,
    actions: &[crate::actions::Action],
    limit: &dyn Terminator,
) -> Option<Veto> {
    let seq = simulate::Sequence { placement, actions };
    // Cheapest replays first (steps per simulated second, times the slowing of the pushes), so
    // that a fragile plan is usually caught before the slow settings run.
    let base = simulate::SimOptions::from_instance(inst);
    let mut settings = simulate::sweep::variants(&base);
    let cost = |o: &simulate::SimOptions| base.dt / o.dt * base.push_speed / o.push_speed;
    settings.sort_by(|a, b| cost(&a.1).total_cmp(&cost(&b.1)));
    for (setting, o) in settings {
        if limit.should_stop() {
            return None;
        }
        let report = simulate::first_failure(inst, &seq, &o).ok()?;
        let Some(failed) = report.actions.iter().find(|a| !a.ok) else {
            continue;
        };
        let k = failed.step - 1;
        let mut layout = crate::actions::Layout::new(inst, placement);
        for a in &actions[..k] {
            layout.apply(a);
        }
        let reason = format!(
            "{} {} ({setting}): turned {:?}°, drifted {:?} mm, others moved {:.2} mm",
            failed.kind,
            failed.objects.join(","),
            failed
                .rotation_deg
                .iter()
                .map(|r| (r * 100.0).round() / 100.0)
                .collect::<Vec<_>>(),
            failed
                .drift_mm
                .iter()
                .map(|r| (r * 100.0).round() / 100.0)
                .collect::<Vec<_>>(),
            failed.disturbed_mm
        );
        return Some(Veto::new(&layout, &actions[k], reason));
    }
    None
}

/// One run of the chosen sequencer on `placement`.
fn sequence_one(
    inst: &Instance,
    opts: &PlanOptions,
    placement: &Placement,
    limit: &dyn Terminator,
    listener: &mut dyn Listener,
    vetoes: &[Veto],
) -> Result<SequenceResult> {
    let seq_opts = SequenceOptions {
        no_direct: opts.no_direct,
        no_multi_push: opts.no_multi_push,
        max_nodes: opts.max_nodes,
        vetoes: vetoes.to_vec(),
    };
    // The sequencers' reach checks build their own IK solvers: on the run's threads.
    crate::robot::ik::with_threads(opts.threads, || match opts.sequencer {
        Sequencer::Paper => sequence::paper::solve_with(inst, placement, &seq_opts, limit, listener),
        Sequencer::Astar => sequence::astar::solve_with(inst, placement, &seq_opts, &opts.astar, limit, listener),
    })
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
    let mut plan = build_plan_with(inst, opts, &placement, &sequence, listener);
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

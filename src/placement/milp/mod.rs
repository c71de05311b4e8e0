//! Exact placement: the area stage by enclosing boxes in area order, each decided by an exact
//! packing search ([`super::area`], [`super::opp`]); the contact stage by enumerating the
//! packings of each optimal box, with the HiGHS grid MILP below for what that leaves open
//! (docs/algorithms.md). The per-width depth MILPs described next were the area stage before
//! issue 21; the models remain for the contact stage.
//!
//! The occupied area `W·D` is bilinear, so it is minimised exactly by enumeration of the
//! occupied width. Every placement can be compacted (slid down and left) into a BL-stable one
//! without growing its extents, and in a BL-stable placement every right edge is a sum of
//! footprint widths along a chain from the left wall. So the optimal occupied width `W*` is a
//! subset sum of footprint x-extents (one orientation per object). For each candidate width
//! `W` a MILP minimises the depth `D(W)` with every footprint inside `[0, W] × [0, D]`; the
//! optimum area is `min_W W·D(W)`. `D(W)` is itself a subset sum of y-extents, so every depth
//! bound is rounded up to those sums. Each candidate carries a proven bound `D_lower(W)`
//! (area, largest depth, stacked wide objects; spread to narrower widths because `D` does not
//! grow with `W`, and to transposed widths when placements transpose). Candidates are visited
//! by increasing `W·D_lower(W)`, each visit with the cut `D ≤` one step above that bound and a
//! time cap; a capped candidate keeps its dual bound and is revisited later with a larger cap.
//! The reported `lower_bound` is the least `W·D_lower(W)` over the candidates not solved, and
//! `optimal` is reported only when it meets the area (docs/algorithms.md).
//!
//! A second, lexicographic MILP maximises the contact length among placements inside the
//! optimal extents, with BL-stability as constraints, warm-started with the compacted
//! area-optimal placement.
//!
//! Model (per pair `i < j`): four binaries `left, right, below, above` with sum ≥ 1 and
//! big-M rows with `M = W` (x) or `M = container depth` (y), the tightest constants the box
//! allows; pairs too wide to sit side by side inside `W` get no left/right binaries. Orientation
//! binaries choose among the distinct footprints of each object. Identical objects (same size
//! and allowed footprints) are ordered by `x` (symmetry breaking; valid because any placement can
//! be relabelled so).

use super::area::{self, subset_sums, BoundPoint, Footprint, Footprints};
use super::{is_bl_stable, Placement, PlacementResult, PlacementStatus, Target};
use crate::control::{Listener, Silent, Terminator};
use crate::error::{Error, Result};
use crate::geometry::{Axis2, Rect, EPS};
use crate::instance::Instance;
use crate::placement::opp::Item;
use crate::placement::progress::Progress;
use good_lp::solvers::highs::highs;
use good_lp::{variable, Constraint, Expression, ProblemVariables, SolverModel, Variable};
use highs::HighsModelStatus;
use serde::{Deserialize, Serialize};
use std::time::Instant;

mod benders;
mod contact;
mod grid;
mod model;
mod solve;
mod solver;

use contact::*;
use grid::*;
use model::*;
pub use solve::*;
use solver::*;

/// Tolerance on areas when collecting the extents tied with the optimum.
const AREA_TOL: f64 = 1e-9;

/// How much time the second, lexicographic stage (maximum contact length among the placements
/// of least area) may take. Whatever it is given, a stop leaves the area proven and reports the
/// status `feasible` with the bound; only the contact proof is lost.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactBudget {
    /// What the time limit leaves (the default): the limit the user set governs both stages.
    Rest,
    /// As long as the area stage took, but at least 1 s, so that a contact stage after an area
    /// stage of milliseconds still gets a chance (the rule before 2026-11-25, kept for
    /// comparisons).
    AreaTime,
    /// At most this many seconds (and never past the time limit).
    Seconds(f64),
}

/// The master of the area stage's Benders split (x-coordinates under the cumulative relaxation;
/// the y-phase checks each x-assignment). Both are exact; they differ in speed
/// (docs/benchmarks.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AreaMaster {
    /// The combinatorial x-phase of [`super::opp`] (the default: the faster one, measured).
    Search,
    /// A HiGHS MILP over normal-pattern left edges, with no-good cuts from the y-phase.
    Highs,
}

/// MILP settings.
#[derive(Debug, Clone, PartialEq)]
pub struct MilpSettings {
    /// Wall-clock limit for the whole placement (s).
    pub time_limit: f64,
    /// Run the second stage (maximum contact length with BL-stability constraints).
    pub contact_stage: bool,
    /// HiGHS random seed.
    pub seed: u64,
    /// What decides each enclosing box of the area stage (default [`AreaMaster::Search`]).
    pub area_master: AreaMaster,
    /// How long the contact stage may run (default [`ContactBudget::Rest`]: what the time
    /// limit leaves after the area stage).
    pub contact_budget: ContactBudget,
    /// Largest grid model (cover-row non-zeros) built before the contact stage falls back to
    /// the disjunctive model (default 400,000; how it was chosen: docs/benchmarks/history.md).
    pub grid_max_nnz: usize,
    /// Extra HiGHS options `(name, value)`, set on every HiGHS model of the placement (the
    /// area stage's HiGHS master, the contact MILPs) after pushpack's own, for experiments
    /// (`output_flag = true` shows HiGHS's log). HiGHS parses and checks each value; an
    /// option it rejects, or a run it fails, is [`Error::Solver`]. Names pushpack sets itself
    /// or whose value changes what HiGHS's "optimal" and "infeasible" prove are refused by
    /// [`MilpSettings::check_highs_options`] (see [`FORBIDDEN_HIGHS_OPTIONS`]). Default: none.
    pub highs_options: Vec<(String, String)>,
    /// Threads searching one enclosing box, in the area stage and in the contact stage's
    /// enumeration (default 1). The answer is the same on any number (`opp::decide_metered`,
    /// `opp::best_packing`); more threads only shorten the wall time.
    pub threads: usize,
}

/// HiGHS options [`MilpSettings::highs_options`] may not set: those pushpack sets for its
/// proofs (time limit, gaps, seed, threads, presolve) and those that change what an answer of
/// HiGHS proves (`objective_bound` and `objective_target` turn "nothing better than the bound"
/// into "infeasible"); every `*_tolerance` is refused as well.
pub const FORBIDDEN_HIGHS_OPTIONS: [&str; 8] = [
    "time_limit",
    "mip_rel_gap",
    "mip_abs_gap",
    "random_seed",
    "threads",
    "presolve",
    "objective_bound",
    "objective_target",
];

impl MilpSettings {
    /// Check [`Self::highs_options`] before any solve: a name must be a HiGHS-style identifier
    /// (lower-case letters, digits, `_`) and not one of [`FORBIDDEN_HIGHS_OPTIONS`] or a
    /// tolerance, and a value must hold no NUL byte. Whether HiGHS knows the name and accepts
    /// the value only HiGHS can say: it is asked when a model is built (an
    /// [`Error::Solver`] then). `file` and `field` name the input in the error.
    pub fn check_highs_options(&self, file: &str, field: &str) -> Result<()> {
        for (name, value) in &self.highs_options {
            let bad = |why: String| Err(Error::input(file, field, format!("HiGHS option {name:?}: {why}")));
            if name.is_empty()
                || !name
                    .bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
            {
                return bad("a name is lower-case letters, digits and '_'".into());
            }
            if FORBIDDEN_HIGHS_OPTIONS.contains(&name.as_str()) || name.ends_with("_tolerance") {
                return bad("pushpack sets it itself, or it changes what HiGHS's answers prove".into());
            }
            if value.contains('\0') {
                return bad("the value holds a NUL byte".into());
            }
        }
        Ok(())
    }
}

impl Default for MilpSettings {
    fn default() -> Self {
        MilpSettings {
            time_limit: 60.0,
            contact_stage: true,
            seed: 0,
            contact_budget: ContactBudget::Rest,
            area_master: AreaMaster::Search,
            grid_max_nnz: GRID_MAX_NNZ,
            highs_options: Vec::new(),
            threads: 1,
        }
    }
}

/// Distinct footprints (x-extent, y-extent) of each object with their orientations.
pub fn footprints(inst: &Instance) -> Vec<Footprints> {
    inst.objects
        .iter()
        .map(|o| {
            let mut v: Footprints = Vec::new();
            for q in &o.orientations {
                let (fp, h) = q.dims(o.size);
                if !v
                    .iter()
                    .any(|Footprint { size: f, .. }| (f[0] - fp[0]).abs() <= EPS && (f[1] - fp[1]).abs() <= EPS)
                {
                    v.push(Footprint {
                        size: fp,
                        orientation: *q,
                        height: h,
                    });
                }
            }
            v
        })
        .collect()
}

/// All sums of at most one x-extent per object that fit in `limit`, sorted, deduplicated.
pub fn candidate_widths(fps: &[Footprints], limit: f64) -> Vec<f64> {
    let mut sums = vec![0.0f64];
    for opts in fps {
        let mut next = sums.clone();
        for s in &sums {
            for Footprint { size: f, .. } in opts {
                let v = s + f[0];
                if v <= limit + EPS {
                    next.push(v);
                }
            }
        }
        next.sort_by(f64::total_cmp);
        next.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
        sums = next;
    }
    sums.retain(|&w| w > EPS);
    sums
}

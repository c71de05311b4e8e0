//! The production push check: sticking equilibrium of every moving box as a convex program in
//! clarabel, maximising the stability margin. See `docs/push_stability.md` for the maths.
//!
//! **2-D (LP).** Per contact `j` of a phase, variables `(f_n, f_t, m)` in units of the contact's
//! reference load `R_j`: normal and tangential force and the normal force's moment about the
//! segment's first end (`m = f_n·s`, `s` the centre of pressure along the segment). The set
//! `{|f_t| ≤ μ' f_n, 0 ≤ m ≤ L f_n}` is exactly the set of non-negative combinations of the
//! friction-cone edges `n ± μ' e` at the two end points. Per moving box: force balance (2 rows)
//! and moment balance about its centre of friction (1 row) with the floor friction `μ m g`
//! against `u`. The margin `t` enters as `m ≥ t`, `L f_n − m ≥ t`; maximise `t`.
//!
//! **3-D.** The planar part is the 2-D LP above (no vertical friction, floor normals = weights),
//! and every moving box gets its own tipping SOCP: per contact, forces at the four corners of its
//! patch, each in a second-order friction cone `‖(f_e, f_z)‖ ≤ μ' f_n`; per box the floor normal
//! `N` with its moments `(P, Q)` about the centroid along the body axes, floor friction `μ N`
//! against `u` at the centre of friction, six balance rows; vertical friction only where that
//! box's tipping would produce it (down on the tipping box, up on its neighbour, zero elsewhere);
//! the margin is that box's footprint margin. The phase margin is the smallest of the planar
//! margin and the tipping margins, so 3-D is never more lenient than 2-D and equals it where
//! nothing tips (`docs/push_stability.md` §3). When no forces exist with every centre of pressure
//! inside the real patches (the planar part already fails), a tipping program is re-solved with
//! every patch extended laterally.
//!
//! Solvers are kept per problem structure (dimension, phase size, variant) in a thread-local
//! table and re-used through clarabel's data-update interface (no new symbolic factorisation);
//! equilibration is off, the data are normalised here, so results do not depend on call history.
//! 2-D line margins are also cached by exact geometry (per phase).

use std::cell::RefCell;
use std::collections::HashMap;

mod assemble;
mod check;
mod data;
mod phase;
mod program;

use assemble::*;
pub use check::*;
use data::*;
pub use phase::*;
use program::*;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use serde::Serialize;

use super::model::{cross, dot, Body, Contact, ContactKind, PushModel, V2};
use super::travel::{self, TravelCheck};
use super::{LineGeometry, LineTravel, LineVerdict, CONE_SHRINK, MARGIN_TOL};

/// Options of a check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckOptions {
    /// Friction cones use `μ (1 − cone_shrink)`.
    pub cone_shrink: f64,
    /// Stable iff margin > `tol` (m).
    pub tol: f64,
    /// Largest rotation (rad) over a phase of finite travel judged by its travel.
    pub max_rotation: f64,
    /// Largest lateral drift (m) over such a phase.
    pub max_drift: f64,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            cone_shrink: CONE_SHRINK,
            tol: MARGIN_TOL,
            max_rotation: super::MAX_ROTATION,
            max_drift: super::MAX_DRIFT,
        }
    }
}

/// Planar (LP) or spatial (SOCP with toppling) model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Dim {
    /// 2-D: forces in the floor plane, moments about the vertical.
    #[serde(rename = "2d")]
    D2,
    /// 3-D: patches with height, floor pressure over the footprint, second-order cones.
    #[serde(rename = "3d")]
    D3,
}

/// Outcome of one phase's program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseStatus {
    /// An optimal margin was found.
    Solved,
    /// No contact forces satisfy the friction cones (at any segment shrink).
    Infeasible,
    /// The solver did not converge (treated as unstable).
    SolverFailed,
}

/// Resultant force of one contact in a solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactForce {
    /// Index of the contact in the model.
    pub contact: usize,
    /// Force on the front body (N; x, y, z).
    pub force: [f64; 3],
    /// Normal component (N).
    pub normal: f64,
    /// Tangential components (N): along the segment, vertical.
    pub tangential: [f64; 2],
    /// Centre of pressure (m; x, y, z) — where the line of action crosses the contact.
    pub point: [f64; 3],
    /// Distance of the centre of pressure from the nearer segment end (m; negative = outside).
    pub segment_margin: f64,
    /// Largest `‖tangential‖ / (μ · normal)` over the contact's end points / corners; `None`
    /// for a frictionless contact (`μ = 0`: nothing to use, and no tangential force beyond
    /// solver noise).
    pub friction_use: Option<f64>,
}

/// Floor reaction of one box in a 3-D solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloorForce {
    /// Index of the body.
    pub body: usize,
    /// Normal force (N).
    pub normal: f64,
    /// Friction force magnitude (N), against `u`.
    pub friction: f64,
    /// Centre of pressure in the plane (m).
    pub cop: V2,
    /// Distance of the centre of pressure from the nearest footprint edge (m; negative = tips).
    pub footprint_margin: f64,
}

/// The constraint that limits the margin (or breaks feasibility) of a phase.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Binding {
    /// A contact's line of action at (or beyond) the segment end `end` (0 = `p0`, 1 = `p1`).
    Segment {
        /// Contact index.
        contact: usize,
        /// Which end.
        end: usize,
    },
    /// A box's floor centre of pressure at (or beyond) a footprint edge: along body axis
    /// `axis` (0, 1) on side `side` (+1 / −1).
    Footprint {
        /// Body index.
        body: usize,
        /// Body axis.
        axis: usize,
        /// Side of the footprint.
        side: i8,
    },
    /// No forces exist inside the friction cones; `excess[i]` is the tangential force the contact
    /// would need beyond its (shrunk) cone, relative to its reference load.
    Slip {
        /// Contact index of the largest excess.
        contact: usize,
        /// `(contact, excess)` for every contact that would slip.
        excess: Vec<(usize, f64)>,
    },
}

/// Result of one phase.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseResult {
    /// Front body of the moving group (bodies `start..k` move).
    pub start: usize,
    /// Program outcome.
    pub status: PhaseStatus,
    /// Margin (m); `None` when infeasible or failed.
    pub margin: Option<f64>,
    /// Contact forces (contacts `start..k`) of the optimal solution.
    pub contacts: Vec<ContactForce>,
    /// Floor reactions (3-D only).
    pub floor: Vec<FloorForce>,
    /// What limits the margin.
    pub binding: Option<Binding>,
    /// True when a 3-D tipping margin came from the extended-patch program (the planar part
    /// already failed: some line of action leaves its contact).
    pub extended: bool,
    /// 3-D: margin of the planar part (segments, no vertical friction): the 2-D margin.
    pub planar_margin: Option<f64>,
    /// 3-D: the smallest tipping margin over the moving boxes (each from its own program).
    pub tip_margin: Option<f64>,
    /// Phases of finite travel whose box would turn: how far it turns and drifts over the
    /// travel, and whether that is within the tolerances (then the phase passes).
    pub travel: Option<TravelCheck>,
}

impl PhaseResult {
    /// Whether the phase passes: margin above `tol`, or judged by its travel and within it.
    pub fn passes(&self, tol: f64) -> bool {
        self.margin.is_some_and(|m| m > tol) || self.travel.as_ref().is_some_and(|t| t.passes)
    }
}

/// Result of a whole push (every phase).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckResult {
    /// Model dimension.
    pub dim: Dim,
    /// Smallest margin (m) of the phases not passed by their travel; `None` when some phase
    /// has no equilibrium at all.
    pub margin: Option<f64>,
    /// Every phase passes (margin above the tolerance, or judged by its travel and within it).
    pub stable: bool,
    /// The phase that limits the push: the first that fails, else the smallest margin.
    pub limiting_phase: Option<usize>,
    /// Phases in the order they occur.
    pub phases: Vec<PhaseResult>,
}

impl CheckResult {
    /// The phase that decides the margin (smallest, infeasible first).
    pub fn worst_phase(&self) -> Option<&PhaseResult> {
        self.phases
            .iter()
            .min_by(|a, b| key(a.margin).total_cmp(&key(b.margin)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reused_solvers_give_identical_results() {
        let line = LineGeometry {
            lateral: vec![[0.0, 0.05], [0.01, 0.07], [0.0, 0.06]],
            weight: vec![0.1, 0.3, 0.2],
            pusher: [0.02, 0.04],
        };
        let model = model_of_line(&line, &[true, true]);
        let opts = CheckOptions::default();
        set_solver_reuse(false);
        let fresh: Vec<_> = [Dim::D2, Dim::D3].iter().map(|&d| margin(&model, d, &opts)).collect();
        set_solver_reuse(true);
        let _ = margin(
            &model_of_line(
                &LineGeometry {
                    pusher: [0.0, 0.01],
                    ..line.clone()
                },
                &[false, true],
            ),
            Dim::D2,
            &opts,
        );
        let reused: Vec<_> = [Dim::D2, Dim::D3].iter().map(|&d| margin(&model, d, &opts)).collect();
        assert_eq!(fresh, reused);
    }
}

//! Stage 3: choose the packing actions and their order.
//!
//! Output is a [`SequenceResult`]: the actions in execution order, each push's stability margin,
//! the plan metrics and the search statistics. Sequencers: [`paper`] (the paper's Algorithm 1
//! assignment enumeration + Algorithm 2 depth-first branch-and-bound on travel).

pub mod astar;
pub mod paper;

use crate::actions::{Action, Layout, PlaceMode};
use crate::instance::Instance;
use crate::motion::keypoints::total_travel;
use crate::placement::Placement;
use serde::{Deserialize, Serialize};

/// How a sequence search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchStatus {
    /// The whole candidate space of the sequencer was searched: its best plan is returned.
    Complete,
    /// The node limit stopped the search; the best plan found is returned.
    NodeLimit,
    /// The time limit stopped the search; the best plan found is returned.
    TimeLimit,
}

impl SearchStatus {
    /// The error of a search that stopped with this status before it had any plan, with the
    /// fewest actions it proved every plan needs, if it proved any.
    pub(crate) fn no_plan(
        self,
        stage: &str,
        nodes: u64,
        elapsed_s: f64,
        min_actions: Option<usize>,
    ) -> crate::error::Error {
        crate::error::Error::Stopped {
            stage: stage.into(),
            limit: match self {
                SearchStatus::NodeLimit => crate::status::Limit::Nodes,
                _ => crate::status::Limit::Time,
            },
            nodes,
            elapsed_s,
            min_actions,
        }
    }
}

/// Options shared by every sequencer.
#[derive(Debug, Clone, PartialEq)]
pub struct SequenceOptions {
    /// Forbid direct placing (ablation).
    pub no_direct: bool,
    /// Forbid multi-object pushes (ablation).
    pub no_multi_push: bool,
    /// Node limit.
    pub max_nodes: u64,
    /// Actions a physics replay rejected, each in its neighbourhood (`actions::veto`): the
    /// sequencers treat them as infeasible there. Empty by default.
    pub vetoes: Vec<crate::actions::veto::Veto>,
}

impl Default for SequenceOptions {
    fn default() -> Self {
        SequenceOptions {
            no_direct: false,
            no_multi_push: false,
            max_nodes: 2_000_000,
            vetoes: Vec::new(),
        }
    }
}

impl SequenceOptions {
    /// [`Self::vetoes`] in the form a [`Layout`] holds them (`None` when there are none).
    pub fn layout_vetoes(&self) -> Option<std::sync::Arc<[crate::actions::veto::Veto]>> {
        (!self.vetoes.is_empty()).then(|| self.vetoes.clone().into())
    }
}

/// Plan metrics (SPEC §5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Number of actions.
    pub seq_len: usize,
    /// Direct placements.
    pub n_place_direct: usize,
    /// Indirect placements.
    pub n_place_indirect: usize,
    /// Pushes (single and multi-object).
    pub n_push: usize,
    /// Pushes of two or more objects.
    pub n_multi_push: usize,
    /// Area of the bounding rectangle from C's origin of every footprint at every moment (m²).
    pub swept_area: f64,
    /// TCP path length of both arms from home back to home (m).
    pub travel: f64,
}

/// Swept area of a set of actions: every target and every release footprint.
pub fn swept_area(inst: &Instance, placement: &Placement, actions: &[Action]) -> f64 {
    let layout = Layout::new(inst, placement);
    let (mut mx, mut my) = placement.extent();
    for a in actions {
        if let Action::Place { object, mode, .. } = a {
            let r = layout.release_rect(*object, mode);
            mx = mx.max(r.x1);
            my = my.max(r.y1);
        }
    }
    mx * my
}

/// Compute the metrics of an ordered action list.
pub fn metrics(inst: &Instance, placement: &Placement, actions: &[Action]) -> Metrics {
    let mut m = Metrics {
        seq_len: actions.len(),
        n_place_direct: 0,
        n_place_indirect: 0,
        n_push: 0,
        n_multi_push: 0,
        swept_area: swept_area(inst, placement, actions),
        travel: total_travel(inst, placement, actions),
    };
    for a in actions {
        match a {
            Action::Place {
                mode: PlaceMode::Direct,
                ..
            } => m.n_place_direct += 1,
            Action::Place { .. } => m.n_place_indirect += 1,
            Action::Push { objects, .. } => {
                m.n_push += 1;
                if objects.len() > 1 {
                    m.n_multi_push += 1;
                }
            }
        }
    }
    m
}

/// A sequenced plan with its statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct SequenceResult {
    /// Actions in execution order.
    pub actions: Vec<Action>,
    /// Stability margin of each push (None for places), aligned with `actions`.
    pub margins: Vec<Option<f64>>,
    /// Metrics.
    pub metrics: Metrics,
    /// How the search ended.
    pub status: SearchStatus,
    /// Search nodes expanded.
    pub nodes: u64,
    /// Assignments (direct/indirect/direction choices) evaluated.
    pub assignments: u64,
    /// Wall-clock seconds.
    pub time_s: f64,
    /// Proven lower bound on each component of the optimal cost (A*), hence also a
    /// lexicographic one; equal to the plan's cost when optimal.
    pub bound: Option<astar::Cost>,
}

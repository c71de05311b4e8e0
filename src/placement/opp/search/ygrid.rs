//! The y-phase's grid: the box's depth and the items' depths in grid steps for the current
//! x-assignment, and each column's base at the current y-node, which the gapless-stacks bounds
//! (`search/stacks.rs`) read.

use super::*;

/// The grid of one complete x-assignment, and the columns' state at the current y-node.
#[derive(Default)]
pub(in crate::placement::opp) struct YGrid {
    /// The grid step of the depths, when the box's depth is at most 63 steps of it (so that the
    /// subset sums fit one word); `None`: the stacks bounds are off for this x-assignment.
    step: Option<f64>,
    /// The box's depth in steps, and each item's depth in its footprint of this x-assignment.
    depth: u32,
    steps: Vec<u32>,
    /// Per column at the current y-node (kept by the wells loop): its base (the highest placed
    /// top, at least the sweep height) and whether it is a well.
    pub(super) at: Vec<(f64, bool)>,
}

impl YGrid {
    /// Whether the grid is on for the current x-assignment.
    pub(super) fn on(&self) -> bool {
        self.step.is_some()
    }

    /// The grid step and the box's depth in steps, when the grid is on for this x-assignment.
    pub(super) fn step_depth(&self) -> Option<(f64, u32)> {
        self.step.map(|g| (g, self.depth))
    }

    /// Each item's depth in grid steps (for this x-assignment, when the grid is on).
    pub(super) fn steps(&self) -> &[u32] {
        &self.steps
    }
}

impl Search<'_> {
    /// Set the grid up for the current x-assignment (after `ycols`): on when the depths share
    /// a grid of at most 63 steps across the box and the columns fit a 128-bit set (they do for
    /// up to 64 items).
    pub(super) fn prepare_grid(&mut self) {
        let h = &mut self.ygrid;
        h.step = None;
        let Some(g) = self.grid.as_ref().map(|g| g.step()) else {
            return;
        };
        let depth = (self.d / g + 1e-6).floor();
        if depth > 63.0 || self.ycols.len() > 128 {
            return;
        }
        let n = self.items.len();
        h.depth = depth as u32;
        h.steps.clear();
        h.steps.extend((0..n).map(|i| (self.ydims[i][1] / g).round() as u32));
        h.step = Some(g);
    }
}

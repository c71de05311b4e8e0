//! What the unplaced items' sides can still add to the contact bound within the area the box
//! has left: one footprint each, their areas within that area — the linear relaxation of this
//! multiple-choice knapsack, over each item's upper hull of (area, width + depth).
//!
//! Why it is exact (docs/algorithms.md, *Sides within the free area*): the x-phase's bound
//! counts an unplaced item at the most width + depth among its footprints. In any completion,
//! the unplaced items' footprints fit in the box's area less what is placed and what is already
//! wasted, so their sides sum to at most the least-area footprints' sides plus the best gain
//! that area buys, and the linear relaxation (greedy along the hulls, steepest step first)
//! bounds that gain from above.

use super::*;

/// One step up an item's hull: from one footprint to the next, the extra area and sides.
#[derive(Debug, Clone, Copy)]
struct Step {
    item: usize,
    area: f64,
    sides: f64,
}

/// Every item's hull steps, steepest first (an item's own steps come in their order).
#[derive(Debug, Default)]
pub(in crate::placement::opp) struct Sides {
    steps: Vec<Step>,
}

impl Sides {
    /// The steps of `items` in `w × d` (their fitting footprints), `t` the tolerance.
    pub(super) fn new(items: &[Item], w: f64, d: f64, t: f64) -> Sides {
        let mut steps = Vec::new();
        for (i, it) in items.iter().enumerate() {
            let pts: Vec<(f64, f64)> = fitting(it, w, d).map(|f| (f[0] * f[1], f[0] + f[1])).collect();
            let Some(least) = pts.iter().map(|p| p.0).min_by(f64::total_cmp) else {
                continue;
            };
            let tol = t * (w + d);
            // From the least area (its most sides), on to the point of steepest gain, until
            // no point has more sides.
            let mut at = (
                least,
                (pts.iter().filter(|p| p.0 <= least + tol).map(|p| p.1)).fold(0.0, f64::max),
            );
            loop {
                let next = (pts.iter())
                    .filter(|p| p.0 > at.0 + tol && p.1 > at.1 + t)
                    .max_by(|a, b| ((a.1 - at.1) / (a.0 - at.0)).total_cmp(&((b.1 - at.1) / (b.0 - at.0))));
                let Some(&p) = next else { break };
                steps.push(Step {
                    item: i,
                    area: p.0 - at.0,
                    sides: p.1 - at.1,
                });
                at = p;
            }
        }
        // Stable: an item's steps, ever less steep, keep their order.
        steps.sort_by(|a, b| (b.sides / b.area).total_cmp(&(a.sides / a.area)));
        Sides { steps }
    }

    /// Whether any item has footprints of different areas and sides (else nothing to bound).
    pub(super) fn any(&self) -> bool {
        !self.steps.is_empty()
    }
}

impl Search<'_> {
    /// Sides the bound counts for the unplaced items that no completion can have: with `free`
    /// area left for their footprints beyond their least areas, the steps up their hulls that
    /// do not fit, steepest first (the last one in part).
    pub(super) fn sides_unreachable(&self, free: f64) -> f64 {
        let mut free = free + self.t * (self.w + self.d);
        let mut lost = 0.0;
        for s in self.sides.steps.iter().filter(|s| !self.placed[s.item]) {
            if free >= s.area {
                free -= s.area;
            } else {
                lost += s.sides * (1.0 - free.max(0.0) / s.area);
                free = 0.0;
            }
        }
        lost
    }
}

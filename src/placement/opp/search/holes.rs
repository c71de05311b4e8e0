//! The y-phase's holes bound: an unplaced item whose columns cannot all be filled exactly up
//! to any height it may take leaves free space under some bottom, contact no other bound counts.
//!
//! Why it is exact (docs/algorithms.md, *Holes under the y-phase's items*): at a y-node, every
//! unplaced item `i` will rest at a height `h` between max(its floor, the sweep height) and
//! `d` less its depth. In a column `c` it covers (between consecutive item edges) that is not
//! a well, the items placed in `c` from now on lie above its base (the highest placed top
//! there, at least the sweep height), so those below `i` fill `[base, h)` exactly only if `h`
//! is the base plus a subset sum of the depths of the other unplaced items covering `c`.
//! When no `h` passes that test in every such column at once, some column `c` of `i` has free
//! space in `[base, h)`, and the item just above that free space (`i` or one below it) loses
//! bottom contact over the whole width of `c`; a column without room (its unplaced items fill
//! it to `d`) cannot hold free space, so when no column of `i` has room no packing completes
//! the node. The wells count well columns only, and `ydef` the bottoms already placed, so these
//! losses are new; items whose column sets are disjoint lose in different columns, so their
//! least widths add up.

use super::*;

/// The holes bound's data for one complete x-assignment, and its scratch.
#[derive(Default)]
pub(in crate::placement::opp) struct Holes {
    /// The grid step of the depths, when the box's depth is at most 63 steps of it (so that the
    /// subset sums fit one word); `None`: the bound is off for this x-assignment.
    step: Option<f64>,
    /// The box's depth in steps, and each item's depth in its footprint of this x-assignment.
    depth: u32,
    steps: Vec<u32>,
    /// Per item, the columns (indices into `ycols`) it covers.
    cols_of: Vec<Vec<usize>>,
    /// Per column at the current y-node (kept by the wells loop): its base, whether it is a
    /// well, and whether it has room (free depth left once every unplaced item covering it is
    /// stacked on the base).
    pub(super) at: Vec<(f64, bool, bool)>,
    /// The items that must leave a hole: the least width of their non-well columns with room
    /// (the hole is in one of them), and those columns as a bit set.
    fails: Vec<(f64, u128)>,
}

impl Holes {
    /// Whether the grid is on for the current x-assignment (the holes bound runs when it is
    /// and the bound is enabled; the grid serves [`super::stacks`] too).
    pub(super) fn on(&self) -> bool {
        self.step.is_some()
    }

    /// The box's depth in grid steps, when the grid is on for this x-assignment.
    pub(super) fn grid_depth(&self) -> Option<u32> {
        self.step.map(|_| self.depth)
    }

    /// Each item's depth in grid steps (for this x-assignment, when the grid is on).
    pub(super) fn steps(&self) -> &[u32] {
        &self.steps
    }
}

impl Search<'_> {
    /// Set the holes bound's grid up for the current x-assignment (after `ycols`): on when the
    /// depths share a grid of at most 63 steps across the box and the columns fit a 128-bit set
    /// (they do for up to 64 items).
    pub(super) fn prepare_holes(&mut self) {
        let h = &mut self.yholes;
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
        h.cols_of.resize(n, Vec::new());
        h.cols_of.iter_mut().for_each(Vec::clear);
        for (c, (_, cover)) in self.ycols.iter().enumerate() {
            for &j in cover {
                h.cols_of[j].push(c);
            }
        }
        h.step = Some(g);
    }

    /// Bottom contact that holes will take at this y-node beyond the wells (`holes.at` filled
    /// for it; the floors are row `row` of `yfloor`): `None` when no packing completes the node.
    pub(super) fn holes_lost(&mut self, done: &[bool], row: usize, last_y: f64) -> Option<f64> {
        let h = &mut self.yholes;
        let g = h.step?;
        let n = self.items.len();
        let floors = &self.yfloor[row..row + n];
        // Lengths here are non-negative sums of grid steps: adding a half and truncating
        // rounds them in one instruction (`round` is a library call on baseline x86-64, 3 % of
        // a random twenty-object contact stage in `perf`).
        let steps = |v: f64| (v / g + 0.5) as i64;
        h.fails.clear();
        for i in (0..n).filter(|&i| !done[i]) {
            let lo = steps(floors[i].max(last_y));
            let hi = h.depth as i64 - h.steps[i] as i64;
            if lo > hi {
                return None;
            }
            // Bits lo..=hi: the heights the item may take (0 ≤ lo ≤ hi ≤ 63).
            let mut heights = (u64::MAX >> (63 - hi)) & (u64::MAX << lo);
            let (mut cols, mut width) = (0u128, f64::INFINITY);
            for &c in &h.cols_of[i] {
                let (base, well, room) = h.at[c];
                if well {
                    continue;
                }
                let mut sums = 1u64;
                for &j in &self.ycols[c].1 {
                    if !done[j] && j != i {
                        sums |= sums << h.steps[j];
                    }
                }
                heights &= sums << steps(base);
                if room {
                    cols |= 1 << c;
                    width = width.min(self.ycols[c].0);
                }
            }
            if heights == 0 {
                if width == f64::INFINITY {
                    return None;
                }
                h.fails.push((width, cols));
            }
        }
        // Items with disjoint columns lose in different columns; widest first, greedily.
        h.fails.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
        let (mut used, mut lost) = (0u128, 0.0);
        for &(width, cols) in &h.fails {
            if cols & used == 0 {
                used |= cols;
                lost += width;
            }
        }
        Some(lost)
    }
}

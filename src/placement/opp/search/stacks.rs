//! The y-phase's gapless-stacks bounds: when the columns of a complete x-assignment cannot all
//! stack without a gap, every packing loses bottom contact over the columns that keep one, and
//! the narrowest such sets of columns bound that loss; at the root from the floor up, at a
//! y-node from each column's placed top up.
//!
//! Why it is exact (docs/algorithms.md, *Gapless stacks*): in a column `c` (between consecutive
//! item edges) with no gap, the items covering `c` fill `[0, S_c)` exactly, `S_c` the sum of
//! their depths. So an item `i` of `c` rests at a height reached from the floor by a chain of
//! the column's items, each at a height it may take, and from its top a chain of them reaches
//! `S_c`. Heights that no such chains reach are struck from every item's set of heights,
//! column by column, until nothing changes; an empty set proves that some column keeps a gap.
//! A gap in `c` leaves the bottom of the item above it free over the whole width of `c`, so a
//! packing whose gaps lie in the columns `G` loses at least their widths, and it stacks without
//! gaps in the other columns: the propagation with the columns of `G` left out passes. When it
//! fails for every set of columns narrower than the margin, every packing loses the margin.
//! The chains may use any item of the column any number of times, `i` itself included, and
//! ignore the other columns' order, which only lets more heights pass (and costs one closure
//! per column instead of one per item: 3–4 % fewer instructions on n20_k4_s0004 and s0017).
//!
//! At a y-node (*Gapless stacks above a y-node*): the placed items are fixed, and in a column
//! that is not a well the unplaced items covering it stack from its placed top `b_c` with no
//! new gap only if they fill `[b_c, b_c + S_c)` exactly, each at a height between its floor
//! (and the sweep height) and the box's depth less its own. A new gap there lies under an
//! unplaced item, so its width is lost beyond the bottoms already placed (`ydef`) and the
//! wells (other columns).

use super::*;

/// Most propagations the search for gap columns may spend on one x-assignment's root; past
/// it, the bound gives up and cuts nothing.
const CALLS: u32 = 64;

/// The same at a y-node below the root, where it may run at every node: 64 cut as much on
/// n20_k4_s0004, s0005 and s0017, and 1.7 % more nodes on squares 1…18, but cost 5 % more
/// instructions there (valgrind, one thread).
const NODE_CALLS: u32 = 16;

/// Scratch of the gapless-stacks bounds.
#[derive(Default)]
pub(in crate::placement::opp) struct Stacks {
    /// Per item, the heights (bit `h`: `h` grid steps) it may take before propagation, and
    /// those it may still take.
    init: Vec<u64>,
    heights: Vec<u64>,
    /// Per column, the height its items stack from and the height they stack to, in steps.
    bases: Vec<u32>,
    sums: Vec<u32>,
    /// The columns with room for a gap (their items stack to less than the box's depth),
    /// narrowest first.
    room: Vec<usize>,
    /// Propagations the search for gap columns may still spend.
    calls: u32,
    /// A y-node's columns (width, the unplaced items covering it), reused between nodes.
    node_cols: Vec<(f64, Vec<usize>)>,
}

/// Columns as (width, the items covering it), at most 128 of them.
type Columns = [(f64, Vec<usize>)];

impl Stacks {
    /// The least width, capped at `below`, of the columns of `cols` under whose bottoms every
    /// packing keeps gaps, the items `steps` deep (grid steps) in a box `depth` steps deep (at
    /// most 63), stacking from the floor: 0 when the search for such columns runs past
    /// [`CALLS`].
    pub(super) fn least_gaps(&mut self, cols: &Columns, steps: &[u32], depth: u32, below: f64) -> f64 {
        debug_assert!(depth <= 63 && cols.len() <= 128);
        self.init.clear();
        for &s in steps {
            if s > depth {
                // No height at all: no packing holds the item, which other checks see.
                return 0.0;
            }
            // Bits 0 ..= depth − s.
            self.init.push(u64::MAX >> (63 - (depth - s)));
        }
        self.bases.clear();
        self.bases.resize(cols.len(), 0);
        self.least_from(cols, steps, depth, below, CALLS)
    }

    /// [`Self::least_gaps`] once `bases` (per column of `cols`) and `init` (per item) are set,
    /// with at most `calls` propagations.
    fn least_from(&mut self, cols: &Columns, steps: &[u32], depth: u32, below: f64, calls: u32) -> f64 {
        self.sums.clear();
        self.room.clear();
        for (c, (_, cover)) in cols.iter().enumerate() {
            let sum: u32 = self.bases[c] + cover.iter().map(|&j| steps[j]).sum::<u32>();
            self.sums.push(sum);
            if sum < depth {
                self.room.push(c);
            }
        }
        self.room.sort_by(|&a, &b| cols[a].0.total_cmp(&cols[b].0));
        if self.pass(cols, steps, depth, 0) {
            return 0.0;
        }
        self.calls = calls.saturating_sub(1);
        let mut best = below;
        if self.gaps_least(cols, steps, depth, (0, 0, 0.0), &mut best) {
            best
        } else {
            0.0
        }
    }

    /// The least width, below `best`, of a set of columns with room, from `room[from]` on,
    /// which added to `skip` (`width` so far) lets the other columns stack without a gap, into
    /// `best`; `false` once its propagations run out (the search gives up).
    fn gaps_least(
        &mut self,
        cols: &Columns,
        steps: &[u32],
        depth: u32,
        (from, skip, width): (usize, u128, f64),
        best: &mut f64,
    ) -> bool {
        for k in from..self.room.len() {
            let c = self.room[k];
            let w = width + cols[c].0;
            // Narrowest first: no later column is narrower.
            if w >= *best {
                break;
            }
            if self.calls == 0 {
                return false;
            }
            self.calls -= 1;
            let s = skip | 1 << c;
            // A set that passes is the narrowest with this prefix: those it is in are wider.
            if self.pass(cols, steps, depth, s) {
                *best = w;
            } else if !self.gaps_least(cols, steps, depth, (k + 1, s, w), best) {
                return false;
            }
        }
        true
    }

    /// Whether the propagation over the columns not in `skip` leaves every item a height.
    fn pass(&mut self, cols: &Columns, steps: &[u32], depth: u32, skip: u128) -> bool {
        self.heights.clone_from(&self.init);
        let hs = &mut self.heights;
        loop {
            let mut changed = false;
            for (c, (_, cover)) in cols.iter().enumerate() {
                if skip >> c & 1 == 1 {
                    continue;
                }
                let sum = self.sums[c];
                if sum > depth {
                    return false;
                }
                // Heights the column's items reach from its base, and those from which they
                // reach its top, by chains at heights each may take.
                let mut up = 1u64 << self.bases[c];
                loop {
                    let next = cover.iter().fold(up, |acc, &j| acc | (acc & hs[j]) << steps[j]);
                    if next == up {
                        break;
                    }
                    up = next;
                }
                let mut down = 1u64 << sum;
                loop {
                    let next = cover.iter().fold(down, |acc, &j| acc | (acc >> steps[j]) & hs[j]);
                    if next == down {
                        break;
                    }
                    down = next;
                }
                for &i in cover {
                    let new = hs[i] & up & (down >> steps[i]);
                    if new != hs[i] {
                        if new == 0 {
                            return false;
                        }
                        hs[i] = new;
                        changed = true;
                    }
                }
            }
            if !changed {
                return true;
            }
        }
    }
}

impl Search<'_> {
    /// The least width, capped at `below`, of the columns under whose bottoms every packing of
    /// the current x-assignment keeps gaps ([`Stacks::least_gaps`] on `ycols`); 0 when the grid
    /// is off.
    pub(super) fn least_gaps(&mut self, below: f64) -> f64 {
        let Some((_, depth)) = self.ygrid.step_depth() else {
            return 0.0;
        };
        self.stacks.least_gaps(&self.ycols, self.ygrid.steps(), depth, below)
    }

    /// The least width, capped at `below`, of the columns (not wells) under whose bottoms every
    /// completion of this y-node keeps new gaps: the unplaced items of each column stacking
    /// from its base (`ygrid.at`, filled by the wells loop), each at its floor (row `row` of
    /// `yfloor`) and `ylo` or higher. `below` when some item has no height left; 0 when the
    /// grid is off or the search gives up.
    pub(super) fn least_gaps_above(&mut self, done: &[bool], row: usize, ylo: f64, below: f64) -> f64 {
        let Some((g, depth)) = self.ygrid.step_depth() else {
            return 0.0;
        };
        // Non-negative lengths on the grid: adding a half and truncating rounds them in one
        // instruction (`round` is a library call on baseline x86-64).
        let steps = |v: f64| (v / g + 0.5) as i64;
        let n = self.items.len();
        let st = &mut self.stacks;
        let item_steps = self.ygrid.steps();
        st.init.clear();
        for i in 0..n {
            if done[i] {
                st.init.push(0);
                continue;
            }
            let lo = steps(self.yfloor[row + i].max(ylo));
            let hi = depth as i64 - item_steps[i] as i64;
            if lo > hi {
                return below;
            }
            // Bits lo ..= hi (0 ≤ lo ≤ hi ≤ 63).
            st.init.push((u64::MAX >> (63 - hi)) & (u64::MAX << lo));
        }
        let mut cols = std::mem::take(&mut st.node_cols);
        st.bases.clear();
        let mut used = 0;
        for ((width, cover), &(base, well)) in self.ycols.iter().zip(&self.ygrid.at) {
            if well || cover.iter().all(|&j| done[j]) {
                continue;
            }
            if used == cols.len() {
                cols.push((0.0, Vec::new()));
            }
            let (w, unplaced) = &mut cols[used];
            *w = *width;
            unplaced.clear();
            unplaced.extend(cover.iter().copied().filter(|&j| !done[j]));
            st.bases.push(steps(base) as u32);
            used += 1;
        }
        let found = st.least_from(&cols[..used], item_steps, depth, below, NODE_CALLS);
        st.node_cols = cols;
        found
    }
}

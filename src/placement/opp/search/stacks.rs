//! The y-phase's gapless-stacks bound: when the columns of a complete x-assignment cannot all
//! stack from the floor without a gap, every packing loses bottom contact over the columns that
//! keep one, and the narrowest such sets of columns bound that loss.
//!
//! Why it is exact (docs/algorithms.md, *Gapless stacks*): in a column `c` (between consecutive
//! item edges) with no gap, the items covering `c` fill `[0, S_c)` exactly, `S_c` the sum of
//! their depths. So an item `i` of `c` rests at a height reached from the floor by a chain of
//! the others, each at a height it may take, and the rest of them stack from `i`'s top up to
//! `S_c`. Heights that no such chains reach are struck from every item's set of heights,
//! column by column, until nothing changes; an empty set proves that some column keeps a gap.
//! A gap in `c` leaves the bottom of the item above it free over the whole width of `c`, so a
//! packing whose gaps lie in the columns `G` loses at least their widths, and it stacks without
//! gaps in the other columns: the propagation with the columns of `G` left out passes. When it
//! fails for every set of columns narrower than the margin, every packing loses the margin.
//! The chains may use an item twice and ignore the other columns' order, which only lets more
//! heights pass.

use super::*;

/// Most propagations the search for gap columns may spend on one x-assignment; past it, the
/// bound gives up and cuts nothing.
const CALLS: u32 = 64;

/// Scratch of the gapless-stacks bound.
#[derive(Default)]
pub(in crate::placement::opp) struct Stacks {
    /// Per item, the heights (bit `h`: `h` grid steps) it may still take.
    heights: Vec<u64>,
    /// Per column, the depth of the items covering it, in steps.
    sums: Vec<u32>,
    /// The columns with room for a gap (their items stack to less than the box's depth),
    /// narrowest first.
    room: Vec<usize>,
}

/// Columns as (width, the items covering it), at most 128 of them.
type Columns = [(f64, Vec<usize>)];

impl Stacks {
    /// The least width, capped at `below`, of the columns of `cols` under whose bottoms every
    /// packing keeps gaps, the items `steps` deep (grid steps) in a box `depth` steps deep (at
    /// most 63): 0 when the search for such columns runs past [`CALLS`].
    pub(super) fn least_gaps(&mut self, cols: &Columns, steps: &[u32], depth: u32, below: f64) -> f64 {
        debug_assert!(depth <= 63 && cols.len() <= 128);
        self.sums.clear();
        self.room.clear();
        for (c, (_, cover)) in cols.iter().enumerate() {
            let sum: u32 = cover.iter().map(|&j| steps[j]).sum();
            self.sums.push(sum);
            if sum < depth {
                self.room.push(c);
            }
        }
        self.room.sort_by(|&a, &b| cols[a].0.total_cmp(&cols[b].0));
        if self.pass(cols, steps, depth, 0) {
            return 0.0;
        }
        let (mut calls, mut best) = (1, below);
        if self.gaps_least(cols, steps, depth, (0, 0, 0.0), &mut best, &mut calls) {
            best
        } else {
            0.0
        }
    }

    /// The least width, below `best`, of a set of columns with room, from `room[from]` on,
    /// which added to `skip` (`width` so far) lets the other columns stack without a gap, into
    /// `best`; `false` once `calls` passes [`CALLS`] (the search gives up).
    fn gaps_least(
        &mut self,
        cols: &Columns,
        steps: &[u32],
        depth: u32,
        (from, skip, width): (usize, u128, f64),
        best: &mut f64,
        calls: &mut u32,
    ) -> bool {
        for k in from..self.room.len() {
            let c = self.room[k];
            let w = width + cols[c].0;
            // Narrowest first: no later column is narrower.
            if w >= *best {
                break;
            }
            *calls += 1;
            if *calls > CALLS {
                return false;
            }
            let s = skip | 1 << c;
            // A set that passes is the narrowest with this prefix: those it is in are wider.
            if self.pass(cols, steps, depth, s) {
                *best = w;
            } else if !self.gaps_least(cols, steps, depth, (k + 1, s, w), best, calls) {
                return false;
            }
        }
        true
    }

    /// Whether the propagation over the columns not in `skip` leaves every item a height.
    fn pass(&mut self, cols: &Columns, steps: &[u32], depth: u32, skip: u128) -> bool {
        self.heights.clear();
        for &s in steps {
            if s > depth {
                return false;
            }
            // Bits 0 ..= depth − s.
            self.heights.push(u64::MAX >> (63 - (depth - s)));
        }
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
                for &i in cover {
                    // Heights the others reach from the floor, and those from which they reach
                    // the column's top, by chains at heights each may take.
                    let mut up = 1u64;
                    loop {
                        let mut next = up;
                        for &j in cover.iter().filter(|&&j| j != i) {
                            next |= (next & hs[j]) << steps[j];
                        }
                        if next == up {
                            break;
                        }
                        up = next;
                    }
                    let mut down = 1u64 << sum;
                    loop {
                        let mut next = down;
                        for &j in cover.iter().filter(|&&j| j != i) {
                            next |= (next >> steps[j]) & hs[j];
                        }
                        if next == down {
                            break;
                        }
                        down = next;
                    }
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
    /// the current x-assignment keeps gaps ([`Stacks::least_gaps`] on `ycols`); 0 when the holes
    /// bound's grid is off.
    pub(super) fn least_gaps(&mut self, below: f64) -> f64 {
        let Some(depth) = self.yholes.grid_depth() else {
            return 0.0;
        };
        self.stacks.least_gaps(&self.ycols, self.yholes.steps(), depth, below)
    }
}

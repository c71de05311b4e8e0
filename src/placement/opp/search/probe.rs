//! The enumeration's probes: is an x-phase state dead even without its smallest items?
//!
//! Why it stays exact (docs/algorithms.md, *Probes without the smallest items*): the x-phase
//! asks of a state whether the items still to place can take x-coordinates from the position
//! `t` on under the open objects' profile, each column holding at most the box's depth (the
//! bar relaxation), and only when some can does a packing follow. A subset of those items can
//! whenever all can. Shifting each item left while the columns allow, a schedule of the subset
//! ends with every item starting at `t` or at another's right edge (an item that cannot move
//! left has a column just left of it fuller than at its left edge, so some item ends there):
//! the x-phase's own enumeration without the left-out items meets it. So when that enumeration
//! (a *probe*) reaches no complete x-assignment of the subset, the state has no packing.
//! Inside a probe only what holds for the subset may cut: its own dead states, never the
//! search's (those may need the left-out items to be dead), and no contact bound; what a
//! probe finds dead is dead for the search too.

use super::*;

/// Most nodes one probe may visit before it gives up (then it refutes nothing): on squares
/// 1…18 and 1…19 a limit of 10⁶ visited the same nodes as none (10⁵ did not on 1…19), so it
/// only bounds a pathological case.
const PROBE_NODES: u64 = 1 << 20;

/// The items the enumeration's probes leave out: the three smallest (least fitting area), each
/// of a class of its own (identical items go in index order, which leaving one out would
/// break), from eight items on; 0 (no probes) otherwise.
pub(in crate::placement::opp) fn left_out(items: &[Item], w: f64, d: f64) -> u64 {
    let n = items.len();
    if !(8..=64).contains(&n) {
        return 0;
    }
    let area = |i: usize| {
        fitting(&items[i], w, d)
            .map(|g| g[0] * g[1])
            .fold(f64::INFINITY, f64::min)
    };
    let alone = |i: usize| items.iter().filter(|it| it.class == items[i].class).count() == 1;
    let mut by_area: Vec<usize> = (0..n).collect();
    by_area.sort_by(|&a, &b| area(a).total_cmp(&area(b)));
    let small = &by_area[..3];
    if !small.iter().all(|&i| alone(i) && area(i).is_finite()) {
        return 0;
    }
    small.iter().map(|&i| 1u64 << i).sum()
}

impl Search<'_> {
    /// Leave `mask`'s items out of the probes (0: no probes; tests compare both).
    pub(in crate::placement::opp) fn set_probe(&mut self, mask: u64) {
        self.probe_items = mask;
        self.probe_rank_bits = (0..self.items.len())
            .filter(|&i| mask >> i & 1 == 1)
            .map(|i| 1u64 << self.depth_rank[i])
            .sum();
    }

    /// Whether the x-phase state `key` at `t` (the arguments of [`Search::xphase`]) has no
    /// complete x-assignment even without the probe's items still unplaced: the x-phase's
    /// branches below it, searched without them, reach none within [`PROBE_NODES`] nodes. Not
    /// asked where a probe is known to reach one ([`Search::known_alive`]); one that does is
    /// recorded so.
    pub(super) fn probe_refutes(
        &mut self,
        key: &[(i32, i32)],
        t: f64,
        min_idx: usize,
        placed_area: f64,
        rem_area: f64,
        waste: f64,
    ) -> bool {
        let n = self.items.len();
        let unplaced = (self.probe_items & !self.placed_mask).count_ones() as usize;
        // Nothing to probe, or only the left-out items still to place: the subset is complete.
        if self.probing || unplaced == 0 || self.xends.len() + unplaced == n {
            return false;
        }
        if self.known_alive(key) {
            self.probes_skipped += 1;
            return false;
        }
        let left_out: f64 = (0..n)
            .filter(|&i| self.probe_items >> i & 1 == 1 && !self.placed[i])
            .map(|i| self.min_area[i])
            .sum();
        self.probing = true;
        self.probe_until = self.nodes + PROBE_NODES;
        let alive = self.xbranch(t, min_idx, placed_area, rem_area - left_out, waste);
        self.probing = false;
        // Giving up stopped the probe, not the search (whose stop is asked again at its next poll).
        if std::mem::replace(&mut self.probe_gave_up, false) {
            self.stopped = false;
            return false;
        }
        if self.stopped {
            return false;
        }
        if alive {
            self.record_alive(key);
        }
        self.probe_cuts += !alive as u64;
        !alive
    }

    /// Whether item `i` is left out of the probe now running.
    #[inline(always)]
    pub(super) fn left_out_now(&self, i: usize) -> bool {
        self.probing && self.probe_items >> i & 1 == 1
    }
}

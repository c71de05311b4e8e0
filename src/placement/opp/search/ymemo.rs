//! The y-phase's memo: y-states reached again through another order of the items placed, whose
//! completions therefore gain the same contact, are cut when the first visit found nothing to
//! beat the bound with no less contact already made.
//!
//! Why it is exact (docs/algorithms.md, *The y-phase's memo*): the contact of a packing is the
//! contact among the placed items with the walls they touch (`ypast`, fixed once they are
//! placed: an unplaced item goes at or above the sweep height, so it never changes what the
//! placed ones touch among themselves), plus the contact of the unplaced items with each other,
//! with the walls and with the placed ones. That second part depends only on where the unplaced
//! items go and on what of the placed ones they can still meet: the skyline over the columns
//! they cover (clipped at the sweep height, below which nothing rests any more), the y-ranges
//! above the sweep height of the placed items on an edge they share with an unplaced one, and
//! whether each of those already touches something on its left (BL-stability). The key holds
//! these, the placed set and the sweep (height and the last item, for the tie rule); the
//! search's rules for the order of identical items read nothing else. So two states with one
//! key have the same completions, each gaining the same contact on top of `ypast`: if the
//! first one's completions made at most its bound `b₁` (it finished without a better packing),
//! they make at most `b₁ − ypast₁` beyond the past, and the second state, with bound `b₂`,
//! holds nothing better when `ypast₂ − b₂ ≤ ypast₁ − b₁`.

use super::*;

/// Most y-states remembered per complete x-assignment before the memo starts afresh.
const YMEMO_MAX: usize = 1 << 16;

/// Most emptied key buffers kept for reuse when the memo starts afresh.
const KEY_POOL: usize = 1 << 12;

/// Lookups the memo gets before it must show that it pays, and the share of them that must
/// cut (one in `YMEMO_RATE`) for it to go on. Its key costs about as much as a y-node, and on
/// most instances it cuts next to nothing: always on, it took 12–16 % more instructions on
/// n20_k4_s0001, s0003 and s0005; with this rule at most 0.4 % more, while n20_k4_s0011 keeps
/// its cut of two thirds of the nodes (docs/algorithms.md, *The y-phase's memo*).
const YMEMO_TRIAL: u64 = 1024;
const YMEMO_RATE: u64 = 10;

/// The y-phase memo of the current complete x-assignment: per key, the largest `ypast − bound`
/// at which a visit finished without a better packing.
pub(in crate::placement::opp) type YMemo = HashMap<Vec<u64>, f64, BuildHasherDefault<FxHasher>>;

impl Search<'_> {
    /// Whether the memo is asked at this y-node: on, and still in its trial or cutting often
    /// enough. Whatever it decides, the memo only cuts what holds nothing better, so this
    /// changes the nodes visited, never the answer.
    pub(super) fn ymemo_worth(&self) -> bool {
        self.ymemo_on && (self.ylookups < YMEMO_TRIAL || self.ymemo_cuts * YMEMO_RATE >= self.ylookups)
    }

    /// The key of the y-state (items `done` at tops `top`, sweep at `last_y` after item
    /// `last_idx`), in a buffer from the pool.
    pub(super) fn ymemo_key(&mut self, done: &[bool], top: &[f64], last_y: f64, last_idx: usize) -> Vec<u64> {
        let n = self.items.len();
        let t = self.t;
        // Positions in tolerance units, as the x-phase's memo keys them.
        let q = |v: f64| (v / t + 0.5) as u64;
        // A fresh buffer has room for a typical key, so that it is not grown push by push.
        let mut key = self.ykey_pool.pop().unwrap_or_else(|| Vec::with_capacity(4 * n));
        key.clear();
        key.push((0..n).filter(|&i| done[i]).fold(0u64, |m, i| m | 1 << i));
        key.push(q(last_y));
        key.push(last_idx as u64);
        for (c, (_, cover)) in self.ycols.iter().enumerate() {
            if cover.iter().all(|&j| done[j]) {
                continue;
            }
            let sky = cover.iter().filter(|&&j| done[j]).fold(0.0, |s: f64, &j| s.max(top[j]));
            // Below the sweep height only "below" matters: nothing rests there any more.
            let below = sky < last_y - t;
            key.push((c as u64) << 1 | below as u64);
            key.push(q(sky.max(last_y)));
        }
        for k in (0..n).filter(|&k| done[k] && top[k] > last_y + t) {
            let left_open = self.yleft[k].iter().any(|&j| !done[j]);
            let right_open = self.yright[k].iter().any(|&j| !done[j]);
            if !left_open && !right_open {
                continue;
            }
            let touched = self.x0[k] <= t
                || (self.yleft[k].iter()).any(|&j| done[j] && top[j].min(top[k]) - self.y0[j].max(self.y0[k]) > t);
            key.push((k as u64) << 1 | touched as u64);
            key.push(q(self.y0[k].max(last_y)));
            key.push(q(top[k]));
        }
        key
    }

    /// Empty the memo, its keys' buffers back to the pool (at most [`KEY_POOL`] kept): each
    /// record takes a buffer with it, and new ones grown push by push were 1.7 % of
    /// n20_k4_s0017's instructions (callgrind).
    pub(super) fn ymemo_forget(&mut self) {
        let room = KEY_POOL.saturating_sub(self.ykey_pool.len());
        // Dropping the rest of the drain empties the map.
        self.ykey_pool.extend(self.ymemo.drain().map(|(key, _)| key).take(room));
    }

    /// Whether a recorded visit of `key` proves that nothing below it beats the bound `bound`
    /// with `ypast` made.
    pub(super) fn ymemo_dead(&self, key: &[u64], bound: f64) -> bool {
        // Sums of the same lengths in another order differ in the last bits only.
        self.ymemo
            .get(key)
            .is_some_and(|&v| self.ypast - bound <= v + 1e-12 * (1.0 + self.ypast.abs()))
    }

    /// Record that below `key` nothing beat `bound` with `ypast` made, and return the buffer.
    pub(super) fn ymemo_record(&mut self, key: Vec<u64>, bound: f64) {
        if self.ymemo.len() >= YMEMO_MAX {
            self.ymemo_forget();
        }
        let v = self.ypast - bound;
        match self.ymemo.get_mut(&key) {
            Some(e) => {
                *e = e.max(v);
                self.ykey_pool.push(key);
            }
            None => {
                self.ymemo.insert(key, v);
            }
        }
    }

    /// Contact item `i`, placed at `y` with top `top_i`, makes with the placed items
    /// (`done`, tops `top`) and the walls: its bottom (`bottom`, computed by the caller), its
    /// left side against the wall or the items ending at its left edge, its right side against
    /// the items starting at its right edge, and the far walls where they count.
    pub(super) fn contact_made(&self, i: usize, y: f64, done: &[bool], top: &[f64], bottom: f64) -> f64 {
        let (w, d) = (self.ydims[i][0], self.ydims[i][1]);
        let top_i = y + d;
        let overlap = |j: usize| (top[j].min(top_i) - self.y0[j].max(y)).max(0.0);
        let mut c = bottom;
        c += if self.x0[i] <= self.t {
            d
        } else {
            self.yleft[i].iter().filter(|&&j| done[j]).map(|&j| overlap(j)).sum()
        };
        c += self.yright[i]
            .iter()
            .filter(|&&j| done[j])
            .map(|&j| overlap(j))
            .sum::<f64>();
        if self.far[0] && self.x0[i] + w >= self.w - self.t {
            c += d;
        }
        if self.far[1] && top_i >= self.d - self.t {
            c += w;
        }
        c
    }

    /// The contact the placed items (`done`, tops `top`) have made with each other and the
    /// walls, summed afresh: each one's bottom, its left side, and the far walls it reaches
    /// (its right side is the left side of the placed items there).
    pub(super) fn past_contact(&self, done: &[bool], top: &[f64]) -> f64 {
        let n = self.items.len();
        let mut c = 0.0;
        for k in (0..n).filter(|&k| done[k]) {
            let (w, d) = (self.ydims[k][0], self.ydims[k][1]);
            let (y, a0, a1) = (self.y0[k], self.x0[k], self.x0[k] + w);
            let overlap = |j: usize| (top[j].min(top[k]) - self.y0[j].max(y)).max(0.0);
            c += self.bottom_contact(k, y, done, top);
            c += if a0 <= self.t {
                d
            } else {
                self.yleft[k].iter().filter(|&&j| done[j]).map(|&j| overlap(j)).sum()
            };
            if self.far[0] && a1 >= self.w - self.t {
                c += d;
            }
            if self.far[1] && top[k] >= self.d - self.t {
                c += w;
            }
        }
        c
    }

    /// Invariant: the contact kept along the path is the contact summed afresh.
    pub(super) fn past_in_step(&self, done: &[bool], top: &[f64]) -> bool {
        let fresh = self.past_contact(done, top);
        (self.ypast - fresh).abs() <= 1e-9 * (1.0 + fresh.abs())
    }
}

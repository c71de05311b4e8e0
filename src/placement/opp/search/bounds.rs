//! The x-phase's bounds: what the columns ahead of `t` can still hold (the bar relaxation
//! with subset sums, and the column at `t` itself), and the contact bound of a node.

use super::*;

impl Search<'_> {
    /// Free depth from `t` on, column by column: an object of depth `h` fits only in columns
    /// with at least `h` free, so the objects of least depth at least `h` (their least areas)
    /// must fit in those columns' free area, for every such `h`.
    pub(super) fn capacity_refutes(&mut self, t: f64, min_idx: usize) -> bool {
        // Buffers kept between calls: this runs at every x-node.
        let mut pieces = std::mem::take(&mut self.buf_pieces);
        pieces.clear();
        // The open objects' ends, in order (`xends`).
        let ends = &self.xends[self.open_from(t)..];
        let mut load: f64 = ends.iter().map(|e| e.1).sum();
        let mut x = t;
        for &(e, h) in ends {
            // Objects ending together leave pieces of no width between them, which hold
            // nothing: left out (the suffix and fill loops below visit every piece per item).
            if e - x > self.t {
                pieces.push((e - x, self.d - load));
            }
            load -= h;
            x = e;
        }
        pieces.push((self.w - x, self.d));
        let tol = self.t * (self.w + self.d);
        let mut area = 0.0;
        let mut refuted = false;
        // The unplaced items, deepest first (`by_depth` is that order over all items). Those
        // covering a column stack to a subset sum of their depths: with a grid, a piece holds
        // at most the largest such sum within its free depth.
        let mut bits = std::mem::take(&mut self.buf_bits);
        let mut tmp = std::mem::take(&mut self.buf_tmp);
        if let Some(g) = &self.grid {
            g.clear(&mut bits);
        }
        // Per piece, with a grid: its free depth and the most the sums so far fill of it, in
        // steps. The sums only grow, so a piece once full stays full and is not asked again
        // (with the free depths in steps computed once per node: 17 % fewer instructions).
        let mut fill = std::mem::take(&mut self.buf_fill);
        fill.clear();
        if let Some(g) = &self.grid {
            fill.extend(pieces.iter().map(|p| (g.steps_in(p.1 + self.t), 0)));
        }
        let mut last_avail = f64::INFINITY;
        // Free depth only grows along the pieces (each end lowers the load), so those with at
        // least `h` free are a suffix, which grows as `h` falls: the sum changes only where a
        // piece joins it or a piece not yet full gains from the new sums.
        match &self.grid {
            // Sums in one machine word (depths of at most 63 steps: the squares' boxes and the
            // random sets), with the pieces not yet full as a bitmask: the loop below, in words.
            Some(g) if self.word_sums && g.one_word() && self.items.len() <= 63 => {
                (refuted, area, last_avail) = self.fill_in_word(g, &pieces, &mut fill, &mut bits[0]);
            }
            _ => {
                let (mut from, mut sum) = (pieces.len(), 0.0);
                for &i in self
                    .by_depth
                    .iter()
                    .filter(|&&i| !self.placed[i] && !self.left_out_now(i))
                {
                    area += self.min_area[i];
                    let h = self.min_depth[i];
                    let avail: f64 = match &self.grid {
                        Some(g) => {
                            g.add(&mut bits, &mut tmp, i);
                            for (p, f) in pieces[from..].iter().zip(fill[from..].iter_mut()) {
                                if f.1 < f.0 {
                                    let m = g.most_steps(&bits, f.0);
                                    sum += p.0 * (g.length(m) - g.length(f.1));
                                    f.1 = m;
                                }
                            }
                            while from > 0 && pieces[from - 1].1 >= h - self.t {
                                from -= 1;
                                let f = &mut fill[from];
                                f.1 = g.most_steps(&bits, f.0);
                                sum += pieces[from].0 * g.length(f.1);
                            }
                            sum
                        }
                        None => pieces.iter().filter(|p| p.1 >= h - self.t).map(|p| p.0 * p.1).sum(),
                    };
                    last_avail = avail;
                    if area > avail + tol {
                        refuted = true;
                        break;
                    }
                }
            }
        }
        // The column at `t` holds only the open objects and those still to start at `t`: the
        // unplaced ones from `min_idx` on (objects at one position come in index order). Those
        // started there fill it, for at least the least width among them (or up to the next
        // end), so the piece at `t` loses what they leave of the most it was counted to hold.
        // Over the candidates by width, widest first: the subsets of the widest ones fill the
        // most they can for at least the width of the narrowest of them.
        if !refuted && min_idx > 0 {
            if let (Some(g), Some(&(first, f0))) = (&self.grid, pieces.first()) {
                let q0 = g.steps_in(f0 + self.t);
                let all = g.length(g.most_steps(&bits, q0));
                let mut loss = first * all;
                // The loss is at most that: when even that leaves room, nothing is refuted.
                if area > last_avail - loss + tol {
                    g.clear(&mut bits);
                    for &i in self.by_width.iter() {
                        if i < min_idx || self.placed[i] || self.min_depth[i] > f0 + self.t {
                            continue;
                        }
                        g.add(&mut bits, &mut tmp, i);
                        let fill = g.length(g.most_steps(&bits, q0));
                        loss = loss.min(first.min(self.min_width[i]) * (all - fill));
                        if loss <= 0.0 {
                            break;
                        }
                    }
                    refuted = area > last_avail - loss + tol;
                }
            }
        }
        self.buf_fill = fill;
        self.buf_bits = bits;
        self.buf_tmp = tmp;
        self.buf_pieces = pieces;
        refuted
    }

    /// The loop over the unplaced items of [`Self::capacity_refutes`] with the sums in one
    /// word (`word`: the empty sum on entry, all the sums on return): the free depths' masks
    /// applied to the word directly, the pieces of the suffix not yet full as a bitmask (about
    /// 60 % of the area stage's instructions were this loop over pieces and bitset slices),
    /// and the filled area summed in width × steps. `fill`: per piece, free depth and fill in
    /// steps. Returns whether it refuted, the items' area so far, and the last free area.
    fn fill_in_word(
        &self,
        g: &subset::Grid,
        pieces: &[(f64, f64)],
        fill: &mut [(usize, usize)],
        word: &mut u64,
    ) -> (bool, f64, f64) {
        debug_assert!(pieces.len() <= 64 && fill.len() == pieces.len());
        let tol = self.t * (self.w + self.d);
        let (mut from, mut sum, mut area, mut last) = (pieces.len(), 0.0, 0.0, f64::INFINITY);
        let mut open = 0u64;
        let mut bits = *word;
        let mut left = self.left_by_depth;
        if self.probing {
            left &= !self.probe_rank_bits;
        }
        while left != 0 {
            let i = self.by_depth[left.trailing_zeros() as usize];
            left &= left - 1;
            area += self.min_area[i];
            let h = self.min_depth[i];
            bits = g.add_word(bits, i);
            let mut o = open;
            while o != 0 {
                let j = o.trailing_zeros() as usize;
                o &= o - 1;
                let f = &mut fill[j];
                let m = subset::most_in_word(bits, f.0);
                if m > f.1 {
                    sum += pieces[j].0 * (m - f.1) as u32 as f64;
                    f.1 = m;
                    if m == f.0 {
                        open &= !(1 << j);
                    }
                }
            }
            while from > 0 && pieces[from - 1].1 >= h - self.t {
                from -= 1;
                let f = &mut fill[from];
                f.1 = subset::most_in_word(bits, f.0);
                sum += pieces[from].0 * f.1 as u32 as f64;
                if f.1 < f.0 {
                    open |= 1 << from;
                }
            }
            last = g.length_of(sum);
            if area > last + tol {
                *word = bits;
                return (true, area, last);
            }
        }
        *word = bits;
        (false, area, last)
    }

    /// Contact-length upper bound in the x-phase: every side in full contact except the
    /// deficits known so far, plus the far walls' lengths. The sides come from
    /// [`Self::sides_now`], which the x-phase keeps as it places (a scan of every item at
    /// every node was 14 % of the contact enumeration's instructions on squares 1…18).
    pub(super) fn contact_ub(&self) -> f64 {
        let far = if self.far[0] { self.d } else { 0.0 } + if self.far[1] { self.w } else { 0.0 };
        self.xsides - self.ldef + far
    }

    /// Every side counted in full: the chosen footprint's width + depth for a placed item, the
    /// largest over its fitting footprints for an unplaced one.
    pub(super) fn sides_now(&self) -> f64 {
        (0..self.items.len())
            .map(|i| {
                if self.placed[i] {
                    let f = self.dims(i);
                    f[0] + f[1]
                } else {
                    self.max_sides[i]
                }
            })
            .sum()
    }

    /// Left contact still to be lost on the rows free just left of `t` (`hprev` of them), beyond
    /// what `ldef` counted at `t`. Each such row goes on free until the left side of an object
    /// (contact lost there, at `t` or later) or to the box's right side, which costs `w − t` of
    /// free area per unit of depth (or the far wall's contact, where it counts). `used` is the
    /// area placed, still to place (least) and wasted, so the free area ahead is at most
    /// `w·d − used`. A function of the memo's key and of the path below it, so the memo stays valid.
    pub(super) fn rows_lost_ahead(&self, t: f64, used: f64) -> f64 {
        if self.hprev <= self.t || (!self.far[0] && self.w - t <= self.t) {
            return 0.0;
        }
        let to_wall = if self.far[0] {
            0.0
        } else {
            (self.w * self.d - used).max(0.0) / (self.w - t)
        };
        (self.hprev - to_wall - (self.ldef - self.ldef_at)).max(0.0)
    }

    /// An upper bound on the contact of every BL-stable packing below this x-node (at `t`,
    /// with `used` the area placed, still to place at the least and wasted): the node's bound
    /// less the rows lost ahead and the sides the free area cannot buy, as the contact cut
    /// takes it.
    pub(super) fn node_contact_bound(&self, t: f64, used: f64) -> f64 {
        self.contact_ub() - self.rows_lost_ahead(t, used) - self.sides_unreachable(self.w * self.d - used)
    }

    /// Rows ahead of `t`: each row holds at most one open object (all cover `t`), so the
    /// `h` rows of an open object ending at `e` leave `w − e` to the unplaced items' widths,
    /// and the rows of no open object leave `w − t`; a row filled by widths summing to at most
    /// the largest subset sum within its room loses the rest. `used`: area placed, still to
    /// place (least) and wasted. Refutes when the rows must lose more than the free area left.
    pub(super) fn rows_refute(&self, t: f64, used: f64) -> bool {
        let Some(g) = &self.wgrid else {
            return false;
        };
        let mut bits = 1u64;
        for i in 0..self.items.len() {
            if !self.placed[i] {
                bits = g.add_word(bits, i);
            }
        }
        let gap = |r: f64| {
            if r <= self.t {
                0.0
            } else {
                r - g.length(subset::most_in_word(bits, g.steps_in(r)))
            }
        };
        let (mut forced, mut load) = (0.0, 0.0);
        for &(e, h) in &self.xends[self.open_from(t)..] {
            forced += h * gap(self.w - e);
            load += h;
        }
        forced += (self.d - load).max(0.0) * gap(self.w - t);
        let tol = self.t * (self.w + self.d);
        forced > self.w * self.d - used + tol
    }
}

//! The y-phase: for one complete x-assignment, the items in the order of their bottom edges,
//! each on the highest top below it (module doc of [`super::super`] says why it is exact), and
//! in enumeration the contact cuts that only BL-stable packings allow.

use super::*;

/// The larger of two lengths. `f64::max` also orders NaN, which no length here is; this form is
/// one instruction, and the y-phase asks it at every node (a fifth of its time in `perf`).
#[inline]
fn max(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// The smaller of two lengths (see [`max`]).
#[inline]
fn min(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

impl Search<'_> {
    /// Left sides, seen from the y-phase. Enumeration visits only packings where every item
    /// touches something on its left (the BL-stable ones; the y-phase already rests every item
    /// on something below). A placed item off the left wall can be touched on its left only by
    /// items ending at its left edge: placed ones by their overlap in y, unplaced ones only
    /// above `ylo` (no later item's bottom is lower); an unplaced item, which sits at its floor
    /// (`floors`) or higher, by placed ones only above that. `None`: some placed
    /// item can no longer be touched, so no completion is BL-stable. Otherwise, the left
    /// contact now known to be missing beyond what the x-phase counted (`ldef`: for the items
    /// sharing a left edge, the least of their sides and the right sides ending there).
    fn left_contact_lost(&self, done: &[bool], top: &[f64], ylo: f64, floors: &[f64]) -> Option<f64> {
        let mut lost = 0.0;
        for (group, &(ends, counted)) in self.ygroups.iter().zip(&self.ygroup_ends) {
            let mut can = 0.0;
            for &k in group {
                let side = self.ydims[k][1];
                if !done[k] {
                    // It will sit at its floor or higher, and at `ylo` or higher: placed items
                    // ending at its left edge touch it only above that.
                    let lo = max(ylo, floors[k]);
                    let mut room = 0.0;
                    for &j in &self.yleft[k] {
                        room += if done[j] {
                            max(top[j] - max(lo, self.y0[j]), 0.0)
                        } else {
                            self.ydims[j][1]
                        };
                    }
                    can += min(room, side);
                    continue;
                }
                let (y0, y1) = (self.y0[k], top[k]);
                let (mut now, mut later) = (0.0, 0.0);
                for &j in &self.yleft[k] {
                    if done[j] {
                        now += max(min(top[j], y1) - max(self.y0[j], y0), 0.0);
                    } else {
                        later += self.ydims[j][1];
                    }
                }
                let room = max(y1 - max(ylo, y0), 0.0);
                let later = min(later, room);
                if now <= self.t && later <= self.t {
                    return None;
                }
                can += min(now + later, side);
            }
            // The x-phase counted min(ends, sides) for the group (`ldef`).
            lost += max(counted - min(ends, can), 0.0);
        }
        Some(lost)
    }

    /// y-phase for the current x-assignment.
    pub(super) fn ycheck(&mut self) -> bool {
        self.yleaves += 1;
        let n = self.items.len();
        // Buffers kept between x-assignments: allocating these per call was a tenth of the
        // y-phase's instructions on n20_k4_s0017 (callgrind).
        let mut done = std::mem::take(&mut self.ydone);
        let mut top = std::mem::take(&mut self.ytop);
        done.clear();
        done.resize(n, false);
        top.clear();
        top.resize(n, 0.0);
        let t = self.t;
        // What the y-phase asks at every node, fixed by the x-assignment: computed once here
        // (the y-phase is nine tenths of the contact enumeration's time on squares 1…18).
        let mut ydims = std::mem::take(&mut self.ydims);
        ydims.clear();
        ydims.extend((0..n).map(|i| self.dims(i)));
        self.ydims = ydims;
        self.yfloor.resize(n * (n + 1), 0.0);
        for i in 0..n {
            let twins = &mut self.ytwins[i];
            twins.clear();
            twins.extend((0..i).filter(|&j| {
                self.items[j].class == self.items[i].class
                    && self.opt[j] == self.opt[i]
                    && (self.x0[j] - self.x0[i]).abs() <= t
            }));
        }
        for k in 0..n {
            let (a0, a1) = (self.x0[k], self.x0[k] + self.ydims[k][0]);
            let (cover, over, left) = (&mut self.ycover[k], &mut self.yover[k], &mut self.yleft[k]);
            cover.clear();
            over.clear();
            left.clear();
            for j in 0..n {
                let (b0, b1) = (self.x0[j], self.x0[j] + self.ydims[j][0]);
                if b0 <= a0 + t && b1 > a0 + t {
                    cover.push(j);
                }
                if j != k && a1.min(b1) - a0.max(b0) > t {
                    over.push(j);
                }
                if (b1 - a0).abs() <= t {
                    left.push(j);
                }
            }
        }
        self.yright.iter_mut().for_each(Vec::clear);
        for k in 0..n {
            for j in 0..self.yleft[k].len() {
                let l = self.yleft[k][j];
                self.yright[l].push(k);
            }
        }
        if self.visit.is_some() {
            // Groups' buffers go back to the pool and come out again in this order.
            self.ypool.extend(self.ygroups.drain(..).map(|mut g| {
                g.clear();
                g
            }));
            for k in (0..n).filter(|&k| self.x0[k] > t) {
                match self
                    .ygroups
                    .iter_mut()
                    .find(|g| (self.x0[g[0]] - self.x0[k]).abs() <= t)
                {
                    Some(g) => g.push(k),
                    None => {
                        let mut g = self.ypool.pop().unwrap_or_default();
                        g.push(k);
                        self.ygroups.push(g);
                    }
                }
            }
            self.ygroup_ends.clear();
            for group in &self.ygroups {
                let ends: f64 = self.yleft[group[0]].iter().map(|&j| self.ydims[j][1]).sum();
                let sides: f64 = group.iter().map(|&k| self.ydims[k][1]).sum();
                self.ygroup_ends.push((ends, ends.min(sides)));
            }
        }
        self.ypool.extend(self.ycols.drain(..).map(|(_, mut c)| {
            c.clear();
            c
        }));
        // Widths where the items stack to less than the box's depth.
        let mut room = 0.0;
        if self.cbound.is_some() {
            let mut edges = std::mem::take(&mut self.yedges);
            edges.clear();
            edges.extend((0..n).flat_map(|i| [self.x0[i], self.x0[i] + self.ydims[i][0]]));
            edges.push(self.w);
            edges.sort_by(f64::total_cmp);
            edges.dedup_by(|a, b| *a - *b <= t);
            for e in edges.windows(2) {
                let mut cover = self.ypool.pop().unwrap_or_default();
                cover.extend((0..n).filter(|&j| self.x0[j] <= e[0] + t && self.x0[j] + self.ydims[j][0] >= e[1] - t));
                if cover.iter().map(|&j| self.ydims[j][1]).sum::<f64>() < self.d - t {
                    room += e[1] - e[0];
                }
                if cover.is_empty() {
                    self.ypool.push(cover);
                } else {
                    self.ycols.push((e[1] - e[0], cover));
                }
            }
            self.yedges = edges;
        }
        self.prepare_grid();
        // The far walls, where they count: the right one touches exactly the items ending at
        // it, which the x-assignment fixes; the top one misses every column with room, or its
        // items keep a gap, so each such column loses its width at the top or at a bottom.
        self.ub_x = self.contact_ub();
        if self.walls_on && self.far[0] {
            let at_wall: f64 = (0..n)
                .filter(|&i| self.x0[i] + self.ydims[i][0] >= self.w - t)
                .map(|i| self.ydims[i][1])
                .sum();
            self.ub_x -= max(self.d - at_wall, 0.0);
        }
        self.ydef = 0.0;
        self.ygaps = if self.walls_on && self.far[1] { room } else { 0.0 };
        self.ypast_ok = false;
        // Clearing touches every bucket of what the map once held, empty or not.
        if !self.ymemo.is_empty() {
            self.ymemo_forget();
        }
        // Counted where the far walls' bound took contact off and the root was cut.
        let walls = self.ub_x < self.contact_ub() || self.ygaps > 0.0;
        let nodes = self.nodes;
        let found = self.yphase(&mut done, &mut top, 0.0, 0, 0);
        self.walls_cuts += (walls && !found && self.nodes == nodes + 1) as u64;
        (self.ydone, self.ytop) = (done, top);
        found
    }

    /// Items go in the order of their bottom edges, each onto the highest top of the placed
    /// items that overlap it in x (ties of equal bottom in index order). `placed` items are done.
    fn yphase(&mut self, done: &mut [bool], top: &mut [f64], last_y: f64, last_idx: usize, placed: usize) -> bool {
        if self.tick() {
            return false;
        }
        let n = self.items.len();
        if placed == n {
            self.yvisited += 1;
            if let Some(v) = self.visit.as_mut() {
                let pos: Vec<Pos> = (0..n)
                    .map(|i| Pos {
                        opt: self.opt[i],
                        x: self.x0[i],
                        y: self.y0[i],
                    })
                    .collect();
                if v(&pos) {
                    // The visitor has what it needs: stop like a limit would.
                    self.stopped = true;
                }
                return false;
            }
            return true;
        }
        // Each depth of the recursion has its own row of floors: the highest placed top over
        // each item, which is its parent's row raised by the top of the item placed last
        // (`last_idx`) over the items it overlaps in x.
        let row = placed * n;
        if placed == 0 {
            self.yfloor[..n].fill(0.0);
        } else {
            self.yfloor.copy_within(row - n..row, row);
            let tp = top[last_idx];
            for &i in &self.yover[last_idx] {
                self.yfloor[row + i] = max(self.yfloor[row + i], tp);
            }
        }
        // Every unplaced item sits at its floor or higher (floors only rise), and at `last_y` or
        // higher: no later bottom is lower than the least of those (`ylo`). Cuts that took
        // `last_y` for it took 23 % fewer y-nodes with it on n20_k4_s0017.
        let ylo = (0..n)
            .filter(|&i| !done[i])
            .fold(f64::INFINITY, |m, i| min(m, self.yfloor[row + i]))
            .max(last_y);
        let mut lost = 0.0;
        if self.visit.is_some() {
            let Some(l) = self.left_contact_lost(done, top, ylo, &self.yfloor[row..row + n]) else {
                return false;
            };
            lost = l;
            if let Some(cb) = self.cbound {
                if self.ub_x - max(self.ydef, self.ygaps) - lost <= cb.get() + 1e-9 {
                    self.cpruned += 1;
                    return false;
                }
            }
        }
        // Every unplaced item goes at or above `last_y` (items go in the order of their bottom
        // edges), above the placed items in its columns: in each column, those covering it
        // stack on max(`last_y`, the highest placed top) within d. The stacked depth changes at
        // left edges of unplaced items, the placed tops at left edges of placed ones. Under a
        // contact bound the loop over all columns below checks this too.
        for k in (0..n).filter(|_| self.cbound.is_none()) {
            let (mut stack, mut base) = (0.0, last_y);
            for &j in &self.ycover[k] {
                if done[j] {
                    base = max(base, top[j]);
                } else {
                    stack += self.ydims[j][1];
                }
            }
            if stack > self.t && base + stack > self.d + self.t {
                return false;
            }
        }
        let floors = &self.yfloor[row..row + n];
        if (0..n).any(|i| !done[i] && floors[i] + self.ydims[i][1] > self.d + self.t) {
            return false;
        }
        if let Some(cb) = self.cbound {
            // Bottoms still to lose: the first item to go over a column sits on its placed top
            // only if that top is at `ylo` or above and the item's floor is no higher; else its
            // bottom faces free space over the whole column.
            let mut wells = 0.0;
            let grid = self.ystacks_on && self.ygrid.on();
            // Widths of the columns where new gaps may lie (open, not wells, with room): if they
            // cannot close the margin, the stacks bound below the root need not run.
            let mut could = 0.0;
            self.ygrid.at.clear();
            for (width, cover) in &self.ycols {
                let (mut sky, mut stack) = (0.0, 0.0);
                for &j in cover {
                    if done[j] {
                        sky = max(sky, top[j]);
                    } else {
                        stack += self.ydims[j][1];
                    }
                }
                let open = stack > self.t;
                let base = max(sky, ylo);
                if open && base + stack > self.d + self.t {
                    return false;
                }
                // Items at `last_y` come in index order, so one before `last_idx` cannot sit there.
                let at_last = (sky - last_y).abs() <= self.t;
                let fits = |j: usize| !done[j] && floors[j] <= sky + self.t && !(at_last && j < last_idx);
                let well = open && (sky < ylo - self.t || !cover.iter().any(|&j| fits(j)));
                if well {
                    wells += width;
                }
                if grid {
                    self.ygrid.at.push((base, well));
                    if open && !well && base + stack < self.d - self.t {
                        could += width;
                    }
                }
            }
            // The bottoms lost: those placed and the wells, or the gaps the root proved.
            let margin = self.ub_x - lost - max(self.ydef + wells, self.ygaps) - cb.get();
            if margin <= 1e-9 {
                self.cpruned += 1;
                return false;
            }
            // At the root, the columns that must keep gaps at all (`search/stacks.rs`): their
            // widths are lost on every path below, whatever the bottoms placed lose.
            if placed == 0 && self.stacks_on {
                let budget = self.ub_x - lost - cb.get();
                self.ygaps = max(self.ygaps, self.least_gaps(budget - 1e-9));
                if self.ygaps >= budget - 1e-9 {
                    self.stack_cuts += 1;
                    self.cpruned += 1;
                    return false;
                }
            }
            // Below the root, the columns that must keep new gaps over their placed tops: bottoms
            // lost beyond the wells and those placed, not beyond the root's gaps, which may lie
            // in the same columns. (At the root the two bounds are one.)
            let margin = self.ub_x - self.ydef - lost - wells - cb.get();
            if grid
                && placed > 0
                && margin <= could + 1e-9
                && self.least_gaps_above(done, row, ylo, margin) >= margin - 1e-9
            {
                self.ystack_cuts += 1;
                self.cpruned += 1;
                return false;
            }
        }
        // A state met before through another order of the placed items: cut when that visit
        // found nothing better with no less contact made (`search/ymemo.rs`).
        let mut fresh = false;
        let key = match self.cbound {
            Some(cb) if self.ymemo_worth() => {
                self.ylookups += 1;
                // The contact made so far is summed once, where the memo is first asked on this
                // path, and kept from there on down.
                if !self.ypast_ok {
                    self.ypast = self.past_contact(done, top);
                    (self.ypast_ok, fresh) = (true, true);
                }
                debug_assert!(self.past_in_step(done, top));
                let key = self.ymemo_key(done, top, last_y, last_idx);
                if self.ymemo_dead(&key, cb.get()) {
                    self.ykey_pool.push(key);
                    self.ymemo_cuts += 1;
                    self.cpruned += 1;
                    self.ypast_ok &= !fresh;
                    return false;
                }
                Some(key)
            }
            _ => None,
        };
        let visited = self.yvisited;
        for i in 0..n {
            if done[i] {
                continue;
            }
            let y = self.yfloor[row + i];
            if y < last_y - self.t || ((y - last_y).abs() <= self.t && i < last_idx) {
                continue;
            }
            // Identical items with the same x-interval are interchangeable: index order.
            if self.ytwins[i].iter().any(|&j| !done[j]) {
                continue;
            }
            // The lowest item of the anchor's class (any copy) in the lower half.
            if self.anchor.is_some_and(|a| self.items[a].class == self.items[i].class)
                && y > self.anchor_limit(1)
                && !(0..n).any(|j| done[j] && self.items[j].class == self.items[i].class)
            {
                continue;
            }
            // Bottom side in contact: with the floor, or with the placed tops at `y`.
            let wi = self.ydims[i][0];
            let bottom = self.bottom_contact(i, y, done, top);
            if let Some(cb) = self.cbound {
                if self.ub_x - self.ydef - (wi - bottom) <= cb.get() + 1e-9 {
                    self.cpruned += 1;
                    continue;
                }
            }
            let past = self.ypast;
            if self.ypast_ok {
                self.ypast += self.contact_made(i, y, done, top, bottom);
            }
            done[i] = true;
            top[i] = y + self.ydims[i][1];
            self.y0[i] = y;
            self.ydef += wi - bottom;
            let found = self.yphase(done, top, y, i, placed + 1);
            self.ydef -= wi - bottom;
            self.ypast = past;
            if found {
                self.ypast_ok &= !fresh;
                return true;
            }
            done[i] = false;
            if self.stopped {
                self.ypast_ok &= !fresh;
                return false;
            }
        }
        self.ypast_ok &= !fresh;
        // Only a subtree that reached no packing is known to hold nothing above the bound: the
        // visitor need not raise the bound to what it was shown.
        if let (Some(key), Some(cb)) = (key, self.cbound) {
            if self.yvisited == visited {
                self.ymemo_record(key, cb.get());
            } else {
                self.ykey_pool.push(key);
            }
        }
        false
    }

    /// The bottom contact of item `i` at height `y` over the placed items (`done`, tops `top`):
    /// its width on the floor, else its overlaps in x with the placed tops at `y`.
    #[inline]
    pub(super) fn bottom_contact(&self, i: usize, y: f64, done: &[bool], top: &[f64]) -> f64 {
        let wi = self.ydims[i][0];
        if y <= self.t {
            return wi;
        }
        let (a0, a1) = (self.x0[i], self.x0[i] + wi);
        let on: f64 = (self.yover[i].iter())
            .filter(|&&j| done[j] && (top[j] - y).abs() <= self.t)
            .map(|&j| max(min(a1, self.x0[j] + self.ydims[j][0]) - max(a0, self.x0[j]), 0.0))
            .sum();
        min(on, wi)
    }
}

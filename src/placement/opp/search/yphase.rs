//! The y-phase: for one complete x-assignment, the items in the order of their bottom edges,
//! each on the highest top below it (module doc of [`super::super`] says why it is exact), and
//! in enumeration the contact cuts that only BL-stable packings allow.

use super::*;

impl Search<'_> {
    /// Left sides, seen from the y-phase. Enumeration visits only packings where every item
    /// touches something on its left (the BL-stable ones; the y-phase already rests every item
    /// on something below). A placed item off the left wall can be touched on its left only by
    /// items ending at its left edge: placed ones by their overlap in y, unplaced ones only
    /// above `last_y` (every later item's bottom is at least `last_y`). `None`: some placed
    /// item can no longer be touched, so no completion is BL-stable. Otherwise, the left
    /// contact now known to be missing beyond what the x-phase counted (`ldef`: for the items
    /// sharing a left edge, the least of their sides and the right sides ending there).
    fn left_contact_lost(&self, done: &[bool], top: &[f64], last_y: f64) -> Option<f64> {
        let mut lost = 0.0;
        for group in &self.ygroups {
            let ends: f64 = self.yleft[group[0]].iter().map(|&j| self.dims(j)[1]).sum();
            let sides: f64 = group.iter().map(|&k| self.dims(k)[1]).sum();
            let mut can = 0.0;
            for &k in group {
                let side = self.dims(k)[1];
                if !done[k] {
                    can += side;
                    continue;
                }
                let (y0, y1) = (self.y0[k], top[k]);
                let (mut now, mut later) = (0.0, 0.0);
                for &j in &self.yleft[k] {
                    if done[j] {
                        now += (top[j].min(y1) - self.y0[j].max(y0)).max(0.0);
                    } else {
                        later += self.dims(j)[1];
                    }
                }
                let room = (y1 - last_y.max(y0)).max(0.0);
                let later = later.min(room);
                if now <= self.t && later <= self.t {
                    return None;
                }
                can += (now + later).min(side);
            }
            // The x-phase counted min(ends, sides) for the group (`ldef`).
            lost += (ends.min(sides) - ends.min(can)).max(0.0);
        }
        Some(lost)
    }

    /// y-phase for the current x-assignment.
    pub(super) fn ycheck(&mut self) -> bool {
        self.yleaves += 1;
        let n = self.items.len();
        let mut done = vec![false; n];
        let mut top = vec![0.0; n];
        let t = self.t;
        for k in 0..n {
            let (a0, a1) = (self.x0[k], self.x0[k] + self.dims(k)[0]);
            let (mut cover, mut over, mut left) = (Vec::new(), Vec::new(), Vec::new());
            for j in 0..n {
                let (b0, b1) = (self.x0[j], self.x0[j] + self.dims(j)[0]);
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
            self.ycover[k] = cover;
            self.yover[k] = over;
            self.yleft[k] = left;
        }
        if self.visit.is_some() {
            self.ygroups.clear();
            for k in (0..n).filter(|&k| self.x0[k] > t) {
                match self
                    .ygroups
                    .iter_mut()
                    .find(|g| (self.x0[g[0]] - self.x0[k]).abs() <= t)
                {
                    Some(g) => g.push(k),
                    None => self.ygroups.push(vec![k]),
                }
            }
        }
        self.ub_x = self.contact_ub();
        self.ydef = 0.0;
        self.yphase(&mut done, &mut top, 0.0, 0)
    }

    /// Items go in the order of their bottom edges, each onto the highest top of the placed
    /// items that overlap it in x (ties of equal bottom in index order).
    fn yphase(&mut self, done: &mut [bool], top: &mut [f64], last_y: f64, last_idx: usize) -> bool {
        if self.tick() {
            return false;
        }
        let n = self.items.len();
        let xr = |s: &Self, i: usize| (s.x0[i], s.x0[i] + s.dims(i)[0]);
        if done.iter().all(|&b| b) {
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
        if self.visit.is_some() {
            let Some(lost) = self.left_contact_lost(done, top, last_y) else {
                return false;
            };
            if let Some(cb) = self.cbound {
                if self.ub_x - self.ydef - lost <= cb.get() + 1e-9 {
                    self.cpruned += 1;
                    return false;
                }
            }
        }
        // Every unplaced item goes at or above `last_y` (items go in the order of their bottom
        // edges), above the placed items in its columns: in each column, those covering it
        // stack on max(`last_y`, the highest placed top) within d. The stacked depth changes at
        // left edges of unplaced items, the placed tops at left edges of placed ones.
        for k in 0..n {
            let (mut stack, mut base) = (0.0, last_y);
            for &j in &self.ycover[k] {
                if done[j] {
                    base = f64::max(base, top[j]);
                } else {
                    stack += self.dims(j)[1];
                }
            }
            if stack > self.t && base + stack > self.d + self.t {
                return false;
            }
        }
        let mut floor = vec![0.0; n];
        for i in 0..n {
            if done[i] {
                continue;
            }
            floor[i] = self.yover[i]
                .iter()
                .filter(|&&j| done[j])
                .map(|&j| top[j])
                .fold(0.0, f64::max);
            if floor[i] + self.dims(i)[1] > self.d + self.t {
                return false;
            }
        }
        for i in 0..n {
            if done[i] {
                continue;
            }
            let y = floor[i];
            if y < last_y - self.t || ((y - last_y).abs() <= self.t && i < last_idx) {
                continue;
            }
            // Identical items with the same x-interval are interchangeable: index order.
            if (0..i).any(|j| {
                !done[j]
                    && self.items[j].class == self.items[i].class
                    && self.opt[j] == self.opt[i]
                    && (self.x0[j] - self.x0[i]).abs() <= self.t
            }) {
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
            let wi = self.dims(i)[0];
            let bottom = if y <= self.t {
                wi
            } else {
                self.yover[i]
                    .iter()
                    .copied()
                    .filter(|&j| done[j] && (top[j] - y).abs() <= self.t)
                    .map(|j| {
                        let (a0, a1) = xr(self, i);
                        let (b0, b1) = xr(self, j);
                        (a1.min(b1) - a0.max(b0)).max(0.0)
                    })
                    .sum::<f64>()
                    .min(wi)
            };
            if let Some(cb) = self.cbound {
                if self.ub_x - self.ydef - (wi - bottom) <= cb.get() + 1e-9 {
                    self.cpruned += 1;
                    continue;
                }
            }
            done[i] = true;
            top[i] = y + self.dims(i)[1];
            self.y0[i] = y;
            self.ydef += wi - bottom;
            let found = self.yphase(done, top, y, i);
            self.ydef -= wi - bottom;
            if found {
                return true;
            }
            done[i] = false;
            if self.stopped {
                return false;
            }
        }
        false
    }
}

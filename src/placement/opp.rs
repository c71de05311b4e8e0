//! Exact decision of the two-dimensional orthogonal packing problem (OPP): do the objects fit
//! in a `w × d` box, each in one of its footprints, without overlap?
//!
//! Cheap bounds first ([`refuted_by_bounds`]): every object fits, total area, objects too wide
//! (or too deep) to sit side by side stack, and the dual-feasible-function bounds of Fekete and
//! Schepers (2004). Then an exact search in two phases, after Simonis and O'Sullivan (2008) and
//! Huang and Korf (2013): x-coordinates first under the cumulative ("bar") relaxation in y, then
//! y-coordinates for each complete x-assignment. The split is the one of the combinatorial
//! Benders decomposition of Côté, Dell'Amico and Iori (2014) — a one-dimensional master with a
//! check of the other coordinate — with the master searched combinatorially.
//!
//! Why it is exact (docs/algorithms.md, "Exact placement"): any packing compacts (slid down and
//! left until nothing moves) into one in the same box where every object touches the left wall
//! or an object on its left, and the floor or an object below it. Take the objects in the order
//! of their left edges: each one starts at 0 or at the right edge of an object taken before it.
//! The x-phase enumerates exactly these sequences (ties by index), so it meets the compacted
//! packing's x-coordinates; likewise the y-phase, in the order of bottom edges, puts each object
//! on the highest top below it, which is where the compacted packing has it. Pruning only
//! removes branches that no packing completes (the area of the objects still to place plus the
//! space already left behind exceeds the box; a column whose objects cannot stack), or that a
//! relabelling or mirror image of a packing they keep covers (identical objects in index order;
//! the first object of the largest class in the left half and the lower half — mirroring a
//! compacted packing and compacting it again moves nothing right or up).

use std::cell::Cell;
use std::collections::HashMap;

/// An x-phase state: placed set, position, (end, depth) of the placed objects still open; lengths
/// in units of the tolerance.
type StateKey = (u64, i64, Vec<(i64, i64)>);

/// Most x-phase states remembered as dead per box (about 100 bytes each).
const DEAD_MAX: usize = 2_000_000;

/// One object: its distinct footprints `[x-extent, y-extent]`, and its class (objects of one
/// class are interchangeable: same footprints).
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// Distinct footprints.
    pub opts: Vec<[f64; 2]>,
    /// Objects with equal class are identical.
    pub class: usize,
}

/// Where one object goes: footprint index and lower-left corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pos {
    /// Index into [`Item::opts`].
    pub opt: usize,
    /// Left edge.
    pub x: f64,
    /// Bottom edge.
    pub y: f64,
}

/// Result of one decision.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// A packing, one position per item.
    Packed(Vec<Pos>),
    /// Proven: no packing exists.
    Infeasible,
    /// Stopped before a proof either way.
    Stopped,
}

/// Comparison tolerance for a box of size `w × d`: far below any size step, far above rounding.
fn tol(w: f64, d: f64) -> f64 {
    1e-9 * (1.0 + w + d)
}

/// The footprints of `it` that fit in `w × d`.
fn fitting(it: &Item, w: f64, d: f64) -> impl Iterator<Item = [f64; 2]> + '_ {
    let t = tol(w, d);
    it.opts.iter().copied().filter(move |f| f[0] <= w + t && f[1] <= d + t)
}

/// Dual-feasible functions for capacity `c` (Fekete and Schepers 2004): each maps sizes so that
/// any set of sizes summing to at most `c` still sums to at most `c`, and `c` to `c`. Hence for
/// any pair (one per axis) the transformed areas of a packing still fit in `c_x · c_y`.
fn dffs(c: f64, sizes: &[f64]) -> Vec<Box<dyn Fn(f64) -> f64>> {
    let t = 1e-9 * (1.0 + c);
    let mut out: Vec<Box<dyn Fn(f64) -> f64>> = vec![Box::new(|x| x)];
    // U^ε: sizes above c − ε become c (two of them never share a line), below ε vanish.
    let mut eps: Vec<f64> = sizes.iter().copied().filter(|&s| s <= c / 2.0 + t && s > t).collect();
    eps.sort_by(f64::total_cmp);
    eps.dedup_by(|a, b| (*a - *b).abs() <= t);
    for e in eps {
        out.push(Box::new(move |x| {
            if x > c - e + t {
                c
            } else if x < e - t {
                0.0
            } else {
                x
            }
        }));
    }
    // u^(k): round (k+1)x/c down to an integer, unless it is one already.
    for k in 1..=4 {
        let q = (k + 1) as f64;
        out.push(Box::new(move |x| {
            let r = q * x / c;
            if (r - r.round()).abs() <= 1e-9 * q {
                x
            } else {
                r.floor() * c / k as f64
            }
        }));
    }
    out
}

/// True when a bound proves that the items do not fit in `w × d`.
pub fn refuted_by_bounds(items: &[Item], w: f64, d: f64) -> bool {
    let t = tol(w, d);
    let fits: Vec<Vec<[f64; 2]>> = items.iter().map(|it| fitting(it, w, d).collect()).collect();
    if fits.iter().any(|f| f.is_empty()) {
        return true;
    }
    let area: f64 = fits
        .iter()
        .map(|f| f.iter().map(|g| g[0] * g[1]).fold(f64::INFINITY, f64::min))
        .sum();
    if area > w * d + t * (w + d) {
        return true;
    }
    // Objects wider than w/2 in every fitting footprint stack in y (and the transpose).
    for axis in 0..2 {
        let (cap, other) = if axis == 0 { (w, d) } else { (d, w) };
        let stack: f64 = fits
            .iter()
            .filter(|f| f.iter().all(|g| g[axis] > cap / 2.0 + t))
            .map(|f| f.iter().map(|g| g[1 - axis]).fold(f64::INFINITY, f64::min))
            .sum();
        if stack > other + t {
            return true;
        }
    }
    let xs: Vec<f64> = fits.iter().flatten().map(|g| g[0]).collect();
    let ys: Vec<f64> = fits.iter().flatten().map(|g| g[1]).collect();
    let (fx, fy) = (dffs(w, &xs), dffs(d, &ys));
    for f in &fx {
        for g in &fy {
            let s: f64 = fits
                .iter()
                .map(|o| o.iter().map(|q| f(q[0]) * g(q[1])).fold(f64::INFINITY, f64::min))
                .sum();
            if s > w * d + t * (w + d) {
                return true;
            }
        }
    }
    false
}

/// Decide the box with [`Search`], after setting aside the unit items when that is safe: items
/// whose only fitting footprint is a `g × g` square, where `g` divides every footprint extent
/// and the box's sides. Every packing the search finds has its edges on the `g`-lattice (left
/// edges are 0 or right edges, bottoms 0 or tops, all sums of extents), so its free space is a
/// union of `g`-cells; when the other items, at their largest footprints, leave at least the
/// units' area free, each unit goes into a free cell, and the others packing is equivalent to all
/// packing. Returns the outcome and the nodes visited.
pub fn decide(items: &[Item], w: f64, d: f64, stop: &dyn Fn() -> bool) -> (Outcome, u64) {
    let units = unit_items(items, w, d);
    if units.is_empty() {
        let mut s = Search::new(items, w, d, stop);
        let r = s.run();
        return (r, s.nodes);
    }
    if refuted_by_bounds(items, w, d) {
        return (Outcome::Infeasible, 0);
    }
    let rest: Vec<usize> = (0..items.len()).filter(|i| !units.contains(i)).collect();
    let sub: Vec<Item> = rest.iter().map(|&i| items[i].clone()).collect();
    let mut s = Search::new(&sub, w, d, stop);
    let r = s.run();
    let r = match r {
        Outcome::Packed(p) => {
            let mut pos: Vec<Option<Pos>> = vec![None; items.len()];
            let mut rects: Vec<[f64; 4]> = Vec::new();
            for (k, &i) in rest.iter().enumerate() {
                let f = items[i].opts[p[k].opt];
                pos[i] = Some(p[k]);
                rects.push([p[k].x, p[k].y, p[k].x + f[0], p[k].y + f[1]]);
            }
            for &u in &units {
                let k = items[u]
                    .opts
                    .iter()
                    .position(|f| f[0] <= w + tol(w, d) && f[1] <= d + tol(w, d))
                    .expect("a unit fits");
                let g = items[u].opts[k][0];
                let cell = free_cell(&rects, g, w, d).expect("the units' area is free, on the lattice");
                rects.push([cell.0, cell.1, cell.0 + g, cell.1 + g]);
                pos[u] = Some(Pos {
                    opt: k,
                    x: cell.0,
                    y: cell.1,
                });
            }
            Outcome::Packed(pos.into_iter().map(|p| p.expect("every item placed")).collect())
        }
        o => o,
    };
    (r, s.nodes)
}

/// The items [`decide`] may set aside (empty: none).
fn unit_items(items: &[Item], w: f64, d: f64) -> Vec<usize> {
    let t = tol(w, d);
    let fits: Vec<Vec<[f64; 2]>> = items.iter().map(|it| fitting(it, w, d).collect()).collect();
    if items.len() < 2 || fits.iter().any(|f| f.is_empty()) {
        return Vec::new();
    }
    // The smallest extent of all; units are the items whose only fitting footprint is g × g.
    let g = fits
        .iter()
        .flatten()
        .flat_map(|f| [f[0], f[1]])
        .fold(f64::INFINITY, f64::min);
    if g <= t {
        return Vec::new();
    }
    let on_lattice = |v: f64| ((v / g) - (v / g).round()).abs() <= 1e-7 * (1.0 + v / g);
    let all_extents = items.iter().flat_map(|it| it.opts.iter()).flat_map(|f| [f[0], f[1]]);
    if !on_lattice(w) || !on_lattice(d) || !all_extents.clone().all(on_lattice) {
        return Vec::new();
    }
    let units: Vec<usize> = (0..items.len())
        .filter(|&i| fits[i].iter().all(|f| (f[0] - g).abs() <= t && (f[1] - g).abs() <= t))
        .collect();
    if units.is_empty() || units.len() == items.len() {
        return Vec::new();
    }
    let others: f64 = (0..items.len())
        .filter(|i| !units.contains(i))
        .map(|i| fits[i].iter().map(|f| f[0] * f[1]).fold(0.0, f64::max))
        .sum();
    if w * d - others < units.len() as f64 * g * g - t * (w + d) {
        return Vec::new();
    }
    units
}

/// A free `g × g` cell among `rects` (`[x0, y0, x1, y1]`, all on the `g`-lattice) in `w × d`:
/// slid left and then down, a free lattice cell stops with its left edge at 0 or a right edge
/// and its bottom at 0 or a top, so those are the only places to look.
fn free_cell(rects: &[[f64; 4]], g: f64, w: f64, d: f64) -> Option<(f64, f64)> {
    let t = tol(w, d);
    let xs = std::iter::once(0.0).chain(rects.iter().map(|r| r[2]));
    let ys: Vec<f64> = std::iter::once(0.0).chain(rects.iter().map(|r| r[3])).collect();
    for x in xs {
        for &y in &ys {
            if x + g > w + t || y + g > d + t {
                continue;
            }
            let clear = rects
                .iter()
                .all(|r| r[2].min(x + g) - r[0].max(x) <= t || r[3].min(y + g) - r[1].max(y) <= t);
            if clear {
                return Some((x, y));
            }
        }
    }
    None
}

/// What enumeration hands each packing to; `true` stops it.
pub type Visitor<'a> = dyn FnMut(&[Pos]) -> bool + 'a;

/// The exact search for one box.
pub struct Search<'a> {
    items: &'a [Item],
    w: f64,
    d: f64,
    t: f64,
    stop: &'a dyn Fn() -> bool,
    /// Search nodes visited (both phases).
    pub nodes: u64,
    stopped: bool,
    /// Previous item of the same class (identical objects are placed in index order).
    prev_same: Vec<Option<usize>>,
    /// Least area of each item among its fitting footprints.
    min_area: Vec<f64>,
    /// Least depth of each item among its fitting footprints.
    min_depth: Vec<f64>,
    /// First item of the largest class, kept in the lower-left quarter (mirror symmetry).
    anchor: Option<usize>,
    /// Per item: chosen footprint and left edge in the x-phase.
    opt: Vec<usize>,
    x0: Vec<f64>,
    placed: Vec<bool>,
    y0: Vec<f64>,
    /// x-phase states (position, placed set, free-depth profile ahead) proven to have no
    /// complete x-assignment, with the least waste at which that was shown.
    dead: HashMap<StateKey, (f64, f64)>,
    /// Complete x-assignments handed to the y-phase so far.
    yleaves: u64,
    /// Enumeration mode: every packing goes to the visitor (which returns `true` to stop);
    /// no mirror symmetry breaking, since what the visitor measures need not be symmetric.
    visit: Option<&'a mut Visitor<'a>>,
    dead_enabled: bool,
    /// Contact pruning (enumeration for the contact stage): branches whose contact-length upper
    /// bound does not beat this value are cut.
    cbound: Option<&'a Cell<f64>>,
    /// The box reaches the container's far walls (x = its width, y = its depth), which then
    /// count as contact.
    far: [bool; 2],
    /// Left sides of placed items that cannot be in full contact, summed (x-phase).
    ldef: f64,
    /// Bottom sides of items placed in the y-phase not in contact, summed.
    ydef: f64,
    /// Contact bound of the current complete x-assignment.
    ub_x: f64,
    /// Branches cut by the contact bound.
    cpruned: u64,
    /// Per item, for the current x-assignment (built by `ycheck`): the items covering its left
    /// edge (itself included), the other items overlapping it in x, and the items ending at its
    /// left edge.
    ycover: Vec<Vec<usize>>,
    yover: Vec<Vec<usize>>,
    yleft: Vec<Vec<usize>>,
    /// The items off the left wall, grouped by left edge (current x-assignment).
    ygroups: Vec<Vec<usize>>,
}

impl<'a> Search<'a> {
    /// Enumerate packings in `w × d` (each at most once, every one whose objects all touch
    /// something on their left and below among them) into `visit`. With `bound`, only packings
    /// whose contact length (objects, the walls x = 0 and y = 0, and the far walls where `far`
    /// says the box reaches them) may exceed it are guaranteed to be visited; the visitor may
    /// raise it. Returns whether the enumeration finished (`false`: stopped by `stop`).
    pub fn enumerate(
        items: &'a [Item],
        w: f64,
        d: f64,
        stop: &'a dyn Fn() -> bool,
        visit: &'a mut Visitor<'a>,
        bound: Option<&'a Cell<f64>>,
        far: [bool; 2],
    ) -> (bool, u64) {
        let mut s = Search::new(items, w, d, stop);
        s.anchor = None;
        s.visit = Some(visit);
        s.cbound = bound;
        s.far = far;
        let complete = matches!(s.run(), Outcome::Infeasible);
        (complete, s.nodes)
    }

    /// A search for `items` in `w × d`; `stop` is polled now and then.
    pub fn new(items: &'a [Item], w: f64, d: f64, stop: &'a dyn Fn() -> bool) -> Self {
        let n = items.len();
        let t = tol(w, d);
        let prev_same: Vec<Option<usize>> = (0..n)
            .map(|i| (0..i).rev().find(|&j| items[j].class == items[i].class))
            .collect();
        let min_area: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[0] * g[1]).fold(f64::INFINITY, f64::min))
            .collect();
        let min_depth: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[1]).fold(f64::INFINITY, f64::min))
            .collect();
        // The anchor is the first item of the class with the largest single area: mirroring
        // keeps footprints, so the bound below uses its narrowest fitting footprint.
        let anchor = (0..n)
            .filter(|&i| prev_same[i].is_none() && min_area[i].is_finite())
            .max_by(|&a, &b| min_area[a].total_cmp(&min_area[b]));
        Search {
            items,
            w,
            d,
            t,
            stop,
            nodes: 0,
            stopped: false,
            prev_same,
            min_area,
            min_depth,
            anchor,
            opt: vec![0; n],
            x0: vec![0.0; n],
            placed: vec![false; n],
            y0: vec![0.0; n],
            visit: None,
            dead: HashMap::new(),
            yleaves: 0,
            dead_enabled: true,
            cbound: None,
            far: [false; 2],
            ldef: 0.0,
            ydef: 0.0,
            ub_x: 0.0,
            cpruned: 0,
            ycover: vec![Vec::new(); n],
            yover: vec![Vec::new(); n],
            yleft: vec![Vec::new(); n],
            ygroups: Vec::new(),
        }
    }

    /// Decide the box.
    pub fn run(&mut self) -> Outcome {
        if self.items.len() > 64 {
            // The state key is a 64-bit set; so large an instance is out of reach anyway.
            self.dead_enabled = false;
        }
        if refuted_by_bounds(self.items, self.w, self.d) {
            return Outcome::Infeasible;
        }
        let rem: f64 = self.min_area.iter().sum();
        if self.xphase(0.0, 0, 0.0, rem, 0.0) {
            return Outcome::Packed(self.positions());
        }
        if self.stopped {
            Outcome::Stopped
        } else {
            Outcome::Infeasible
        }
    }

    /// Where every item is now.
    fn positions(&self) -> Vec<Pos> {
        (0..self.items.len())
            .map(|i| Pos {
                opt: self.opt[i],
                x: self.x0[i],
                y: self.y0[i],
            })
            .collect()
    }

    /// The y-phase alone, for a given x-assignment (per item: footprint index and left edge): a
    /// packing with exactly these x-coordinates and footprints, or `Infeasible` (none exists),
    /// or `Stopped`. This is the subproblem of the Benders decomposition
    /// ([`crate::placement::milp`]'s HiGHS master decides the x-coordinates).
    pub fn y_for(&mut self, opt: &[usize], x0: &[f64]) -> Outcome {
        // The mirror rule of `run` pairs with the x-phase's; the master has no such rule.
        self.anchor = None;
        self.opt.copy_from_slice(opt);
        self.x0.copy_from_slice(x0);
        self.placed.iter_mut().for_each(|p| *p = true);
        if self.ycheck() {
            Outcome::Packed(self.positions())
        } else if self.stopped {
            Outcome::Stopped
        } else {
            Outcome::Infeasible
        }
    }

    fn tick(&mut self) -> bool {
        self.nodes += 1;
        if self.nodes & 1023 == 0 && (self.stop)() {
            self.stopped = true;
        }
        self.stopped
    }

    fn dims(&self, i: usize) -> [f64; 2] {
        self.items[i].opts[self.opt[i]]
    }

    /// Largest left edge the anchor may take with its narrowest fitting footprint.
    fn anchor_limit(&self, axis: usize) -> f64 {
        let cap = if axis == 0 { self.w } else { self.d };
        let a = self.anchor.expect("anchor exists when items do");
        let least = fitting(&self.items[a], self.w, self.d)
            .map(|g| g[axis])
            .fold(f64::INFINITY, f64::min);
        (cap - least) / 2.0 + self.t
    }

    /// Free depth from `t` on, column by column: an object of depth `h` fits only in columns
    /// with at least `h` free, so the objects of least depth at least `h` (their least areas)
    /// must fit in those columns' free area, for every such `h`.
    fn capacity_refutes(&self, t: f64) -> bool {
        let n = self.items.len();
        let mut ends: Vec<(f64, f64)> = (0..n)
            .filter(|&j| self.placed[j])
            .map(|j| (self.x0[j] + self.dims(j)[0], self.dims(j)[1]))
            .filter(|&(e, _)| e > t + self.t)
            .collect();
        ends.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut load: f64 = ends.iter().map(|e| e.1).sum();
        let mut pieces: Vec<(f64, f64)> = Vec::with_capacity(ends.len() + 1);
        let mut x = t;
        for &(e, h) in &ends {
            pieces.push((e - x, self.d - load));
            load -= h;
            x = e;
        }
        pieces.push((self.w - x, self.d));
        let mut rem: Vec<usize> = (0..n).filter(|&i| !self.placed[i]).collect();
        rem.sort_by(|&a, &b| self.min_depth[b].total_cmp(&self.min_depth[a]));
        let tol = self.t * (self.w + self.d);
        let mut area = 0.0;
        for &i in &rem {
            area += self.min_area[i];
            let h = self.min_depth[i];
            let avail: f64 = pieces.iter().filter(|p| p.1 >= h - self.t).map(|p| p.0 * p.1).sum();
            if area > avail + tol {
                return true;
            }
        }
        false
    }

    /// Contact-length upper bound in the x-phase: every side in full contact except the
    /// deficits known so far, plus the far walls' lengths.
    fn contact_ub(&self) -> f64 {
        let n = self.items.len();
        let sides: f64 = (0..n)
            .map(|i| {
                if self.placed[i] {
                    let f = self.dims(i);
                    f[0] + f[1]
                } else {
                    fitting(&self.items[i], self.w, self.d)
                        .map(|g| g[0] + g[1])
                        .fold(0.0, f64::max)
                }
            })
            .sum();
        let far = if self.far[0] { self.d } else { 0.0 } + if self.far[1] { self.w } else { 0.0 };
        sides - self.ldef + far
    }

    /// x-phase at position `t` (every placed item starts at or before it): place an item at
    /// `t` (index at least `min_idx`, so that items sharing a left edge come in index order),
    /// or move `t` to the next right edge, leaving the column's free height unused for good.
    fn xphase(&mut self, t: f64, min_idx: usize, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        if self.tick() {
            return false;
        }
        let n = self.items.len();
        if let Some(cb) = self.cbound {
            if self.contact_ub() <= cb.get() + 1e-9 {
                self.cpruned += 1;
                return false;
            }
        }
        if (0..n).all(|i| self.placed[i]) {
            return self.ycheck();
        }
        let tol = self.t * (self.w + self.d);
        if placed_area + rem_area + waste > self.w * self.d + tol {
            return false;
        }
        if self.capacity_refutes(t) {
            return false;
        }
        // States reached again by another order of the objects behind `t`: the x-phase ahead
        // depends only on which objects are placed, where the placed ones end, and how deep they
        // are — and on the waste so far, which only makes pruning easier. A state whose subtree
        // failed without reaching the y-phase fails again at no less waste. When enumerating
        // under a contact bound, the contact cuts ahead depend on the state, on the right sides
        // ending at `t` (put in the key) and on the contact bound of the placed part; the bound
        // to beat only rises, so a subtree cut at some contact bound is cut again at no more.
        let key = (min_idx == 0 && self.dead_enabled).then(|| self.state_key(t));
        let ub = if self.cbound.is_some() { self.contact_ub() } else { 0.0 };
        if let Some(k) = &key {
            if self
                .dead
                .get(k)
                .is_some_and(|&(w0, u0)| w0 <= waste + tol && ub <= u0 + 1e-9)
            {
                return false;
            }
        }
        let (leaves_before, cut_before) = (self.yleaves, self.cpruned);
        let found = self.xbranch(t, min_idx, placed_area, rem_area, waste);
        if let Some(k) = key {
            if !found && !self.stopped && self.yleaves == leaves_before && self.dead.len() < DEAD_MAX {
                let u = if self.cpruned == cut_before { f64::INFINITY } else { ub };
                let e = self.dead.entry(k).or_insert((waste, u));
                // Keep the record that covers more (the waste is the same for one key: the
                // area behind `t` is placed or wasted, and the placed part ahead is in the key).
                if waste <= e.0 + tol && u >= e.1 {
                    *e = (waste, u);
                }
            }
        }
        found
    }

    /// The memo key of the x-phase state at `t`, lengths in units of the tolerance.
    fn state_key(&self, t: f64) -> StateKey {
        let q = |v: f64| (v / self.t).round() as i64;
        let n = self.items.len();
        let mut mask = 0u64;
        let mut active = Vec::new();
        for j in 0..n {
            if self.placed[j] {
                mask |= 1 << j;
                let e = self.x0[j] + self.dims(j)[0];
                if e > t + self.t {
                    active.push((q(e), q(self.dims(j)[1])));
                }
            }
        }
        active.sort_unstable();
        if self.cbound.is_some() {
            // Contact bounds at `t` depend on the right sides ending there.
            let ends: f64 = (0..n)
                .filter(|&j| self.placed[j] && (self.x0[j] + self.dims(j)[0] - t).abs() <= self.t)
                .map(|j| self.dims(j)[1])
                .sum();
            active.push((i64::MIN, q(ends)));
        }
        (mask, q(t), active)
    }

    /// The branches of [`Self::xphase`] at `t`.
    fn xbranch(&mut self, t: f64, min_idx: usize, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        let n = self.items.len();
        let load: f64 = (0..n)
            .filter(|&j| self.placed[j] && self.x0[j] + self.dims(j)[0] > t + self.t)
            .map(|j| self.dims(j)[1])
            .sum();
        let cap = self.d - load;
        for i in min_idx..n {
            if self.placed[i] || self.prev_same[i].is_some_and(|p| !self.placed[p]) {
                continue;
            }
            if Some(i) == self.anchor && t > self.anchor_limit(0) {
                continue;
            }
            for k in 0..self.items[i].opts.len() {
                let f = self.items[i].opts[k];
                if f[0] > self.w - t + self.t || f[1] > cap + self.t {
                    continue;
                }
                // Its left side touches only objects ending at `t` (all placed) or the wall; the
                // objects starting at `t` share the right sides of those ending there, so what
                // the ones placed at `t` before it took is not left for it.
                let left = if t <= self.t {
                    f[1]
                } else {
                    let (mut ends, mut starts) = (0.0, 0.0);
                    for j in (0..n).filter(|&j| self.placed[j]) {
                        if (self.x0[j] + self.dims(j)[0] - t).abs() <= self.t {
                            ends += self.dims(j)[1];
                        } else if (self.x0[j] - t).abs() <= self.t {
                            starts += self.dims(j)[1];
                        }
                    }
                    f64::max(ends - starts, 0.0).min(f[1])
                };
                self.placed[i] = true;
                self.opt[i] = k;
                self.x0[i] = t;
                self.ldef += f[1] - left;
                let a = f[0] * f[1];
                let found = self.xphase(t, i + 1, placed_area + a, rem_area - self.min_area[i], waste);
                self.ldef -= f[1] - left;
                if found {
                    return true;
                }
                self.placed[i] = false;
                if self.stopped {
                    return false;
                }
            }
        }
        // Advance to the next right edge: nothing placed later starts before it.
        let next = (0..n)
            .filter(|&j| self.placed[j])
            .map(|j| self.x0[j] + self.dims(j)[0])
            .filter(|&e| e > t + self.t)
            .fold(f64::INFINITY, f64::min);
        if !next.is_finite() || next > self.w - self.t {
            return false;
        }
        if let Some(a) = self.anchor {
            if !self.placed[a] && next > self.anchor_limit(0) {
                return false;
            }
        }
        self.xphase(next, 0, placed_area, rem_area, waste + (next - t) * cap)
    }

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
    fn ycheck(&mut self) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn squares(n: usize) -> Vec<Item> {
        (1..=n)
            .rev()
            .map(|s| Item {
                opts: vec![[s as f64, s as f64]],
                class: s,
            })
            .collect()
    }

    /// Each item's rectangle `[x0, y0, x1, y1]`.
    fn rects(items: &[Item], p: &[Pos]) -> Vec<[f64; 4]> {
        p.iter()
            .zip(items)
            .map(|(q, it)| {
                let f = it.opts[q.opt];
                [q.x, q.y, q.x + f[0], q.y + f[1]]
            })
            .collect()
    }

    fn valid(items: &[Item], p: &[Pos], w: f64, d: f64) -> bool {
        let r = rects(items, p);
        r.iter()
            .all(|a| a[0] >= -1e-9 && a[1] >= -1e-9 && a[2] <= w + 1e-9 && a[3] <= d + 1e-9)
            && (0..r.len()).all(|i| {
                (i + 1..r.len()).all(|j| {
                    let (a, b) = (r[i], r[j]);
                    a[2].min(b[2]) - a[0].max(b[0]) <= 1e-9 || a[3].min(b[3]) - a[1].max(b[1]) <= 1e-9
                })
            })
    }

    #[test]
    fn squares_one_to_eight_fit_fourteen_by_fifteen_not_smaller() {
        let it = squares(8);
        let never = || false;
        match Search::new(&it, 14.0, 15.0, &never).run() {
            Outcome::Packed(p) => assert!(valid(&it, &p, 14.0, 15.0)),
            o => panic!("expected a packing, got {o:?}"),
        }
        // 13 × 16 = 208 < 210: the optimum is 210 (OEIS A038666).
        assert_eq!(Search::new(&it, 13.0, 16.0, &never).run(), Outcome::Infeasible);
        assert_eq!(Search::new(&it, 12.0, 17.0, &never).run(), Outcome::Infeasible);
    }

    /// A small linear congruential generator (the tests need no statistics, only variety).
    struct Lcg(u64);
    impl Lcg {
        fn below(&mut self, n: u64) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 33) % n
        }
    }

    /// 2 to 6 random items of integer sides 1 to 4, some rotatable, a third of them unit squares
    /// when `units`; identical items share a class and come in index order.
    fn random_items(rng: &mut Lcg, units: bool) -> Vec<Item> {
        let n = 2 + rng.below(5) as usize;
        let mut items: Vec<Item> = Vec::new();
        for k in 0..n {
            let (a, b) = if units && rng.below(3) == 0 {
                (1.0, 1.0)
            } else {
                ((1 + rng.below(4)) as f64, (1 + rng.below(4)) as f64)
            };
            let opts = if a != b && rng.below(2) == 0 {
                vec![[a, b], [b, a]]
            } else {
                vec![[a, b]]
            };
            let class = items.iter().find(|it| it.opts == opts).map(|it| it.class).unwrap_or(k);
            items.push(Item { opts, class });
        }
        items.sort_by_key(|it| it.class);
        items
    }

    /// Random small instances with unit squares among rectangles (some rotatable), in random
    /// boxes: setting the units aside never changes the answer of the full search.
    #[test]
    fn setting_unit_items_aside_keeps_every_answer() {
        let mut rng = Lcg(7);
        let never = || false;
        let (mut packed, mut refuted, mut with_units) = (0, 0, 0);
        for case in 0..400 {
            let items = random_items(&mut rng, true);
            let (w, d) = ((1 + rng.below(6)) as f64, (1 + rng.below(6)) as f64);
            let full = Search::new(&items, w, d, &never).run();
            with_units += !unit_items(&items, w, d).is_empty() as u32;
            let (r, _) = decide(&items, w, d, &never);
            match (&full, &r) {
                (Outcome::Packed(_), Outcome::Packed(p)) => {
                    assert!(valid(&items, p, w, d), "case {case}: {items:?} in {w} × {d}: {p:?}");
                    packed += 1;
                }
                (Outcome::Infeasible, Outcome::Infeasible) => refuted += 1,
                _ => panic!("case {case}: {items:?} in {w} × {d}: full {full:?}, with units aside {r:?}"),
            }
        }
        assert!(
            packed > 50 && refuted > 50 && with_units > 50,
            "{packed} {refuted} {with_units}"
        );
    }

    /// Contact length of a packing in `w × d` placed at the container's corner (far walls not
    /// counted), from the definition: shared edge lengths plus edges on x = 0 and y = 0; `None`
    /// when some item touches nothing on its left or below (not BL-stable).
    fn contact_if_stable(items: &[Item], p: &[Pos]) -> Option<f64> {
        let r = rects(items, p);
        let ov = |a0: f64, a1: f64, b0: f64, b1: f64| (a1.min(b1) - a0.max(b0)).max(0.0);
        let mut total = 0.0;
        for a in &r {
            let left: f64 = if a[0] <= 1e-9 {
                a[3] - a[1]
            } else {
                r.iter()
                    .filter(|b| (b[2] - a[0]).abs() <= 1e-9)
                    .map(|b| ov(a[1], a[3], b[1], b[3]))
                    .sum()
            };
            let below: f64 = if a[1] <= 1e-9 {
                a[2] - a[0]
            } else {
                r.iter()
                    .filter(|b| (b[3] - a[1]).abs() <= 1e-9)
                    .map(|b| ov(a[0], a[2], b[0], b[2]))
                    .sum()
            };
            if left <= 1e-9 || below <= 1e-9 {
                return None;
            }
            total += left + below;
        }
        Some(total)
    }

    /// Every contact cut of the enumeration (left sides shared at one edge, bottoms over
    /// committed holes, dead states under a contact bound) keeps the best packing: on random
    /// small instances, the most contact over the BL-stable packings of a box is the same with
    /// the cuts (bound raised by every find) as without them.
    #[test]
    fn contact_cuts_keep_the_best_packing() {
        let mut rng = Lcg(11);
        let never = || false;
        let mut compared = 0;
        for case in 0..300 {
            let items = random_items(&mut rng, false);
            // Boxes near the items' area, where packings exist and have waste to place.
            let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
            let w = (2 + rng.below(5)) as f64;
            let d = (area / w).ceil() + rng.below(3) as f64;
            let mut all = f64::NEG_INFINITY;
            let mut visit_all = |p: &[Pos]| {
                if let Some(c) = contact_if_stable(&items, p) {
                    all = all.max(c);
                }
                false
            };
            let (done, _) = Search::enumerate(&items, w, d, &never, &mut visit_all, None, [false; 2]);
            assert!(done);
            let bound = Cell::new(-1.0);
            let mut best = f64::NEG_INFINITY;
            let mut visit_cut = |p: &[Pos]| {
                if let Some(c) = contact_if_stable(&items, p) {
                    if c > bound.get() + 1e-9 {
                        bound.set(c);
                        best = c;
                    }
                }
                false
            };
            let (done, _) = Search::enumerate(&items, w, d, &never, &mut visit_cut, Some(&bound), [false; 2]);
            assert!(done);
            assert!(
                (all - best).abs() <= 1e-9 || (all.is_infinite() && best.is_infinite()),
                "case {case}: {items:?} in {w} × {d}: {all} without cuts, {best} with"
            );
            compared += all.is_finite() as u32;
        }
        assert!(compared > 150, "{compared}");
    }

    #[test]
    fn bounds_refute_only_what_cannot_fit() {
        let it = squares(3);
        assert!(refuted_by_bounds(&it, 4.0, 3.0));
        assert!(!refuted_by_bounds(&it, 5.0, 3.0));
    }
}

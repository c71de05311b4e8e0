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

/// An x-phase state: placed set (low and high halves), position (and 0), then the (end, depth)
/// of the placed objects still open, sorted, and, enumerating under a contact bound, `i32::MIN`
/// and the right sides ending at the position; lengths in units of the tolerance. Lengths fit
/// 32 bits (a length of at most `w + d` is below 10⁹ tolerances, [`tol`]), which halves what the
/// memo keeps per state; one slice, so that a key built in a buffer is looked up as it is.
type StateKey = Box<[(i32, i32)]>;

/// Most x-phase states remembered as dead at once, per memo and search thread (about 150 bytes
/// each: some 75 MB). A full memo starts afresh. Measured on the box 71 × 47 of squares 1…21
/// (`placement_squares -- --boxes 21 --only 71x47`): 35 M nodes and 52 MB at 250 k states,
/// 32 M and 152 MB at 1 M, 31 M and 396 MB never full.
const DEAD_MAX: usize = 500_000;

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

impl Pos {
    /// The same position mirrored in the line `x = y` (for [`turned`] items).
    pub fn transposed(self) -> Pos {
        Pos {
            opt: self.opt,
            x: self.y,
            y: self.x,
        }
    }
}

/// The items with x and y swapped: each footprint transposed, in the same order, so that a
/// [`Pos`] of the turned items, [`Pos::transposed`], is one of the items.
pub fn turned(items: &[Item]) -> Vec<Item> {
    items
        .iter()
        .map(|it| Item {
            opts: it.opts.iter().map(|f| [f[1], f[0]]).collect(),
            class: it.class,
        })
        .collect()
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

/// Decide the box with [`Search`]: first the instance without its three smallest items (from
/// eight items on; a box that relaxation does not fit in is refuted), then the whole instance,
/// with the unit items set aside when that is safe: items whose only fitting footprint is a
/// `g × g` square, where `g` divides every footprint extent and the box's sides. Every packing
/// the search finds has its edges on the `g`-lattice (left edges are 0 or right edges, bottoms
/// 0 or tops, all sums of extents), so its free space is a union of `g`-cells; when the other
/// items, at their largest footprints, leave at least the units' area free, each unit goes into
/// a free cell, and the others packing is equivalent to all packing. Returns the outcome and
/// the nodes visited.
pub fn decide(items: &[Item], w: f64, d: f64, stop: &dyn Fn() -> bool) -> (Outcome, u64) {
    decide_metered(items, w, d, stop, None, 1)
}

/// [`decide`], keeping `meter` up to date with the nodes visited ([`Search::metered`]; the
/// caller adds the returned count when it returns), on `threads` threads (the same answer on
/// any number: docs/algorithms.md, *Threads*).
pub fn decide_metered(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    meter: Option<&std::cell::Cell<u64>>,
    threads: usize,
) -> (Outcome, u64) {
    let mut nodes = 0;
    if let Some(sub) = relaxation(items, w, d) {
        let (r, n) = decide_all(&sub, w, d, stop, meter, threads);
        nodes += n;
        // When the relaxation packs, only the whole instance can say whether it does.
        if !matches!(r, Outcome::Packed(_)) {
            return (r, nodes);
        }
    }
    let (r, n) = decide_all(items, w, d, stop, meter, threads);
    (r, nodes + n)
}

/// How many of the smallest items [`relaxation`] leaves out: three was the fastest on squares
/// 1…22 (two, four and five took 1.5–3.4× as long; docs/algorithms.md, *Small items left out
/// first*).
const RELAX_DROP: usize = 3;

/// The fewest items for which [`relaxation`] leaves any out: below that every box is decided
/// in milliseconds anyway, and the relaxation would be most of the instance's freedom.
const RELAX_MIN_ITEMS: usize = 8;

/// The relaxation [`decide_metered`] decides before the whole instance: the instance without
/// its [`RELAX_DROP`] smallest items (least fitting area, ties in index order). A box the
/// relaxation cannot be packed in holds no packing of all the items; the small items are what
/// multiplies the x-phase's branches (each fits almost anywhere) while adding little to what
/// the bounds can refute.
fn relaxation(items: &[Item], w: f64, d: f64) -> Option<Vec<Item>> {
    if items.len() < RELAX_MIN_ITEMS || refuted_by_bounds(items, w, d) {
        return None;
    }
    let area = |i: usize| {
        fitting(&items[i], w, d)
            .map(|g| g[0] * g[1])
            .fold(f64::INFINITY, f64::min)
    };
    let mut by_area: Vec<usize> = (0..items.len()).collect();
    by_area.sort_by(|&a, &b| area(a).total_cmp(&area(b)));
    let drop = &by_area[..RELAX_DROP];
    let keep = (0..items.len()).filter(|i| !drop.contains(i));
    Some(keep.map(|i| items[i].clone()).collect())
}

/// [`decide_metered`] on the whole instance: the unit items set aside when that is safe, then
/// the search.
fn decide_all(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    meter: Option<&std::cell::Cell<u64>>,
    threads: usize,
) -> (Outcome, u64) {
    let units = unit_items(items, w, d);
    if units.is_empty() {
        return search(items, w, d, stop, meter, threads);
    }
    if refuted_by_bounds(items, w, d) {
        return (Outcome::Infeasible, 0);
    }
    let rest: Vec<usize> = (0..items.len()).filter(|i| !units.contains(i)).collect();
    let sub: Vec<Item> = rest.iter().map(|&i| items[i].clone()).collect();
    let (r, nodes) = search(&sub, w, d, stop, meter, threads);
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
    (r, nodes)
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

mod dominance;
mod faces;
mod search;
mod subset;
mod threads;
pub use search::{Search, Visitor};
use threads::search;
pub use threads::{best_packing, Scored};

#[cfg(test)]
mod tests;

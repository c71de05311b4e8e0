//! First, area stage of the exact placement: enclosing boxes `W × D` in increasing area, each
//! decided exactly by [`super::opp`].
//!
//! Every placement compacts into a BL-stable one with no larger extents, whose extents are
//! subset sums of footprint x- and y-extents (one per object). So the least occupied area is the
//! area of the first box `(W, D)`, `W` and `D` such sums within the container, that holds a
//! packing, when boxes go in increasing area: every smaller box has been proven empty of
//! packings. The next box not yet decided is therefore a proven lower bound at any moment, and
//! it only rises. A box proven infeasible also rules out every box it contains (and, when every
//! object's footprints are closed under swapping x and y and the container allows, its
//! transpose).

use super::opp::{self, Item, Outcome};
use super::{Placement, Target};
use crate::geometry::{Orientation, Rect, EPS};
use crate::instance::Instance;
use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::time::Instant;

/// One way an object can stand: the extents of its footprint, an orientation giving them, and
/// its height then.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// x- and y-extent.
    pub size: [f64; 2],
    /// An orientation with this footprint.
    pub orientation: Orientation,
    /// Height in that orientation.
    pub height: f64,
}

/// The distinct footprints of one object.
pub type Footprints = Vec<Footprint>;

/// One point of the bound-over-time trace.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoundPoint {
    /// Seconds since the start of the placement.
    pub t_s: f64,
    /// Proven lower bound on the occupied area then.
    pub lower_bound: f64,
    /// Occupied area of the best placement then (`null` before the first).
    pub incumbent: Option<f64>,
}

/// What the area stage found and proved.
#[derive(Debug, Clone, Default)]
pub struct AreaStage {
    /// Best placement found (compacted), if any.
    pub best: Option<Placement>,
    /// Proven lower bound on the occupied area.
    pub lower_bound: f64,
    /// Every box smaller than the best placement's area is proven infeasible.
    pub optimal: bool,
    /// No placement fits the container at all (proven by exhausting the boxes).
    pub infeasible: bool,
    /// Placements of every extent reaching the best area that was decided (for the contact
    /// stage), with transposes.
    pub solutions: Vec<Placement>,
    /// Every box tied with the best area was decided.
    pub ties_closed: bool,
    /// Search nodes over all boxes.
    pub nodes: u64,
    /// Boxes decided by the exact search (bounds alone decide the others).
    pub boxes_searched: u64,
    /// Boxes decided in all.
    pub boxes: u64,
    /// The proven bound and the incumbent over time.
    pub trace: Vec<BoundPoint>,
}

/// Per object, the extents of its footprints along `axis` (0: x, 1: y).
pub fn extents(fps: &[Footprints], axis: usize) -> Vec<Vec<f64>> {
    fps.iter().map(|o| o.iter().map(|f| f.size[axis]).collect()).collect()
}

/// Sorted distinct subset sums (at most one value per object) up to `limit`.
pub fn subset_sums(vals: &[Vec<f64>], limit: f64) -> Vec<f64> {
    let mut sums = vec![0.0f64];
    for opts in vals {
        let mut next = sums.clone();
        for s in &sums {
            for v in opts {
                if s + v <= limit + EPS {
                    next.push(s + v);
                }
            }
        }
        next.sort_by(f64::total_cmp);
        next.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
        sums = next;
    }
    sums
}

/// Items for the search, largest first (the search places in index order), with the map back.
fn items(fps: &[Footprints]) -> (Vec<Item>, Vec<usize>) {
    let mut order: Vec<usize> = (0..fps.len()).collect();
    let big = |i: usize| {
        fps[i]
            .iter()
            .map(|Footprint { size: f, .. }| f[0] * f[1])
            .fold(0.0, f64::max)
    };
    order.sort_by(|&a, &b| big(b).total_cmp(&big(a)).then(a.cmp(&b)));
    let same = |a: usize, b: usize| {
        fps[a].len() == fps[b].len()
            && fps[a].iter().all(|Footprint { size: f, .. }| {
                fps[b]
                    .iter()
                    .any(|Footprint { size: g, .. }| (f[0] - g[0]).abs() <= EPS && (f[1] - g[1]).abs() <= EPS)
            })
    };
    let mut class: Vec<usize> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let c = (0..k).find(|&m| same(order[m], i)).map(|m| class[m]).unwrap_or(k);
        class.push(c);
    }
    let items = order
        .iter()
        .zip(&class)
        .map(|(&i, &c)| Item {
            opts: fps[i].iter().map(|Footprint { size: f, .. }| *f).collect(),
            class: c,
        })
        .collect();
    (items, order)
}

/// Decides one box `w × d` for the items: the outcome and the nodes visited. A solver failure is
/// an error, never a refutation.
pub type Decider<'a> = dyn Fn(&[Item], f64, f64, &dyn Fn() -> bool) -> crate::error::Result<(Outcome, u64)> + 'a;

/// The exact packing search of [`opp`] as a [`Decider`].
pub fn by_search(items: &[Item], w: f64, d: f64, stop: &dyn Fn() -> bool) -> crate::error::Result<(Outcome, u64)> {
    Ok(opp::decide(items, w, d, stop))
}

/// Decide `w × d` with the x-phase along the longer side: a packing transposes with its box, and
/// the cumulative relaxation prunes more along the long side (measured: squares 1…16, 27 boxes
/// and 12.8 s with the short side first, docs/benchmarks.md). Returns the outcome and nodes.
fn decide(
    decider: &Decider,
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
) -> crate::error::Result<(Outcome, u64)> {
    if w >= d {
        return decider(items, w, d, stop);
    }
    let t = opp::turned(items);
    let (r, nodes) = decider(&t, d, w, stop)?;
    let r = match r {
        Outcome::Packed(pos) => Outcome::Packed(pos.into_iter().map(opp::Pos::transposed).collect()),
        o => o,
    };
    Ok((r, nodes))
}

/// The targets of a search result: `pos[k]` places object `order[k]`.
fn targets_of(fps: &[Footprints], order: &[usize], pos: impl Iterator<Item = opp::Pos>) -> Vec<Target> {
    let mut targets = vec![None; fps.len()];
    for (k, p) in pos.enumerate() {
        let i = order[k];
        let Footprint {
            size: f,
            orientation: q,
            height: h,
        } = fps[i][p.opt];
        targets[i] = Some(Target {
            orientation: q,
            rect: Rect::new(p.x, p.y, f[0], f[1]),
            height: h,
        });
    }
    targets.into_iter().map(|t| t.expect("every item placed")).collect()
}

/// The placement of a search result, compacted.
fn placement(fps: &[Footprints], order: &[usize], pos: &[opp::Pos]) -> Placement {
    super::milp::compact(&Placement {
        targets: targets_of(fps, order, pos.iter().copied()),
    })
}

/// `p` mirrored in the line `x = y` (each object turned to its footprint with swapped sizes),
/// if every object has one.
pub fn transpose(p: &Placement, fps: &[Footprints]) -> Option<Placement> {
    let targets = p
        .targets
        .iter()
        .zip(fps)
        .map(|(t, opts)| {
            let (w, d) = (t.rect.width(), t.rect.depth());
            opts.iter()
                .find(|Footprint { size: f, .. }| (f[0] - d).abs() <= EPS && (f[1] - w).abs() <= EPS)
                .map(
                    |&Footprint {
                         size: f,
                         orientation: q,
                         height: h,
                     }| Target {
                        orientation: q,
                        rect: Rect::new(t.rect.y0, t.rect.x0, f[0], f[1]),
                        height: h,
                    },
                )
        })
        .collect::<Option<Vec<_>>>()?;
    Some(Placement { targets })
}

/// A box in the queue, ordered by area, then width.
#[derive(Debug, Clone, Copy, PartialEq)]
struct BoxKey {
    area: f64,
    w: f64,
    /// Index of `D` in the depth sums.
    di: usize,
}
impl Eq for BoxKey {}
impl PartialOrd for BoxKey {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for BoxKey {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.area
            .total_cmp(&o.area)
            .then(self.w.total_cmp(&o.w))
            .then(self.di.cmp(&o.di))
    }
}

/// How the area stage runs.
pub struct AreaOptions<'a> {
    /// Also decide the boxes tied with the best area (the contact stage needs them).
    pub contact: bool,
    /// When the placement started (the trace's time origin).
    pub start: Instant,
    /// Seconds the search for a first packing may take when there is no valid warm start.
    pub budget_first_s: f64,
    /// What decides each box.
    pub decider: &'a Decider<'a>,
    /// Told the proven lower bound and the incumbent's area whenever either changes (the
    /// progress events).
    pub on_bound: &'a dyn Fn(f64, Option<f64>),
}

/// Run the area stage. `warm`: a placement to start from (ignored unless valid); `stop`: polled
/// between and inside searches.
///
/// Long on purpose: one loop over the enclosing boxes in area order, whose state (incumbent,
/// proven bound, trace, ties still open, the budget for a first packing) every branch updates
/// together. Deciding one box is `decide`'s job and the packing search is [`super::opp`]'s;
/// what stays here is the order of the boxes and that shared state.
pub fn solve(
    inst: &Instance,
    fps: &[Footprints],
    warm: Option<&Placement>,
    opts: &AreaOptions,
    stop: &dyn Fn() -> bool,
) -> crate::error::Result<AreaStage> {
    let AreaOptions {
        contact,
        start,
        budget_first_s: budget_first,
        decider,
        on_bound,
    } = *opts;
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let (items, order) = items(fps);
    let (xv, yv) = (extents(fps, 0), extents(fps, 1));
    let widths: Vec<f64> = subset_sums(&xv, cw).into_iter().filter(|&v| v > EPS).collect();
    let depths: Vec<f64> = subset_sums(&yv, cd).into_iter().filter(|&v| v > EPS).collect();
    let area_tol = 1e-9 * (1.0 + cw * cd);
    let transposable = fps.iter().all(|o| {
        o.iter().all(|Footprint { size: f, .. }| {
            o.iter()
                .any(|Footprint { size: g, .. }| (g[0] - f[1]).abs() <= EPS && (g[1] - f[0]).abs() <= EPS)
        })
    });
    let mut out = AreaStage {
        lower_bound: 0.0,
        ties_closed: true,
        ..AreaStage::default()
    };
    let valid = |p: &Placement| p.violations(inst).is_empty();
    let mut best: Option<Placement> = warm.filter(|p| valid(p)).map(super::milp::compact).filter(|p| valid(p));
    let elapsed = || start.elapsed().as_secs_f64();
    let trace = |out: &mut AreaStage, lb: f64, best: &Option<Placement>| {
        let inc = best.as_ref().map(|p| p.occupied_area());
        on_bound(lb, inc);
        if out
            .trace
            .last()
            .is_none_or(|b| b.lower_bound < lb - area_tol || b.incumbent != inc)
        {
            out.trace.push(BoundPoint {
                t_s: elapsed(),
                lower_bound: lb,
                incumbent: inc,
            });
        }
    };
    // Without a valid start, look for any packing in the container first, so that a stop
    // leaves a placement to report; a proof that none exists ends the stage.
    if best.is_none() {
        let t0 = elapsed();
        let first_stop = || stop() || elapsed() - t0 > budget_first;
        let (res, nodes) = decide(decider, &items, cw, cd, &first_stop)?;
        out.nodes += nodes;
        out.boxes += 1;
        out.boxes_searched += 1;
        match res {
            Outcome::Packed(pos) => best = Some(placement(fps, &order, &pos)),
            Outcome::Infeasible => {
                out.infeasible = true;
                out.lower_bound = f64::INFINITY;
                return Ok(out);
            }
            Outcome::Stopped => {}
        }
    }
    // Least depth for each width, from the bounds that need no search.
    let mut heap: BinaryHeap<Reverse<BoxKey>> = BinaryHeap::new();
    let sum_area: f64 = fps
        .iter()
        .map(|o| {
            o.iter()
                .map(|Footprint { size: f, .. }| f[0] * f[1])
                .fold(f64::INFINITY, f64::min)
        })
        .sum();
    for &w in &widths {
        let need = sum_area / w - 1e-9 * (1.0 + cd);
        let di = depths.partition_point(|&t| t < need);
        if di < depths.len() {
            heap.push(Reverse(BoxKey {
                area: w * depths[di],
                w,
                di,
            }));
        }
    }
    let mut refuted: Vec<(f64, f64)> = Vec::new();
    let mut solutions: Vec<Placement> = Vec::new();
    let mut best_area = best.as_ref().map(|p| p.occupied_area()).unwrap_or(f64::INFINITY);
    if let Some(p) = &best {
        solutions.push(p.clone());
        solutions.extend(transpose(p, fps).filter(valid));
    }
    let mut lb = heap.peek().map(|k| k.0.area).unwrap_or(f64::INFINITY).min(best_area);
    trace(&mut out, lb, &best);
    let mut stopped = false;
    while let Some(Reverse(k)) = heap.peek().copied() {
        // Past the incumbent: done (ties only matter to the contact stage).
        if k.area > best_area + area_tol || (!contact && k.area >= best_area - area_tol) {
            break;
        }
        if stop() {
            stopped = true;
            break;
        }
        heap.pop();
        let (w, d) = (k.w, depths[k.di]);
        let contained = |(rw, rd): (f64, f64)| w <= rw + 1e-9 && d <= rd + 1e-9;
        let feasible_known = best
            .as_ref()
            .is_some_and(|p| (p.extent().0 - w).abs() <= 1e-9 && (p.extent().1 - d).abs() <= 1e-9);
        let res = if refuted.iter().any(|&r| contained(r)) {
            Outcome::Infeasible
        } else if feasible_known {
            Outcome::Stopped // decided already; nothing to record
        } else {
            out.boxes_searched += 1;
            let (r, nodes) = decide(decider, &items, w, d, stop)?;
            out.nodes += nodes;
            r
        };
        out.boxes += 1;
        match res {
            Outcome::Infeasible => {
                refuted.push((w, d));
                if transposable && d <= cw + 1e-9 && w <= cd + 1e-9 {
                    refuted.push((d, w));
                }
                if k.di + 1 < depths.len() {
                    heap.push(Reverse(BoxKey {
                        area: w * depths[k.di + 1],
                        w,
                        di: k.di + 1,
                    }));
                }
            }
            Outcome::Packed(pos) => {
                let p = placement(fps, &order, &pos);
                let a = p.occupied_area();
                if a < best_area - area_tol {
                    best_area = a;
                    solutions.clear();
                }
                if a <= best_area + area_tol {
                    for q in std::iter::once(p.clone()).chain(transpose(&p, fps).filter(valid)) {
                        let e = q.extent();
                        if !solutions
                            .iter()
                            .any(|s| (s.extent().0 - e.0).abs() <= 1e-9 && (s.extent().1 - e.1).abs() <= 1e-9)
                        {
                            solutions.push(q);
                        }
                    }
                }
                if best.as_ref().is_none_or(|b| a < b.occupied_area() - area_tol) {
                    best = Some(p);
                }
            }
            Outcome::Stopped if !feasible_known => {
                // Not decided: it stays the least open box.
                heap.push(Reverse(k));
                stopped = true;
                break;
            }
            Outcome::Stopped => {}
        }
        let next = heap.peek().map(|k| k.0.area).unwrap_or(f64::INFINITY);
        lb = lb.max(next.min(best_area));
        trace(&mut out, lb, &best);
    }
    let next_open = heap.peek().map(|k| k.0.area).unwrap_or(f64::INFINITY);
    out.lower_bound = lb.max(next_open.min(best_area));
    if best.is_none() && !stopped && heap.is_empty() {
        out.infeasible = true;
    }
    out.optimal = best.is_some() && out.lower_bound >= best_area - area_tol;
    out.ties_closed = out.optimal && !(stopped && next_open <= best_area + area_tol);
    out.solutions = solutions;
    let final_lb = out.lower_bound;
    trace(&mut out, final_lb, &best);
    out.best = best;
    Ok(out)
}

/// Second stage by enumeration: the most contact length among the BL-stable packings inside
/// `w × d` (the search meets every one of them, see [`opp`]), if more than `to_beat`, on
/// `threads` threads (the same answer on any number: [`opp::best_packing`]). Returns the best
/// placement found (`None`: none beats `to_beat`), whether the enumeration finished (then
/// nothing in the box beats the result), the nodes visited, and an upper bound on the contact
/// of the placements it did not rule out (`-∞` when it finished). `meter`: a node count kept
/// up to date for progress events.
pub fn max_contact(
    inst: &Instance,
    fps: &[Footprints],
    (w, d): (f64, f64),
    to_beat: f64,
    stop: &dyn Fn() -> bool,
    meter: Option<&std::cell::Cell<u64>>,
    threads: usize,
) -> (Option<Placement>, bool, u64, f64) {
    let (items, order) = items(fps);
    let flip = w < d;
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let far = [w >= cw - EPS, d >= cd - EPS];
    let far = if flip { [far[1], far[0]] } else { far };
    let unflip = |p: &opp::Pos| if flip { p.transposed() } else { *p };
    // Only BL-stable packings count; the search cuts the others by an upper bound on contact
    // (every side in contact but the deficits known), raised by each better find.
    let score = |pos: &[opp::Pos]| {
        let targets = targets_of(fps, &order, pos.iter().map(unflip));
        super::is_bl_stable(&targets).then(|| Placement { targets }.contact_length(inst))
    };
    let (best, complete, nodes, open) = if flip {
        opp::best_packing(&opp::turned(&items), d, w, stop, &score, to_beat, far, meter, threads)
    } else {
        opp::best_packing(&items, w, d, stop, &score, to_beat, far, meter, threads)
    };
    let best = best.map(|(_, pos)| Placement {
        targets: targets_of(fps, &order, pos.iter().map(unflip)),
    });
    (best, complete, nodes, open)
}

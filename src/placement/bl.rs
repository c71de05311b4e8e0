//! The paper's extended Bottom-Left placement (Section III-B), repeated over seeded random orders.
//!
//! For one order: the first object goes to the origin with its largest face against the y–z wall
//! (its smallest edge along x); every next object takes, among its allowed orientations, the one
//! whose Bottom-Left position (lowest y, then lowest x, reached by alternately sliding down and
//! left from every corner candidate) gives the most contact length with walls and placed objects.
//! Orders: first by decreasing footprint area, then random shuffles from a ChaCha8 generator
//! seeded with the given seed. The best placement (occupied area, then contact length) is kept.

use super::{area_lower_bound, Placement, PlacementResult, PlacementStatus, Target};
use crate::control::Terminator;
use crate::error::{Error, Result};
use crate::geometry::{Rect, EPS};
use crate::instance::Instance;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

/// Run Bottom-Left over `orders` orders (the first deterministic, the rest shuffled by `seed`).
pub fn solve(inst: &Instance, seed: u64, orders: usize, stop: &dyn Terminator) -> Result<PlacementResult> {
    let start = Instant::now();
    let mut best: Option<(f64, f64, Placement)> = None;
    let tried = for_each_order(inst, seed, orders, stop, |p| {
        let area = p.occupied_area();
        let contact = p.contact_length(inst);
        let better = match &best {
            None => true,
            Some((ba, bc, _)) => area < ba - 1e-12 || (area <= ba + 1e-12 && contact > bc + 1e-12),
        };
        if better {
            best = Some((area, contact, p));
        }
    });
    let (_, _, placement) = best.ok_or_else(|| Error::Infeasible {
        reason: format!("Bottom-Left found no placement that fits the container in {tried} orders"),
    })?;
    debug_assert!(super::is_bl_stable(&placement.targets));
    Ok(PlacementResult {
        placement,
        status: PlacementStatus::Feasible,
        lower_bound: area_lower_bound(inst),
        solver: "bl".into(),
        time_s: start.elapsed().as_secs_f64(),
        nodes: tried,
        subproblems: 0,
    })
}

/// Every distinct placement the orders of [`solve`] produce, best first (occupied area, then
/// contact length, each on a 1e-10 grid so that the order is total, then the order that found
/// it). For a sequencer that proves a placement has no plan, these are the next ones to try.
pub fn alternatives(inst: &Instance, seed: u64, orders: usize, stop: &dyn Terminator) -> Vec<Placement> {
    let mut found: Vec<((i64, i64, usize), Placement)> = Vec::new();
    for_each_order(inst, seed, orders, stop, |p| {
        if found.iter().all(|(_, q)| *q != p) {
            let key = (
                (p.occupied_area() * 1e10).round() as i64,
                -(p.contact_length(inst) * 1e10).round() as i64,
                found.len(),
            );
            found.push((key, p));
        }
    });
    found.sort_by_key(|(k, _)| *k);
    found.into_iter().map(|(_, p)| p).collect()
}

/// Run Bottom-Left in each of [`solve`]'s orders until `stop` fires, handing every placement
/// that fits to `f`; returns the number of orders tried.
fn for_each_order(
    inst: &Instance,
    seed: u64,
    orders: usize,
    stop: &dyn Terminator,
    mut f: impl FnMut(Placement),
) -> u64 {
    let n = inst.n();
    let mut order: Vec<usize> = (0..n).collect();
    let min_area = |i: usize| {
        let o = &inst.objects[i];
        o.orientations
            .iter()
            .map(|q| q.dims(o.size).0[0] * q.dims(o.size).0[1])
            .fold(0.0, f64::max)
    };
    order.sort_by(|a, b| min_area(*b).total_cmp(&min_area(*a)).then(a.cmp(b)));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut tried = 0u64;
    for k in 0..orders.max(1) {
        if k > 0 {
            if stop.should_stop() {
                break;
            }
            order.shuffle(&mut rng);
        }
        tried += 1;
        if let Some(p) = place_in_order(inst, &order) {
            f(p);
        }
    }
    tried
}

/// Bottom-Left for one order of objects; `None` when some object does not fit.
pub fn place_in_order(inst: &Instance, order: &[usize]) -> Option<Placement> {
    let (w, d) = (inst.container.width, inst.container.depth);
    let mut targets: Vec<Option<Target>> = vec![None; inst.n()];
    let mut placed: Vec<Rect> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let o = &inst.objects[i];
        let mut best: Option<(Target, f64, f64)> = None; // target, contact, area after
        let smallest = o.size.iter().cloned().fold(f64::INFINITY, f64::min);
        let first_choices: Vec<_> = o
            .orientations
            .iter()
            .filter(|q| (q.dims(o.size).0[0] - smallest).abs() <= EPS)
            .collect();
        let choices: Vec<_> = if k == 0 && !first_choices.is_empty() {
            first_choices
        } else {
            o.orientations.iter().collect()
        };
        for ori in choices {
            let (fp, h) = ori.dims(o.size);
            let Some(r) = bl_position(&placed, fp[0], fp[1], w, d) else {
                continue;
            };
            let contact = r.wall_contact_length(w, d) + placed.iter().map(|p| p.contact_length(&r)).sum::<f64>();
            let (mx, my) = placed.iter().fold((r.x1, r.y1), |(a, b), p| (a.max(p.x1), b.max(p.y1)));
            let area = mx * my;
            let t = Target {
                orientation: *ori,
                rect: r,
                height: h,
            };
            let better = match &best {
                None => true,
                Some((bt, bc, ba)) => {
                    contact > bc + EPS
                        || (contact > bc - EPS
                            && (area < ba - 1e-12 || (area <= ba + 1e-12 && (r.y0, r.x0) < (bt.rect.y0, bt.rect.x0))))
                }
            };
            if better {
                best = Some((t, contact, area));
            }
        }
        let (t, _, _) = best?;
        placed.push(t.rect);
        targets[i] = Some(t);
    }
    Some(Placement {
        targets: targets.into_iter().map(|t| t.expect("every object placed")).collect(),
    })
}

/// Lowest-then-leftmost BL-stable position of a `fw × fd` rectangle among `placed`, inside
/// `[0, w] × [0, d]`: the first free one of the corner points (x = 0 or a right edge, y = 0 or
/// a top edge) in order of y, then x. Sliding a free rectangle down and left until neither
/// moves (BL-stable) stops on such a point, lower or further left, so the first free point in
/// that order does not move and is the lowest-then-leftmost BL-stable position; no point
/// after it needs checking.
pub fn bl_position(placed: &[Rect], fw: f64, fd: f64, w: f64, d: f64) -> Option<Rect> {
    let mut xs: Vec<f64> = std::iter::once(0.0).chain(placed.iter().map(|p| p.x1)).collect();
    let mut ys: Vec<f64> = std::iter::once(0.0).chain(placed.iter().map(|p| p.y1)).collect();
    xs.sort_by(f64::total_cmp);
    ys.sort_by(f64::total_cmp);
    xs.dedup();
    ys.dedup();
    let floor = Rect::new(0.0, 0.0, w, d);
    // Per row, only the rectangles overlapping it in y can overlap a candidate there (the y
    // half of `Rect::overlaps`, so the answer is the same): the warm start of the exact
    // placement tries 256 orders, and checking every placed rectangle at every corner point was
    // most of its time.
    let mut band: Vec<&Rect> = Vec::with_capacity(placed.len());
    for &y in &ys {
        let row = Rect::new(0.0, y, fw, fd);
        if !row.inside(&floor) {
            // Rows only rise: no later one fits either.
            break;
        }
        band.clear();
        band.extend(placed.iter().filter(|p| p.y0 < row.y1 - EPS && row.y0 < p.y1 - EPS));
        for &x in &xs {
            let r = Rect::new(x, y, fw, fd);
            if !r.inside(&floor) {
                break;
            }
            if band.iter().all(|p| !p.overlaps(&r)) {
                return Some(r);
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bl_position_fills_the_bottom_row_first() {
        let placed = vec![Rect::new(0.0, 0.0, 0.1, 0.05)];
        let r = bl_position(&placed, 0.1, 0.05, 0.3, 0.2).unwrap();
        assert!((r.x0 - 0.1).abs() < 1e-12 && r.y0.abs() < 1e-12);
        let placed = vec![Rect::new(0.0, 0.0, 0.2, 0.05)];
        let r = bl_position(&placed, 0.15, 0.05, 0.3, 0.2).unwrap();
        assert!(
            r.x0.abs() < 1e-12 && (r.y0 - 0.05).abs() < 1e-12,
            "too wide for the row: goes on top, {r:?}"
        );
    }

    /// The search `bl_position` replaced: every corner point that is free, slid down and left
    /// until neither moves, the lowest-then-leftmost result (first found among ties).
    fn by_sliding(placed: &[Rect], fw: f64, fd: f64, w: f64, d: f64) -> Option<Rect> {
        let floor = Rect::new(0.0, 0.0, w, d);
        let free = |r: &Rect| r.inside(&floor) && placed.iter().all(|p| !p.overlaps(r));
        let slide = |mut r: Rect| loop {
            let down = (placed.iter())
                .filter(|p| p.overlap_on(&r, crate::geometry::Axis2::X) > EPS && p.y1 <= r.y0 + EPS)
                .fold(0.0, |a: f64, p| a.max(p.y1));
            let at = Rect::new(r.x0, down, fw, fd);
            let left = (placed.iter())
                .filter(|p| p.overlap_on(&at, crate::geometry::Axis2::Y) > EPS && p.x1 <= r.x0 + EPS)
                .fold(0.0, |a: f64, p| a.max(p.x1));
            let next = Rect::new(left, down, fw, fd);
            if (next.x0 - r.x0).abs() <= EPS && (next.y0 - r.y0).abs() <= EPS {
                return next;
            }
            r = next;
        };
        let mut best: Option<Rect> = None;
        for x in std::iter::once(0.0).chain(placed.iter().map(|p| p.x1)) {
            for y in std::iter::once(0.0).chain(placed.iter().map(|p| p.y1)) {
                let r = Rect::new(x, y, fw, fd);
                if !free(&r) {
                    continue;
                }
                let r = slide(r);
                if best.is_none_or(|b| r.y0 < b.y0 - EPS || ((r.y0 - b.y0).abs() <= EPS && r.x0 < b.x0 - EPS)) {
                    best = Some(r);
                }
            }
        }
        best
    }

    proptest::proptest! {
        /// The first free corner point in order of y, then x, is where sliding every free
        /// corner point down and left ends lowest-then-leftmost, up to rounding (ties among
        /// edges at one position); random rectangles on a 5 mm grid placed one by one.
        #[test]
        fn the_first_free_corner_is_where_sliding_ends(
            sizes in proptest::collection::vec((1u32..=12, 1u32..=12), 1..16)
        ) {
            let (w, d) = (0.3, 0.2);
            let mut placed: Vec<Rect> = Vec::new();
            for (a, b) in sizes {
                let (fw, fd) = (a as f64 * 0.005, b as f64 * 0.005);
                let got = bl_position(&placed, fw, fd, w, d);
                let want = by_sliding(&placed, fw, fd, w, d);
                match (got, want) {
                    (Some(g), Some(s)) => {
                        proptest::prop_assert!(
                            (g.x0 - s.x0).abs() <= 1e-12 && (g.y0 - s.y0).abs() <= 1e-12,
                            "{g:?} against {s:?} among {placed:?}"
                        );
                        placed.push(g);
                    }
                    (None, None) => {}
                    (g, s) => proptest::prop_assert!(false, "{g:?} against {s:?} among {placed:?}"),
                }
            }
        }
    }

    #[test]
    fn bl_position_none_when_full() {
        let placed = vec![Rect::new(0.0, 0.0, 0.3, 0.2)];
        assert!(bl_position(&placed, 0.01, 0.01, 0.3, 0.2).is_none());
    }
}

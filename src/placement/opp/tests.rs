//! Tests of the packing search against enumeration and known packings.

use super::*;
use std::cell::Cell;

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
pub(super) struct Lcg(pub(super) u64);
impl Lcg {
    pub(super) fn below(&mut self, n: u64) -> u64 {
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
    random_items_of(rng, units, (2, 5), 4)
}

/// [`random_items`] with `counts.0` to `counts.0 + counts.1 − 1` items of sides 1 to `side`.
pub(super) fn random_items_of(rng: &mut Lcg, units: bool, counts: (usize, u64), side: u64) -> Vec<Item> {
    let n = counts.0 + rng.below(counts.1) as usize;
    let mut items: Vec<Item> = Vec::new();
    for k in 0..n {
        let (a, b) = if units && rng.below(3) == 0 {
            (1.0, 1.0)
        } else {
            ((1 + rng.below(side)) as f64, (1 + rng.below(side)) as f64)
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

/// Every packing of integer `items` in the integer box `w × d` into `visit` (which returns
/// `true` to stop; identical items in index order), by the plainest complete search: the first
/// cell not yet decided (rows bottom-up, each left to right) is either the lower-left corner of
/// some unplaced item (an item covering it has its corner there: the cells before it are
/// decided) or left empty, while the undecided cells still hold the unplaced items' least areas.
/// Returns whether `visit` stopped it.
fn cell_packings(items: &[Item], w: usize, d: usize, visit: &mut dyn FnMut(&[Pos]) -> bool) -> bool {
    struct Cells<'a> {
        items: &'a [Item],
        w: usize,
        d: usize,
        pos: Vec<Option<Pos>>,
        grid: Vec<bool>,
    }
    fn go(c: &mut Cells, visit: &mut dyn FnMut(&[Pos]) -> bool) -> bool {
        let Some(k) = c.grid.iter().position(|&g| !g) else {
            let all: Option<Vec<Pos>> = c.pos.iter().copied().collect();
            return all.is_some_and(|p| visit(&p));
        };
        let (x, y, w) = (k % c.w, k / c.w, c.w);
        for i in 0..c.items.len() {
            if c.pos[i].is_some() || (0..i).any(|j| c.pos[j].is_none() && c.items[j].class == c.items[i].class) {
                continue;
            }
            for (o, f) in c.items[i].opts.iter().enumerate() {
                let (fw, fd) = (f[0] as usize, f[1] as usize);
                let cells = move || (y..y + fd).flat_map(move |yy| (x..x + fw).map(move |xx| yy * w + xx));
                if x + fw > c.w || y + fd > c.d || cells().any(|k| c.grid[k]) {
                    continue;
                }
                cells().for_each(|k| c.grid[k] = true);
                c.pos[i] = Some(Pos {
                    opt: o,
                    x: x as f64,
                    y: y as f64,
                });
                let stop = go(c, visit);
                c.pos[i] = None;
                cells().for_each(|k| c.grid[k] = false);
                if stop {
                    return true;
                }
            }
        }
        let undecided = c.grid.iter().filter(|&&g| !g).count();
        let need: f64 = (0..c.items.len())
            .filter(|&i| c.pos[i].is_none())
            .map(|i| least_area(&c.items[i]))
            .sum();
        if (undecided as f64) < need + 1.0 {
            return false;
        }
        c.grid[k] = true;
        let stop = go(c, visit);
        c.grid[k] = false;
        stop
    }
    let mut c = Cells {
        items,
        w,
        d,
        pos: vec![None; items.len()],
        grid: vec![false; w * d],
    };
    go(&mut c, visit)
}

/// Whether integer `items` pack in `w × d` ([`cell_packings`]).
fn packs_by_cells(items: &[Item], w: usize, d: usize) -> bool {
    cell_packings(items, w, d, &mut |_| true)
}

/// A packing as a set: per item its class, corner and footprint, sorted (identical items may
/// come in another order).
fn packing_key(items: &[Item], p: &[Pos]) -> Vec<[i64; 5]> {
    let mut k: Vec<[i64; 5]> = p
        .iter()
        .zip(items)
        .map(|(q, it)| {
            let f = it.opts[q.opt];
            [
                it.class as i64,
                q.x.round() as i64,
                q.y.round() as i64,
                f[0] as i64,
                f[1] as i64,
            ]
        })
        .collect();
    k.sort_unstable();
    k
}

/// A random instance of `counts.0` to `counts.0 + counts.1 − 1` items (integer sides 1 to 4,
/// some rotatable, some unit squares) and an integer box at or just above its area, of width 3
/// to `2 + widths`; `None` when the box has more than `cells` cells.
fn tight_case(rng: &mut Lcg, counts: (usize, u64), widths: u64, cells: usize) -> Option<(Vec<Item>, usize, usize)> {
    let items = random_items_of(rng, true, counts, 4);
    tight_box(rng, items, widths, cells)
}

/// A box for `items` as [`tight_case`] draws it, from their least areas.
fn tight_box(rng: &mut Lcg, items: Vec<Item>, widths: u64, cells: usize) -> Option<(Vec<Item>, usize, usize)> {
    let area: f64 = items.iter().map(least_area).sum();
    let w = 3 + rng.below(widths) as usize;
    let d = ((area / w as f64).ceil() as usize + rng.below(3) as usize / 2).max(1);
    (w * d <= cells).then_some((items, w, d))
}

/// The enumeration the contact stage relies on meets every BL-stable packing: on random
/// instances of 4 to 7 items in boxes at or just above their area, then of 3 to 5 boxes lying
/// on any face, the BL-stable packings [`Search::enumerate`] visits (without a contact bound)
/// are exactly those of [`cell_packings`]. (Identical items with several footprints can be met
/// more than once, in swapped footprints: that costs time, not exactness.)
#[test]
fn the_enumeration_meets_every_bl_stable_packing() {
    let never = || false;
    let mut rng = Lcg(43);
    let (mut compared, mut packings, mut lying) = (0, 0, 0);
    for case in 0..450 {
        let case_of = if case < 300 {
            tight_case(&mut rng, (4, 4), 5, 36)
        } else {
            let items = random_lying_items(&mut rng, (3, 3));
            tight_box(&mut rng, items, 5, 36)
        };
        let Some((items, w, d)) = case_of else {
            continue;
        };
        let (wf, df) = (w as f64, d as f64);
        let stable = |p: &[Pos]| contact_if_stable(&items, p, (wf, df), [false; 2]).is_some();
        let mut want = Vec::new();
        cell_packings(&items, w, d, &mut |p| {
            if stable(p) {
                want.push(packing_key(&items, p));
            }
            false
        });
        let mut got = Vec::new();
        let mut visit = |p: &[Pos]| {
            if stable(p) {
                got.push(packing_key(&items, p));
            }
            false
        };
        let (done, _) = Search::enumerate(&items, wf, df, &never, &mut visit, None, [false; 2], None);
        assert!(done);
        let what = format!("case {case}: {items:?} in {w} × {d}");
        let n = got.len();
        got.sort();
        got.dedup();
        want.sort();
        assert_eq!(got, want, "{what}");
        compared += 1;
        packings += n;
        lying += (case >= 300) as u32;
    }
    assert!(
        compared > 150 && packings > 300 && lying > 50,
        "{compared} {packings} {lying}"
    );
}

/// The search, with and without the unit items set aside, and on two threads, against
/// [`packs_by_cells`] on random instances of 5 to 10 items (integer sides 1 to 4, some
/// rotatable, some unit squares) in boxes of at most 64 cells at or just above their area,
/// then of 3 to 6 boxes lying on any face (footprints of different areas).
#[test]
fn the_search_agrees_with_a_cell_by_cell_search() {
    let never = || false;
    let mut rng = Lcg(41);
    let (mut packed, mut refuted, mut lying) = (0, 0, 0);
    for case in 0..900 {
        let case_of = if case < 600 {
            tight_case(&mut rng, (5, 6), 7, 64)
        } else {
            let items = random_lying_items(&mut rng, (3, 4));
            tight_box(&mut rng, items, 7, 64)
        };
        let Some((items, w, d)) = case_of else {
            continue;
        };
        lying += (case >= 600) as u32;
        let (wf, df) = (w as f64, d as f64);
        let want = packs_by_cells(&items, w, d);
        let what = format!("case {case}: {items:?} in {w} × {d}");
        for r in [
            Search::new(&items, wf, df, &never).run(),
            decide(&items, wf, df, &never).0,
            decide_metered(&items, wf, df, &never, None, 2).0,
        ] {
            match r {
                Outcome::Packed(p) => assert!(want && valid(&items, &p, wf, df), "{what}: {p:?}"),
                o => assert!(!want && o == Outcome::Infeasible, "{what}: {o:?}"),
            }
        }
        packed += want as u32;
        refuted += !want as u32;
    }
    assert!(packed > 40 && refuted > 40 && lying > 150, "{packed} {refuted} {lying}");
}

/// An oracle the search does not share: the consecutive squares 1…N (9 ≤ N ≤ 14) fit in no
/// box of area below OEIS A038666(N) and in some box of that area (with the unit square set
/// aside, as the area stage decides them, and without).
#[test]
fn squares_pack_first_at_their_known_optimum() {
    let never = || false;
    for (n, best) in [
        (9usize, 300usize),
        (10, 405),
        (11, 513),
        (12, 667),
        (13, 836),
        (14, 1035),
    ] {
        let items = squares(n);
        let sum: usize = (1..=n).map(|s| s * s).sum();
        let mut packed = 0;
        for w in n..=best / n {
            for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                let (wf, df) = (w as f64, d as f64);
                let plain = Search::new(&items, wf, df, &never).run();
                let aside = decide(&items, wf, df, &never).0;
                for r in [&plain, &aside] {
                    match r {
                        Outcome::Packed(p) => {
                            assert!(w * d == best, "squares 1…{n} packed in {w} × {d}, below {best}");
                            assert!(valid(&items, p, wf, df), "squares 1…{n} in {w} × {d}");
                            packed += 1;
                        }
                        Outcome::Infeasible => {}
                        Outcome::Stopped => panic!("stopped without a stop"),
                    }
                }
                assert_eq!(
                    matches!(plain, Outcome::Packed(_)),
                    matches!(aside, Outcome::Packed(_)),
                    "squares 1…{n} in {w} × {d}"
                );
            }
        }
        assert!(packed > 0, "squares 1…{n}: no box of area {best} packed");
    }
}

/// The memo and the threads only change how fast an answer comes, never which: decided on two
/// threads, and on one with memos of 4 records that start afresh again and again, random boxes
/// and the consecutive squares 1…N (N = 9, 10, 11, 13) in every box up to their optimum give
/// the very packing (or refutation) of the plain search, and the small memo hands the same
/// complete x-assignments to the y-phase. A stop on two threads is `Stopped`, never a
/// refutation.
/// (The unit items are set aside in `decide_metered` and not in `Search::run`, so the two are
/// compared only with each other.)
#[test]
fn threads_and_a_full_memo_change_no_answer() {
    let never = || false;
    let mut rng = Lcg(23);
    let mut cases: Vec<(Vec<Item>, f64, f64)> = Vec::new();
    for _ in 0..200 {
        let items = random_items_of(&mut rng, true, (5, 5), 5);
        let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
        let w = (3 + rng.below(6)) as f64;
        let d = ((area / w).ceil() + rng.below(3) as f64).max(3.0);
        cases.push((items, w, d));
    }
    for (n, best) in [(9usize, 300usize), (10, 405), (11, 513), (13, 836)] {
        let sum: usize = (1..=n).map(|s| s * s).sum();
        for w in n..=best / n {
            for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                cases.push((squares(n), w as f64, d as f64));
            }
        }
    }
    let (mut packed, mut refuted, mut restarts) = (0, 0, 0);
    // Nodes and index of the refutation that took the most nodes.
    let mut hardest = (0u64, 0usize);
    for (case, (items, w, d)) in cases.iter().enumerate() {
        let what = format!("case {case}: {items:?} in {w} × {d}");
        let mut plain = Search::new(items, *w, *d, &never);
        let r = plain.run();
        let mut small = Search::new(items, *w, *d, &never);
        small.memo_cap = 4;
        assert_eq!(small.run(), r, "{what}: small memo");
        assert_eq!(small.yleaves, plain.yleaves, "{what}: small memo, y-phase leaves");
        restarts += (small.nodes > plain.nodes) as u32;
        let (one, one_nodes) = decide_metered(items, *w, *d, &never, None, 1);
        let two = decide_metered(items, *w, *d, &never, None, 2).0;
        assert_eq!(two, one, "{what}: two threads");
        match &r {
            Outcome::Packed(p) => {
                assert!(valid(items, p, *w, *d), "{what}");
                packed += 1;
            }
            Outcome::Infeasible => {
                refuted += 1;
                hardest = hardest.max((one_nodes, case));
            }
            Outcome::Stopped => panic!("{what}: stopped without a stop"),
        }
    }
    assert!(
        packed > 40 && refuted > 40 && restarts > 10,
        "{packed} {refuted} {restarts}"
    );
    // The hardest refutation among them, stopped at the first poll on two threads.
    let (items, w, d) = &cases[hardest.1];
    assert!(hardest.0 > 5_000, "{hardest:?}");
    let always = || true;
    assert_eq!(decide_metered(items, *w, *d, &always, None, 2).0, Outcome::Stopped);
}

/// Contact length of a packing in `w × d` placed at the container's corner, from the
/// definition: shared edge lengths plus edges on x = 0 and y = 0, and on x = `w` and y = `d`
/// where `far` says the box reaches the container's walls there; `None` when some item
/// touches nothing on its left or below (not BL-stable).
fn contact_if_stable(items: &[Item], p: &[Pos], (w, d): (f64, f64), far: [bool; 2]) -> Option<f64> {
    let r = rects(items, p);
    let walls: f64 = r
        .iter()
        .map(|a| {
            let right = if far[0] && (a[2] - w).abs() <= 1e-9 {
                a[3] - a[1]
            } else {
                0.0
            };
            let top = if far[1] && (a[3] - d).abs() <= 1e-9 {
                a[2] - a[0]
            } else {
                0.0
            };
            right + top
        })
        .sum();
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
    Some(total + walls)
}

/// The least area of an item's footprints.
fn least_area(it: &Item) -> f64 {
    it.opts.iter().map(|f| f[0] * f[1]).fold(f64::INFINITY, f64::min)
}

/// `counts.0` to `counts.0 + counts.1 − 1` random boxes of integer edges 1 to 3 that may lie on
/// any face: each has the distinct footprints of its three faces, turned both ways, of
/// different areas and perimeters (as the committed random sets, orientations `any`).
fn random_lying_items(rng: &mut Lcg, counts: (usize, u64)) -> Vec<Item> {
    let n = counts.0 + rng.below(counts.1) as usize;
    let mut items: Vec<Item> = Vec::new();
    for k in 0..n {
        let [a, b, c] = [0; 3].map(|_| (1 + rng.below(3)) as f64);
        let mut opts: Vec<[f64; 2]> = Vec::new();
        for f in [[a, b], [b, a], [a, c], [c, a], [b, c], [c, b]] {
            if !opts.contains(&f) {
                opts.push(f);
            }
        }
        let class = items.iter().find(|it| it.opts == opts).map(|it| it.class).unwrap_or(k);
        items.push(Item { opts, class });
    }
    items.sort_by_key(|it| it.class);
    items
}

/// Every contact cut of the enumeration (left sides shared at one edge, bottoms over
/// committed holes, dead states under a contact bound) keeps the best packing: on random small instances, the most contact over the
/// BL-stable packings of a box is the same with the cuts (bound raised by every find) as
/// without them. The first 300 cases count no far wall; the next 300 count random far walls (a
/// box reaching the container's walls); the last 300 are boxes lying on any face, with random
/// far walls.
#[test]
fn contact_cuts_keep_the_best_packing() {
    let mut rng = Lcg(11);
    let never = || false;
    let (mut compared, mut lying) = (0, 0);
    for case in 0..900 {
        let far = if case < 300 {
            [false; 2]
        } else {
            [rng.below(2) == 1, rng.below(2) == 1]
        };
        let items = if case < 600 {
            random_items(&mut rng, false)
        } else {
            random_lying_items(&mut rng, (2, 3))
        };
        // Boxes near the items' least area, where packings exist and have waste to place.
        let area: f64 = items.iter().map(least_area).sum();
        let w = (2 + rng.below(5)) as f64;
        let d = (area / w).ceil() + rng.below(3) as f64;
        let mut all = f64::NEG_INFINITY;
        let mut visit_all = |p: &[Pos]| {
            if let Some(c) = contact_if_stable(&items, p, (w, d), far) {
                all = all.max(c);
            }
            false
        };
        let (done, _) = Search::enumerate(&items, w, d, &never, &mut visit_all, None, far, None);
        assert!(done);
        let bound = Cell::new(-1.0);
        let mut best = f64::NEG_INFINITY;
        let mut visit_cut = |p: &[Pos]| {
            if let Some(c) = contact_if_stable(&items, p, (w, d), far) {
                if c > bound.get() + 1e-9 {
                    bound.set(c);
                    best = c;
                }
            }
            false
        };
        let (done, _) = Search::enumerate(&items, w, d, &never, &mut visit_cut, Some(&bound), far, None);
        assert!(done);
        assert!(
            (all - best).abs() <= 1e-9 || (all.is_infinite() && best.is_infinite()),
            "case {case}: {items:?} in {w} × {d}, far walls {far:?}: {all} without cuts, {best} with"
        );
        compared += all.is_finite() as u32;
        lying += (case >= 600 && all.is_finite()) as u32;
    }
    assert!(
        compared > 450 && lying > 150,
        "{compared} compared, {lying} of boxes lying"
    );
}

/// The best contact on two threads is the one thread's: the same score and the very same
/// packing, on random instances of 4 to 7 items near their area (some boxes reaching the far
/// walls) and on the consecutive squares 1…8 and 1…9 in their optimal boxes. A stop on two
/// threads leaves the enumeration unfinished.
#[test]
fn threads_find_the_same_best_packing() {
    let mut rng = Lcg(31);
    let never = || false;
    let mut cases: Vec<(Vec<Item>, f64, f64, [bool; 2])> = Vec::new();
    for _ in 0..150 {
        let items = random_items_of(&mut rng, true, (4, 4), 4);
        let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
        let w = (3 + rng.below(5)) as f64;
        let d = (area / w).ceil() + rng.below(2) as f64;
        cases.push((items, w, d, [rng.below(3) == 0, rng.below(3) == 0]));
    }
    for (n, w, d) in [(8usize, 15.0, 14.0), (9, 20.0, 15.0)] {
        cases.push((squares(n), w, d, [false; 2]));
    }
    let mut found = 0;
    for (case, (items, w, d, far)) in cases.iter().enumerate() {
        let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
        let one = best_packing(items, *w, *d, &never, &score, 0.0, *far, None, 1);
        let two = best_packing(items, *w, *d, &never, &score, 0.0, *far, None, 2);
        let what = format!("case {case}: {items:?} in {w} × {d}, far {far:?}");
        assert!(one.1 && two.1, "{what}: finished");
        assert_eq!(two.0, one.0, "{what}");
        if let Some((_, p)) = &one.0 {
            assert!(valid(items, p, *w, *d), "{what}");
            found += 1;
        }
    }
    assert!(found > 80, "{found}");
    let always = || true;
    let (items, w, d, far) = cases.last().expect("the squares");
    let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
    assert!(!best_packing(items, *w, *d, &always, &score, 0.0, *far, None, 2).1);
}

#[test]
fn bounds_refute_only_what_cannot_fit() {
    let it = squares(3);
    assert!(refuted_by_bounds(&it, 4.0, 3.0));
    assert!(!refuted_by_bounds(&it, 5.0, 3.0));
}

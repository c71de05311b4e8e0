//! Oracles the search does not share: a cell-by-cell search of integer boxes, and the
//! consecutive squares' known optima (OEIS A038666).

use super::*;

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
/// are exactly those of [`cell_packings`], each once.
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
        assert_eq!(got.len(), n, "{what}: a packing met twice");
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

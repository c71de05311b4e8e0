//! Tests of the packing search against enumeration and known packings: shared helpers,
//! generators and the contact length from its definition here, the oracles the search does not
//! share in `oracles`, the contact enumeration's cross-checks in `contact`.

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
        push_item(&mut items, opts, k);
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

/// Deciding the relaxation without the smallest items first ([`relaxation`]) never changes
/// the answer: on random instances of 8 to 11 items (sides 1 to 6) in the least box of their
/// width, and on the squares 1…N (N = 9 … 13) in
/// every box up to their optimum, [`decide_metered`] agrees with the whole instance decided
/// alone, and its packings are valid. Each way the relaxation can go is met many times:
/// refuting the box, packing in a box the whole instance does not fit, and packing where the
/// whole instance does.
#[test]
fn leaving_the_smallest_items_out_first_keeps_every_answer() {
    let never = || false;
    let mut rng = Lcg(31);
    let mut cases: Vec<(Vec<Item>, f64, f64)> = (0..1000)
        .map(|_| {
            let units = rng.below(2) == 0;
            let items = random_items_of(&mut rng, units, (8, 4), 6);
            let area: f64 = items.iter().map(least_area).sum();
            let w = (6 + rng.below(6)) as f64;
            let d = (area / w).ceil().max(3.0);
            (items, w, d)
        })
        .collect();
    for (n, best) in [(9usize, 300usize), (10, 405), (11, 513), (12, 667), (13, 836)] {
        let sum: usize = (1..=n).map(|s| s * s).sum();
        for w in n..=best / n {
            for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                cases.push((squares(n), w as f64, d as f64));
            }
        }
    }
    let (mut refuted_by_relaxation, mut packed_not_whole, mut packed) = (0, 0, 0);
    for (case, (items, w, d)) in cases.iter().enumerate() {
        let what = format!("case {case}: {items:?} in {w} × {d}");
        let whole = decide_all(items, *w, *d, &never, None, 1).0;
        let r = decide_metered(items, *w, *d, &never, None, 1).0;
        match (&whole, &r) {
            (Outcome::Packed(_), Outcome::Packed(p)) => assert!(valid(items, p, *w, *d), "{what}: {p:?}"),
            (Outcome::Infeasible, Outcome::Infeasible) => {}
            _ => panic!("{what}: whole {whole:?}, relaxation first {r:?}"),
        }
        if let Some(sub) = relaxation(items, *w, *d) {
            match (decide_all(&sub, *w, *d, &never, None, 1).0, &whole) {
                (Outcome::Infeasible, _) => refuted_by_relaxation += 1,
                (Outcome::Packed(_), Outcome::Infeasible) => packed_not_whole += 1,
                (Outcome::Packed(_), _) => packed += 1,
                (o, _) => panic!("{what}: relaxation {o:?}"),
            }
        }
    }
    assert!(
        refuted_by_relaxation > 30 && packed_not_whole > 30 && packed > 30,
        "{refuted_by_relaxation} {packed_not_whole} {packed}"
    );
}

/// The memo and the threads only change how fast an answer comes, never which: decided on two
/// and three threads (the boxes' split at once, and after a lead on one thread too short for
/// them, whose dead profiles the split inherits), and on one with memos of 4 records that start
/// afresh again and again, random boxes
/// and the consecutive squares 1…N (N = 9, 10, 11, 13, 14) in every box up to their optimum give
/// the very packing (or refutation) of the plain search, and the small memo hands the same
/// complete x-assignments to the y-phase. A stop on two threads is `Stopped`, never a
/// refutation the search did not finish.
/// (The unit items are set aside in `decide_metered` and not in `Search::run`, so the two are
/// compared only with each other.)
/// 5 to 9 random items of sides 1 to 5 (some unit squares) in a box about as large as their
/// area, some boxes packing and some not.
fn random_box_case(rng: &mut Lcg) -> (Vec<Item>, f64, f64) {
    let items = random_items_of(rng, true, (5, 5), 5);
    let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
    let w = (3 + rng.below(6)) as f64;
    let d = ((area / w).ceil() + rng.below(3) as f64).max(3.0);
    (items, w, d)
}

#[test]
fn threads_and_a_full_memo_change_no_answer() {
    let never = || false;
    let mut rng = Lcg(23);
    let mut cases: Vec<(Vec<Item>, f64, f64)> = (0..200).map(|_| random_box_case(&mut rng)).collect();
    for (n, best) in [(9usize, 300usize), (10, 405), (11, 513), (13, 836), (14, 1035)] {
        let sum: usize = (1..=n).map(|s| s * s).sum();
        for w in n..=best / n {
            for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                cases.push((squares(n), w as f64, d as f64));
            }
        }
    }
    let (mut packed, mut refuted, mut restarts, mut led) = (0, 0, 0, 0);
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
        let one = decide_metered(items, *w, *d, &never, None, 1).0;
        let one_nodes = decide_all(items, *w, *d, &never, None, 1).1;
        for threads in [2, 3] {
            let many = decide_metered(items, *w, *d, &never, None, threads).0;
            assert_eq!(many, one, "{what}: {threads} threads");
            // The split itself, at once and after a lead that hands on its dead profiles
            // (most of these boxes take fewer nodes than the default lead).
            for lead in [0, 1024] {
                let split = super::threads::search_led(items, *w, *d, &never, None, threads, lead).0;
                assert_eq!(split, r, "{what}: {threads} threads, lead {lead}");
            }
        }
        led += (one_nodes > 1024) as u32;
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
        packed > 40 && refuted > 40 && restarts > 10 && led > 10,
        "{packed} {refuted} {restarts} {led}"
    );
    // The hardest refutation among them (decided whole), with a stop asked before it starts,
    // on two threads: no thread takes a task (before, a thread scheduled early could finish
    // the box before the first poll, and this failed once under load). With the relaxation
    // first, a refutation may come before the search, which is then a proof: never a
    // refutation the search did not make.
    let (items, w, d) = &cases[hardest.1];
    assert!(hardest.0 > 5_000, "{hardest:?}");
    let always = || true;
    assert_eq!(decide_all(items, *w, *d, &always, None, 2).0, Outcome::Stopped);
    assert!(matches!(
        decide_metered(items, *w, *d, &always, None, 2).0,
        Outcome::Stopped | Outcome::Infeasible
    ));
}

/// The tasks a search splits into ([`Search::tasks`]), run in order on one search, give the
/// plain search's answer — its very packing, or its refutation — whatever the depth of the
/// split and however few tasks it may make (past that many, the nodes above the depth become
/// tasks as they are), on the random boxes and squares 1…9 and 1…10 in every box up to their
/// optimum.
#[test]
fn the_tasks_of_a_split_search_cover_it() {
    let never = || false;
    let mut rng = Lcg(29);
    let mut cases: Vec<(Vec<Item>, f64, f64)> = (0..150).map(|_| random_box_case(&mut rng)).collect();
    for (n, best) in [(9usize, 300usize), (10, 405)] {
        let sum: usize = (1..=n).map(|s| s * s).sum();
        for w in n..=best / n {
            for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                cases.push((squares(n), w as f64, d as f64));
            }
        }
    }
    let mut split = 0;
    for (case, (items, w, d)) in cases.iter().enumerate() {
        let plain = Search::new(items, *w, *d, &never).run();
        for (at, most) in [(1, usize::MAX), (3, usize::MAX), (3, 4), (6, 1)] {
            let tasks = Search::new(items, *w, *d, &never).tasks(at, most);
            split += (tasks.len() > 1) as u32;
            let mut s = Search::new(items, *w, *d, &never);
            let first = tasks
                .iter()
                .map(|path| s.run_task(path))
                .find(|r| *r != Outcome::Infeasible)
                .unwrap_or(Outcome::Infeasible);
            assert_eq!(
                first, plain,
                "case {case}, depth {at}, at most {most}: {items:?} in {w} × {d}"
            );
        }
    }
    assert!(split > 400, "{split} splits into more than one task");
}

/// The capacity check's one-word path (`Search::fill_in_word`) refutes exactly what the
/// general loop over bitset slices does: the same answers and the same nodes, in decisions and
/// in enumerations under a contact bound, on integer sizes and on a half-unit grid.
#[test]
fn the_capacity_check_in_one_word_matches_the_general_loop() {
    let never = || false;
    let mut rng = Lcg(41);
    let mut cases: Vec<(Vec<Item>, f64, f64)> = Vec::new();
    for k in 0..160 {
        let (mut items, mut w, mut d) = random_box_case(&mut rng);
        if k % 4 == 0 {
            // Half the sizes: a grid of 0.5 over the same boxes.
            for it in &mut items {
                it.opts.iter_mut().flatten().for_each(|v| *v /= 2.0);
            }
            (w, d) = (w / 2.0, d / 2.0);
        }
        cases.push((items, w, d));
    }
    for (w, d) in [(20.0, 15.0), (23.0, 13.0), (21.0, 14.0)] {
        cases.push((squares(9), w, d));
    }
    let (mut refuted, mut packed, mut enumerated) = (0, 0, 0);
    for (case, (items, w, d)) in cases.iter().enumerate() {
        let what = format!("case {case}: {items:?} in {w} × {d}");
        assert!(
            subset::Grid::new(items, *w, *d).is_some_and(|g| g.one_word()),
            "{what}: one word"
        );
        let mut word = Search::new(items, *w, *d, &never);
        let mut general = Search::new(items, *w, *d, &never);
        general.word_sums = false;
        let r = word.run();
        assert_eq!(general.run(), r, "{what}");
        assert_eq!(general.nodes, word.nodes, "{what}: nodes");
        match r {
            Outcome::Infeasible => refuted += 1,
            Outcome::Packed(_) => packed += 1,
            Outcome::Stopped => panic!("{what}: stopped without a stop"),
        }
        if case % 3 == 0 {
            // The contact enumeration, each way: the same best contact in the same nodes.
            let best = |word_sums: bool| {
                let bound = Cell::new(0.0f64);
                let mut top = 0.0f64;
                let mut visit = |p: &[Pos]| {
                    if let Some(c) = contact_if_stable(items, p, (*w, *d), [false; 2]) {
                        top = top.max(c);
                        bound.set(bound.get().max(c));
                    }
                    false
                };
                let mut s = Search::enumerator(items, *w, *d, &never, &mut visit, Some(&bound), [false; 2]);
                s.word_sums = word_sums;
                let done = matches!(s.run(), Outcome::Infeasible);
                let nodes = s.nodes;
                drop(s);
                (done, nodes, top)
            };
            assert_eq!(best(false), best(true), "{what}: enumeration");
            enumerated += 1;
        }
    }
    assert!(
        refuted > 30 && packed > 30 && enumerated > 40,
        "{refuted} {packed} {enumerated}"
    );
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

/// Add an item of footprints `opts`, in the class of an earlier item with the same footprints
/// or in class `k` of its own.
fn push_item(items: &mut Vec<Item>, opts: Vec<[f64; 2]>, k: usize) {
    let class = items.iter().find(|it| it.opts == opts).map(|it| it.class).unwrap_or(k);
    items.push(Item { opts, class });
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
        push_item(&mut items, opts, k);
    }
    items.sort_by_key(|it| it.class);
    items
}

#[test]
fn bounds_refute_only_what_cannot_fit() {
    let it = squares(3);
    assert!(refuted_by_bounds(&it, 4.0, 3.0));
    assert!(!refuted_by_bounds(&it, 5.0, 3.0));
}

mod contact;
mod oracles;

/// A lead cut short hands the split its dead profiles, and the split still finds the plain
/// search's very packing: squares 1…N in boxes that pack, each taking the plain search 1.5 k
/// to 14 k nodes (more than a lead of 1,024 and, for most, of the default 4,096), decided on
/// two and three threads after no lead, after those two leads and after the default. (The
/// threads test above meets few such boxes: most of its packings come within 1,024 nodes.)
#[test]
fn a_lead_cut_short_changes_no_packing() {
    let never = || false;
    let boxes = [
        (12usize, 32usize, 21usize),
        (13, 37, 23),
        (13, 35, 24),
        (13, 34, 25),
        (14, 34, 31),
        (15, 36, 36),
        (15, 49, 26),
        (15, 48, 27),
        (16, 61, 25),
        (16, 57, 27),
    ];
    for (n, w, d) in boxes {
        let items = squares(n);
        let (w, d) = (w as f64, d as f64);
        let mut plain = Search::new(&items, w, d, &never);
        let r = plain.run();
        assert!(
            matches!(r, Outcome::Packed(_)) && plain.nodes > 1024,
            "squares 1…{n} in {w} × {d}: {r:?}, {} nodes",
            plain.nodes
        );
        for threads in [2, 3] {
            for lead in [0, 1024, 4096, super::threads::LEAD_NODES] {
                let (split, _) = super::threads::search_led(&items, w, d, &never, None, threads, lead);
                assert_eq!(split, r, "squares 1…{n} in {w} × {d}: {threads} threads, lead {lead}");
            }
        }
    }
}

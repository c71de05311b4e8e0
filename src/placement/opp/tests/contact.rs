//! The contact enumeration: every contact cut against the enumeration without them, and the
//! same best packing on any number of threads and in any order of its tasks.

use super::super::faces::{restrict, Faces};
use super::super::threads::{best_packing_piloted, Best};
use super::*;
use std::cell::Cell;

/// Every contact cut of the enumeration (left sides shared at one edge, bottoms over
/// committed holes, dead states under a contact bound) keeps the best packing: on random small
/// instances, the most contact over the BL-stable packings of a box is the same with the cuts
/// (bound raised by every find) as without them. The first 300 cases count no far wall; the next 300 count random far walls (a
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

/// Random instances of 4 to 7 items near their area (some boxes reaching the far walls), then
/// squares 1…8 and 1…9 in their optimal boxes: instance, box and far walls.
fn split_cases(rng: &mut Lcg) -> Vec<(Vec<Item>, f64, f64, [bool; 2])> {
    let mut cases: Vec<(Vec<Item>, f64, f64, [bool; 2])> = Vec::new();
    for _ in 0..150 {
        let items = random_items_of(rng, true, (4, 4), 4);
        let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
        let w = (3 + rng.below(5)) as f64;
        let d = (area / w).ceil() + rng.below(2) as f64;
        cases.push((items, w, d, [rng.below(3) == 0, rng.below(3) == 0]));
    }
    for (n, w, d) in [(8usize, 15.0, 14.0), (9, 20.0, 15.0)] {
        cases.push((squares(n), w, d, [false; 2]));
    }
    cases
}

/// `count` random instances near their area, rectangles of sides 1 to 5 (`rects` items, as
/// [`random_items_of`] counts them) and boxes lying on any face (`lying` items) in turn, in
/// boxes 3 to 8 wide, some reaching the far walls: instance, box and far walls.
fn near_their_area(
    rng: &mut Lcg,
    count: usize,
    rects: (usize, u64),
    lying: (usize, u64),
) -> Vec<(Vec<Item>, f64, f64, [bool; 2])> {
    (0..count)
        .map(|case| {
            let items = if case % 2 == 0 {
                random_items_of(rng, false, rects, 5)
            } else {
                random_lying_items(rng, lying)
            };
            let area: f64 = items.iter().map(least_area).sum();
            let w = (3 + rng.below(6)) as f64;
            let d = (area / w).ceil() + rng.below(2) as f64;
            (items, w, d, [rng.below(3) == 0, rng.below(3) == 0])
        })
        .collect()
}

/// The best contact on two and three threads is the one thread's: the same score and the very same
/// packing, on random instances of 4 to 7 items near their area (some boxes reaching the far
/// walls) and on the consecutive squares 1…8 and 1…9 in their optimal boxes. A stop on two
/// threads leaves the enumeration of squares 1…12 unfinished.
#[test]
fn threads_find_the_same_best_packing() {
    let mut rng = Lcg(31);
    let never = || false;
    let cases = split_cases(&mut rng);
    let mut found = 0;
    for (case, (items, w, d, far)) in cases.iter().enumerate() {
        let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
        let one = best_packing(items, *w, *d, &never, &score, 0.0, *far, None, 1);
        let what = format!("case {case}: {items:?} in {w} × {d}, far {far:?}");
        for threads in [2, 3] {
            let many = best_packing(items, *w, *d, &never, &score, 0.0, *far, None, threads);
            assert!(one.1 && many.1, "{what}: finished on {threads} threads");
            assert_eq!(many.0, one.0, "{what}: {threads} threads");
        }
        if let Some((_, p)) = &one.0 {
            assert!(valid(items, p, *w, *d), "{what}");
            found += 1;
        }
    }
    assert!(found > 80, "{found}");
    // A stop asked before it starts leaves the enumeration unfinished: the pilot asks before
    // its first task, and so does every thread after it.
    let always = || true;
    let items = squares(12);
    let score = |p: &[Pos]| contact_if_stable(&items, p, (29.0, 23.0), [false; 2]);
    assert!(!best_packing(&items, 29.0, 23.0, &always, &score, 0.0, [false; 2], None, 2).1);
}

/// The first packing of the highest score in the order of one search along the x-axis given
/// (`Search::enumerate` under a bound raised by each find).
fn along(items: &[Item], w: f64, d: f64, far: [bool; 2], score: &dyn Fn(&[Pos]) -> Option<f64>) -> Option<Scored> {
    let never = || false;
    let bound = Cell::new(0.0);
    let mut best = None;
    let mut visit = |pos: &[Pos]| {
        if let Some(c) = score(pos).filter(|&c| c > bound.get() + 1e-9) {
            bound.set(c);
            best = Some((c, pos.to_vec()));
        }
        false
    };
    let (complete, _) = Search::enumerate(items, w, d, &never, &mut visit, Some(&bound), far, None);
    assert!(complete);
    best
}

/// The tasks of a split enumeration give the plain enumeration's best packing ([`along`])
/// whatever order a thread takes them in (threads take later halves of each other's ranges, so one thread may move back
/// to an earlier task, where ties with the tasks it has done win again): in reverse order,
/// rotated by half, and shuffled, on random instances of 4 to 7 items near their area (some
/// boxes reaching the far walls) and squares 1…8 and 1…9 in their optimal boxes; each order
/// taken by two searches in turn, the second starting from the first one's dead profiles.
#[test]
fn tasks_in_any_order_find_the_same_best_packing() {
    let mut rng = Lcg(37);
    let never = || false;
    let cases = split_cases(&mut rng);
    let mut split = 0;
    for (case, (items, w, d, far)) in cases.iter().enumerate() {
        let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
        let one = along(items, *w, *d, *far, &score);
        let n = Best::new(items, *w, *d, &score, 0.0, *far).tasks.len();
        split += (n > 1) as u32;
        let mut shuffled: Vec<usize> = (0..n).collect();
        for k in (1..n).rev() {
            shuffled.swap(k, rng.below(k as u64 + 1) as usize);
        }
        let orders = [(0..n).rev().collect(), (n / 2..n).chain(0..n / 2).collect(), shuffled];
        for (o, order) in orders.iter().enumerate() {
            let best = Best::new(items, *w, *d, &score, 0.0, *far);
            // Two searches one after the other, the second with the first one's dead profiles.
            let (first, then) = order.split_at(n / 2);
            for part in [first, then] {
                let mut next = part.iter().copied();
                best.work(&never, &mut || next.next(), None, true);
            }
            let what = format!("case {case}, order {o}: {items:?} in {w} × {d}, far {far:?}");
            assert_eq!(best.result(), (one.clone(), true), "{what}");
        }
    }
    assert!(split > 100, "{split} of the cases split into tasks");
}

/// Probes (x-phase states refuted without the three smallest items, `search/probe.rs`) cut
/// only states that no packing completes. Without a contact bound, the enumeration visits the
/// very same packings (the first 2,000), in the same order, with probes and without them, on
/// random instances of 8 to 10 items (sides 1 to 6) in boxes at or just above their least
/// area; under a contact bound raised by each find, it finds the same best contact there and
/// on the squares 1…N (N = 9 … 12) in their optimal boxes. Probes refute states in many of
/// the cases.
#[test]
fn probes_cut_only_states_no_packing_completes() {
    let mut rng = Lcg(47);
    let never = || false;
    let (mut compared, mut probed, mut packings) = (0, 0, 0);
    let mut cases: Vec<(Vec<Item>, f64, f64, bool)> = Vec::new();
    for _ in 0..240 {
        let items = random_items_of(&mut rng, false, (8, 3), 6);
        let area: f64 = items.iter().map(least_area).sum();
        let w = (5 + rng.below(6)) as f64;
        let d = (area / w).ceil() + rng.below(2) as f64;
        cases.push((items, w, d, true));
    }
    for (n, w, d) in [
        (9usize, 20.0, 15.0),
        (10, 27.0, 15.0),
        (11, 27.0, 19.0),
        (12, 29.0, 23.0),
    ] {
        cases.push((squares(n), w, d, false));
    }
    for (case, (items, w, d, unbounded)) in cases.iter().enumerate() {
        let what = format!("case {case}: {items:?} in {w} × {d}");
        if super::super::search::probe_left_out(items, *w, *d) == 0 {
            continue;
        }
        let far = [false; 2];
        let mut cuts = 0;
        if *unbounded {
            let mut runs: Vec<Vec<Vec<Pos>>> = Vec::new();
            for probes in [true, false] {
                // The first 2,000 packings (the visitor stops the enumeration there).
                let mut seen: Vec<Vec<Pos>> = Vec::new();
                let mut visit = |p: &[Pos]| {
                    seen.push(p.to_vec());
                    seen.len() >= 2_000
                };
                let mut s = Search::enumerator(items, *w, *d, &never, &mut visit, None, far);
                if !probes {
                    s.set_probe(0);
                }
                s.run();
                cuts += s.probe_cuts;
                drop(s);
                runs.push(seen);
            }
            if let Some(k) = (0..runs[0].len().max(runs[1].len())).find(|&k| runs[0].get(k) != runs[1].get(k)) {
                let met = runs[1].get(k).and_then(|p| runs[0].iter().position(|q| q == p));
                panic!(
                    "{what}: packing {k} differs; without probes it is {:?}, met with them at {met:?}",
                    runs[1].get(k)
                );
            }
            packings += runs[0].len();
        }
        let mut best = [f64::NEG_INFINITY; 2];
        for (k, probes) in [true, false].into_iter().enumerate() {
            let bound = Cell::new(-1.0);
            let mut top = f64::NEG_INFINITY;
            let mut visit = |p: &[Pos]| {
                if let Some(c) = contact_if_stable(items, p, (*w, *d), far) {
                    if c > bound.get() + 1e-9 {
                        bound.set(c);
                        top = c;
                    }
                }
                false
            };
            let mut s = Search::enumerator(items, *w, *d, &never, &mut visit, Some(&bound), far);
            if !probes {
                s.set_probe(0);
            }
            assert_eq!(s.run(), Outcome::Infeasible, "{what}: finished");
            cuts += s.probe_cuts;
            drop(s);
            best[k] = top;
        }
        assert!(
            best[0] == best[1] || (best[0].is_infinite() && best[1].is_infinite()),
            "{what}: best contact {} with probes, {} without",
            best[0],
            best[1]
        );
        compared += 1;
        probed += (cuts > 0) as u32;
    }
    assert!(
        compared > 60 && probed > 30 && packings > 500,
        "{compared} {probed} {packings}"
    );
}

/// A probe is skipped only where it would not have refuted: on random instances of 8 to 10
/// items and on squares 1…9 to 1…12, the enumeration under a contact bound (raised by each
/// find) visits the same packings in the same order with and without the record of the
/// states probes reached a complete x-assignment from, refutes as many states by probes and
/// hands as many x-assignments to the y-phase, in no more nodes; and probes are skipped in
/// many of them.
#[test]
fn probes_skipped_where_known_alive_refute_nothing() {
    let mut rng = Lcg(59);
    let never = || false;
    let mut cases: Vec<(Vec<Item>, f64, f64)> = Vec::new();
    for _ in 0..240 {
        let items = random_items_of(&mut rng, false, (8, 3), 6);
        let area: f64 = items.iter().map(least_area).sum();
        let w = (5 + rng.below(6)) as f64;
        let d = (area / w).ceil() + rng.below(2) as f64;
        cases.push((items, w, d));
    }
    for (n, w, d) in [
        (9usize, 20.0, 15.0),
        (10, 27.0, 15.0),
        (11, 27.0, 19.0),
        (12, 29.0, 23.0),
    ] {
        cases.push((squares(n), w, d));
    }
    let (mut compared, mut skipping, mut fewer) = (0, 0, 0);
    for (case, (items, w, d)) in cases.iter().enumerate() {
        if super::super::search::probe_left_out(items, *w, *d) == 0 {
            continue;
        }
        let what = format!("case {case}: {items:?} in {w} × {d}");
        let far = [false; 2];
        let mut runs = Vec::new();
        for witnesses in [true, false] {
            let bound = Cell::new(-1.0);
            let mut seen: Vec<(Vec<Pos>, f64)> = Vec::new();
            let mut visit = |p: &[Pos]| {
                if let Some(c) = contact_if_stable(items, p, (*w, *d), far) {
                    if c > bound.get() + 1e-9 {
                        bound.set(c);
                        seen.push((p.to_vec(), c));
                    }
                }
                false
            };
            let mut s = Search::enumerator(items, *w, *d, &never, &mut visit, Some(&bound), far);
            s.witnesses = witnesses;
            assert_eq!(s.run(), Outcome::Infeasible, "{what}: finished");
            let counts = (s.probe_cuts, s.yleaves, s.nodes, s.probes_skipped);
            drop(s);
            runs.push((seen, counts));
        }
        let ((with, a), (without, b)) = (&runs[0], &runs[1]);
        assert_eq!(with, without, "{what}: the packings found");
        assert_eq!((a.0, a.1), (b.0, b.1), "{what}: probe refutations and y-phase leaves");
        assert!(a.2 <= b.2, "{what}: {} nodes with the record, {} without", a.2, b.2);
        assert_eq!(b.3, 0, "{what}: skipped without the record");
        compared += 1;
        skipping += (a.3 > 0) as u32;
        fewer += (a.2 < b.2) as u32;
    }
    assert!(
        compared > 150 && skipping > 80 && fewer > 80,
        "{compared} {skipping} {fewer}"
    );
}

/// The gapless-stacks bound below the y-phase's root cuts only branches that hold no packing
/// above the bound: on random instances of 6 to 9 items (some lying on any face) near their
/// area, some boxes reaching the far walls, the enumeration under a fixed contact bound (the
/// best contact less 0.5 or 1.5; sizes are integers) visits the very same BL-stable packings
/// above it with and without the bound (the first 2,000 of them), and the bound cuts in many
/// of them; and on 100 more 2.5 or 3.5 below the best.
#[test]
fn the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(53);
    // The far walls' bound and the root's stacks cut much of what this bound would: off here.
    let set = |s: &mut Search, on: bool| (s.ystacks_on, s.stacks_on, s.walls_on) = (on, false, false);
    let cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([0.5, 1.5], 0.5), &set, &|s| s.ystack_cuts);
    let cases = near_their_area(&mut rng, 100, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.25), &set, &|s| s.ystack_cuts);
}

/// The gapless-stacks bound cuts only x-assignments that hold no packing above the bound: the
/// same comparison as [`the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound`], with and without
/// it, on 300 instances of 6 to 9 items under bounds 0.5 or 1.5 below the best, and 100 more
/// 2.5 or 3.5 below it (where a gap in one column of width 1 no longer closes the margin).
#[test]
fn the_stacks_bound_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(67);
    // The far walls' bound cuts much of what the stacks bound would: off here.
    let set = |s: &mut Search, on: bool| (s.stacks_on, s.walls_on) = (on, false);
    let cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([0.5, 1.5], 0.25), &set, &|s| s.stack_cuts);
    let cases = near_their_area(&mut rng, 100, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.25), &set, &|s| s.stack_cuts);
}

/// The far walls' bound (the right wall touches only the items ending at it; where the top
/// wall counts, each column with room loses its width at the top or at a bottom) cuts only
/// branches that hold no packing above the bound: the same comparison as
/// [`the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound`], with and without it, on 300
/// instances of 6 to 9 items, every box reaching one far wall or both, under bounds 0.5 or 1.5
/// below the best, and 100 more 2.5 or 3.5 below it.
#[test]
fn the_far_walls_bound_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(71);
    let set = |s: &mut Search, on: bool| s.walls_on = on;
    let walls = [[true, false], [false, true], [true, true]];
    let mut cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    cases.iter_mut().enumerate().for_each(|(k, c)| c.3 = walls[k % 3]);
    same_packings_above_the_bound(&cases, ([0.5, 1.5], 0.25), &set, &|s| s.walls_cuts);
    let mut cases = near_their_area(&mut rng, 100, (6, 4), (6, 4));
    cases.iter_mut().enumerate().for_each(|(k, c)| c.3 = walls[k % 3]);
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.25), &set, &|s| s.walls_cuts);
}

/// The y-phase's memo cuts only states whose completions hold no packing above the bound: the
/// same comparison as [`the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound`], with and without
/// the memo, on 300 instances of 6 to 9 items and 40 of 7 to 10, under bounds further below the
/// best (2.5 or 3.5), where more y-states are met again.
#[test]
fn the_y_memo_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(59);
    let set = |s: &mut Search, on: bool| s.ymemo_on = on;
    let cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.5), &set, &|s| s.ymemo_cuts);
    let cases = near_their_area(&mut rng, 40, (7, 4), (7, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.5), &set, &|s| s.ymemo_cuts);
}

/// The x-phase's bound over the footprints' sides within the free area cuts only branches that
/// hold no packing above the bound: the same comparison as
/// [`the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound`], with and without it, on 300
/// instances of 6 to 9 items (half of them boxes lying on any face, whose footprints differ in
/// area and sides) under bounds 0.5 or 1.5 below the best, and 100 more 2.5 or 3.5 below it.
#[test]
fn the_sides_bound_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(61);
    let set = |s: &mut Search, on: bool| s.sides_on = on;
    let cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([0.5, 1.5], 0.25), &set, &|s| s.sides_cuts);
    let cases = near_their_area(&mut rng, 100, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.25), &set, &|s| s.sides_cuts);
}

/// The rows check (each row ahead of `t` holds at most one open object and a subset of the
/// unplaced widths within its room) and the dead states recorded given it, which cut only
/// states whose open objects end where theirs do, cut only branches that hold no packing above
/// the bound: the same comparison as
/// [`the_stacks_bound_below_the_root_keeps_every_packing_above_the_bound`], with and without
/// it, on 300 instances of 6 to 9 items under bounds 0.5 or 1.5 below the best, and 100 more
/// 2.5 or 3.5 below it; and those records cut in some of them.
#[test]
fn the_rows_check_keeps_every_packing_above_the_bound() {
    let mut rng = Lcg(73);
    let set = |s: &mut Search, on: bool| s.rows_on = on;
    let recorded = Cell::new(0u64);
    let cuts = |s: &Search| {
        recorded.set(recorded.get() + s.row_dominance_cuts);
        s.row_cuts
    };
    let cases = near_their_area(&mut rng, 300, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([0.5, 1.5], 0.25), &set, &cuts);
    let cases = near_their_area(&mut rng, 100, (6, 4), (6, 4));
    same_packings_above_the_bound(&cases, ([2.5, 3.5], 0.25), &set, &cuts);
    assert!(recorded.get() > 0, "no state cut by a record dead given the rows check");
}

/// The packings above a fixed contact bound (the best contact less `below`, in turn), visited
/// with a cut on and off (`set`), are the same, the first 2,000 of them in the same order; the
/// cut (counted by `cuts_of`) cut in more than `share` of the cases.
fn same_packings_above_the_bound(
    cases: &[(Vec<Item>, f64, f64, [bool; 2])],
    (below, share): ([f64; 2], f64),
    set: &dyn Fn(&mut Search, bool),
    cuts_of: &dyn Fn(&Search) -> u64,
) {
    let never = || false;
    let (mut compared, mut cut_in, mut packings) = (0, 0, 0);
    for (case, (items, w, d, far)) in cases.iter().enumerate() {
        let what = format!("case {case}: {items:?} in {w} × {d}, far walls {far:?}");
        let Some(best) = along(items, *w, *d, *far, &|p| contact_if_stable(items, p, (*w, *d), *far)) else {
            continue;
        };
        let above = best.0 - below[case % 2];
        let mut runs: Vec<Vec<Vec<Pos>>> = Vec::new();
        let mut cuts = 0;
        for on in [true, false] {
            let bound = Cell::new(above);
            let mut seen: Vec<Vec<Pos>> = Vec::new();
            let mut visit = |p: &[Pos]| {
                if contact_if_stable(items, p, (*w, *d), *far).is_some_and(|c| c > above) {
                    seen.push(p.to_vec());
                }
                seen.len() >= 2_000
            };
            let mut s = Search::enumerator(items, *w, *d, &never, &mut visit, Some(&bound), *far);
            set(&mut s, on);
            s.run();
            cuts += cuts_of(&s);
            drop(s);
            runs.push(seen);
        }
        assert!(
            runs[0] == runs[1],
            "{what}: {} packings above {above} with the cut, {} without",
            runs[0].len(),
            runs[1].len()
        );
        compared += 1;
        packings += runs[0].len();
        cut_in += (cuts > 0) as usize;
    }
    let count = cases.len();
    assert!(
        compared > count * 2 / 3 && cut_in as f64 > share * count as f64 && packings > count * 100,
        "{compared} compared, the cut cut in {cut_in}, {packings} packings"
    );
}

/// Turning to the other axis keeps the answer: with a pilot of 1,024 nodes that turns above
/// one complete x-assignment per 1,000 nodes (so that many enumerations turn), the best score
/// is the one of the enumeration along the given axis, the packing is valid in the given frame
/// and has that score, and one, two and three threads return the very same packing. On random
/// instances of 5 to 9 items (some lying on any face) near their area, some boxes reaching the
/// far walls, and the squares 1…8 and 1…9 in their optimal boxes; both axes are taken many
/// times.
#[test]
fn the_other_axis_finds_the_same_best_packing() {
    let mut rng = Lcg(53);
    let never = || false;
    let mut cases = split_cases(&mut rng);
    cases.extend(near_their_area(&mut rng, 200, (5, 5), (3, 4)));
    let (mut turned, mut kept) = (0, 0);
    for (case, (items, w, d, far)) in cases.iter().enumerate() {
        let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
        let one = along(items, *w, *d, *far, &score);
        let what = format!("case {case}: {items:?} in {w} × {d}, far {far:?}");
        let mut first = None;
        for threads in 1..=3 {
            let (found, complete, _, turn, _) =
                best_packing_piloted(items, *w, *d, &never, &score, 0.0, *far, None, threads, (1024, 0.001));
            assert!(complete, "{what}");
            assert_eq!(
                found.as_ref().map(|f| f.0),
                one.as_ref().map(|f| f.0),
                "{what}: {threads} threads"
            );
            if let Some((c, p)) = &found {
                assert!(valid(items, p, *w, *d), "{what}: {p:?}");
                assert_eq!(score(p), Some(*c), "{what}: {p:?}");
            }
            match &first {
                None => {
                    first = Some(found);
                    turned += turn as u32;
                    kept += (!turn && one.is_some()) as u32;
                }
                Some(f) => assert_eq!(&found, f, "{what}: {threads} threads"),
            }
        }
    }
    assert!(turned > 20 && kept > 20, "{turned} turned, {kept} kept the given axis");
}

/// Objects of different classes left with the same footprints become one class, and each then
/// lists them in one order: two boxes that share only their 1 × 2 face, listed in opposite
/// orders, fit a 3 × 4 box beside a 2 × 4 object only stacked in its one free column, both
/// standing, which the rule for identical objects at one position (footprints in order)
/// forbids when the lists keep their own orders.
#[test]
fn merged_classes_list_their_footprints_alike() {
    let faces = |a: f64, b: f64, c: f64| vec![[a, b], [b, a], [a, c], [c, a], [b, c], [c, b]];
    let items = vec![
        Item {
            opts: faces(2.0, 1.0, 3.0),
            class: 0,
        },
        Item {
            opts: faces(1.0, 2.0, 4.0),
            class: 1,
        },
        Item {
            opts: vec![[2.0, 4.0]],
            class: 2,
        },
    ];
    let (w, d, far) = (3.0, 4.0, [false, false]);
    let Faces::Only(kept) = restrict(&items, w, d, 0.0, far, 1e-9) else {
        panic!("only the 1 × 2 faces fit the area");
    };
    assert!(kept.merged && kept.items[0].class == kept.items[1].class);
    assert_eq!(kept.items[0].opts, kept.items[1].opts);
    let never = || false;
    let score = |p: &[Pos]| contact_if_stable(&items, p, (w, d), far);
    let (got, done, ..) = best_packing(&items, w, d, &never, &score, 0.0, far, None, 1);
    let (want, ..) = best_packing_piloted(&items, w, d, &never, &score, 0.0, far, None, 1, (1 << 16, 0.01));
    assert!(done && want.is_some());
    assert_eq!(got.as_ref().map(|g| g.0), want.as_ref().map(|g| g.0));
    let (c, p) = got.expect("a packing");
    assert!(valid(&items, &p, w, d) && score(&p) == Some(c), "{p:?}");
}

/// Leaving out the footprints that no combination able to beat the incumbent uses changes no
/// answer: on boxes lying on any face (several areas and sides per item) near their area, with
/// random far walls, and incumbents from nothing up to the best contact itself, the enumeration
/// with the restriction finds the same score as without it, and the very same packing unless
/// objects of different classes were left the same footprints (then one class, met in another
/// order). Each outcome of the restriction occurs: some footprints left out (classes merged or
/// not), none can beat, nothing left out.
#[test]
fn footprints_that_cannot_beat_are_left_out_exactly() {
    let mut rng = Lcg(71);
    let never = || false;
    let (mut only, mut nothing, mut all, mut merged) = (0, 0, 0, 0);
    // The pilot of `best_packing`, so that both choose the same axis.
    let pilot = (1 << 16, 0.01);
    for (case, (items, w, d, far)) in near_their_area(&mut rng, 300, (4, 2), (4, 4)).iter().enumerate() {
        // Each class lists its footprints in an order of its own (the same for its copies), so
        // that classes left the same footprints often list them differently.
        let mut items = items.clone();
        for class in 0..items.len() {
            let shift = rng.below(6) as usize;
            for it in items.iter_mut().filter(|it| it.class == class) {
                let k = shift % it.opts.len();
                it.opts.rotate_left(k);
            }
        }
        let items = &items;
        let score = |p: &[Pos]| contact_if_stable(items, p, (*w, *d), *far);
        let (best, done, ..) = best_packing_piloted(items, *w, *d, &never, &score, 0.0, *far, None, 1, pilot);
        assert!(done);
        let Some((top, _)) = best else { continue };
        for to_beat in [0.0, top - 3.0, top - 2.0, top - 1.0, top - 0.5, top] {
            let what = format!("case {case}: {items:?} in {w} × {d}, far {far:?}, to beat {to_beat}");
            let to_beat = to_beat.max(0.0);
            let merges = match restrict(items, *w, *d, to_beat, *far, 1e-9) {
                Faces::All => {
                    all += 1;
                    false
                }
                Faces::Nothing => {
                    nothing += 1;
                    false
                }
                Faces::Only(kept) => {
                    only += 1;
                    merged += kept.merged as u32;
                    kept.merged
                }
            };
            let (want, done, ..) = best_packing_piloted(items, *w, *d, &never, &score, to_beat, *far, None, 1, pilot);
            assert!(done, "{what}");
            let (got, done, ..) = best_packing(items, *w, *d, &never, &score, to_beat, *far, None, 1);
            assert!(done, "{what}");
            if merges {
                assert_eq!(got.as_ref().map(|g| g.0), want.as_ref().map(|g| g.0), "{what}");
            } else {
                assert_eq!(got, want, "{what}");
            }
            if let Some((c, p)) = &got {
                assert!(valid(items, p, *w, *d), "{what}: {p:?}");
                assert_eq!(score(p), Some(*c), "{what}: {p:?}");
            }
        }
    }
    assert!(
        only > 100 && merged > 50 && nothing > 100 && all > 100,
        "{only} restricted ({merged} with classes merged), {nothing} with nothing to beat it, {all} kept whole"
    );
}

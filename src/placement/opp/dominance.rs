//! Dominance between x-phase states: when one state's open objects load every column ahead at
//! least as much as a dead state's, with the same objects placed and the same position, it is
//! dead too (every completion of it would complete the dead one).

/// Whether the open objects `b` (sorted `(end, depth)`, as in the memo key) load every column at
/// least as much as `a` do: at every end `e` of `a`, `b`'s objects ending at or after `e` are at
/// least as deep in sum as `a`'s. The load is a step function falling at ends, so comparing it
/// just left of each of `a`'s ends covers every column. Lengths are rounded to the tolerance;
/// a rounding difference only makes the answer `false`, which keeps the search complete.
pub(super) fn dominated(b: &[(i64, i64)], a: &[(i64, i64)]) -> bool {
    let mut j = b.len();
    let (mut sa, mut sb) = (0i64, 0i64);
    for &(e, h) in a.iter().rev() {
        sa += h;
        while j > 0 && b[j - 1].0 >= e {
            j -= 1;
            sb += b[j].1;
        }
        if sb < sa {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::super::{Item, Outcome, Pos, Search};
    use super::dominated;
    use proptest::prelude::*;

    /// The load of open objects at column `x` (those ending after it).
    fn load(p: &[(i64, i64)], x: i64) -> i64 {
        p.iter().filter(|&&(e, _)| e > x).map(|&(_, h)| h).sum()
    }

    fn profile() -> impl Strategy<Value = Vec<(i64, i64)>> {
        prop::collection::vec((1i64..12, 1i64..6), 0..6).prop_map(|mut v| {
            v.sort_unstable();
            v
        })
    }

    proptest! {
        /// The definition, column by column.
        #[test]
        fn dominated_means_at_least_the_load_everywhere(a in profile(), b in profile()) {
            let by_columns = (0..12).all(|x| load(&b, x) >= load(&a, x));
            prop_assert_eq!(dominated(&b, &a), by_columns);
        }
    }

    /// Random instances of 6 to 9 items (integer sides 1 to 5, some rotatable, some identical)
    /// in boxes around their area, decided with and without the dominance cut: the same answer
    /// every time, the same complete x-assignments handed to the y-phase, and the cut must have
    /// fired (else the test shows nothing). Then the same for
    /// the consecutive squares, whose near-perfect boxes make the memo work hard.
    #[test]
    fn the_dominance_cut_changes_no_answer() {
        let mut state = 11u64;
        let mut below = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let never = || false;
        let (mut cuts, mut packed, mut refuted, mut leaves) = (0, 0, 0, 0);
        let (mut packings, mut enum_cuts) = (0, 0);
        for case in 0..300 {
            let n = 6 + below(4) as usize;
            let mut items: Vec<Item> = Vec::new();
            for k in 0..n {
                let (a, b) = ((1 + below(5)) as f64, (1 + below(5)) as f64);
                let opts = if a != b && below(3) == 0 {
                    vec![[a, b], [b, a]]
                } else {
                    vec![[a, b]]
                };
                let class = items.iter().find(|it| it.opts == opts).map(|it| it.class).unwrap_or(k);
                items.push(Item { opts, class });
            }
            items.sort_by_key(|it| it.class);
            let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
            let w = (4 + below(6)) as f64;
            let d = ((area / w).ceil() + below(2) as f64).max(5.0);
            let mut with = Search::new(&items, w, d, &never);
            let r1 = with.run();
            cuts += with.dominance_cuts;
            let mut without = Search::new(&items, w, d, &never);
            without.dominance = false;
            let r2 = without.run();
            assert_eq!(
                matches!(r1, Outcome::Packed(_)),
                matches!(r2, Outcome::Packed(_)),
                "case {case}: {items:?} in {w} × {d}"
            );
            // Only subtrees without a complete x-assignment are cut, so the y-phase sees the same
            // ones, in the same order.
            assert_eq!(with.yleaves, without.yleaves, "case {case}: {items:?} in {w} × {d}");
            leaves += with.yleaves;
            assert!(!matches!(r1, Outcome::Stopped));
            // Every packing, counted with and without the cut: the count is the same. Loose
            // boxes hold too many to count; those stop (about 100 k nodes) and are skipped.
            let count = |dominance: bool| {
                let polls = std::cell::Cell::new(0);
                let stop = || {
                    polls.set(polls.get() + 1);
                    polls.get() > 100
                };
                let mut found = 0u64;
                let mut visit = |_: &[Pos]| {
                    found += 1;
                    false
                };
                let mut s = Search::new(&items, w, d, &stop).enumerating(&mut visit);
                s.dominance = dominance;
                let done = !matches!(s.run(), Outcome::Stopped);
                let cuts = s.dominance_cuts;
                drop(s);
                done.then_some((found, cuts))
            };
            if let (Some((all, c)), Some((all_without, _))) = (count(true), count(false)) {
                assert_eq!(
                    all, all_without,
                    "case {case}: {items:?} in {w} × {d}: packings enumerated"
                );
                (packings, enum_cuts) = (packings + all, enum_cuts + c);
            }
            packed += matches!(r1, Outcome::Packed(_)) as u32;
            refuted += matches!(r1, Outcome::Infeasible) as u32;
        }
        // Consecutive squares 1…N in every box from their area up to the optimum (A038666).
        for (n, best) in [(9u32, 300u32), (10, 405), (11, 513), (12, 657)] {
            let items: Vec<Item> = (1..=n)
                .rev()
                .map(|s| Item {
                    opts: vec![[s as f64, s as f64]],
                    class: s as usize,
                })
                .collect();
            let sum: u32 = (1..=n).map(|s| s * s).sum();
            for w in n..=best / n {
                for d in n..=w {
                    if w * d < sum || w * d > best {
                        continue;
                    }
                    let mut with = Search::new(&items, w as f64, d as f64, &never);
                    let r1 = with.run();
                    cuts += with.dominance_cuts;
                    let mut without = Search::new(&items, w as f64, d as f64, &never);
                    without.dominance = false;
                    let r2 = without.run();
                    assert_eq!(
                        matches!(r1, Outcome::Packed(_)),
                        matches!(r2, Outcome::Packed(_)),
                        "squares 1…{n} in {w} × {d}"
                    );
                    assert_eq!(with.yleaves, without.yleaves, "squares 1…{n} in {w} × {d}");
                    packed += matches!(r1, Outcome::Packed(_)) as u32;
                    refuted += matches!(r1, Outcome::Infeasible) as u32;
                }
            }
        }
        assert!(
            cuts > 100 && packed > 30 && refuted > 30 && leaves > 100 && enum_cuts > 100,
            "cuts {cuts}, packed {packed}, refuted {refuted}, y-phase leaves {leaves}, packings {packings}, cuts enumerating {enum_cuts}"
        );
    }
}

//! Dominance between x-phase states: when one state's open objects load every column ahead at
//! least as much as a dead state's, with the same objects placed and the same position, it is
//! dead too (every completion of it would complete the dead one).

/// Whether the open objects `b` (sorted `(end, depth)`, as in the memo key) load every column at
/// least as much as `a` do: at every end `e` of `a`, `b`'s objects ending at or after `e` are at
/// least as deep in sum as `a`'s. The load is a step function falling at ends, so comparing it
/// just left of each of `a`'s ends covers every column. Lengths are rounded to the tolerance;
/// a rounding difference only makes the answer `false`, which keeps the search complete.
pub(super) fn dominated(b: &[(i32, i32)], a: &[(i32, i32)]) -> bool {
    let mut j = b.len();
    let (mut sa, mut sb) = (0i64, 0i64);
    for &(e, h) in a.iter().rev() {
        sa += h as i64;
        while j > 0 && b[j - 1].0 >= e {
            j -= 1;
            sb += b[j].1 as i64;
        }
        if sb < sa {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::super::tests::{random_items_of, Lcg};
    use super::super::{Item, Outcome, Pos, Search};
    use super::dominated;
    use proptest::prelude::*;

    /// The load of open objects at column `x` (those ending after it).
    fn load(p: &[(i32, i32)], x: i32) -> i64 {
        p.iter().filter(|&&(e, _)| e > x).map(|&(_, h)| h as i64).sum()
    }

    fn profile() -> impl Strategy<Value = Vec<(i32, i32)>> {
        prop::collection::vec((1i32..12, 1i32..6), 0..6).prop_map(|mut v| {
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

    /// Decide `items` in `w × d` with and without the dominance cut: the same answer and, since
    /// only subtrees without a complete x-assignment are cut, the same complete x-assignments
    /// handed to the y-phase, in the same order. Returns the answer, those y-phase leaves and the
    /// cuts.
    fn decide_both(items: &[Item], w: f64, d: f64, what: &str) -> (Outcome, u64, u64) {
        let never = || false;
        let mut with = Search::new(items, w, d, &never);
        let r1 = with.run();
        let mut without = Search::new(items, w, d, &never);
        without.dominance = false;
        let r2 = without.run();
        assert_eq!(
            matches!(r1, Outcome::Packed(_)),
            matches!(r2, Outcome::Packed(_)),
            "{what}"
        );
        assert_eq!(with.yleaves, without.yleaves, "{what}");
        assert!(!matches!(r1, Outcome::Stopped), "{what}");
        (r1, with.yleaves, with.dominance_cuts)
    }

    /// Every packing of `items` in `w × d`, counted with or without the cut, and the cuts; `None`
    /// when the count stops (loose boxes hold too many packings: about 100 k nodes).
    fn count_packings(items: &[Item], w: f64, d: f64, dominance: bool) -> Option<(u64, u64)> {
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
        let mut s = Search::new(items, w, d, &stop).enumerating(&mut visit);
        s.dominance = dominance;
        let done = !matches!(s.run(), Outcome::Stopped);
        let cuts = s.dominance_cuts;
        drop(s);
        done.then_some((found, cuts))
    }

    /// Random instances of 6 to 9 items (integer sides 1 to 5, some rotatable, some identical)
    /// in boxes around their area, decided with and without the dominance cut ([`decide_both`]),
    /// and their packings counted both ways where the count finishes: the same number. Then the
    /// consecutive squares, whose near-perfect boxes make the memo work hard. The cut must have
    /// fired (else the test shows nothing).
    #[test]
    fn the_dominance_cut_changes_no_answer() {
        let mut rng = Lcg(11);
        let (mut cuts, mut packed, mut refuted, mut leaves) = (0, 0, 0, 0);
        let (mut packings, mut enum_cuts) = (0, 0);
        for case in 0..300 {
            let items = random_items_of(&mut rng, false, (6, 4), 5);
            let area: f64 = items.iter().map(|it| it.opts[0][0] * it.opts[0][1]).sum();
            let w = (4 + rng.below(6)) as f64;
            let d = ((area / w).ceil() + rng.below(2) as f64).max(5.0);
            let what = format!("case {case}: {items:?} in {w} × {d}");
            let (r, l, c) = decide_both(&items, w, d, &what);
            (leaves, cuts) = (leaves + l, cuts + c);
            packed += matches!(r, Outcome::Packed(_)) as u32;
            refuted += matches!(r, Outcome::Infeasible) as u32;
            let both = (count_packings(&items, w, d, true), count_packings(&items, w, d, false));
            if let (Some((all, c)), Some((all_without, _))) = both {
                assert_eq!(all, all_without, "{what}: packings enumerated");
                (packings, enum_cuts) = (packings + all, enum_cuts + c);
            }
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
                for d in (n..=w).filter(|&d| w * d >= sum && w * d <= best) {
                    let (r, _, c) = decide_both(&items, w as f64, d as f64, &format!("squares 1…{n} in {w} × {d}"));
                    cuts += c;
                    packed += matches!(r, Outcome::Packed(_)) as u32;
                    refuted += matches!(r, Outcome::Infeasible) as u32;
                }
            }
        }
        assert!(
            cuts > 100 && packed > 30 && refuted > 30 && leaves > 100 && enum_cuts > 100,
            "cuts {cuts}, packed {packed}, refuted {refuted}, y-phase leaves {leaves}, packings {packings}, cuts enumerating {enum_cuts}"
        );
    }
}

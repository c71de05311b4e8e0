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

/// Necessary conditions of [`dominated`], checked before its scan: a state loads every column
/// at least as much as a dead one only if its open objects are at least as deep in sum (the
/// load just left of the dead one's first end), one of them ends no earlier than the dead
/// one's last (the load just left of that end is positive), and its load is no less at eight
/// columns spread over the rest of the box, each rounded down to a 127th of the box's depth
/// (rounding down keeps the order, so nothing dominated fails the test; the eight compare as
/// the bytes of one word). In the contact enumeration the lists of dead profiles per placed set
/// and position run to dozens (n20_k4_s0017: 58 on average per lookup, 4.5 in an area stage),
/// and most lookups find none dominating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Sig {
    load: i32,
    last: i32,
    loads: u64,
}

/// The high bit of each byte of [`Sig::loads`].
const HIGH: u64 = 0x8080_8080_8080_8080;

impl Sig {
    /// The signature of `profile` at position `t` in a box `w` wide and `d` deep, all three in
    /// the profile's units.
    pub(super) fn of(profile: &[(i32, i32)], t: i64, w: i64, d: i64) -> Sig {
        let load: i64 = profile.iter().map(|&(_, h)| h as i64).sum();
        let mut loads = 0u64;
        let (mut rest, mut j) = (load, 0);
        // One scale for every profile, so the rounding is one monotone function of the load.
        let scale = 127.0 / d.max(1) as f64;
        for k in 0..8 {
            let x = t + (((w - t) * (2 * k + 1)) >> 4);
            while j < profile.len() && profile[j].0 as i64 <= x {
                rest -= profile[j].1 as i64;
                j += 1;
            }
            let q = ((rest.max(0) as f64 * scale) as u64).min(127);
            loads |= q << (8 * k);
        }
        Sig {
            // Saturating is monotone too (the load of one column is at most `d`, which fits).
            load: load.clamp(0, i32::MAX as i64) as i32,
            last: profile.last().map_or(i32::MIN, |e| e.0),
            loads,
        }
    }

    /// The signature every profile passes against: for profiles kept without one.
    pub(super) const NONE: Sig = Sig {
        load: i32::MIN,
        last: i32::MIN,
        loads: 0,
    };

    /// As two entries of the profiles' arena, stored just before the profile.
    pub(super) fn words(self) -> [(i32, i32); 2] {
        [
            (self.load, self.last),
            (self.loads as u32 as i32, (self.loads >> 32) as u32 as i32),
        ]
    }

    /// The signature [`Self::words`] stored.
    pub(super) fn from_words(w: &[(i32, i32)]) -> Sig {
        Sig {
            load: w[0].0,
            last: w[0].1,
            loads: w[1].0 as u32 as u64 | (w[1].1 as u32 as u64) << 32,
        }
    }

    /// Whether a profile of this signature may load every column at least as much as one of
    /// signature `a` ([`dominated`] is false otherwise).
    pub(super) fn may_dominate(self, a: Sig) -> bool {
        // Bytewise `self ≥ a`: no byte exceeds 127, so setting its high bit leaves room for the
        // subtraction without a borrow into the next byte, and the bit stays set exactly where
        // `self`'s byte is at least `a`'s.
        let bytes_ge = ((self.loads | HIGH) - a.loads) & HIGH == HIGH;
        self.load >= a.load && self.last >= a.last && bytes_ge
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{random_items_of, Lcg};
    use super::super::{Item, Outcome, Pos, Search};
    use super::{dominated, Sig};
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
        /// The signature's test never fails where [`dominated`] holds, at any position and box.
        #[test]
        fn a_dominating_profile_passes_the_signature(a in profile(), b in profile(), t in 0i64..3, w in 12i64..40, d in 1i64..30) {
            if dominated(&b, &a) {
                prop_assert!(Sig::of(&b, t, w, d).may_dominate(Sig::of(&a, t, w, d)));
            }
        }

        /// Likewise where `b` is `a` with every object ending later and deeper, and more of them,
        /// so that it dominates by construction (random pairs rarely do).
        #[test]
        fn a_profile_made_to_dominate_passes_the_signature(
            a in profile(),
            more in prop::collection::vec((0i32..4, 0i32..3), 6),
            extra in profile(),
            t in 0i64..3, w in 12i64..40, d in 1i64..30,
        ) {
            let mut b: Vec<(i32, i32)> = a.iter().zip(&more).map(|(&(e, h), &(de, dh))| (e + de, h + dh)).collect();
            b.extend(extra);
            b.sort_unstable();
            prop_assert!(dominated(&b, &a));
            prop_assert!(Sig::of(&b, t, w, d).may_dominate(Sig::of(&a, t, w, d)));
            let sig = Sig::of(&b, t, w, d);
            prop_assert_eq!(Sig::from_words(&sig.words()), sig);
            prop_assert!(sig.may_dominate(Sig::NONE));
        }

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

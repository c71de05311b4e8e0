//! Subset sums of depths on the sizes' common grid: the most that objects stacked in one column
//! can fill of its free depth.
//!
//! The x-phase's capacity check counts a column's free depth `f` as fillable in full. Objects
//! stacked in a column fill a sum of their depths, so at most the largest subset sum `≤ f` of
//! the depths still to place; where the sizes share a grid `g`, those sums are a bitset of
//! `d / g + 1` bits. This only lowers an upper bound on what the columns can hold, so every
//! refutation it adds is a proof (docs/algorithms.md, "Subset sums per column").

use super::{fitting, Item};

/// Largest grid size in steps (bits per bitset) for which the sums are kept: beyond it the bitset
/// work per node outweighs what it prunes.
const MAX_STEPS: f64 = 4096.0;

/// The depths of the items in grid steps, and the bitset size.
pub(super) struct Grid {
    g: f64,
    words: usize,
    /// Per item, its distinct fitting depths in steps.
    steps: Vec<Vec<usize>>,
}

/// Greatest common divisor of two positive lengths, remainders below `eps` taken as zero.
fn gcd(a: f64, b: f64, eps: f64) -> f64 {
    let (mut a, mut b) = (a.max(b), a.min(b));
    while b > eps {
        let r = a % b;
        let r = if r > b - eps { 0.0 } else { r };
        a = b;
        b = r;
    }
    a
}

impl Grid {
    /// The grid of the items' fitting depths in `w × d`; `None` when they share none coarse
    /// enough (no grid of at most [`MAX_STEPS`] steps across `d`).
    pub(super) fn new(items: &[Item], w: f64, d: f64) -> Option<Grid> {
        let eps = 1e-7 * (1.0 + d);
        let depths: Vec<Vec<f64>> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|f| f[1]).collect())
            .collect();
        let g = depths
            .iter()
            .flatten()
            .fold(0.0, |g, &v| if g == 0.0 { v } else { gcd(g, v, eps) });
        if g <= eps || d / g > MAX_STEPS {
            return None;
        }
        let step = |v: f64| {
            let s = (v / g).round();
            ((v / g - s).abs() <= 1e-6 * (1.0 + s)).then_some(s as usize)
        };
        let mut steps = Vec::with_capacity(items.len());
        for ds in &depths {
            let mut s: Vec<usize> = ds.iter().map(|&v| step(v)).collect::<Option<_>>()?;
            s.sort_unstable();
            s.dedup();
            steps.push(s);
        }
        let words = (d / g + 1e-6).floor() as usize / 64 + 1;
        Some(Grid { g, words, steps })
    }

    /// `bits` set to the empty sum only.
    pub(super) fn clear(&self, bits: &mut Vec<u64>) {
        bits.clear();
        bits.resize(self.words, 0);
        bits[0] = 1;
    }

    /// Add item `i` to the sums in `bits` (it contributes one of its depths or nothing);
    /// `tmp` is scratch.
    #[inline]
    pub(super) fn add(&self, bits: &mut [u64], tmp: &mut Vec<u64>, i: usize) {
        if let [one] = bits {
            // Depths of at most 63 steps (the common case), in one word, without the copy.
            let b = *one;
            for &s in &self.steps[i] {
                *one |= b << s;
            }
            return;
        }
        self.add_wide(bits, tmp, i);
    }

    /// The grid step, as a length.
    pub(super) fn step(&self) -> f64 {
        self.g
    }

    /// Whether the sums fit one word (every depth within 63 steps): [`Self::add_word`] and
    /// [`most_in_word`] then do the work of [`Self::add`] and [`Self::most_steps`].
    pub(super) fn one_word(&self) -> bool {
        self.words == 1
    }

    /// The sums `bits` (one word) with item `i` added.
    #[inline]
    pub(super) fn add_word(&self, bits: u64, i: usize) -> u64 {
        // Most items have one fitting depth (the squares): that one without the loop.
        match self.steps[i][..] {
            [s] => bits | bits << s,
            ref all => all.iter().fold(bits, |acc, &s| acc | bits << s),
        }
    }

    /// `steps` grid steps as a length, for a count of steps already multiplied by widths (an
    /// area in width × steps).
    #[inline]
    pub(super) fn length_of(&self, steps: f64) -> f64 {
        steps * self.g
    }

    /// [`Self::add`] on sums wider than one word, out of line so that the common case inlines.
    #[inline(never)]
    fn add_wide(&self, bits: &mut [u64], tmp: &mut Vec<u64>, i: usize) {
        tmp.clear();
        tmp.extend_from_slice(bits);
        for &s in &self.steps[i] {
            let (wsh, bsh) = (s / 64, s % 64);
            for k in (wsh..self.words).rev() {
                let lo = tmp[k - wsh] << bsh;
                let hi = if bsh > 0 && k > wsh {
                    tmp[k - wsh - 1] >> (64 - bsh)
                } else {
                    0
                };
                bits[k] |= lo | hi;
            }
        }
    }

    /// The largest sum in `bits` at most `f`, as a length.
    #[cfg(test)]
    pub(super) fn most(&self, bits: &[u64], f: f64) -> f64 {
        self.length(self.most_steps(bits, self.steps_in(f)))
    }

    /// `steps` grid steps as a length.
    #[inline]
    pub(super) fn length(&self, steps: usize) -> f64 {
        // Through u32 (steps ≤ 4096): converting a u64 takes a dozen instructions on x86-64.
        steps as u32 as f64 * self.g
    }

    /// The length `f` in whole grid steps (0 below 0), for [`Self::most_steps`]: computed once
    /// where one length is asked about many times (`floor` is a library call, and it took 5 %
    /// of the packing search's time).
    #[inline]
    pub(super) fn steps_in(&self, f: f64) -> usize {
        if f < 0.0 {
            return 0;
        }
        // Truncation is the floor of a value that is not negative, without a call to libm's
        // `floor`, which is no instruction on the baseline x86-64 target (it was 4 % of the area
        // stage's instructions).
        ((f / self.g + 1e-6) as i64 as usize).min(self.words * 64 - 1)
    }

    /// The largest sum in `bits` at most `q` steps, in steps.
    #[inline]
    pub(super) fn most_steps(&self, bits: &[u64], q: usize) -> usize {
        let (mut k, b) = (q / 64, q % 64);
        let mut word = bits[k] & (u64::MAX >> (63 - b));
        loop {
            if word != 0 {
                return k * 64 + 63 - word.leading_zeros() as usize;
            }
            if k == 0 {
                return 0;
            }
            k -= 1;
            word = bits[k];
        }
    }
}

/// The largest sum in the one-word sums `bits` at most `q ≤ 63` steps, in steps (the empty sum
/// is always there).
#[inline]
pub(super) fn most_in_word(bits: u64, q: usize) -> usize {
    63 - (bits & (u64::MAX >> (63 - q))).leading_zeros() as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(sizes: &[[f64; 2]]) -> Item {
        Item {
            opts: sizes.to_vec(),
            class: 0,
        }
    }

    #[test]
    fn the_largest_subset_sum_below_a_depth() {
        let items = vec![
            item(&[[1.0, 0.3]]),
            item(&[[1.0, 0.5], [0.5, 1.0]]),
            item(&[[1.0, 0.7]]),
        ];
        let g = Grid::new(&items, 2.0, 2.0).expect("a 0.1 grid");
        let (mut bits, mut tmp) = (Vec::new(), Vec::new());
        g.clear(&mut bits);
        for i in 0..3 {
            g.add(&mut bits, &mut tmp, i);
        }
        // Sums: 0, .3, .5, .7, .8, 1.0, 1.2, 1.3, 1.5, 1.7, 2.0.
        let want = [
            (0.25, 0.0),
            (0.45, 0.3),
            (0.69, 0.5),
            (0.9, 0.8),
            (1.1, 1.0),
            (1.25, 1.2),
            (1.9, 1.7),
            (2.0, 2.0),
        ];
        for (f, m) in want {
            assert!((g.most(&bits, f) - m).abs() < 1e-9, "most({f}) = {}", g.most(&bits, f));
        }
    }

    #[test]
    fn sums_cross_word_boundaries() {
        // Steps of 1 across 300: depths 70 and 130 reach 200 only together.
        let items = vec![item(&[[1.0, 70.0]]), item(&[[1.0, 130.0]])];
        let g = Grid::new(&items, 300.0, 300.0).expect("a unit grid");
        let (mut bits, mut tmp) = (Vec::new(), Vec::new());
        g.clear(&mut bits);
        g.add(&mut bits, &mut tmp, 0);
        g.add(&mut bits, &mut tmp, 1);
        assert_eq!(g.most(&bits, 199.0), 130.0);
        assert_eq!(g.most(&bits, 250.0), 200.0);
        assert_eq!(g.most(&bits, 69.0), 0.0);
        // 61 + 10 = 71: a sum carried from one word into the next.
        let items = vec![item(&[[1.0, 61.0]]), item(&[[1.0, 10.0]])];
        let g = Grid::new(&items, 300.0, 300.0).expect("a unit grid");
        g.clear(&mut bits);
        g.add(&mut bits, &mut tmp, 0);
        g.add(&mut bits, &mut tmp, 1);
        assert_eq!(g.most(&bits, 70.0), 61.0);
        assert_eq!(g.most(&bits, 80.0), 71.0);
    }

    #[test]
    fn no_grid_for_unrelated_sizes() {
        let items = vec![item(&[[1.0, 1.0]]), item(&[[1.0, std::f64::consts::PI]])];
        assert!(Grid::new(&items, 10.0, 10.0).is_none());
    }
}

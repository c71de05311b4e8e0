//! Time law of one rest-to-rest joint path: a trapezoid on the path parameter, smoothed by a
//! moving average so that the joint velocity is continuous and the joint acceleration bounded.
//!
//! The raw motion `r(t)` runs the waypoint polyline with one trapezoidal profile on the path
//! parameter τ (τ̇ ≤ rate, |τ̈| ≤ α; τ is the time the path takes with its fastest joint at its
//! limit). Its velocity is bounded but jumps at every bend of the polyline. The motion that is
//! recorded is its moving average over a window of `w` seconds,
//! `q(t) = (1/w) ∫_{t−w}^{t} r(s) ds`, which lasts `w` longer. Then
//!
//! * `q̇(t) = (r(t) − r(t−w)) / w` is continuous (r is), and every `|q̇_j|` is at most the largest
//!   `|ṙ_j|`, so the velocity limit carries over exactly;
//! * `q̈(t) = (ṙ(t) − ṙ(t−w)) / w`: on a straight leg (two waypoints) at most the trapezoid's
//!   tangential acceleration, and in general the tangential part plus the velocity jumps at the
//!   bends inside the window (the centripetal acceleration of the smoothed curve). Its largest
//!   value is computed exactly (q̈ is piecewise linear in t) and, when it exceeds the limit, the
//!   whole law is slowed down uniformly (time scaled by k: accelerations fall by k²);
//! * on a straight leg `q` stays on the segment (an average of points of a segment), so
//!   joint moves are exactly the collision-checked path; on a sampled Cartesian line it is an
//!   average of the polyline over the window, inside its bends by far less than the line's own
//!   tolerance (measured in docs/robot.md);
//! * the finite differences of any samples of `q` obey the same bounds: the mean of q̇ over an
//!   interval is within the velocity limit, and the difference of two adjacent means divided by
//!   the distance of the intervals' midpoints is a weighted mean of q̈.
//!
//! `r` is quadratic in t between its break points (phase changes of the trapezoid and the times
//! of the waypoints), so the integral is exact with Simpson's rule between break points.

/// Length of the moving-average window at full speed (s). Longer windows round the bends of a
/// Cartesian line more (and add their length to every leg); shorter ones leave the velocity
/// jumps at the bends as steeper accelerations, which the uniform slow-down then pays for.
pub const SMOOTHING_WINDOW: f64 = 0.1;

/// Smallest time between an extra sample at a bend and any other sample (s): samples closer than
/// this add nothing for a controller and make finite differences sensitive to rounding.
const MIN_SAMPLE_GAP: f64 = 1e-3;

/// The polyline timed with one trapezoid on τ.
struct Raw<'a> {
    w: &'a [[f64; 6]],
    tau: &'a [f64],
    l: f64,
    alpha: f64,
    peak: f64,
    ta: f64,
    dur: f64,
}

impl<'a> Raw<'a> {
    fn new(w: &'a [[f64; 6]], tau: &'a [f64], alpha: f64, rate: f64) -> Self {
        let l = *tau.last().expect("non-empty");
        let (peak, ta, dur) = if l * alpha >= rate * rate {
            (rate, rate / alpha, l / rate + rate / alpha)
        } else {
            let p = (alpha * l).sqrt();
            (p, p / alpha, 2.0 * p / alpha)
        };
        Raw {
            w,
            tau,
            l,
            alpha,
            peak,
            ta,
            dur,
        }
    }

    /// Path parameter and its rate at time t (at rest outside [0, dur]).
    fn x(&self, t: f64) -> (f64, f64) {
        let (a, ta, dur) = (self.alpha, self.ta, self.dur);
        if t <= 0.0 {
            (0.0, 0.0)
        } else if t >= dur {
            (self.l, 0.0)
        } else if t <= ta {
            (0.5 * a * t * t, a * t)
        } else if t >= dur - ta {
            let r = dur - t;
            (self.l - 0.5 * a * r * r, a * r)
        } else {
            (0.5 * a * ta * ta + self.peak * (t - ta), self.peak)
        }
    }

    /// Time at which the path parameter reaches x.
    fn time_at(&self, x: f64) -> f64 {
        let xa = 0.5 * self.alpha * self.ta * self.ta;
        let t = if x <= xa {
            (2.0 * x / self.alpha).sqrt()
        } else if x >= self.l - xa {
            self.dur - (2.0 * (self.l - x).max(0.0) / self.alpha).sqrt()
        } else {
            self.ta + (x - xa) / self.peak
        };
        t.clamp(0.0, self.dur)
    }

    /// Piece of the polyline that holds path parameter x, and the fraction along it.
    fn piece(&self, x: f64) -> (usize, f64) {
        let last = self.tau.len() - 2;
        let k = self.tau.partition_point(|&v| v <= x).saturating_sub(1).min(last);
        let span = self.tau[k + 1] - self.tau[k];
        let u = if span > 1e-15 {
            ((x - self.tau[k]) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        (k, u)
    }

    fn pos(&self, t: f64) -> [f64; 6] {
        let (x, _) = self.x(t);
        let (k, u) = self.piece(x);
        let (a, b) = (&self.w[k], &self.w[k + 1]);
        std::array::from_fn(|j| a[j] + u * (b[j] - a[j]))
    }

    fn vel(&self, t: f64) -> [f64; 6] {
        let (x, rate) = self.x(t);
        let (k, _) = self.piece(x);
        let span = self.tau[k + 1] - self.tau[k];
        if span <= 1e-15 || rate == 0.0 {
            return [0.0; 6];
        }
        let (a, b) = (&self.w[k], &self.w[k + 1]);
        std::array::from_fn(|j| (b[j] - a[j]) / span * rate)
    }

    /// Sorted times between which `pos` is quadratic in t.
    fn breaks(&self) -> Vec<f64> {
        let mut b = vec![0.0, self.ta, self.dur - self.ta, self.dur];
        b.extend(self.tau[1..self.tau.len() - 1].iter().map(|&x| self.time_at(x)));
        b.sort_by(f64::total_cmp);
        b.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        b
    }
}

/// The smoothed law of one leg: the raw motion averaged over `win` seconds.
pub(crate) struct Smoothed<'a> {
    raw: Raw<'a>,
    win: f64,
    breaks: Vec<f64>,
}

impl<'a> Smoothed<'a> {
    /// The law of the polyline `w` (path parameter `tau` at its waypoints, τ ends > 0) with
    /// tangential acceleration `alpha`, largest rate 1 and window [`SMOOTHING_WINDOW`], slowed
    /// down uniformly until no joint accelerates faster than `amax`.
    pub(crate) fn new(w: &'a [[f64; 6]], tau: &'a [f64], alpha: f64, amax: f64) -> Self {
        let mut k = 1.0f64;
        loop {
            let raw = Raw::new(w, tau, alpha / (k * k), 1.0 / k);
            let breaks = raw.breaks();
            let s = Smoothed {
                raw,
                win: SMOOTHING_WINDOW * k,
                breaks,
            };
            let ratio = s.max_acceleration() / amax;
            // One slow-down suffices in exact arithmetic; the bound on k only guards against
            // non-finite input (which the verifier then reports) looping forever; a NaN ratio
            // returns too.
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(ratio > 1.0 + 1e-9) || k > 1e6 {
                return s;
            }
            // Time scaled by k' divides every acceleration by k'²; a hair more for rounding.
            k *= ratio.sqrt() * (1.0 + 1e-9);
        }
    }

    /// Duration (s), from rest to rest.
    pub(crate) fn duration(&self) -> f64 {
        self.raw.dur + self.win
    }

    /// Joint positions at time t (exact integral of the raw motion over the window).
    pub(crate) fn pos(&self, t: f64) -> [f64; 6] {
        let (a, b) = (t - self.win, t);
        let i0 = self.breaks.partition_point(|&x| x <= a);
        let i1 = self.breaks.partition_point(|&x| x < b);
        let mut cuts = vec![a];
        cuts.extend_from_slice(&self.breaks[i0..i1]);
        cuts.push(b);
        let mut sum = [0.0; 6];
        for c in cuts.windows(2) {
            let h = c[1] - c[0];
            if h <= 0.0 {
                continue;
            }
            let (p0, pm, p1) = (
                self.raw.pos(c[0]),
                self.raw.pos(0.5 * (c[0] + c[1])),
                self.raw.pos(c[1]),
            );
            for j in 0..6 {
                sum[j] += h / 6.0 * (p0[j] + 4.0 * pm[j] + p1[j]);
            }
        }
        sum.map(|s| s / self.win)
    }

    /// Joint velocities at time t.
    pub(crate) fn vel(&self, t: f64) -> [f64; 6] {
        let (a, b) = (self.raw.pos(t - self.win), self.raw.pos(t));
        std::array::from_fn(|j| (b[j] - a[j]) / self.win)
    }

    fn acc(&self, t: f64) -> [f64; 6] {
        let (a, b) = (self.raw.vel(t - self.win), self.raw.vel(t));
        std::array::from_fn(|j| (b[j] - a[j]) / self.win)
    }

    /// Largest |q̈_j| over the whole law: q̈ is linear in t between the break points of the raw
    /// motion and those shifted by the window, so its extremes are one-sided limits there.
    pub(crate) fn max_acceleration(&self) -> f64 {
        let eps = 1e-9 * self.duration().max(1.0);
        let mut worst = 0.0f64;
        for &b in &self.breaks {
            for c in [b, b + self.win] {
                for t in [c - eps, c + eps] {
                    worst = self.acc(t).iter().fold(worst, |m, a| m.max(a.abs()));
                }
            }
        }
        worst
    }

    /// Sample times: every ≤ `dt` from 0 to the end, plus, on a bent polyline, the times at
    /// which the window is centred on each waypoint and on the middle of each piece, none of those
    /// closer than [`MIN_SAMPLE_GAP`] to another sample. The averaged curve lies slightly inside
    /// the polyline's bends, and the chords between samples cut further inside; with two samples
    /// per piece a controller interpolating between points stays as close to a Cartesian line as
    /// the waypoints themselves (measured in `tests/robot.rs`).
    pub(crate) fn sample_times(&self, dt: f64) -> Vec<f64> {
        let end = self.duration();
        let n = (end / dt).ceil().max(1.0) as usize;
        let mut grid: Vec<f64> = (0..=n).map(|i| end * i as f64 / n as f64).collect();
        grid[n] = end;
        // A straight leg needs none: its samples all lie on its segment.
        let tau = self.raw.tau;
        let mut extra: Vec<f64> = if tau.len() > 2 {
            tau.windows(2)
                .flat_map(|p| [0.5 * (p[0] + p[1]), p[1]])
                .map(|x| self.raw.time_at(x) + 0.5 * self.win)
                .collect()
        } else {
            Vec::new()
        };
        extra.sort_by(f64::total_cmp);
        let mut times = grid.clone();
        let mut last_extra = f64::NEG_INFINITY;
        for t in extra {
            let i = grid.partition_point(|&g| g < t);
            let near_grid =
                grid.get(i).is_some_and(|g| g - t < MIN_SAMPLE_GAP) || (i > 0 && t - grid[i - 1] < MIN_SAMPLE_GAP);
            if !near_grid && t - last_extra >= MIN_SAMPLE_GAP {
                times.push(t);
                last_extra = t;
            }
        }
        times.sort_by(f64::total_cmp);
        times
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// τ of a polyline whose fastest joint moves at `v` (the law's path parameter).
    fn tau_of(w: &[[f64; 6]], v: f64) -> Vec<f64> {
        let mut tau = vec![0.0];
        for p in w.windows(2) {
            let d = (0..6).map(|j| (p[1][j] - p[0][j]).abs() / v).fold(0.0, f64::max);
            tau.push(tau.last().unwrap() + d);
        }
        tau
    }

    /// An arc of 1 rad radius in joints 0 and 1 through 0.04 rad chords: a Cartesian line's joint
    /// path bends about this much per waypoint.
    fn arc(n: usize, step: f64) -> Vec<[f64; 6]> {
        (0..=n)
            .map(|i| {
                let a = i as f64 * step;
                [a.sin(), 1.0 - a.cos(), 0.1, 0.0, 0.0, 0.0]
            })
            .collect()
    }

    #[test]
    fn the_smoothed_law_keeps_the_limits_and_is_continuous() {
        let (v, amax) = (0.45, 0.81);
        for w in [arc(25, 0.04), vec![[0.0; 6], [0.3, -0.2, 0.1, 0.0, 0.5, 0.0]]] {
            let tau = tau_of(&w, v);
            let s = Smoothed::new(&w, &tau, amax / v, amax);
            assert!(s.max_acceleration() <= amax * (1.0 + 1e-6));
            let end = s.duration();
            let (start, fin) = (s.pos(0.0), s.pos(end));
            assert!((0..6).all(|j| (start[j] - w[0][j]).abs() < 1e-12));
            assert!((0..6).all(|j| (fin[j] - w.last().unwrap()[j]).abs() < 1e-12));
            // Dense samples: finite-difference velocity within v, acceleration within amax, and
            // the recorded velocity is the derivative of the position.
            let h = 1e-3;
            let ts: Vec<f64> = (0..=((end / h) as usize)).map(|i| i as f64 * h).collect();
            let qs: Vec<[f64; 6]> = ts.iter().map(|&t| s.pos(t)).collect();
            let mut prev: Option<[f64; 6]> = None;
            for i in 1..qs.len() {
                let fd: [f64; 6] = std::array::from_fn(|j| (qs[i][j] - qs[i - 1][j]) / h);
                let mid = s.vel(ts[i] - 0.5 * h);
                for j in 0..6 {
                    assert!(fd[j].abs() <= v * (1.0 + 1e-9), "speed {}", fd[j]);
                    assert!((fd[j] - mid[j]).abs() < amax * h, "velocity {} vs {}", mid[j], fd[j]);
                    if let Some(p) = prev {
                        assert!((fd[j] - p[j]).abs() / h <= amax * (1.0 + 1e-6), "acc");
                    }
                }
                prev = Some(fd);
            }
        }
    }

    #[test]
    fn a_straight_leg_has_continuous_acceleration_and_bounded_jerk() {
        let (v, amax) = (0.45, 0.81);
        // A long leg (trapezoid) and a short one (triangle shorter than the window).
        for b in [[0.9, -0.3, 0.2, 0.0, 0.4, 0.1], [0.002, 0.0, 0.001, 0.0, 0.0, 0.0]] {
            let w = vec![[0.0; 6], b];
            let tau = tau_of(&w, v);
            let s = Smoothed::new(&w, &tau, amax / v, amax);
            let h = 1e-4;
            let n = (s.duration() / h) as usize;
            for i in 0..n {
                let (a0, a1) = (s.acc(i as f64 * h), s.acc((i + 1) as f64 * h));
                for j in 0..6 {
                    let jerk = (a1[j] - a0[j]).abs() / h;
                    assert!(jerk <= 2.0 * amax / SMOOTHING_WINDOW * (1.0 + 1e-6), "jerk {jerk}");
                }
            }
        }
    }

    #[test]
    fn a_straight_leg_stays_on_its_segment_and_a_bent_one_near_its_polyline() {
        let v = 0.45;
        let w = vec![[0.0; 6], [0.4, -0.2, 0.1, 0.0, 0.5, 0.0]];
        let tau = tau_of(&w, v);
        let s = Smoothed::new(&w, &tau, 0.81 / v, 0.81);
        for t in s.sample_times(0.05) {
            let q = s.pos(t);
            let u = q[4] / 0.5;
            assert!((0..6).all(|j| (q[j] - u * w[1][j]).abs() < 1e-12), "off the segment");
        }
        // The arc: every sample within a small distance of the polyline's chords.
        let w = arc(25, 0.04);
        let tau = tau_of(&w, v);
        let s = Smoothed::new(&w, &tau, 0.81 / v, 0.81);
        let mut worst = 0.0f64;
        for t in s.sample_times(0.1) {
            let q = s.pos(t);
            // Distance to the unit circle through the waypoints (the chords are inside it by
            // at most 0.04²/8 = 2e-4).
            let r = (q[0].powi(2) + (1.0 - q[1]).powi(2)).sqrt();
            worst = worst.max((1.0 - r).abs());
        }
        assert!(worst < 2e-4 + 2e-4, "{worst}");
    }

    #[test]
    fn sample_times_cover_the_law_every_dt_and_keep_a_gap() {
        let w = arc(25, 0.04);
        let tau = tau_of(&w, 0.45);
        let s = Smoothed::new(&w, &tau, 0.81 / 0.45, 0.81);
        let ts = s.sample_times(0.1);
        assert_eq!(ts[0], 0.0);
        assert_eq!(*ts.last().unwrap(), s.duration());
        assert!(ts.len() > 25, "the bends are sampled");
        for p in ts.windows(2) {
            assert!(p[1] - p[0] >= MIN_SAMPLE_GAP * (1.0 - 1e-9) && p[1] - p[0] <= 0.1 + 1e-12);
        }
    }
}

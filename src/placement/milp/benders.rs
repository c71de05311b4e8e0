//! One enclosing box decided by combinatorial Benders decomposition with a HiGHS master: the
//! x-coordinates by a MILP under the cumulative relaxation in y, the y-coordinates by the
//! exact y-phase of [`crate::placement::opp`], and a no-good cut from every x-assignment the
//! y-phase refutes (Côté, Dell'Amico and Iori 2014).
//!
//! Master, for a box `W × D`: a binary `z[i,k,p]` per item `i`, fitting footprint `k` and left
//! edge `p`, where `p` runs over the normal patterns (subset sums of footprint widths) up to
//! `W − w_ik`; each item takes exactly one; at every normal pattern `q` the items covering `q`
//! have depths summing to at most `D` (the load only rises at left edges, so these rows bound it
//! everywhere); identical items in order of their left edges. Every packing compacts to one
//! whose left edges are normal patterns (docs/algorithms.md), so the master's relaxation drops
//! no packing's x-assignment. When the master is infeasible, no packing exists.
//!
//! Subproblem: [`Search::y_for`] places the items in y with the x-assignment fixed; it is exact
//! for that assignment. When it fails, a deletion filter shrinks the items to a subset `S` that
//! still fails on its own (an irreducible one when the filter completes), and the cut
//! `Σ_{i∈S} z[i,k_i,p_i] ≤ |S| − 1` forbids that combination of footprints and left edges in
//! every later master: no packing has it, because the items of `S` alone cannot be stacked with
//! it. So every cut keeps every packing, and the loop ends with a packing or a proof.

use super::*;
use crate::placement::area::subset_sums;
use crate::placement::opp::{Item, Outcome, Search};

/// The x-assignment of one master solution: per item, footprint index and left edge; plus the
/// master columns it came from.
struct Assignment {
    opt: Vec<usize>,
    x0: Vec<f64>,
    cols: Vec<usize>,
}

/// The master's columns: item, footprint, left edge.
struct Master {
    cols: Vec<(usize, usize, f64)>,
    /// Every left edge a row must bound the load at.
    points: Vec<f64>,
}

impl Master {
    fn new(items: &[Item], w: f64, d: f64) -> Master {
        let widths: Vec<Vec<f64>> = items.iter().map(|it| it.opts.iter().map(|f| f[0]).collect()).collect();
        let sums = subset_sums(&widths, w);
        let mut cols = Vec::new();
        for (i, it) in items.iter().enumerate() {
            for (k, f) in it.opts.iter().enumerate() {
                if f[0] > w + 1e-9 || f[1] > d + 1e-9 {
                    continue;
                }
                for &p in &sums {
                    if p + f[0] <= w + 1e-9 {
                        cols.push((i, k, p));
                    }
                }
            }
        }
        Master { cols, points: sums }
    }

    /// Solve the master with `cuts`; `Ok(None)`: infeasible (proven by HiGHS).
    fn solve(
        &self,
        items: &[Item],
        d: f64,
        cuts: &[Vec<usize>],
        time_left: f64,
        options: &[(String, String)],
        nodes: &mut u64,
    ) -> Result<Option<Option<Assignment>>> {
        let mut pv = ProblemVariables::new();
        let z: Vec<Variable> = self.cols.iter().map(|_| pv.add(variable().binary())).collect();
        let mut rows: Vec<Constraint> = Vec::new();
        for i in 0..items.len() {
            let one: Expression = self
                .cols
                .iter()
                .zip(&z)
                .filter(|((j, _, _), _)| *j == i)
                .map(|(_, v)| *v)
                .sum();
            rows.push(one.eq(1.0));
        }
        for &q in &self.points {
            let load: Expression = self
                .cols
                .iter()
                .zip(&z)
                .filter(|((i, k, p), _)| *p <= q + 1e-9 && p + items[*i].opts[*k][0] > q + 1e-9)
                .map(|((i, k, _), v)| items[*i].opts[*k][1] * *v)
                .sum();
            // The search's tolerance: sums of extents carry rounding (0.07 + 0.07 > 0.14).
            rows.push(load.leq(d + 1e-9 * (1.0 + d)));
        }
        // Identical items: the later one starts no further left.
        for j in 1..items.len() {
            if let Some(i) = (0..j).rev().find(|&i| items[i].class == items[j].class) {
                let x = |m: usize| -> Expression {
                    self.cols
                        .iter()
                        .zip(&z)
                        .filter(|((c, _, p), _)| *c == m && *p > 0.0)
                        .map(|((_, _, p), v)| *p * *v)
                        .sum()
                };
                rows.push((x(i) - x(j)).leq(0.0));
            }
        }
        for cut in cuts {
            let e: Expression = cut.iter().map(|&c| z[c]).sum();
            rows.push(e.leq(cut.len() as f64 - 1.0));
        }
        let mut problem = pv.minimise(Expression::from(0.0)).using(highs);
        for r in rows {
            problem = problem.with(r);
        }
        // Presolve off: HiGHS 1.x presolve reduced five equal squares in 3 × 2 slots to an empty
        // model whose postsolved solution broke a row, and then reported an error
        // (`benders::tests::five_equal_squares_fit_three_by_two`).
        let solved = run_highs(
            problem,
            &HighsRun {
                initial: None,
                time_left,
                seed: 0,
                abs_gap: 0.0,
                presolve: false,
                options,
            },
        )?;
        *nodes += solved.nodes;
        match solved.status {
            HighsModelStatus::Infeasible => Ok(None),
            _ => Ok(Some(solved.cols.map(|c| {
                let n = items.len();
                let (mut opt, mut x0, mut cols) = (vec![0; n], vec![0.0; n], Vec::new());
                for (ci, &(i, k, p)) in self.cols.iter().enumerate() {
                    if c[ci] > 0.5 {
                        opt[i] = k;
                        x0[i] = p;
                        cols.push(ci);
                    }
                }
                Assignment { opt, x0, cols }
            }))),
        }
    }
}

/// The y-phase for the items of `subset` with their assigned footprints and left edges.
fn y_check(
    items: &[Item],
    a: &Assignment,
    subset: &[usize],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
) -> (Outcome, u64) {
    let sub: Vec<Item> = subset.iter().map(|&i| items[i].clone()).collect();
    let opt: Vec<usize> = subset.iter().map(|&i| a.opt[i]).collect();
    let x0: Vec<f64> = subset.iter().map(|&i| a.x0[i]).collect();
    let mut s = Search::new(&sub, w, d, stop);
    let r = s.y_for(&opt, &x0);
    (r, s.nodes)
}

/// Decide `w × d` by the HiGHS master and the y-phase (the module's doc says why it is exact).
/// A HiGHS failure is an error; a stop, or a master stopped without an answer, is `Stopped`.
pub fn decide_benders(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    time_left: &dyn Fn() -> f64,
    options: &[(String, String)],
) -> Result<(Outcome, u64)> {
    if crate::placement::opp::refuted_by_bounds(items, w, d) {
        return Ok((Outcome::Infeasible, 0));
    }
    let master = Master::new(items, w, d);
    let mut cuts: Vec<Vec<usize>> = Vec::new();
    let mut nodes = 0u64;
    loop {
        if stop() || time_left() <= 0.0 {
            return Ok((Outcome::Stopped, nodes));
        }
        let Some(sol) = master.solve(items, d, &cuts, time_left(), options, &mut nodes)? else {
            return Ok((Outcome::Infeasible, nodes));
        };
        let Some(a) = sol else {
            return Ok((Outcome::Stopped, nodes));
        };
        let all: Vec<usize> = (0..items.len()).collect();
        let (r, n) = y_check(items, &a, &all, w, d, stop);
        nodes += n;
        match r {
            Outcome::Packed(pos) => return Ok((Outcome::Packed(pos), nodes)),
            Outcome::Stopped => return Ok((Outcome::Stopped, nodes)),
            Outcome::Infeasible => {}
        }
        // Deletion filter, smallest items first: drop every item the failure does not need.
        let mut keep = all;
        let mut by_area = keep.clone();
        by_area.sort_by(|&i, &j| {
            let ar = |m: usize| items[m].opts[a.opt[m]][0] * items[m].opts[a.opt[m]][1];
            ar(i).total_cmp(&ar(j))
        });
        for i in by_area {
            let trial: Vec<usize> = keep.iter().copied().filter(|&j| j != i).collect();
            let (r, n) = y_check(items, &a, &trial, w, d, stop);
            nodes += n;
            if r == Outcome::Infeasible {
                keep = trial;
            }
        }
        cuts.push(
            a.cols
                .iter()
                .copied()
                .filter(|&c| keep.contains(&master.cols[c].0))
                .collect(),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn five_equal_squares_fit_three_by_two() {
        let items: Vec<Item> = (0..5)
            .map(|_| Item {
                opts: vec![[0.07, 0.07]],
                class: 0,
            })
            .collect();
        let (r, _) = decide_benders(&items, 0.21, 0.14, &|| false, &|| 10.0, &[]).unwrap();
        assert!(matches!(r, Outcome::Packed(_)), "{r:?}");
    }
}

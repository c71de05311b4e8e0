//! Exact placement: the area stage by enclosing boxes in area order, each decided by an exact
//! packing search ([`super::area`], [`super::opp`]); the contact stage by enumerating the
//! packings of each optimal box, with the HiGHS grid MILP below for what that leaves open
//! (docs/algorithms.md). The per-width depth MILPs described next were the area stage before
//! issue 21; the models remain for the contact stage.
//!
//! The occupied area `W·D` is bilinear, so it is minimised exactly by enumeration of the
//! occupied width. Every placement can be compacted (slid down and left) into a BL-stable one
//! without growing its extents, and in a BL-stable placement every right edge is a sum of
//! footprint widths along a chain from the left wall. So the optimal occupied width `W*` is a
//! subset sum of footprint x-extents (one orientation per object). For each candidate width
//! `W` a MILP minimises the depth `D(W)` with every footprint inside `[0, W] × [0, D]`; the
//! optimum area is `min_W W·D(W)`. `D(W)` is itself a subset sum of y-extents, so every depth
//! bound is rounded up to those sums. Each candidate carries a proven bound `D_lower(W)`
//! (area, largest depth, stacked wide objects; spread to narrower widths because `D` does not
//! grow with `W`, and to transposed widths when placements transpose). Candidates are visited
//! by increasing `W·D_lower(W)`, each visit with the cut `D ≤` one step above that bound and a
//! time cap; a capped candidate keeps its dual bound and is revisited later with a larger cap.
//! The reported `lower_bound` is the least `W·D_lower(W)` over the candidates not solved, and
//! `optimal` is reported only when it meets the area (docs/algorithms.md).
//!
//! A second, lexicographic MILP maximises the contact length among placements inside the
//! optimal extents, with BL-stability as constraints, warm-started with the compacted
//! area-optimal placement.
//!
//! Model (per pair `i < j`): four binaries `left, right, below, above` with sum ≥ 1 and
//! big-M rows with `M = W` (x) or `M = container depth` (y), the tightest constants the box
//! allows; pairs too wide to sit side by side inside `W` get no left/right binaries. Orientation
//! binaries choose among the distinct footprints of each object. Identical objects (same size
//! and allowed footprints) are ordered by `x` (symmetry breaking; valid because any placement can
//! be relabelled so).

use super::area::{self, subset_sums, BoundPoint};
use super::{is_bl_stable, Placement, PlacementResult, PlacementStatus, Target};
use crate::control::Terminator;
use crate::error::{Error, Result};
use crate::geometry::{Axis2, Orientation, Rect, EPS};
use crate::instance::Instance;
use good_lp::solvers::highs::highs;
use good_lp::{variable, Constraint, Expression, ProblemVariables, SolverModel, Variable};
use highs::HighsModelStatus;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Tolerance on areas when collecting the extents tied with the optimum.
const AREA_TOL: f64 = 1e-9;

/// MILP settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MilpSettings {
    /// Wall-clock limit for the whole placement (s).
    pub time_limit: f64,
    /// Run the second stage (maximum contact length with BL-stability constraints).
    pub contact_stage: bool,
    /// HiGHS random seed.
    pub seed: u64,
}

impl Default for MilpSettings {
    fn default() -> Self {
        MilpSettings {
            time_limit: 60.0,
            contact_stage: true,
            seed: 0,
        }
    }
}

/// Distinct footprints (x-extent, y-extent) of each object with their orientations.
fn footprints(inst: &Instance) -> Vec<Vec<([f64; 2], Orientation, f64)>> {
    inst.objects
        .iter()
        .map(|o| {
            let mut v: Vec<([f64; 2], Orientation, f64)> = Vec::new();
            for q in &o.orientations {
                let (fp, h) = q.dims(o.size);
                if !v
                    .iter()
                    .any(|(f, _, _)| (f[0] - fp[0]).abs() <= EPS && (f[1] - fp[1]).abs() <= EPS)
                {
                    v.push((fp, *q, h));
                }
            }
            v
        })
        .collect()
}

/// All sums of at most one x-extent per object that fit in `limit`, sorted, deduplicated.
pub fn candidate_widths(fps: &[Vec<([f64; 2], Orientation, f64)>], limit: f64) -> Vec<f64> {
    let mut sums = vec![0.0f64];
    for opts in fps {
        let mut next = sums.clone();
        for s in &sums {
            for (f, _, _) in opts {
                let v = s + f[0];
                if v <= limit + EPS {
                    next.push(v);
                }
            }
        }
        next.sort_by(f64::total_cmp);
        next.dedup_by(|a, b| (*a - *b).abs() <= 1e-9);
        sums = next;
    }
    sums.retain(|&w| w > EPS);
    sums
}

/// Good_lp variables with their column index (good_lp creates HiGHS columns in this order).
struct Cols {
    pv: ProblemVariables,
    n: usize,
}

impl Cols {
    fn add(&mut self, def: good_lp::VariableDefinition) -> (Variable, usize) {
        let v = self.pv.add(def);
        self.n += 1;
        (v, self.n - 1)
    }
}

/// One pair's relation binaries (i, j, [left, right, below, above]), `None` when fixed to 0.
type PairVars = (usize, usize, [Option<(Variable, usize)>; 4]);

/// The placement MILP for one width bound: owns its variables.
struct PlacementModel {
    /// Orientation binaries per object: (variable, column, footprint index).
    s: Vec<Vec<(Variable, usize)>>,
    x: Vec<(Variable, usize)>,
    y: Vec<(Variable, usize)>,
    /// Pair binaries: (i, j, [left, right, below, above]) — `None` when fixed to 0.
    pairs: Vec<PairVars>,
    depth: (Variable, usize),
    constraints: Vec<Constraint>,
}

impl PlacementModel {
    fn width(&self, fps: &[Vec<([f64; 2], Orientation, f64)>], i: usize) -> Expression {
        self.s[i].iter().zip(&fps[i]).map(|((v, _), (f, _, _))| f[0] * *v).sum()
    }
    fn depth_of(&self, fps: &[Vec<([f64; 2], Orientation, f64)>], i: usize) -> Expression {
        self.s[i].iter().zip(&fps[i]).map(|((v, _), (f, _, _))| f[1] * *v).sum()
    }

    /// Variables and the geometric rows: one orientation each, inside `[0,W]×[0,D]`,
    /// pairwise non-overlap, symmetry breaking.
    fn build(
        inst: &Instance,
        fps: &[Vec<([f64; 2], Orientation, f64)>],
        w: f64,
        d_max: f64,
        cols: &mut Cols,
    ) -> Option<Self> {
        let n = inst.n();
        let mut s = Vec::new();
        for opts in fps.iter() {
            // A footprint that cannot fit is fixed to 0 (kept as a column so indices stay aligned).
            let row: Vec<(Variable, usize)> = opts
                .iter()
                .map(|(f, _, _)| {
                    let fits = f[0] <= w + EPS && f[1] <= d_max + EPS;
                    cols.add(if fits {
                        variable().binary()
                    } else {
                        variable().integer().min(0.0).max(0.0)
                    })
                })
                .collect();
            if opts.iter().all(|(f, _, _)| f[0] > w + EPS || f[1] > d_max + EPS) {
                return None;
            }
            s.push(row);
        }
        let x: Vec<_> = (0..n).map(|_| cols.add(variable().min(0.0).max(w))).collect();
        let y: Vec<_> = (0..n).map(|_| cols.add(variable().min(0.0).max(d_max))).collect();
        let depth = cols.add(variable().min(0.0).max(d_max));
        let mut m = PlacementModel {
            s,
            x,
            y,
            pairs: Vec::new(),
            depth,
            constraints: Vec::new(),
        };
        m.orientation_rows();
        m.containment_rows(fps, w);
        m.non_overlap_rows(fps, w, d_max, cols);
        m.symmetry_rows(inst, fps);
        Some(m)
    }

    fn orientation_rows(&mut self) {
        for row in &self.s {
            let sum: Expression = row.iter().map(|(v, _)| *v).sum();
            self.constraints.push(sum.eq(1.0));
        }
    }

    fn containment_rows(&mut self, fps: &[Vec<([f64; 2], Orientation, f64)>], w: f64) {
        for i in 0..self.s.len() {
            let wi = self.width(fps, i);
            let di = self.depth_of(fps, i);
            self.constraints.push((self.x[i].0 + wi).leq(w));
            self.constraints.push((self.y[i].0 + di).leq(self.depth.0));
        }
        // Area cut (valid, and strong in the LP relaxation): the footprints fit in W·D.
        let area: Expression = self
            .s
            .iter()
            .zip(fps)
            .flat_map(|(row, opts)| row.iter().zip(opts).map(|((v, _), (f, _, _))| f[0] * f[1] * *v))
            .sum();
        self.constraints.push(area.leq(w * self.depth.0));
    }

    fn non_overlap_rows(&mut self, fps: &[Vec<([f64; 2], Orientation, f64)>], w: f64, d_max: f64, cols: &mut Cols) {
        let n = self.s.len();
        let min_w = |i: usize| fps[i].iter().map(|(f, _, _)| f[0]).fold(f64::INFINITY, f64::min);
        let min_d = |i: usize| fps[i].iter().map(|(f, _, _)| f[1]).fold(f64::INFINITY, f64::min);
        for i in 0..n {
            for j in i + 1..n {
                let side_by_side_x = min_w(i) + min_w(j) <= w + EPS;
                let side_by_side_y = min_d(i) + min_d(j) <= d_max + EPS;
                let mut b: [Option<(Variable, usize)>; 4] = [None; 4];
                if side_by_side_x {
                    b[0] = Some(cols.add(variable().binary()));
                    b[1] = Some(cols.add(variable().binary()));
                }
                if side_by_side_y {
                    b[2] = Some(cols.add(variable().binary()));
                    b[3] = Some(cols.add(variable().binary()));
                }
                let sum: Expression = b.iter().flatten().map(|(v, _)| *v).sum();
                self.constraints.push(sum.geq(1.0));
                let (wi, wj) = (self.width(fps, i), self.width(fps, j));
                let (di, dj) = (self.depth_of(fps, i), self.depth_of(fps, j));
                let (xi, xj, yi, yj) = (self.x[i].0, self.x[j].0, self.y[i].0, self.y[j].0);
                if let Some((l, _)) = b[0] {
                    self.constraints.push((xi + wi - xj).leq(w * (1.0 - l)));
                }
                if let Some((r, _)) = b[1] {
                    self.constraints.push((xj + wj - xi).leq(w * (1.0 - r)));
                }
                if let Some((bl, _)) = b[2] {
                    self.constraints.push((yi + di - yj).leq(d_max * (1.0 - bl)));
                }
                if let Some((ab, _)) = b[3] {
                    self.constraints.push((yj + dj - yi).leq(d_max * (1.0 - ab)));
                }
                self.pairs.push((i, j, b));
            }
        }
    }

    fn symmetry_rows(&mut self, inst: &Instance, fps: &[Vec<([f64; 2], Orientation, f64)>]) {
        let n = self.s.len();
        for i in 0..n {
            // Next identical object after i: order them by x.
            if let Some(j) = (i + 1..n).find(|&j| identical(inst, fps, i, j)) {
                self.constraints.push(Expression::from(self.x[i].0).leq(self.x[j].0));
            }
        }
    }
}

fn identical(inst: &Instance, fps: &[Vec<([f64; 2], Orientation, f64)>], i: usize, j: usize) -> bool {
    inst.objects[i].size == inst.objects[j].size
        && fps[i].len() == fps[j].len()
        && fps[i].iter().zip(&fps[j]).all(|(a, b)| a.0 == b.0)
        && inst.objects[i].mass == inst.objects[j].mass
}

/// Positions restricted to *normal patterns* (subset sums of the other footprints' extents),
/// which loses nothing: every BL-stable placement has such coordinates. One binary per
/// (group of identical objects, footprint, x, y); non-overlap as "at most one footprint covers
/// each grid point" — exact on this grid, because two overlapping rectangles both cover the
/// point (max x0, max y0). Identical objects share variables (no symmetry left to break).
struct GridModel {
    /// Per variable: group, footprint index, x, y, column.
    vars: Vec<(usize, usize, f64, f64, Variable, usize)>,
    /// Objects of each group.
    groups: Vec<Vec<usize>>,
    depth: (Variable, usize),
    constraints: Vec<Constraint>,
}

/// Objects grouped by identical size, footprints and mass.
fn groups(inst: &Instance, fps: &[Vec<([f64; 2], Orientation, f64)>]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = Vec::new();
    for i in 0..inst.n() {
        match out.iter_mut().find(|g| identical(inst, fps, g[0], i)) {
            Some(g) => g.push(i),
            None => out.push(vec![i]),
        }
    }
    out
}

impl GridModel {
    /// Grid coordinates for width bound `w` and depth bound `d`.
    fn axes(fps: &[Vec<([f64; 2], Orientation, f64)>], w: f64, d: f64) -> (Vec<f64>, Vec<f64>) {
        let xv: Vec<Vec<f64>> = fps.iter().map(|o| o.iter().map(|(f, _, _)| f[0]).collect()).collect();
        let yv: Vec<Vec<f64>> = fps.iter().map(|o| o.iter().map(|(f, _, _)| f[1]).collect()).collect();
        (subset_sums(&xv, w), subset_sums(&yv, d))
    }

    /// Non-zeros of the cover rows the model would have (its size measure: the cover rows
    /// dominate the work HiGHS does in presolve).
    fn size(inst: &Instance, fps: &[Vec<([f64; 2], Orientation, f64)>], w: f64, d: f64) -> usize {
        let (xs, ys) = Self::axes(fps, w, d);
        let covered = |pos: &[f64], lim: f64, ext: f64| -> usize {
            // Σ over positions p ≤ lim − ext of #grid values in [p, p + ext).
            pos.iter()
                .filter(|&&p| p + ext <= lim + EPS)
                .map(|&p| pos.partition_point(|&q| q < p + ext - 1e-9) - pos.partition_point(|&q| q < p - 1e-9))
                .sum()
        };
        groups(inst, fps)
            .iter()
            .map(|g| {
                fps[g[0]]
                    .iter()
                    .map(|(f, _, _)| covered(&xs, w, f[0]) * covered(&ys, d, f[1]))
                    .sum::<usize>()
            })
            .sum()
    }

    fn build(
        inst: &Instance,
        fps: &[Vec<([f64; 2], Orientation, f64)>],
        w: f64,
        d: f64,
        cols: &mut Cols,
    ) -> Option<Self> {
        let (xs, ys) = Self::axes(fps, w, d);
        let groups = groups(inst, fps);
        let mut vars = Vec::new();
        for (g, members) in groups.iter().enumerate() {
            let before = vars.len();
            for (k, (f, _, _)) in fps[members[0]].iter().enumerate() {
                for &x in xs.iter().filter(|&&x| x + f[0] <= w + EPS) {
                    for &y in ys.iter().filter(|&&y| y + f[1] <= d + EPS) {
                        let (v, c) = cols.add(variable().binary());
                        vars.push((g, k, x, y, v, c));
                    }
                }
            }
            if vars.len() == before {
                return None;
            }
        }
        let depth = cols.add(variable().min(0.0).max(d));
        let mut constraints = Vec::new();
        for (g, members) in groups.iter().enumerate() {
            let sum: Expression = vars.iter().filter(|v| v.0 == g).map(|v| v.4).sum();
            constraints.push(sum.eq(members.len() as f64));
        }
        // Cover rows: each grid point is covered by at most one footprint (half-open rectangles).
        let mut cover: Vec<Vec<Variable>> = vec![Vec::new(); xs.len() * ys.len()];
        for &(g, k, x, y, v, _) in &vars {
            let f = fps[groups[g][0]][k].0;
            let xi0 = xs.partition_point(|&p| p < x - 1e-9);
            let yi0 = ys.partition_point(|&q| q < y - 1e-9);
            for (xi, &p) in xs.iter().enumerate().skip(xi0) {
                if p >= x + f[0] - 1e-9 {
                    break;
                }
                for (yi, &q) in ys.iter().enumerate().skip(yi0) {
                    if q >= y + f[1] - 1e-9 {
                        break;
                    }
                    cover[xi * ys.len() + yi].push(v);
                }
            }
        }
        for c in cover.into_iter().filter(|c| c.len() > 1) {
            let sum: Expression = c.into_iter().sum();
            constraints.push(sum.leq(1.0));
        }
        for &(g, k, _, y, v, _) in &vars {
            let top = y + fps[groups[g][0]][k].0[1];
            constraints.push((Expression::from(depth.0) - top * v).geq(0.0));
        }
        let area: Expression = vars
            .iter()
            .map(|&(g, k, _, _, v, _)| {
                let f = fps[groups[g][0]][k].0;
                f[0] * f[1] * v
            })
            .sum();
        constraints.push(area.leq(w * depth.0));
        Some(GridModel {
            vars,
            groups,
            depth,
            constraints,
        })
    }

    fn initial(&self, fps: &[Vec<([f64; 2], Orientation, f64)>], p: &Placement, ncols: usize) -> Option<Vec<f64>> {
        let mut v = vec![0.0; ncols];
        for (g, members) in self.groups.iter().enumerate() {
            for &i in members {
                let t = p.targets[i].rect;
                let hit = self.vars.iter().find(|&&(gg, k, x, y, _, _)| {
                    if gg != g {
                        return false;
                    }
                    let f = fps[members[0]][k].0;
                    (x - t.x0).abs() <= 1e-7
                        && (y - t.y0).abs() <= 1e-7
                        && (f[0] - t.width()).abs() <= EPS
                        && (f[1] - t.depth()).abs() <= EPS
                })?;
                v[hit.5] = 1.0;
            }
        }
        v[self.depth.1] = p.extent().1;
        Some(v)
    }

    fn extract(&self, fps: &[Vec<([f64; 2], Orientation, f64)>], n: usize, cols: &[f64]) -> Placement {
        let mut targets: Vec<Option<Target>> = vec![None; n];
        let mut next = vec![0usize; self.groups.len()];
        for &(g, k, x, y, _, c) in &self.vars {
            if cols[c] > 0.5 && next[g] < self.groups[g].len() {
                let i = self.groups[g][next[g]];
                next[g] += 1;
                let (f, q, h) = fps[i][k];
                targets[i] = Some(Target {
                    orientation: q,
                    rect: Rect::new(x, y, f[0], f[1]),
                    height: h,
                });
            }
        }
        Placement {
            targets: targets
                .into_iter()
                .enumerate()
                .map(|(i, t)| {
                    // A missing target only happens with a solver tolerance failure; the caller's
                    // validity check then rejects the placement.
                    t.unwrap_or(Target {
                        orientation: fps[i][0].1,
                        rect: Rect::new(-1.0, -1.0, fps[i][0].0[0], fps[i][0].0[1]),
                        height: fps[i][0].2,
                    })
                })
                .collect(),
        }
    }
}

/// Largest grid model (cover-row non-zeros) built before falling back to the disjunctive model.
const GRID_MAX_NNZ: usize = 400_000;

/// The grid limit, overridable by `PUSHPACK_GRID_MAX_NNZ` for measurements (how the 400k
/// default was chosen against 60k: docs/benchmarks.md).
fn grid_max_nnz() -> usize {
    std::env::var("PUSHPACK_GRID_MAX_NNZ")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(GRID_MAX_NNZ)
}

/// Outcome of one HiGHS run.
struct Solved {
    status: HighsModelStatus,
    cols: Option<Vec<f64>>,
    nodes: u64,
}

fn run_highs(
    problem: good_lp::solvers::highs::HighsProblem,
    initial: Option<&[f64]>,
    time_left: f64,
    seed: u64,
    abs_gap: f64,
    presolve: bool,
) -> Result<Solved> {
    let t0 = Instant::now();
    let mut model = problem.try_into_inner().map_err(|e| Error::Solver {
        solver: "HiGHS".into(),
        reason: format!("could not build the model: {e}"),
    })?;
    model.make_quiet();
    if std::env::var("PUSHPACK_DEBUG").map(|v| v == "2").unwrap_or(false) {
        model.set_option("output_flag", true);
        model.set_option("log_to_console", true);
    }
    model.set_option("time_limit", time_left.max(0.01));
    model.set_option("mip_rel_gap", 0.0);
    model.set_option("mip_abs_gap", abs_gap);
    model.set_option("random_seed", (seed % i32::MAX as u64) as i32);
    model.set_option("threads", 1);
    if !presolve {
        model.set_option("presolve", "off");
    }
    // Experiments only (documented in docs/algorithms.md): extra HiGHS options as
    // `name=value,...`, applied last so they override the settings above.
    if let Ok(extra) = std::env::var("PUSHPACK_HIGHS_OPTIONS") {
        for kv in extra.split(',').filter(|s| !s.is_empty()) {
            let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
            match (v.parse::<bool>(), v.parse::<i32>(), v.parse::<f64>()) {
                (Ok(b), _, _) => model.set_option(k, b),
                (_, Ok(i), _) => model.set_option(k, i),
                (_, _, Ok(f)) => model.set_option(k, f),
                _ => model.set_option(k, v),
            }
        }
    }
    if let Some(sol) = initial {
        model.set_solution(Some(sol), None, None, None);
    }
    let t1 = Instant::now();
    let solved = model.try_solve().map_err(|e| Error::Solver {
        solver: "HiGHS".into(),
        reason: format!("{e:?}"),
    })?;
    if std::env::var_os("PUSHPACK_DEBUG").is_some() {
        eprintln!(
            "  highs: into_inner {:.2}s, solve {:.2}s",
            (t1 - t0).as_secs_f64(),
            t1.elapsed().as_secs_f64()
        );
    }
    let status = solved.status();
    let has_sol = solved.primal_solution_status() == highs::HighsSolutionStatus::Feasible;
    let cols = if has_sol {
        Some(solved.get_solution().columns().to_vec())
    } else {
        None
    };
    let nodes = mip_node_count(&solved);
    Ok(Solved { status, cols, nodes })
}

/// HiGHS's branch-and-bound node count (an int64 info value the `highs` crate does not read).
fn mip_node_count(solved: &highs::SolvedModel) -> u64 {
    let mut v: i64 = 0;
    // SAFETY: `solved` owns a live HiGHS instance for the duration of the call, the name is a
    // NUL-terminated C string, and `v` is a valid, writable i64 as the C API requires.
    let status = unsafe { highs_sys::Highs_getInt64InfoValue(solved.as_ptr(), c"mip_node_count".as_ptr(), &mut v) };
    if status == highs_sys::STATUS_OK {
        v.max(0) as u64
    } else {
        0
    }
}

/// Read a placement from a solved column vector.
fn extract(inst: &Instance, fps: &[Vec<([f64; 2], Orientation, f64)>], m: &PlacementModel, cols: &[f64]) -> Placement {
    let targets = (0..inst.n())
        .map(|i| {
            let k = m.s[i]
                .iter()
                .enumerate()
                .max_by(|a, b| cols[a.1 .1].total_cmp(&cols[b.1 .1]))
                .map(|(k, _)| k)
                .expect("at least one orientation");
            let (f, q, h) = fps[i][k];
            // Snap to the 0.1 µm grid: MILP solutions carry solver tolerances.
            let snap = |v: f64| (v * 1e7).round() / 1e7;
            Target {
                orientation: q,
                rect: Rect::new(snap(cols[m.x[i].1]).max(0.0), snap(cols[m.y[i].1]).max(0.0), f[0], f[1]),
                height: h,
            }
        })
        .collect();
    Placement { targets }
}

/// Column vector of a known placement for the model (warm start).
fn initial_columns(
    fps: &[Vec<([f64; 2], Orientation, f64)>],
    m: &PlacementModel,
    p: &Placement,
    ncols: usize,
) -> Vec<f64> {
    let mut v = vec![0.0; ncols];
    for (i, t) in p.targets.iter().enumerate() {
        for ((_, c), (f, _, _)) in m.s[i].iter().zip(&fps[i]) {
            if (f[0] - t.rect.width()).abs() <= EPS && (f[1] - t.rect.depth()).abs() <= EPS {
                v[*c] = 1.0;
                break;
            }
        }
        v[m.x[i].1] = t.rect.x0;
        v[m.y[i].1] = t.rect.y0;
    }
    for (i, j, b) in &m.pairs {
        let (a, c) = (p.targets[*i].rect, p.targets[*j].rect);
        let rel = [
            a.x1 <= c.x0 + EPS,
            c.x1 <= a.x0 + EPS,
            a.y1 <= c.y0 + EPS,
            c.y1 <= a.y0 + EPS,
        ];
        for k in 0..4 {
            if let (Some((_, col)), true) = (b[k], rel[k]) {
                v[col] = 1.0;
                break;
            }
        }
    }
    v[m.depth.1] = p.extent().1;
    v
}

/// Slide every object down and left until none moves: the result is BL-stable and its extents
/// are no larger.
pub fn compact(p: &Placement) -> Placement {
    let mut t = p.targets.clone();
    for _ in 0..10_000 {
        let mut moved = false;
        let mut order: Vec<usize> = (0..t.len()).collect();
        order.sort_by(|&a, &b| (t[a].rect.y0 + t[a].rect.x0).total_cmp(&(t[b].rect.y0 + t[b].rect.x0)));
        for &i in &order {
            let r = t[i].rect;
            let down = t
                .iter()
                .enumerate()
                .filter(|(j, o)| *j != i && o.rect.overlap_on(&r, Axis2::X) > EPS && o.rect.y1 <= r.y0 + EPS)
                .map(|(_, o)| o.rect.y1)
                .fold(0.0, f64::max);
            let r2 = Rect::new(r.x0, down, r.width(), r.depth());
            let left = t
                .iter()
                .enumerate()
                .filter(|(j, o)| *j != i && o.rect.overlap_on(&r2, Axis2::Y) > EPS && o.rect.x1 <= r2.x0 + EPS)
                .map(|(_, o)| o.rect.x1)
                .fold(0.0, f64::max);
            let r3 = Rect::new(left, down, r.width(), r.depth());
            if (r3.x0 - r.x0).abs() > EPS || (r3.y0 - r.y0).abs() > EPS {
                t[i].rect = r3;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    Placement { targets: t }
}

/// Minimise the occupied area exactly (then maximise contact). `warm` only seeds the
/// incumbent: an empty or invalid warm placement changes nothing but speed.
pub fn solve(
    inst: &Instance,
    warm: &PlacementResult,
    settings: &MilpSettings,
    stop: &dyn Terminator,
) -> Result<PlacementResult> {
    solve_report(inst, warm, settings, stop).map(|(r, _)| r)
}

/// What [`solve_report`] did besides its result.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct MilpReport {
    /// Proven lower bound and incumbent area over time.
    pub trace: Vec<BoundPoint>,
    /// Seconds in the area stage (boxes by area, exact packing search).
    pub area_stage_s: f64,
    /// Seconds in the contact stage (HiGHS MILPs).
    pub contact_stage_s: f64,
    /// Enclosing boxes decided, and how many of them needed the exact search.
    pub boxes: u64,
    /// Boxes decided by the exact search rather than by bounds or dominance.
    pub boxes_searched: u64,
    /// The area is proven minimal.
    pub area_optimal: bool,
    /// The contact length is proven maximal among area-optimal placements.
    pub contact_optimal: bool,
}

/// [`solve`], with the bound-over-time trace and the cost of each stage.
pub fn solve_report(
    inst: &Instance,
    warm: &PlacementResult,
    settings: &MilpSettings,
    stop: &dyn Terminator,
) -> Result<(PlacementResult, MilpReport)> {
    let start = Instant::now();
    let left = |s: &MilpSettings| s.time_limit - start.elapsed().as_secs_f64();
    let fps = footprints(inst);
    let halt = || stop.should_stop() || left(settings) <= 0.0;
    let warm_p = (!warm.placement.targets.is_empty()).then_some(&warm.placement);
    // Without a warm start, a quarter of the limit may go to finding any packing at all.
    let area = area::solve(
        inst,
        &fps,
        warm_p,
        settings.contact_stage,
        start,
        settings.time_limit * 0.25,
        &halt,
    );
    let area_stage_s = start.elapsed().as_secs_f64();
    let mut report = MilpReport {
        trace: area.trace.clone(),
        area_stage_s,
        boxes: area.boxes,
        boxes_searched: area.boxes_searched,
        area_optimal: area.optimal,
        ..MilpReport::default()
    };
    if area.infeasible {
        return Err(Error::Infeasible {
            reason: format!(
                "the objects fit in no box inside the {} × {} container: every enclosing box was refuted by bounds or an exhaustive search ({} boxes)",
                inst.container.width, inst.container.depth, area.boxes
            ),
        });
    }
    let Some(mut best) = area.best.clone() else {
        return Err(Error::Stopped {
            stage: "placement (milp)".into(),
            limit: crate::error::TIME_LIMIT.into(),
            nodes: area.nodes,
            elapsed_s: area_stage_s,
            min_actions: None,
        });
    };
    let best_area = best.occupied_area();
    let area_optimal = area.optimal;
    let ties_closed = area.ties_closed;
    let lower_bound = area.lower_bound;
    let solutions = area.solutions;
    let mut milps = 0u64;
    let mut nodes = warm.nodes + area.nodes;
    // Every object's footprints closed under swapping x and y: a placement transposes.
    let transposable = fps.iter().all(|o| {
        o.iter().all(|(f, _, _)| {
            o.iter()
                .any(|(g, _, _)| (g[0] - f[1]).abs() <= EPS && (g[1] - f[0]).abs() <= EPS)
        })
    });
    let mut contact_optimal = false;
    if settings.contact_stage && left(settings) > 0.0 && !stop.should_stop() {
        // Every distinct extent pair reaching the optimal area gets its own contact stage.
        let mut extents: Vec<(f64, f64)> = Vec::new();
        for p in &solutions {
            let e = p.extent();
            if e.0 * e.1 <= best_area + AREA_TOL
                && !extents
                    .iter()
                    .any(|f| (f.0 - e.0).abs() <= 1e-9 && (f.1 - e.1).abs() <= 1e-9)
            {
                extents.push(e);
            }
        }
        let mut all_optimal = area_optimal && ties_closed;
        let mut best_contact = best.contact_length(inst);
        // The high walls earn contact only where the extent reaches them; with those matched,
        // the contact stage of `(d, w)` is the transpose of that of `(w, d)`.
        let (cw, cd) = (inst.container.width, inst.container.depth);
        let walls_transpose =
            |(w, d): (f64, f64)| (w >= cw - EPS) == (w >= cd - EPS) && (d >= cd - EPS) == (d >= cw - EPS);
        let mut done: Vec<((f64, f64), bool)> = Vec::new();
        for e in extents {
            if left(settings) <= 0.0 {
                all_optimal = false;
                break;
            }
            // A transposed extent already solved has the same optimum, reached by the transposed
            // placement; that ties with a contact already taken into `best_contact`, and only a
            // strictly larger one replaces `best`, so the stage would change nothing.
            if transposable && walls_transpose(e) {
                if let Some(&(_, opt)) = done
                    .iter()
                    .find(|(f, _)| (f.0 - e.1).abs() <= 1e-9 && (f.1 - e.0).abs() <= 1e-9)
                {
                    all_optimal &= opt;
                    continue;
                }
            }
            let warm_p = solutions.iter().find(|p| {
                let f = p.extent();
                (f.0 - e.0).abs() <= 1e-9 && (f.1 - e.1).abs() <= 1e-9
            });
            // Enumeration first: in a box of the optimal area packings are few. It gets the
            // area stage's time (at least a second); the MILP gets what remains of it.
            // `PUSHPACK_CONTACT_BUDGET` (seconds) overrides it, for measurements only
            // (docs/benchmarks.md).
            let deadline = std::env::var("PUSHPACK_CONTACT_BUDGET")
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(area_stage_s.max(1.0));
            let contact_left = || (deadline - (start.elapsed().as_secs_f64() - area_stage_s)).min(left(settings));
            let halt_contact = || stop.should_stop() || contact_left() <= 0.0;
            let (enum_best, complete, n_enum) = area::max_contact(inst, &fps, e, best_contact, &halt_contact);
            nodes += n_enum;
            if let Some(p) = &enum_best {
                let c = p.contact_length(inst);
                if c > best_contact + 1e-9 && p.occupied_area() <= best_area + 1e-12 {
                    best = p.clone();
                    best_contact = c;
                }
            }
            if complete {
                done.push((e, true));
                continue;
            }
            if contact_left() <= 0.0 {
                all_optimal = false;
                continue;
            }
            let warm_p = enum_best.as_ref().or(warm_p);
            let res = if GridModel::size(inst, &fps, e.0, e.1) <= grid_max_nnz() {
                grid_contact_stage(inst, &fps, e, warm_p, contact_left(), settings.seed)?
            } else if let Some(wp) = warm_p {
                contact_stage(inst, &fps, wp, contact_left(), settings.seed)?
            } else {
                None
            };
            milps += 1;
            match res {
                Some((p, opt, n2)) => {
                    nodes += n2;
                    all_optimal &= opt;
                    done.push((e, opt));
                    let c = p.contact_length(inst);
                    if c > best_contact + 1e-9 && p.occupied_area() <= best_area + 1e-12 {
                        best = p;
                        best_contact = c;
                    }
                }
                None => all_optimal = false,
            }
        }
        contact_optimal = all_optimal;
    }
    debug_assert!(is_bl_stable(&best.targets));
    report.contact_stage_s = start.elapsed().as_secs_f64() - area_stage_s;
    report.contact_optimal = contact_optimal;
    let status = if area_optimal && contact_optimal {
        PlacementStatus::Optimal
    } else {
        PlacementStatus::Feasible
    };
    let result = PlacementResult {
        placement: best,
        status,
        lower_bound: if area_optimal { best_area } else { lower_bound },
        solver: "milp".into(),
        time_s: start.elapsed().as_secs_f64() + warm.time_s,
        nodes,
        subproblems: milps,
    };
    Ok((result, report))
}

/// Second stage on the normal-pattern grid: maximise contact length inside extents `(w, d)`
/// with BL-stability as constraints. Boundaries are cut into segments between consecutive grid
/// coordinates; on each segment of each grid line, `L` (a footprint's low edge lies there) and
/// `R` (a footprint's high edge lies there) are sums of binaries, at most 1 by non-overlap, and
/// a contact variable `c ≤ L, c ≤ R` earns the segment length (walls earn `L` or `R` directly).
/// Exact: every BL-stable placement has grid coordinates.
fn grid_contact_stage(
    inst: &Instance,
    fps: &[Vec<([f64; 2], Orientation, f64)>],
    (w, d): (f64, f64),
    warm: Option<&Placement>,
    time_left: f64,
    seed: u64,
) -> Result<Option<(Placement, bool, u64)>> {
    let mut cols = Cols {
        pv: ProblemVariables::new(),
        n: 0,
    };
    let Some(mut m) = GridModel::build(inst, fps, w, d, &mut cols) else {
        return Ok(None);
    };
    m.constraints.push(Expression::from(m.depth.0).leq(d));
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let (xs, ys) = GridModel::axes(fps, w, d);
    let dims = |g: usize, k: usize| fps[m.groups[g][0]][k].0;
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-7;
    let mut objective = Expression::from(0.0);
    // contact[(axis, line index, segment index)] = variable, for the BL-stability rows.
    let mut contact: std::collections::HashMap<(usize, usize, usize), Variable> = std::collections::HashMap::new();
    for axis in 0..2 {
        // axis 0: vertical lines x = const, segments along y; axis 1: horizontal lines.
        let (lines, segs, wall_hi) = if axis == 0 {
            (&xs, &ys, (w >= cw - EPS).then_some(cw))
        } else {
            (&ys, &xs, (d >= cd - EPS).then_some(cd))
        };
        for (li, &line) in lines.iter().enumerate() {
            for si in 0..segs.len().saturating_sub(1) {
                let (s0, s1) = (segs[si], segs[si + 1]);
                let mut lo_edge: Vec<Variable> = Vec::new();
                let mut hi_edge: Vec<Variable> = Vec::new();
                for &(g, k, x, y, v, _) in &m.vars {
                    let f = dims(g, k);
                    let (p0, ext, q0, len) = if axis == 0 {
                        (x, f[0], y, f[1])
                    } else {
                        (y, f[1], x, f[0])
                    };
                    if q0 <= s0 + 1e-9 && q0 + len >= s1 - 1e-9 {
                        if near(p0, line) {
                            lo_edge.push(v);
                        }
                        if near(p0 + ext, line) {
                            hi_edge.push(v);
                        }
                    }
                }
                let seg = s1 - s0;
                if line.abs() <= 1e-9 {
                    let e: Expression = lo_edge.iter().copied().sum();
                    objective += seg * e;
                } else if wall_hi.map(|h| near(line, h)).unwrap_or(false) {
                    let e: Expression = hi_edge.iter().copied().sum();
                    objective += seg * e;
                } else if !lo_edge.is_empty() && !hi_edge.is_empty() {
                    let (c, _) = cols.add(variable().min(0.0).max(1.0));
                    let l: Expression = lo_edge.iter().copied().sum();
                    let r: Expression = hi_edge.iter().copied().sum();
                    m.constraints.push((c - l).leq(0.0));
                    m.constraints.push((c - r).leq(0.0));
                    objective += seg * c;
                    contact.insert((axis, li, si), c);
                }
            }
        }
    }
    // BL-stability: a chosen footprint not on the low wall touches something along its low edge.
    for &(g, k, x, y, v, _) in &m.vars {
        let f = dims(g, k);
        for axis in 0..2 {
            let (p0, q0, len, lines, segs) = if axis == 0 {
                (x, y, f[1], &xs, &ys)
            } else {
                (y, x, f[0], &ys, &xs)
            };
            if p0.abs() <= 1e-9 {
                continue;
            }
            let Some(li) = lines.iter().position(|&l| near(l, p0)) else {
                continue;
            };
            let support: Expression = (0..segs.len().saturating_sub(1))
                .filter(|&si| q0 <= segs[si] + 1e-9 && q0 + len >= segs[si + 1] - 1e-9)
                .filter_map(|si| contact.get(&(axis, li, si)).copied())
                .sum();
            m.constraints.push((Expression::from(v) - support).leq(0.0));
        }
    }
    let init = warm.and_then(|p| m.initial(fps, p, cols.n)).map(|mut v| {
        // Contact variables start at 0; HiGHS repairs a partial start when it can.
        v.resize(cols.n, 0.0);
        v
    });
    let mut problem = cols.pv.maximise(objective).using(highs);
    for c in m.constraints.iter().cloned() {
        problem = problem.with(c);
    }
    let solved = run_highs(problem, init.as_deref(), time_left, seed, 1e-9, false)?;
    let Some(c) = solved.cols.as_deref() else {
        return Ok(None);
    };
    let q = m.extract(fps, inst.n(), c);
    if !q.violations(inst).is_empty() {
        return Ok(None);
    }
    Ok(Some((q, solved.status == HighsModelStatus::Optimal, solved.nodes)))
}

/// Second stage: maximise contact length inside the extents of `p`, BL-stable, warm-started
/// with `p`. Returns the placement, whether it is proven optimal, and HiGHS nodes.
fn contact_stage(
    inst: &Instance,
    fps: &[Vec<([f64; 2], Orientation, f64)>],
    p: &Placement,
    time_left: f64,
    seed: u64,
) -> Result<Option<(Placement, bool, u64)>> {
    let (w, d) = p.extent();
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let n = inst.n();
    let mut cols = Cols {
        pv: ProblemVariables::new(),
        n: 0,
    };
    let Some(mut m) = PlacementModel::build(inst, fps, w, d, &mut cols) else {
        return Ok(None);
    };
    m.constraints.push(Expression::from(m.depth.0).leq(d));
    let big = cw.max(cd);
    let eps = 1e-5;
    let mut objective = Expression::from(0.0);
    let mut init_extra: Vec<(usize, f64)> = Vec::new();
    // Wall contacts: left (x = 0), front (y = 0), right (x = cw), back (y = cd).
    let mut left_wall = Vec::new();
    let mut front_wall = Vec::new();
    for i in 0..n {
        let t = p.targets[i].rect;
        let walls: [(bool, bool); 4] = [
            (true, t.x0.abs() <= EPS),
            (true, t.y0.abs() <= EPS),
            (w >= cw - EPS, (t.x1 - cw).abs() <= EPS),
            (d >= cd - EPS, (t.y1 - cd).abs() <= EPS),
        ];
        for (side, (possible, now)) in walls.iter().enumerate() {
            if !possible {
                if side == 0 {
                    left_wall.push(None);
                }
                if side == 1 {
                    front_wall.push(None);
                }
                continue;
            }
            let (z, zc) = cols.add(variable().binary());
            init_extra.push((zc, if *now { 1.0 } else { 0.0 }));
            let wi = m.width(fps, i);
            let di = m.depth_of(fps, i);
            match side {
                0 => m.constraints.push(Expression::from(m.x[i].0).leq(big * (1.0 - z))),
                1 => m.constraints.push(Expression::from(m.y[i].0).leq(big * (1.0 - z))),
                2 => m.constraints.push((m.x[i].0 + wi).geq(cw - big * (1.0 - z))),
                _ => m.constraints.push((m.y[i].0 + di).geq(cd - big * (1.0 - z))),
            }
            // Contact length = the face length times z: u_k ≤ s_k, u_k ≤ z.
            for (k, (f, _, _)) in fps[i].iter().enumerate() {
                let (u, uc) = cols.add(variable().min(0.0).max(1.0));
                let on = *now && (f[0] - t.width()).abs() <= EPS && (f[1] - t.depth()).abs() <= EPS;
                init_extra.push((uc, if on { 1.0 } else { 0.0 }));
                m.constraints.push(Expression::from(u).leq(m.s[i][k].0));
                m.constraints.push(Expression::from(u).leq(z));
                let len = if side % 2 == 0 { f[1] } else { f[0] };
                objective += len * u;
            }
            if side == 0 {
                left_wall.push(Some(z));
            }
            if side == 1 {
                front_wall.push(Some(z));
            }
        }
    }
    // Object contacts: touch[a][b][axis] = a's high face meets b's low face along axis.
    let mut supports_x: Vec<Vec<Variable>> = vec![Vec::new(); n];
    let mut supports_y: Vec<Vec<Variable>> = vec![Vec::new(); n];
    for a in 0..n {
        for b in 0..n {
            if a == b {
                continue;
            }
            for axis in [Axis2::X, Axis2::Y] {
                let (ta, tb) = (p.targets[a].rect, p.targets[b].rect);
                let now_touch = (ta.hi(axis) - tb.lo(axis)).abs() <= EPS;
                let now_ov = if now_touch {
                    ta.overlap_on(&tb, axis.other()).max(0.0)
                } else {
                    0.0
                };
                let (t, tc) = cols.add(variable().binary());
                let (ov, oc) = cols.add(variable().min(0.0).max(big));
                init_extra.push((tc, if now_touch && now_ov > eps { 1.0 } else { 0.0 }));
                init_extra.push((oc, if now_touch && now_ov > eps { now_ov } else { 0.0 }));
                // Along `axis`: positions p and extents l; across it: positions q and extents m.
                let (pa, pb, la, qa, qb, ma, mb) = match axis {
                    Axis2::X => (
                        m.x[a].0,
                        m.x[b].0,
                        m.width(fps, a),
                        m.y[a].0,
                        m.y[b].0,
                        m.depth_of(fps, a),
                        m.depth_of(fps, b),
                    ),
                    Axis2::Y => (
                        m.y[a].0,
                        m.y[b].0,
                        m.depth_of(fps, a),
                        m.x[a].0,
                        m.x[b].0,
                        m.width(fps, a),
                        m.width(fps, b),
                    ),
                };
                // Touch: pa + la = pb when t = 1.
                m.constraints.push((pa + la.clone() - pb).leq(big * (1.0 - t)));
                m.constraints.push((pb - pa - la).leq(big * (1.0 - t)));
                // Overlap along the other axis: ov ≤ min(qa+ma, qb+mb) − max(qa, qb), ov ≤ big·t.
                m.constraints.push((ov + qb - qa - ma.clone()).leq(big * (1.0 - t)));
                m.constraints.push((ov + qa - qb - mb.clone()).leq(big * (1.0 - t)));
                m.constraints.push((ov - ma).leq(0.0));
                m.constraints.push((ov - mb).leq(0.0));
                m.constraints.push(Expression::from(ov).leq(big * t));
                m.constraints.push((ov - eps * t).geq(0.0));
                objective += ov;
                match axis {
                    Axis2::X => supports_x[b].push(t),
                    Axis2::Y => supports_y[b].push(t),
                }
            }
        }
    }
    // BL-stability: each object touches the wall or an object on its −x and −y sides.
    for i in 0..n {
        let sx: Expression =
            supports_x[i].iter().copied().sum::<Expression>() + left_wall[i].map(Expression::from).unwrap_or_default();
        let sy: Expression =
            supports_y[i].iter().copied().sum::<Expression>() + front_wall[i].map(Expression::from).unwrap_or_default();
        m.constraints.push(sx.geq(1.0));
        m.constraints.push(sy.geq(1.0));
    }
    let ncols = cols.n;
    let mut init = initial_columns(fps, &m, p, ncols);
    init[m.depth.1] = d;
    for (c, v) in init_extra {
        init[c] = v;
    }
    let mut problem = cols.pv.maximise(objective).using(highs);
    for c in m.constraints.iter().cloned() {
        problem = problem.with(c);
    }
    let solved = run_highs(problem, Some(&init), time_left, seed, 1e-9, true)?;
    let Some(c) = solved.cols.as_deref() else {
        return Ok(None);
    };
    let q = extract(inst, fps, &m, c);
    let ok = q.violations(inst).is_empty() && q.occupied_area() <= p.occupied_area() + 1e-9;
    if !ok {
        return Ok(None);
    }
    let better = q.contact_length(inst) >= p.contact_length(inst) - 1e-9;
    let optimal = solved.status == HighsModelStatus::Optimal;
    Ok(Some((
        if better { q } else { p.clone() },
        optimal && better,
        solved.nodes,
    )))
}

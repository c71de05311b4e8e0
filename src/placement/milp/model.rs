//! The per-width depth MILP: variables, non-overlap rows, symmetry breaking (good_lp).

use super::*;

/// Good_lp variables with their column index (good_lp creates HiGHS columns in this order).
pub(super) struct Cols {
    pub(super) pv: ProblemVariables,
    pub(super) n: usize,
}

impl Cols {
    pub(super) fn add(&mut self, def: good_lp::VariableDefinition) -> (Variable, usize) {
        let v = self.pv.add(def);
        self.n += 1;
        (v, self.n - 1)
    }
}

/// One pair's relation binaries (i, j, [left, right, below, above]), `None` when fixed to 0.
pub(super) type PairVars = (usize, usize, [Option<(Variable, usize)>; 4]);

/// The placement MILP for one width bound: owns its variables.
pub(super) struct PlacementModel {
    /// Orientation binaries per object: (variable, column, footprint index).
    pub(super) s: Vec<Vec<(Variable, usize)>>,
    pub(super) x: Vec<(Variable, usize)>,
    pub(super) y: Vec<(Variable, usize)>,
    /// Pair binaries: (i, j, [left, right, below, above]) — `None` when fixed to 0.
    pub(super) pairs: Vec<PairVars>,
    pub(super) depth: (Variable, usize),
    pub(super) constraints: Vec<Constraint>,
}

impl PlacementModel {
    pub(super) fn width(&self, fps: &[Footprints], i: usize) -> Expression {
        self.s[i]
            .iter()
            .zip(&fps[i])
            .map(|((v, _), Footprint { size: f, .. })| f[0] * *v)
            .sum()
    }
    pub(super) fn depth_of(&self, fps: &[Footprints], i: usize) -> Expression {
        self.s[i]
            .iter()
            .zip(&fps[i])
            .map(|((v, _), Footprint { size: f, .. })| f[1] * *v)
            .sum()
    }

    /// Variables and the geometric rows: one orientation each, inside `[0,W]×[0,D]`,
    /// pairwise non-overlap, symmetry breaking.
    pub(super) fn build(inst: &Instance, fps: &[Footprints], w: f64, d_max: f64, cols: &mut Cols) -> Option<Self> {
        let n = inst.n();
        let mut s = Vec::new();
        for opts in fps.iter() {
            // A footprint that cannot fit is fixed to 0 (kept as a column so indices stay aligned).
            let row: Vec<(Variable, usize)> = opts
                .iter()
                .map(|Footprint { size: f, .. }| {
                    let fits = f[0] <= w + EPS && f[1] <= d_max + EPS;
                    cols.add(if fits {
                        variable().binary()
                    } else {
                        variable().integer().min(0.0).max(0.0)
                    })
                })
                .collect();
            if opts
                .iter()
                .all(|Footprint { size: f, .. }| f[0] > w + EPS || f[1] > d_max + EPS)
            {
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

    pub(super) fn orientation_rows(&mut self) {
        for row in &self.s {
            let sum: Expression = row.iter().map(|(v, _)| *v).sum();
            self.constraints.push(sum.eq(1.0));
        }
    }

    pub(super) fn containment_rows(&mut self, fps: &[Footprints], w: f64) {
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
            .flat_map(|(row, opts)| {
                row.iter()
                    .zip(opts)
                    .map(|((v, _), Footprint { size: f, .. })| f[0] * f[1] * *v)
            })
            .sum();
        self.constraints.push(area.leq(w * self.depth.0));
    }

    pub(super) fn non_overlap_rows(&mut self, fps: &[Footprints], w: f64, d_max: f64, cols: &mut Cols) {
        let n = self.s.len();
        let min_w = |i: usize| {
            fps[i]
                .iter()
                .map(|Footprint { size: f, .. }| f[0])
                .fold(f64::INFINITY, f64::min)
        };
        let min_d = |i: usize| {
            fps[i]
                .iter()
                .map(|Footprint { size: f, .. }| f[1])
                .fold(f64::INFINITY, f64::min)
        };
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

    pub(super) fn symmetry_rows(&mut self, inst: &Instance, fps: &[Footprints]) {
        let n = self.s.len();
        for i in 0..n {
            // Next identical object after i: order them by x.
            if let Some(j) = (i + 1..n).find(|&j| identical(inst, fps, i, j)) {
                self.constraints.push(Expression::from(self.x[i].0).leq(self.x[j].0));
            }
        }
    }
}

pub(super) fn identical(inst: &Instance, fps: &[Footprints], i: usize, j: usize) -> bool {
    inst.objects[i].size == inst.objects[j].size
        && fps[i].len() == fps[j].len()
        && fps[i].iter().zip(&fps[j]).all(|(a, b)| a.size == b.size)
        && inst.objects[i].mass == inst.objects[j].mass
}

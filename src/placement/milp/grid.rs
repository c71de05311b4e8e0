//! The grid MILP of the contact stage: footprints on a grid of candidate positions.

use super::*;

/// Positions restricted to *normal patterns* (subset sums of the other footprints' extents),
/// which loses nothing: every BL-stable placement has such coordinates. One binary per
/// (group of identical objects, footprint, x, y); non-overlap as "at most one footprint covers
/// each grid point" — exact on this grid, because two overlapping rectangles both cover the
/// point (max x0, max y0). Identical objects share variables (no symmetry left to break).
pub(super) struct GridModel {
    /// Per variable: group, footprint index, x, y, column.
    pub(super) vars: Vec<(usize, usize, f64, f64, Variable, usize)>,
    /// Objects of each group.
    pub(super) groups: Vec<Vec<usize>>,
    pub(super) depth: (Variable, usize),
    pub(super) constraints: Vec<Constraint>,
}

/// Objects grouped by identical size, footprints and mass.
pub(super) fn groups(inst: &Instance, fps: &[Footprints]) -> Vec<Vec<usize>> {
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
    pub(super) fn axes(fps: &[Footprints], w: f64, d: f64) -> (Vec<f64>, Vec<f64>) {
        (
            subset_sums(&area::extents(fps, 0), w),
            subset_sums(&area::extents(fps, 1), d),
        )
    }

    /// Non-zeros of the cover rows the model would have (its size measure: the cover rows
    /// dominate the work HiGHS does in presolve).
    pub(super) fn size(inst: &Instance, fps: &[Footprints], w: f64, d: f64) -> usize {
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
                    .map(|Footprint { size: f, .. }| covered(&xs, w, f[0]) * covered(&ys, d, f[1]))
                    .sum::<usize>()
            })
            .sum()
    }

    pub(super) fn build(inst: &Instance, fps: &[Footprints], w: f64, d: f64, cols: &mut Cols) -> Option<Self> {
        let (xs, ys) = Self::axes(fps, w, d);
        let groups = groups(inst, fps);
        let mut vars = Vec::new();
        for (g, members) in groups.iter().enumerate() {
            let before = vars.len();
            for (k, Footprint { size: f, .. }) in fps[members[0]].iter().enumerate() {
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
            let f = fps[groups[g][0]][k].size;
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
            let top = y + fps[groups[g][0]][k].size[1];
            constraints.push((Expression::from(depth.0) - top * v).geq(0.0));
        }
        let area: Expression = vars
            .iter()
            .map(|&(g, k, _, _, v, _)| {
                let f = fps[groups[g][0]][k].size;
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

    pub(super) fn initial(&self, fps: &[Footprints], p: &Placement, ncols: usize) -> Option<Vec<f64>> {
        let mut v = vec![0.0; ncols];
        for (g, members) in self.groups.iter().enumerate() {
            for &i in members {
                let t = p.targets[i].rect;
                let hit = self.vars.iter().find(|&&(gg, k, x, y, _, _)| {
                    if gg != g {
                        return false;
                    }
                    let f = fps[members[0]][k].size;
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

    pub(super) fn extract(&self, fps: &[Footprints], n: usize, cols: &[f64]) -> Placement {
        let mut targets: Vec<Option<Target>> = vec![None; n];
        let mut next = vec![0usize; self.groups.len()];
        for &(g, k, x, y, _, c) in &self.vars {
            if cols[c] > 0.5 && next[g] < self.groups[g].len() {
                let i = self.groups[g][next[g]];
                next[g] += 1;
                let Footprint {
                    size: f,
                    orientation: q,
                    height: h,
                } = fps[i][k];
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
                        orientation: fps[i][0].orientation,
                        rect: Rect::new(-1.0, -1.0, fps[i][0].size[0], fps[i][0].size[1]),
                        height: fps[i][0].height,
                    })
                })
                .collect(),
        }
    }
}

/// Largest grid model (cover-row non-zeros) built before falling back to the disjunctive model.
pub(super) const GRID_MAX_NNZ: usize = 400_000;

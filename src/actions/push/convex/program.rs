//! The convex programs and their solution: clarabel settings, the margin rows, the Dinkelbach iteration.

use super::*;

/// A conic program `min qᵀx  s.t.  A x + s = b, s ∈ K` under assembly.
pub(super) struct Program {
    pub(super) nv: usize,
    pub(super) rows: usize,
    pub(super) trip: Vec<(usize, usize, f64)>,
    pub(super) b: Vec<f64>,
    pub(super) q: Vec<f64>,
    pub(super) cones: Vec<SupportedConeT<f64>>,
}

impl Program {
    pub(super) fn new(nv: usize, rows: usize) -> Program {
        Program {
            nv,
            rows,
            trip: Vec::with_capacity(8 * nv),
            b: vec![0.0; rows],
            q: vec![0.0; nv],
            cones: Vec::new(),
        }
    }
    /// Add a structural entry (kept even when zero, so the sparsity pattern depends only on the
    /// problem structure and solvers can be re-used).
    pub(super) fn a(&mut self, row: usize, col: usize, v: f64) {
        self.trip.push((row, col, v));
    }
    pub(super) fn csc(&mut self) -> CscMatrix<f64> {
        self.trip.sort_by_key(|&(r, c, _)| (c, r));
        let mut colptr = vec![0usize; self.nv + 1];
        let mut rowval = Vec::with_capacity(self.trip.len());
        let mut nzval: Vec<f64> = Vec::with_capacity(self.trip.len());
        let mut last: Option<(usize, usize)> = None;
        for &(r, c, v) in &self.trip {
            if last == Some((r, c)) {
                *nzval.last_mut().expect("entry") += v;
                continue;
            }
            last = Some((r, c));
            colptr[c + 1] += 1;
            rowval.push(r);
            nzval.push(v);
        }
        for c in 0..self.nv {
            colptr[c + 1] += colptr[c];
        }
        CscMatrix::new(self.rows, self.nv, colptr, rowval, nzval)
    }
}

pub(super) fn settings() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .presolve_enable(false)
        .equilibrate_enable(false)
        .max_iter(100)
        .tol_gap_abs(1e-10)
        .tol_gap_rel(1e-10)
        .tol_feas(1e-10)
        .iterative_refinement_enable(false)
        .build()
        .expect("valid clarabel settings")
}

/// Outcome of a solve: primal solution, or the status when there is none.
pub(super) enum Solved {
    Optimal(Vec<f64>),
    Infeasible,
    Failed,
}

pub(super) fn run(key: SolverKey, prog: &mut Program) -> Solved {
    let a = prog.csc();
    let reuse = REUSE.with(|r| *r.borrow());
    SOLVERS.with(|table| {
        let mut table = table.borrow_mut();
        let fresh = |prog: &Program, a: &CscMatrix<f64>| {
            let p = CscMatrix::zeros((prog.nv, prog.nv));
            DefaultSolver::new(&p, &prog.q, a, &prog.b, &prog.cones, settings()).ok()
        };
        let mut local;
        let solver: &mut DefaultSolver<f64> = if reuse {
            let updated = match table.get_mut(&key) {
                Some(s) => s.update_A(&a.nzval).is_ok() && s.update_b(&prog.b).is_ok() && s.update_q(&prog.q).is_ok(),
                None => false,
            };
            if !updated {
                match fresh(prog, &a) {
                    Some(s) => {
                        table.insert(key.clone(), s);
                    }
                    None => return Solved::Failed,
                }
            }
            table.get_mut(&key).expect("inserted")
        } else {
            local = match fresh(prog, &a) {
                Some(s) => s,
                None => return Solved::Failed,
            };
            &mut local
        };
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Solved::Optimal(solver.solution.x.clone()),
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => Solved::Infeasible,
            _ => Solved::Failed,
        }
    })
}

/// Weights of the margin rows: `N_i(x) − θ D_i(x) − t w_i ≥ 0` for every margin constraint `i`
/// (numerator `N_i` = distance of a centre of pressure from a segment end or footprint edge times
/// the normal force `D_i`). `θ = 0, w = 1` is the reference-load program; other values are the
/// generalized Dinkelbach steps of [`optimise`]. One `(θ, w)` per group: per contact (2-D,
/// 3-D), then per body (3-D), in program order. A group with `θ = w = 0` is a plain feasibility
/// constraint (centre of pressure inside), which is how a tipping program leaves every row but
/// its own box's footprint out of the margin.
pub(super) struct MarginRows {
    pub(super) theta: Vec<f64>,
    pub(super) w: Vec<f64>,
}

impl MarginRows {
    /// The reference-load rows: 2-D, every contact carries the margin; 3-D (tipping program of
    /// body `tip` of each phase), only that body's footprint does.
    pub(super) fn reference(ds: &[PhaseData], dim: Dim, tip: usize) -> MarginRows {
        let total: usize = ds.iter().map(|d| d.n).sum();
        match dim {
            Dim::D2 => MarginRows {
                theta: vec![0.0; total],
                w: vec![1.0; total],
            },
            Dim::D3 => {
                let mut w = vec![0.0; 2 * total];
                let mut off = 0;
                for d in ds {
                    w[total + off + tip] = 1.0;
                    off += d.n;
                }
                MarginRows {
                    theta: vec![0.0; 2 * total],
                    w,
                }
            }
        }
    }
}

/// Column of the margin variable.
pub(super) fn t_col(ds: &[PhaseData], dim: Dim) -> usize {
    let total: usize = ds.iter().map(|d| d.n).sum();
    match dim {
        Dim::D2 => 3 * total,
        Dim::D3 => 15 * total,
    }
}

/// Assemble the phases `ds` into one program with a common margin and solve it.
pub(super) fn solve_rows(
    ds: &[PhaseData],
    dim: Dim,
    variant: Variant,
    ext: f64,
    rows: &MarginRows,
    tip: usize,
) -> Solved {
    let mut prog = match dim {
        Dim::D2 => assemble_2d(ds, variant, rows),
        Dim::D3 => assemble_3d(ds, ext, rows, tip),
    };
    let shape: Vec<usize> = ds.iter().map(|d| d.n).collect();
    run((dim, shape, variant), &mut prog)
}

/// One margin constraint evaluated at a solution: the geometric distance (normalised) of a
/// centre of pressure from a segment end / footprint edge, its normal force, and what it is.
pub(super) struct Ratio {
    pub(super) value: f64,
    pub(super) denom: f64,
    pub(super) binding: Binding,
}

/// Every margin constraint of a solution `x` of the program over `ds`, in group order (two per
/// group).
pub(super) fn ratios(ds: &[PhaseData], dim: Dim, x: &[f64], ext: f64) -> Vec<Ratio> {
    let total: usize = ds.iter().map(|d| d.n).sum();
    let mut contacts = Vec::with_capacity(2 * total);
    let mut floors = Vec::new();
    let mut off = 0;
    for d in ds {
        for j in 0..d.n {
            let c = d.contact(j);
            let len = c.len / d.l0;
            let (f, m) = match dim {
                Dim::D2 => (x[3 * (off + j)], x[3 * (off + j) + 2]),
                Dim::D3 => {
                    let lat = ends(len, ext);
                    (0..4).fold((0.0, 0.0), |(f, m), k| {
                        let v = x[col3_contact(off, j, k)];
                        (f + v, m + lat[k / 2] * v)
                    })
                }
            };
            let den = f.max(DENOM_MIN);
            let contact = d.start + j;
            contacts.push(Ratio {
                value: m / den,
                denom: f,
                binding: Binding::Segment { contact, end: 0 },
            });
            contacts.push(Ratio {
                value: (len * f - m) / den,
                denom: f,
                binding: Binding::Segment { contact, end: 1 },
            });
        }
        if dim == Dim::D3 {
            for i in 0..d.n {
                let body = d.body(i);
                let h = [body.half[0] / d.l0, body.half[1] / d.l0];
                let nc = col3_floor(off, d.n, i);
                let nn = x[nc];
                let den = nn.max(DENOM_MIN);
                for axis in 0..2 {
                    let mom = x[nc + 1 + axis];
                    for side in [1i8, -1] {
                        floors.push(Ratio {
                            value: (h[axis] * nn - side as f64 * mom) / den,
                            denom: nn,
                            binding: Binding::Footprint {
                                body: d.start + i,
                                axis,
                                side,
                            },
                        });
                    }
                }
            }
        }
        off += d.n;
    }
    contacts.extend(floors);
    contacts
}

/// Smallest normal force (in units of the reference load) used as a denominator.
pub(super) const DENOM_MIN: f64 = 1e-9;
/// Dinkelbach iterations at most (3-D); each is one solve.
pub(super) const MAX_DINKELBACH: usize = 8;

/// Maximise the margin over the phases `ds` (common margin). Returns the solution and the
/// margin in units of the length scale.
///
/// 2-D: the largest `t` such that every centre of pressure lies `t` inside its segment. The
/// normal force of every contact of a line is fixed by equilibrium and equals its reference load,
/// so the reference-load LP is already exact (one solve).
///
/// 3-D (one phase, the tipping program of its body `tip`): the largest `t` such that that body's
/// floor centre of pressure lies `t` inside its footprint. Vertical friction changes the normal
/// loads, so the max–min of the ratios `N_i/D_i` is found by the generalized Dinkelbach method
/// (Crouzeix, Ferland & Schaible 1985): from `θ_k = min_i N_i(x_k)/D_i(x_k)` solve
/// `max s : N_i(x) − θ_k D_i(x) ≥ s D_i(x_k)`; stop when `s ≈ 0`.
pub(super) fn optimise(
    ds: &[PhaseData],
    dim: Dim,
    ext: f64,
    tip: usize,
) -> std::result::Result<(Vec<f64>, f64), Solved> {
    let mut rows = MarginRows::reference(ds, dim, tip);
    let tc = t_col(ds, dim);
    let mut x = match solve_rows(ds, dim, Variant::Margin, ext, &rows, tip) {
        Solved::Optimal(x) => x,
        other => return Err(other),
    };
    if dim == Dim::D2 {
        let t = x[tc];
        return Ok((x, t));
    }
    debug_assert_eq!(ds.len(), 1, "3-D programs hold one phase");
    let body = ds[0].start + tip;
    let group = ds[0].n + tip;
    // The target body's four footprint ratios (the order of `ratios`).
    let target = |rs: &[Ratio]| -> (f64, f64) {
        rs.iter()
            .filter(|r| matches!(r.binding, Binding::Footprint { body: b, .. } if b == body))
            .fold((f64::INFINITY, 0.0), |(v, d), r| (v.min(r.value), d.max(r.denom)))
    };
    let (mut theta, mut denom) = target(&ratios(ds, dim, &x, ext));
    for _ in 0..MAX_DINKELBACH {
        rows.theta[group] = theta;
        rows.w[group] = denom.max(1e-6);
        let xn = match solve_rows(ds, dim, Variant::Margin, ext, &rows, tip) {
            Solved::Optimal(xn) => xn,
            _ => break,
        };
        let s = xn[tc];
        let (tn, dn) = target(&ratios(ds, dim, &xn, ext));
        if tn > theta {
            x = xn;
            theta = tn;
            denom = dn;
        }
        if s <= 1e-9 {
            break;
        }
    }
    Ok((x, theta))
}

/// Assemble and solve one phase's 2-D slip diagnosis; `Some(x)` at an optimum.
pub(super) fn solve_slip(d: &PhaseData) -> Option<Vec<f64>> {
    let one = std::slice::from_ref(d);
    match solve_rows(
        one,
        Dim::D2,
        Variant::Slip,
        0.0,
        &MarginRows::reference(one, Dim::D2, 0),
        0,
    ) {
        Solved::Optimal(x) => Some(x),
        _ => None,
    }
}

/// Lateral positions (normalised, from `p0`) of a contact's two ends in a program.
pub(super) fn ends(len: f64, ext: f64) -> [f64; 2] {
    [-ext, len + ext]
}

//! The production push check: sticking equilibrium of every moving box as a convex program in
//! clarabel, maximising the stability margin. See `docs/push_stability.md` for the maths.
//!
//! **2-D (LP).** Per contact `j` of a phase, variables `(f_n, f_t, m)` in units of the contact's
//! reference load `R_j`: normal and tangential force and the normal force's moment about the
//! segment's first end (`m = f_n·s`, `s` the centre of pressure along the segment). The set
//! `{|f_t| ≤ μ' f_n, 0 ≤ m ≤ L f_n}` is exactly the set of non-negative combinations of the
//! friction-cone edges `n ± μ' e` at the two end points. Per moving box: force balance (2 rows)
//! and moment balance about its centre of friction (1 row) with the floor friction `μ m g`
//! against `u`. The margin `t` enters as `m ≥ t`, `L f_n − m ≥ t`; maximise `t`.
//!
//! **3-D.** The planar part is the 2-D LP above (no vertical friction, floor normals = weights),
//! and every moving box gets its own tipping SOCP: per contact, forces at the four corners of its
//! patch, each in a second-order friction cone `‖(f_e, f_z)‖ ≤ μ' f_n`; per box the floor normal
//! `N` with its moments `(P, Q)` about the centroid along the body axes, floor friction `μ N`
//! against `u` at the centre of friction, six balance rows; vertical friction only where that
//! box's tipping would produce it (down on the tipping box, up on its neighbour, zero elsewhere);
//! the margin is that box's footprint margin. The phase margin is the smallest of the planar
//! margin and the tipping margins, so 3-D is never more lenient than 2-D and equals it where
//! nothing tips (`docs/push_stability.md` §3). When no forces exist with every centre of pressure
//! inside the real patches (the planar part already fails), a tipping program is re-solved with
//! every patch extended laterally.
//!
//! Solvers are kept per problem structure (dimension, phase size, variant) in a thread-local
//! table and re-used through clarabel's data-update interface (no new symbolic factorisation);
//! equilibration is off, the data are normalised here, so results do not depend on call history.
//! 2-D line margins are also cached by exact geometry (per phase).

use std::cell::RefCell;
use std::collections::HashMap;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use serde::Serialize;

use super::model::{cross, dot, Body, Contact, ContactKind, PushModel, V2};
use super::travel::{self, TravelCheck};
use super::{LineGeometry, CONE_SHRINK, MARGIN_TOL};

/// Options of a check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CheckOptions {
    /// Friction cones use `μ (1 − cone_shrink)`.
    pub cone_shrink: f64,
    /// Stable iff margin > `tol` (m).
    pub tol: f64,
    /// Largest rotation (rad) over a phase of finite travel judged by its travel.
    pub max_rotation: f64,
    /// Largest lateral drift (m) over such a phase.
    pub max_drift: f64,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            cone_shrink: CONE_SHRINK,
            tol: MARGIN_TOL,
            max_rotation: super::MAX_ROTATION,
            max_drift: super::MAX_DRIFT,
        }
    }
}

/// Planar (LP) or spatial (SOCP with toppling) model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Dim {
    /// 2-D: forces in the floor plane, moments about the vertical.
    #[serde(rename = "2d")]
    D2,
    /// 3-D: patches with height, floor pressure over the footprint, second-order cones.
    #[serde(rename = "3d")]
    D3,
}

/// Outcome of one phase's program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseStatus {
    /// An optimal margin was found.
    Solved,
    /// No contact forces satisfy the friction cones (at any segment shrink).
    Infeasible,
    /// The solver did not converge (treated as unstable).
    SolverFailed,
}

/// Resultant force of one contact in a solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactForce {
    /// Index of the contact in the model.
    pub contact: usize,
    /// Force on the front body (N; x, y, z).
    pub force: [f64; 3],
    /// Normal component (N).
    pub normal: f64,
    /// Tangential components (N): along the segment, vertical.
    pub tangential: [f64; 2],
    /// Centre of pressure (m; x, y, z) — where the line of action crosses the contact.
    pub point: [f64; 3],
    /// Distance of the centre of pressure from the nearer segment end (m; negative = outside).
    pub segment_margin: f64,
    /// Largest `‖tangential‖ / (μ · normal)` over the contact's end points / corners; `None`
    /// for a frictionless contact (`μ = 0`: nothing to use, and no tangential force beyond
    /// solver noise).
    pub friction_use: Option<f64>,
}

/// Floor reaction of one box in a 3-D solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloorForce {
    /// Index of the body.
    pub body: usize,
    /// Normal force (N).
    pub normal: f64,
    /// Friction force magnitude (N), against `u`.
    pub friction: f64,
    /// Centre of pressure in the plane (m).
    pub cop: V2,
    /// Distance of the centre of pressure from the nearest footprint edge (m; negative = tips).
    pub footprint_margin: f64,
}

/// The constraint that limits the margin (or breaks feasibility) of a phase.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Binding {
    /// A contact's line of action at (or beyond) the segment end `end` (0 = `p0`, 1 = `p1`).
    Segment {
        /// Contact index.
        contact: usize,
        /// Which end.
        end: usize,
    },
    /// A box's floor centre of pressure at (or beyond) a footprint edge: along body axis
    /// `axis` (0, 1) on side `side` (+1 / −1).
    Footprint {
        /// Body index.
        body: usize,
        /// Body axis.
        axis: usize,
        /// Side of the footprint.
        side: i8,
    },
    /// No forces exist inside the friction cones; `excess[i]` is the tangential force the contact
    /// would need beyond its (shrunk) cone, relative to its reference load.
    Slip {
        /// Contact index of the largest excess.
        contact: usize,
        /// `(contact, excess)` for every contact that would slip.
        excess: Vec<(usize, f64)>,
    },
}

/// Result of one phase.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseResult {
    /// Front body of the moving group (bodies `start..k` move).
    pub start: usize,
    /// Program outcome.
    pub status: PhaseStatus,
    /// Margin (m); `None` when infeasible or failed.
    pub margin: Option<f64>,
    /// Contact forces (contacts `start..k`) of the optimal solution.
    pub contacts: Vec<ContactForce>,
    /// Floor reactions (3-D only).
    pub floor: Vec<FloorForce>,
    /// What limits the margin.
    pub binding: Option<Binding>,
    /// True when a 3-D tipping margin came from the extended-patch program (the planar part
    /// already failed: some line of action leaves its contact).
    pub extended: bool,
    /// 3-D: margin of the planar part (segments, no vertical friction): the 2-D margin.
    pub planar_margin: Option<f64>,
    /// 3-D: the smallest tipping margin over the moving boxes (each from its own program).
    pub tip_margin: Option<f64>,
    /// Phases of finite travel whose box would turn: how far it turns and drifts over the
    /// travel, and whether that is within the tolerances (then the phase passes).
    pub travel: Option<TravelCheck>,
}

impl PhaseResult {
    /// Whether the phase passes: margin above `tol`, or judged by its travel and within it.
    pub fn passes(&self, tol: f64) -> bool {
        self.margin.is_some_and(|m| m > tol) || self.travel.as_ref().is_some_and(|t| t.passes)
    }
}

/// Result of a whole push (every phase).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckResult {
    /// Model dimension.
    pub dim: Dim,
    /// Smallest margin (m) of the phases not passed by their travel; `None` when some phase
    /// has no equilibrium at all.
    pub margin: Option<f64>,
    /// Every phase passes (margin above the tolerance, or judged by its travel and within it).
    pub stable: bool,
    /// The phase that limits the push: the first that fails, else the smallest margin.
    pub limiting_phase: Option<usize>,
    /// Phases in the order they occur.
    pub phases: Vec<PhaseResult>,
}

impl CheckResult {
    /// The phase that decides the margin (smallest, infeasible first).
    pub fn worst_phase(&self) -> Option<&PhaseResult> {
        self.phases
            .iter()
            .min_by(|a, b| key(a.margin).total_cmp(&key(b.margin)))
    }
}

fn key(m: Option<f64>) -> f64 {
    m.unwrap_or(f64::NEG_INFINITY)
}

/// Check every phase of a push.
pub fn check(model: &PushModel, dim: Dim, opts: &CheckOptions) -> CheckResult {
    let mut phases: Vec<PhaseResult> = model.phase_starts.iter().map(|&s| phase(model, s, dim, opts)).collect();
    for (p, &travel) in phases.iter_mut().zip(&model.phase_travel) {
        p.travel = judge_travel(model, p, travel, dim, opts);
    }
    let judged = |p: &PhaseResult| p.travel.as_ref().is_none_or(|t| !t.passes);
    let margin = phases
        .iter()
        .filter(|p| judged(p))
        .map(|p| p.margin)
        .try_fold(f64::INFINITY, |acc, m| m.map(|m| acc.min(m)));
    let stable = phases.iter().all(|p| p.passes(opts.tol));
    let limiting_phase = phases.iter().position(|p| !p.passes(opts.tol)).or_else(|| {
        (0..phases.len())
            .filter(|&k| judged(&phases[k]))
            .min_by(|&a, &b| key(phases[a].margin).total_cmp(&key(phases[b].margin)))
    });
    CheckResult {
        dim,
        margin,
        stable,
        limiting_phase,
        phases,
    }
}

/// The travel judgement of a phase (`docs/push_stability.md` §5.4): only for a phase of finite
/// travel in which one box moves alone and turns because its pusher's line of action leaves the
/// finger (not for slip or tipping, which short travel does not make harmless).
fn judge_travel(model: &PushModel, p: &PhaseResult, travel: f64, dim: Dim, opts: &CheckOptions) -> Option<TravelCheck> {
    let k = model.k();
    let m = p.margin?;
    if !travel.is_finite() || m > opts.tol || p.start + 1 != k {
        return None;
    }
    if dim == Dim::D3 && p.tip_margin.is_none_or(|t| t <= opts.tol) {
        return None;
    }
    match p.binding {
        Some(Binding::Segment { contact, end }) if contact == k - 1 => Some(travel::judge(
            model,
            contact,
            end,
            travel,
            opts.max_rotation,
            opts.max_drift,
        )),
        _ => None,
    }
}

/// Margin only (no certificate): the fast path. The planar part of every phase goes into one
/// LP with a common margin (one solve); in 3-D each moving box of each phase then gets its own
/// tipping program (`tip_margin`). `None` when some phase has no equilibrium at all.
pub fn margin(model: &PushModel, dim: Dim, opts: &CheckOptions) -> Option<f64> {
    let ds: Vec<PhaseData> = model
        .phase_starts
        .iter()
        .map(|&s| PhaseData::new(model, s, opts))
        .collect();
    let l0 = ds.iter().map(|d| d.l0).fold(0.0, f64::max);
    // One length unit for the common margin: rescale every phase to the largest.
    let ds: Vec<PhaseData> = ds.into_iter().map(|d| d.with_l0(l0)).collect();
    let planar = optimise(&ds, Dim::D2, 0.0, 0).ok()?.1 * l0;
    if dim == Dim::D2 {
        return Some(planar);
    }
    let mut out = planar;
    for d in &ds {
        for i in 0..d.n {
            out = out.min(tip_margin(d, i)?.1 * l0);
        }
    }
    Some(out)
}

/// The tipping program of body `i` of phase `d`: solution, margin (units of `d.l0`) and whether
/// the patches had to be extended. Real patches first; extended ones when no forces exist with
/// every centre of pressure inside its real patch (which only happens when the planar part
/// already fails, see `docs/push_stability.md` §3). `None` when the solver finds nothing.
fn tip_margin(d: &PhaseData, i: usize) -> Option<(Vec<f64>, f64, bool)> {
    let one = std::slice::from_ref(d);
    match optimise(one, Dim::D3, 0.0, i) {
        Ok((x, t)) => Some((x, t, false)),
        Err(_) => optimise(one, Dim::D3, EXTEND, i).ok().map(|(x, t)| (x, t, true)),
    }
}
/// The clarabel 2-D margin of a planner line (see [`super::geometry_margin`]): every phase in
/// one LP, cached by exact geometry.
pub fn line_margin_2d(line: &LineGeometry, gaps: &[bool]) -> f64 {
    let k = line.lateral.len();
    let mut key: Vec<u64> = Vec::with_capacity(3 * k + 4);
    key.push(k as u64);
    key.extend(gaps.iter().map(|&g| g as u64));
    for m in 0..k {
        key.extend([
            line.lateral[m][0].to_bits(),
            line.lateral[m][1].to_bits(),
            line.weight[m].to_bits(),
        ]);
    }
    key.extend([line.pusher[0].to_bits(), line.pusher[1].to_bits()]);
    if let Some(m) = LINE_CACHE.with(|c| c.borrow().get(&key).copied()) {
        return m;
    }
    let model = model_of_line(line, gaps);
    let m = margin(&model, Dim::D2, &CheckOptions::default()).unwrap_or(f64::NEG_INFINITY);
    LINE_CACHE.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() >= CACHE_CAP {
            c.clear();
        }
        c.insert(key, m);
    });
    m
}

/// Clear this thread's geometry cache and solver table (for benchmarks and tests).
pub fn clear_caches() {
    LINE_CACHE.with(|c| c.borrow_mut().clear());
    SOLVERS.with(|s| s.borrow_mut().clear());
}

/// Whether solvers are re-used between calls (default true). Re-use gives bit-identical results
/// to fresh solvers; switching it off exists for tests and benchmarks.
pub fn set_solver_reuse(on: bool) {
    REUSE.with(|r| *r.borrow_mut() = on);
}

/// The 2-D model of a planner line in a canonical frame: `u = +x`, lateral = y. Lengths along
/// `u` do not enter the 2-D problem (every contact normal is along `u`, so tangential forces
/// vanish and their lever arms are irrelevant). Non-positive weights are replaced by `10⁻⁹` of
/// the largest (all by 1 when every weight is zero), the limit of a nearly frictionless box.
pub fn model_of_line(line: &LineGeometry, gaps: &[bool]) -> PushModel {
    let k = line.lateral.len();
    let wmax = line.weight.iter().cloned().fold(0.0, f64::max);
    let bodies: Vec<Body> = (0..k)
        .map(|m| {
            let [lo, hi] = line.lateral[m];
            let w = if wmax > 0.0 {
                line.weight[m].max(1e-9 * wmax)
            } else {
                1.0
            };
            Body::aligned(
                &format!("#{m}"),
                [0.0, (lo + hi) / 2.0],
                [0.0, (hi - lo) / 2.0],
                0.0,
                w,
                1.0,
            )
        })
        .collect();
    let contacts = (0..k)
        .map(|m| {
            let (kind, behind) = if m + 1 < k {
                (ContactKind::Object, line.lateral[m + 1])
            } else {
                (ContactKind::Pusher, line.pusher)
            };
            let lo = line.lateral[m][0].max(behind[0]);
            let hi = line.lateral[m][1].min(behind[1]);
            Contact {
                front: m,
                kind,
                p0: [0.0, lo],
                dir: [0.0, 1.0],
                len: hi - lo,
                normal: [1.0, 0.0],
                z: [0.0, 0.0],
                mu: 1.0,
            }
        })
        .collect();
    PushModel::new([1.0, 0.0], bodies, contacts, gaps)
}

const CACHE_CAP: usize = 1 << 16;
/// Lateral extension (in units of the phase's length scale) of the 3-D diagnostic program.
const EXTEND: f64 = 2.0;
/// Bound on |t| (in units of the length scale) that keeps every program bounded.
const T_CAP: f64 = 10.0;

/// Problem structure: dimension, phase sizes, variant.
type SolverKey = (Dim, Vec<usize>, Variant);

thread_local! {
    static LINE_CACHE: RefCell<HashMap<Vec<u64>, f64>> = RefCell::new(HashMap::new());
    static SOLVERS: RefCell<HashMap<SolverKey, DefaultSolver<f64>>> = RefCell::new(HashMap::new());
    static REUSE: RefCell<bool> = const { RefCell::new(true) };
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Variant {
    /// Maximise the margin.
    Margin,
    /// Minimise the friction excess (slip diagnosis); segments and footprints relaxed.
    Slip,
}

/// One phase, normalised: positions relative to the front body's centre in units of `l0`.
struct PhaseData<'a> {
    model: &'a PushModel,
    start: usize,
    n: usize,
    l0: f64,
    origin: V2,
    /// Reference load of each contact of the phase (N): the normal force it carries in the 2-D
    /// statically determinate line.
    r: Vec<f64>,
    /// Floor friction load of each body (N).
    w: Vec<f64>,
    /// Weight of each body (N).
    g: Vec<f64>,
    /// Shrunk friction coefficient of each contact.
    mu: Vec<f64>,
}

impl<'a> PhaseData<'a> {
    fn new(model: &'a PushModel, start: usize, opts: &CheckOptions) -> PhaseData<'a> {
        let n = model.k() - start;
        let bodies = &model.bodies[start..];
        let contacts = &model.contacts[start..];
        let mut l0: f64 = 0.0;
        for b in bodies {
            l0 = l0.max(2.0 * b.half[0]).max(2.0 * b.half[1]).max(b.height);
        }
        for c in contacts {
            l0 = l0.max(c.len.abs()).max(c.z[1]);
        }
        if l0.is_nan() || l0 <= 0.0 || !l0.is_finite() {
            l0 = 1.0;
        }
        let w: Vec<f64> = bodies.iter().map(|b| b.load(model.gravity)).collect();
        let g: Vec<f64> = bodies.iter().map(|b| b.mass * model.gravity).collect();
        let gsum: f64 = g.iter().sum::<f64>().max(w.iter().sum::<f64>());
        let tiny = 1e-12 * gsum.max(f64::MIN_POSITIVE);
        let mut acc = 0.0;
        let r = contacts
            .iter()
            .enumerate()
            .map(|(j, c)| {
                acc += w[j];
                let cos = dot(model.u, c.normal);
                let r = if cos > 1e-9 { acc * cos } else { acc };
                r.max(tiny)
            })
            .collect();
        let mu = contacts.iter().map(|c| c.mu * (1.0 - opts.cone_shrink)).collect();
        PhaseData {
            model,
            start,
            n,
            l0,
            origin: bodies[0].centre,
            r,
            w,
            g,
            mu,
        }
    }

    /// The same phase measured in another length unit.
    fn with_l0(mut self, l0: f64) -> PhaseData<'a> {
        self.l0 = l0;
        self
    }
    fn body(&self, i: usize) -> &Body {
        &self.model.bodies[self.start + i]
    }
    fn contact(&self, j: usize) -> &Contact {
        &self.model.contacts[self.start + j]
    }
    /// Normalised position.
    fn pos(&self, p: V2) -> V2 {
        [(p[0] - self.origin[0]) / self.l0, (p[1] - self.origin[1]) / self.l0]
    }
    /// Row scale of body `i`: the largest load acting on it.
    fn scale(&self, i: usize, dim: Dim) -> f64 {
        let mut s = self.r[i].max(self.w[i]);
        if i > 0 {
            s = s.max(self.r[i - 1]);
        }
        if dim == Dim::D3 {
            s = s.max(self.g[i]);
        }
        s
    }
    /// Contacts acting on body `i`: `(contact, sign)` — `+1` for the one pushing it from behind,
    /// `−1` for the one through which it pushes the body in front.
    fn acting(&self, i: usize) -> impl Iterator<Item = (usize, f64)> {
        std::iter::once((i, 1.0)).chain((i > 0).then(|| (i - 1, -1.0)))
    }
}

/// A conic program `min qᵀx  s.t.  A x + s = b, s ∈ K` under assembly.
struct Program {
    nv: usize,
    rows: usize,
    trip: Vec<(usize, usize, f64)>,
    b: Vec<f64>,
    q: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
}

impl Program {
    fn new(nv: usize, rows: usize) -> Program {
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
    fn a(&mut self, row: usize, col: usize, v: f64) {
        self.trip.push((row, col, v));
    }
    fn csc(&mut self) -> CscMatrix<f64> {
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

fn settings() -> DefaultSettings<f64> {
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
enum Solved {
    Optimal(Vec<f64>),
    Infeasible,
    Failed,
}

fn run(key: SolverKey, prog: &mut Program) -> Solved {
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
struct MarginRows {
    theta: Vec<f64>,
    w: Vec<f64>,
}

impl MarginRows {
    /// The reference-load rows: 2-D, every contact carries the margin; 3-D (tipping program of
    /// body `tip` of each phase), only that body's footprint does.
    fn reference(ds: &[PhaseData], dim: Dim, tip: usize) -> MarginRows {
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
fn t_col(ds: &[PhaseData], dim: Dim) -> usize {
    let total: usize = ds.iter().map(|d| d.n).sum();
    match dim {
        Dim::D2 => 3 * total,
        Dim::D3 => 15 * total,
    }
}

/// Assemble the phases `ds` into one program with a common margin and solve it.
fn solve_rows(ds: &[PhaseData], dim: Dim, variant: Variant, ext: f64, rows: &MarginRows, tip: usize) -> Solved {
    let mut prog = match dim {
        Dim::D2 => assemble_2d(ds, variant, rows),
        Dim::D3 => assemble_3d(ds, ext, rows, tip),
    };
    let shape: Vec<usize> = ds.iter().map(|d| d.n).collect();
    run((dim, shape, variant), &mut prog)
}

/// One margin constraint evaluated at a solution: the geometric distance (normalised) of a
/// centre of pressure from a segment end / footprint edge, its normal force, and what it is.
struct Ratio {
    value: f64,
    denom: f64,
    binding: Binding,
}

/// Every margin constraint of a solution `x` of the program over `ds`, in group order (two per
/// group).
fn ratios(ds: &[PhaseData], dim: Dim, x: &[f64], ext: f64) -> Vec<Ratio> {
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
const DENOM_MIN: f64 = 1e-9;
/// Dinkelbach iterations at most (3-D); each is one solve.
const MAX_DINKELBACH: usize = 8;

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
fn optimise(ds: &[PhaseData], dim: Dim, ext: f64, tip: usize) -> std::result::Result<(Vec<f64>, f64), Solved> {
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
fn solve_slip(d: &PhaseData) -> Option<Vec<f64>> {
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
fn ends(len: f64, ext: f64) -> [f64; 2] {
    [-ext, len + ext]
}

/// Smallest friction coefficient used in a cone: keeps `f_n ≥ 0` implied by the cone rows.
const MU_MIN: f64 = 1e-9;

/// 2-D LP. Columns: per phase, per contact `(f_n, f_t, m)`; then `t`; then (slip) `σ_j`.
/// Rows: 3 balance rows per body; 4 inequality rows per contact (two cone edges, two segment
/// ends); the cap on `t`; (slip) `σ ≥ 0` and `t ≥ −T`.
fn assemble_2d(ds: &[PhaseData], variant: Variant, mr: &MarginRows) -> Program {
    let total: usize = ds.iter().map(|d| d.n).sum();
    let slip = variant == Variant::Slip;
    let t = 3 * total;
    let sig = |j: usize| 3 * total + 1 + j;
    let nv = 3 * total + 1 + if slip { total } else { 0 };
    let n_nn = 4 * total + 1 + if slip { total + 1 } else { 0 };
    let rows = 3 * total + n_nn;
    let mut p = Program::new(nv, rows);
    let mut off = 0;
    for d in ds {
        let n = d.n;
        let u = d.model.u;
        for i in 0..n {
            let s = d.scale(i, Dim::D2);
            let o = d.pos(d.body(i).cof);
            let row = 3 * (off + i);
            for (j, sign) in d.acting(i) {
                let c = d.contact(j);
                let k = sign * d.r[j] / s;
                let dp = {
                    let p0 = d.pos(c.p0);
                    [p0[0] - o[0], p0[1] - o[1]]
                };
                let col = 3 * (off + j);
                p.a(row, col, k * c.normal[0]);
                p.a(row, col + 1, k * c.dir[0]);
                p.a(row + 1, col, k * c.normal[1]);
                p.a(row + 1, col + 1, k * c.dir[1]);
                p.a(row + 2, col, k * cross(dp, c.normal));
                p.a(row + 2, col + 1, k * cross(dp, c.dir));
                p.a(row + 2, col + 2, k * cross(c.dir, c.normal));
            }
            p.b[row] = d.w[i] / s * u[0];
            p.b[row + 1] = d.w[i] / s * u[1];
        }
        for j in 0..n {
            let c = d.contact(j);
            let len = c.len / d.l0;
            let mu = d.mu[j].max(MU_MIN);
            let (w, th) = (mr.w[off + j], mr.theta[off + j]);
            let r = 3 * total + 4 * (off + j);
            let col = 3 * (off + j);
            p.a(r, col, -mu);
            p.a(r, col + 1, 1.0);
            p.a(r + 1, col, -mu);
            p.a(r + 1, col + 1, -1.0);
            if slip {
                p.a(r, sig(off + j), -1.0);
                p.a(r + 1, sig(off + j), -1.0);
            }
            // m − θ f_n − w t ≥ 0
            p.a(r + 2, col, th);
            p.a(r + 2, col + 2, -1.0);
            p.a(r + 2, t, w);
            // (L − θ) f_n − m − w t ≥ 0
            p.a(r + 3, col, -(len - th));
            p.a(r + 3, col + 2, 1.0);
            p.a(r + 3, t, w);
        }
        off += n;
    }
    let cap = 3 * total + 4 * total;
    p.a(cap, t, 1.0);
    p.b[cap] = T_CAP;
    if slip {
        for j in 0..total {
            p.a(cap + 1 + j, sig(j), -1.0);
            p.q[sig(j)] = 1.0;
        }
        p.a(cap + 1 + total, t, -1.0);
        p.b[cap + 1 + total] = T_CAP;
    } else {
        p.q[t] = -1.0;
    }
    p.cones = vec![
        SupportedConeT::ZeroConeT(3 * total),
        SupportedConeT::NonnegativeConeT(n_nn),
    ];
    p
}

/// Column of the normal force at corner `corner` of contact `j` (phase offset `off` bodies);
/// the two tangential components follow.
fn col3_contact(off: usize, j: usize, corner: usize) -> usize {
    15 * off + 12 * j + 3 * corner
}

/// Column of the floor normal `N` of body `i` of a phase of `n` bodies; `P`, `Q` follow.
fn col3_floor(off: usize, n: usize, i: usize) -> usize {
    15 * off + 12 * n + 3 * i
}

/// Lateral half extent added (normalised) to the footprints of the bodies a tipping program
/// does not judge: their floor moments become free, so another box's tipping (its own program)
/// cannot make this one infeasible.
const RELAX: f64 = T_CAP;

/// 3-D SOCP, the tipping program of body `tip` of each phase. Columns: per phase, 4 corners ×
/// `(f_n, f_e, f_z)` per contact, then `(N, P, Q)` per body; then `t`. Rows: 6 balance rows per
/// body; 2 lateral rows per contact and 5 floor rows per body; the cap on `t`; 2 sign rows per
/// corner (vertical friction only where `tip` tipping would produce it); then one 3-dimensional
/// second-order cone per corner.
fn assemble_3d(ds: &[PhaseData], ext: f64, mr: &MarginRows, tip: usize) -> Program {
    let total: usize = ds.iter().map(|d| d.n).sum();
    let t = 15 * total;
    let nv = 15 * total + 1;
    let n_nn = 7 * total + 1 + 8 * total;
    let n_soc = 12 * total;
    let rows = 6 * total + n_nn + n_soc;
    let mut p = Program::new(nv, rows);
    let soc0 = 6 * total + n_nn;
    let cap = 6 * total + 7 * total;
    let mut off = 0;
    for d in ds {
        let n = d.n;
        let u = d.model.u;
        for i in 0..n {
            let s = d.scale(i, Dim::D3);
            let body = d.body(i);
            let cen = d.pos(body.centre);
            let row = 6 * (off + i);
            for (j, sign) in d.acting(i) {
                let c = d.contact(j);
                let k = sign * d.r[j] / s;
                let p0 = d.pos(c.p0);
                let [nx, ny] = c.normal;
                let [ex, ey] = c.dir;
                let lat = ends(c.len / d.l0, ext);
                for corner in 0..4 {
                    let sl = lat[corner / 2];
                    let rz = c.z[corner % 2] / d.l0;
                    let rx = p0[0] + sl * ex - cen[0];
                    let ry = p0[1] + sl * ey - cen[1];
                    let col = col3_contact(off, j, corner);
                    // Normal force along n.
                    p.a(row, col, k * nx);
                    p.a(row + 1, col, k * ny);
                    p.a(row + 3, col, k * (-rz * ny));
                    p.a(row + 4, col, k * (rz * nx));
                    p.a(row + 5, col, k * (rx * ny - ry * nx));
                    // Tangential along the segment, e.
                    p.a(row, col + 1, k * ex);
                    p.a(row + 1, col + 1, k * ey);
                    p.a(row + 3, col + 1, k * (-rz * ey));
                    p.a(row + 4, col + 1, k * (rz * ex));
                    p.a(row + 5, col + 1, k * (rx * ey - ry * ex));
                    // Vertical tangential, z.
                    p.a(row + 2, col + 2, k);
                    p.a(row + 3, col + 2, k * ry);
                    p.a(row + 4, col + 2, k * (-rx));
                }
            }
            let gk = d.g[i] / s;
            let mu = body.mu_floor;
            let dc = {
                let q = d.pos(body.cof);
                [q[0] - cen[0], q[1] - cen[1]]
            };
            let nc = col3_floor(off, n, i);
            p.a(row, nc, gk * (-mu * u[0]));
            p.a(row + 1, nc, gk * (-mu * u[1]));
            p.a(row + 2, nc, gk);
            p.a(row + 5, nc, gk * (-mu * cross(dc, u)));
            let [a, b] = body.axes;
            p.a(row + 3, nc + 1, gk * a[1]);
            p.a(row + 4, nc + 1, gk * (-a[0]));
            p.a(row + 3, nc + 2, gk * b[1]);
            p.a(row + 4, nc + 2, gk * (-b[0]));
            p.b[row + 2] = gk;
        }
        let nn0 = 6 * total + 7 * off;
        for j in 0..n {
            let c = d.contact(j);
            let len = c.len / d.l0;
            let lat = ends(len, ext);
            let (w, th) = (mr.w[off + j], mr.theta[off + j]);
            let r = nn0 + 2 * j;
            for corner in 0..4 {
                let col = col3_contact(off, j, corner);
                // Σ (s_k + e − θ) f_k − w t ≥ 0 and Σ (L + e − s_k − θ) f_k − w t ≥ 0: the centre
                // of pressure inside the (extended by e) patch; segments carry no margin here.
                p.a(r, col, -(lat[corner / 2] + ext - th));
                p.a(r + 1, col, -(len + ext - lat[corner / 2] - th));
            }
            p.a(r, t, w);
            p.a(r + 1, t, w);
            let mu = d.mu[j].max(MU_MIN);
            // A tipping box rises everywhere but on its tipping edge, so friction pulls it down
            // at each of its contacts and lifts the neighbour; f_z is the force on the front body.
            let down = tip == j;
            let up = tip == j + 1 && c.kind == ContactKind::Object;
            for corner in 0..4 {
                let col = col3_contact(off, j, corner);
                let sr = soc0 + 3 * (4 * (off + j) + corner);
                p.a(sr, col, -mu);
                p.a(sr + 1, col + 1, -1.0);
                p.a(sr + 2, col + 2, -1.0);
                let gr = cap + 1 + 8 * (off + j) + 2 * corner;
                // −f_z ≥ 0 unless it may push the front body up; f_z ≥ 0 unless down.
                p.a(gr, col + 2, if up { 0.0 } else { 1.0 });
                p.a(gr + 1, col + 2, if down { 0.0 } else { -1.0 });
            }
        }
        for i in 0..n {
            let body = d.body(i);
            let relax = if i == tip { 0.0 } else { RELAX };
            let [ha, hb] = [body.half[0] / d.l0 + relax, body.half[1] / d.l0 + relax];
            let nc = col3_floor(off, n, i);
            let (w, th) = (mr.w[total + off + i], mr.theta[total + off + i]);
            let r = nn0 + 2 * n + 5 * i;
            p.a(r, nc, -1.0);
            for (k, (h, col)) in [(ha, nc + 1), (hb, nc + 2)].into_iter().enumerate() {
                for (m, side) in [1.0, -1.0].into_iter().enumerate() {
                    // (h − θ) N ∓ P − w t ≥ 0
                    let rr = r + 1 + 2 * k + m;
                    p.a(rr, nc, -(h - th));
                    p.a(rr, col, side);
                    p.a(rr, t, w);
                }
            }
        }
        off += n;
    }
    p.a(cap, t, 1.0);
    p.b[cap] = T_CAP;
    p.q[t] = -1.0;
    let mut cones = vec![
        SupportedConeT::ZeroConeT(6 * total),
        SupportedConeT::NonnegativeConeT(n_nn),
    ];
    cones.extend((0..4 * total).map(|_| SupportedConeT::SecondOrderConeT(3)));
    p.cones = cones;
    p
}

/// Solve one phase and extract the certificate. 3-D: the planar part (the 2-D LP) and one
/// tipping program per moving box; the phase margin is the smallest, and the certificate's
/// contact forces are those of the program that sets it.
pub fn phase(model: &PushModel, start: usize, dim: Dim, opts: &CheckOptions) -> PhaseResult {
    let d = PhaseData::new(model, start, opts);
    let planar = phase_2d(&d);
    if dim == Dim::D2 {
        return planar;
    }
    let mut out = PhaseResult {
        planar_margin: planar.margin,
        ..planar
    };
    if out.margin.is_none() {
        // A contact slips: no tipping question to ask.
        return out;
    }
    let mut tip: Option<f64> = Some(f64::INFINITY);
    let mut floor = Vec::with_capacity(d.n);
    for i in 0..d.n {
        let Some((x, t, extended)) = tip_margin(&d, i) else {
            tip = None;
            break;
        };
        let m = t * d.l0;
        floor.push(floor_force(&d, &x, i));
        out.extended |= extended;
        if tip.is_some_and(|tm| m < tm) {
            tip = Some(m);
            if out.margin.is_some_and(|pm| m < pm) {
                let ext = if extended { EXTEND } else { 0.0 };
                out.margin = Some(m);
                out.contacts = contact_forces(&d, Dim::D3, &x, ext);
                out.binding = ratios(std::slice::from_ref(&d), Dim::D3, &x, ext)
                    .into_iter()
                    .filter(|r| matches!(r.binding, Binding::Footprint { body, .. } if body == d.start + i))
                    .min_by(|a, b| a.value.total_cmp(&b.value))
                    .map(|r| r.binding);
            }
        }
    }
    out.tip_margin = tip;
    if tip.is_none() {
        out.status = PhaseStatus::SolverFailed;
        out.margin = None;
        out.binding = None;
    } else {
        out.floor = floor;
    }
    out
}

/// The 2-D phase: margin, certificate, or the slip diagnosis when no forces exist.
fn phase_2d(d: &PhaseData) -> PhaseResult {
    let one = std::slice::from_ref(d);
    match optimise(one, Dim::D2, 0.0, 0) {
        Ok((x, t)) => PhaseResult {
            start: d.start,
            status: PhaseStatus::Solved,
            margin: Some(t * d.l0),
            contacts: contact_forces(d, Dim::D2, &x, 0.0),
            floor: Vec::new(),
            binding: ratios(one, Dim::D2, &x, 0.0)
                .into_iter()
                .min_by(|a, b| a.value.total_cmp(&b.value))
                .map(|r| r.binding),
            extended: false,
            planar_margin: None,
            tip_margin: None,
            travel: None,
        },
        Err(status) => {
            let failed = matches!(status, Solved::Failed);
            let binding = solve_slip(d).and_then(|x| {
                let off = t_col(one, Dim::D2) + 1;
                let mut excess: Vec<(usize, f64)> = (0..d.n)
                    .map(|j| (d.start + j, x[off + j]))
                    .filter(|&(_, e)| e > 1e-7)
                    .collect();
                excess.sort_by(|a, b| b.1.total_cmp(&a.1));
                excess.first().map(|&(c, _)| Binding::Slip {
                    contact: c,
                    excess: excess.clone(),
                })
            });
            PhaseResult {
                start: d.start,
                status: if failed && binding.is_none() {
                    PhaseStatus::SolverFailed
                } else {
                    PhaseStatus::Infeasible
                },
                margin: None,
                contacts: Vec::new(),
                floor: Vec::new(),
                binding,
                extended: false,
                planar_margin: None,
                tip_margin: None,
                travel: None,
            }
        }
    }
}

/// Contact forces of a solution `x` of one phase's program.
fn contact_forces(d: &PhaseData, dim: Dim, x: &[f64], ext: f64) -> Vec<ContactForce> {
    let n = d.n;
    let mut contacts = Vec::with_capacity(n);
    for j in 0..n {
        let c = d.contact(j);
        let len = c.len / d.l0;
        let rj = d.r[j];
        // Below MU_MIN the program uses MU_MIN: measure use against what it could use.
        let mu = c.mu.max(MU_MIN);
        let (fnv, fe, fz, mom, zc, use_) = match dim {
            Dim::D2 => {
                let (f, ft, m) = (x[3 * j], x[3 * j + 1], x[3 * j + 2]);
                let use_ = if f > 1e-12 { ft.abs() / (mu * f) } else { 0.0 };
                (f, ft, 0.0, m, 0.0, use_)
            }
            Dim::D3 => {
                let lat = ends(len, ext);
                let (mut f, mut fe, mut fz, mut m, mut zm, mut use_) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0f64);
                for corner in 0..4 {
                    let col = col3_contact(0, j, corner);
                    let (a, b, cz) = (x[col], x[col + 1], x[col + 2]);
                    f += a;
                    fe += b;
                    fz += cz;
                    m += lat[corner / 2] * a;
                    zm += c.z[corner % 2] * a;
                    if a > 1e-9 {
                        use_ = use_.max((b * b + cz * cz).sqrt() / (mu * a));
                    }
                }
                let zc = if f > 1e-12 { zm / f } else { c.z[0] };
                (f, fe, fz, m, zc, use_)
            }
        };
        let s = if fnv > 1e-12 { mom / fnv } else { len / 2.0 };
        let point = [c.p0[0] + s * d.l0 * c.dir[0], c.p0[1] + s * d.l0 * c.dir[1], zc];
        let force = [
            rj * (fnv * c.normal[0] + fe * c.dir[0]),
            rj * (fnv * c.normal[1] + fe * c.dir[1]),
            rj * fz,
        ];
        contacts.push(ContactForce {
            contact: d.start + j,
            force,
            normal: rj * fnv,
            tangential: [rj * fe, rj * fz],
            point,
            segment_margin: d.l0 * s.min(len - s),
            friction_use: (c.mu > 0.0).then_some(use_),
        });
    }
    contacts
}

/// Floor reaction of body `i` in a solution `x` of one phase's 3-D program.
fn floor_force(d: &PhaseData, x: &[f64], i: usize) -> FloorForce {
    let body = d.body(i);
    let col = col3_floor(0, d.n, i);
    let (nn, pp, qq) = (x[col], x[col + 1], x[col + 2]);
    let [ha, hb] = [body.half[0] / d.l0, body.half[1] / d.l0];
    let (al, be) = if nn > 1e-12 { (pp / nn, qq / nn) } else { (0.0, 0.0) };
    let [a, b] = body.axes;
    let cop = [
        body.centre[0] + d.l0 * (al * a[0] + be * b[0]),
        body.centre[1] + d.l0 * (al * a[1] + be * b[1]),
    ];
    let gn = d.g[i] * nn;
    FloorForce {
        body: d.start + i,
        normal: gn,
        friction: body.mu_floor * gn,
        cop,
        footprint_margin: d.l0 * (ha - al.abs()).min(hb - be.abs()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reused_solvers_give_identical_results() {
        let line = LineGeometry {
            lateral: vec![[0.0, 0.05], [0.01, 0.07], [0.0, 0.06]],
            weight: vec![0.1, 0.3, 0.2],
            pusher: [0.02, 0.04],
        };
        let model = model_of_line(&line, &[true, true]);
        let opts = CheckOptions::default();
        set_solver_reuse(false);
        let fresh: Vec<_> = [Dim::D2, Dim::D3].iter().map(|&d| margin(&model, d, &opts)).collect();
        set_solver_reuse(true);
        let _ = margin(
            &model_of_line(
                &LineGeometry {
                    pusher: [0.0, 0.01],
                    ..line.clone()
                },
                &[false, true],
            ),
            Dim::D2,
            &opts,
        );
        let reused: Vec<_> = [Dim::D2, Dim::D3].iter().map(|&d| margin(&model, d, &opts)).collect();
        assert_eq!(fresh, reused);
    }
}

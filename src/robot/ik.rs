//! Inverse kinematics of one 6-joint NEXTAGE arm.
//!
//! Method (see `docs/robot.md`): Levenberg–Marquardt (damped least squares) on the full 6-D TCP
//! pose error with the analytic geometric Jacobian, joints projected onto their limits after every
//! step, from several seeds. Before descending from a seed, the wrist roll (joint 5) is set in
//! closed form to the angle that best aligns the TCP frame with the target (for the NEXTAGE the
//! TCP lies on the joint-5 axis, so this angle *is* the yaw part of the solution and the numeric
//! problem that remains is the 5-joint position + approach-axis problem). A solution is returned
//! only when both residuals are below the tolerances (1e-10 m, 1e-10 rad by default), so a pose
//! that is out of reach gives [`RobotError::Unreachable`] with the best residuals reached, never a
//! wrong configuration.
//!
//! Branches: [`IkSolver::solve_near`] first descends from the previous configuration (which keeps
//! the branch along a finely sampled path) and falls back to every seed, returning the solution
//! nearest to the previous configuration; [`IkSolver::solve_all`] returns every distinct solution
//! the seeds find.

use super::{tcp_rotation_in_wrist, Arm, RobotError, RobotModel};
use nalgebra::{Isometry3, Matrix3, Matrix6, Rotation3, Translation3, UnitQuaternion, Vector3, Vector6};
use std::cell::Cell;
use std::collections::HashMap;
use std::sync::Mutex;

/// Rotation of a top-down TCP frame whose finger closing axis (TCP y) makes angle `yaw` with
/// world x: z = (0, 0, −1), y = (cos yaw, sin yaw, 0), x = y × z.
pub fn top_down_rotation(yaw: f64) -> Rotation3<f64> {
    let (s, c) = yaw.sin_cos();
    Rotation3::from_matrix_unchecked(Matrix3::new(-s, c, 0.0, c, s, 0.0, 0.0, 0.0, -1.0))
}

/// Top-down TCP pose at `position` with closing-axis angle `yaw`.
pub fn top_down_pose(position: &Vector3<f64>, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(*position),
        UnitQuaternion::from_rotation_matrix(&top_down_rotation(yaw)),
    )
}

/// Characteristic length that weighs rotation errors against position errors (m/rad).
const ROT_WEIGHT: f64 = 0.2;

/// Position and rotation residuals of `q` for `target`: (|Δp| in m, |Δθ| in rad).
pub fn pose_residual(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let dp = (a.translation.vector - b.translation.vector).norm();
    let dr = (a.rotation.inverse() * b.rotation).angle();
    (dp, dr)
}

/// Result of one descent.
#[derive(Debug, Clone)]
struct Attempt {
    q: [f64; 6],
    pos: f64,
    rot: f64,
    at_limit: Option<usize>,
}

/// IK solver for one arm with a given TCP offset. Cheap to build; holds its seeds.
#[derive(Debug, Clone)]
pub struct IkSolver<'a> {
    model: &'a RobotModel,
    arm: Arm,
    tool: Isometry3<f64>,
    lower: [f64; 6],
    upper: [f64; 6],
    seeds: Vec<[f64; 6]>,
    /// Iteration cap per seed (default 150).
    pub max_iters: usize,
    /// Position tolerance (m, default 1e-10).
    pub tol_pos: f64,
    /// Rotation tolerance (rad, default 1e-10).
    pub tol_rot: f64,
    /// In [`IkSolver::solve_near`], a solution from the previous configuration is taken without
    /// trying other seeds when no joint moved more than this (rad, default 1.0; a wrist flip
    /// moves joints 3–5 by about π).
    pub near_jump: f64,
    /// Threads that make one call's descents from the seeds side by side (default: 1, or what
    /// [`with_threads`] set for this thread). Each descent is a pure function of its target,
    /// seed and settings, so the answer is the same on any number.
    pub threads: usize,
    /// The descents from the solver's own seeds by target and descent settings, in seed order
    /// (see [`IkSolver::run_seeds_until`]): they do not depend on the caller's configuration,
    /// and the joint plan asks for one target from several (the hand variants of an action
    /// share their poses, and a failed local descent falls back to every seed). Behind a lock
    /// so that threads may share the solver.
    seed_runs: SeedRuns,
}

/// [`IkSolver::seed_runs`].
#[derive(Debug, Default)]
struct SeedRuns(Mutex<HashMap<SeedKey, Vec<Attempt>>>);

impl SeedRuns {
    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<SeedKey, Vec<Attempt>>> {
        self.0.lock().expect("no descent panics holding it")
    }
}

impl Clone for SeedRuns {
    fn clone(&self) -> Self {
        SeedRuns(Mutex::new(self.lock().clone()))
    }
}

thread_local! {
    /// The default of [`IkSolver::threads`] for solvers built on this thread.
    static THREADS: Cell<usize> = const { Cell::new(1) };
}

/// Run `f` with `threads` as the default of [`IkSolver::threads`] for every solver it builds
/// on this thread (the planner's stages build their own: `PlanOptions::threads`); the
/// previous default comes back after it, even when `f` panics.
pub fn with_threads<R>(threads: usize, f: impl FnOnce() -> R) -> R {
    struct Restore(usize);
    impl Drop for Restore {
        fn drop(&mut self) {
            THREADS.with(|t| t.set(self.0));
        }
    }
    let _restore = Restore(THREADS.with(|t| t.replace(threads.max(1))));
    f()
}

/// Extra seeds whose descents are made side by side at a time: the extra seeds stop at the
/// first that solves, so a batch of all of them would make descents one thread never makes.
const EXTRA_BATCH: usize = 8;

/// A target's bits and the settings a descent reads (iteration cap, tolerances).
type SeedKey = [u64; 10];

/// Number of pseudo-random seeds (besides the home pose and the caller's configuration).
pub const RANDOM_SEEDS: usize = 40;
/// Further seeds tried only when the first ones found no solution.
pub const EXTRA_SEEDS: usize = 160;

impl<'a> IkSolver<'a> {
    /// A solver for `arm` with the TCP at `tcp_offset` in `*ARM_JOINT5_Link`.
    pub fn new(model: &'a RobotModel, arm: Arm, tcp_offset: &[f64; 3]) -> IkSolver<'a> {
        let chain = &model.arms[arm.index()];
        let lower: [f64; 6] = std::array::from_fn(|k| chain[k].lower);
        let upper: [f64; 6] = std::array::from_fn(|k| chain[k].upper);
        let tool = Isometry3::from_parts(
            Translation3::from(Vector3::from(*tcp_offset)),
            UnitQuaternion::from_rotation_matrix(&tcp_rotation_in_wrist()),
        );
        // Seeds: the standard initial pose (if within limits), then a fixed pseudo-random set
        // inside the limits shrunk by 5 % (deterministic: same seeds every run).
        let mut seeds = Vec::new();
        let home = super::NEXTAGE_INITIAL_POSE_DEG[arm.index()].map(f64::to_radians);
        if (0..6).all(|k| home[k] >= lower[k] && home[k] <= upper[k]) {
            seeds.push(home);
        }
        let mut state: u64 = 0x5EED_0000 + arm.index() as u64;
        let mut next = || {
            state = state.wrapping_add(0x9E3779B97F4A7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        for i in 0..RANDOM_SEEDS + EXTRA_SEEDS {
            // The first seeds avoid the last 5 % of each range; the extra ones (tried only when
            // the first found nothing) cover the whole range, for poses near the limits.
            let shrink = if i < RANDOM_SEEDS { 0.05 } else { 0.0 };
            seeds.push(std::array::from_fn(|k| {
                let m = shrink * (upper[k] - lower[k]);
                lower[k] + m + (upper[k] - lower[k] - 2.0 * m) * next()
            }));
        }
        IkSolver {
            model,
            arm,
            tool,
            lower,
            upper,
            seeds,
            max_iters: 150,
            tol_pos: 1e-10,
            tol_rot: 1e-10,
            near_jump: 1.0,
            threads: THREADS.with(Cell::get),
            seed_runs: SeedRuns::default(),
        }
    }

    /// The arm.
    pub fn arm(&self) -> Arm {
        self.arm
    }

    /// TCP pose of `q` (world).
    pub fn fk(&self, q: &[f64; 6]) -> Isometry3<f64> {
        self.model.wrist_pose(self.arm, q) * self.tool
    }

    /// TCP pose and weighted geometric Jacobian (rows: position, ROT_WEIGHT × rotation).
    fn fk_jac(&self, q: &[f64; 6]) -> (Isometry3<f64>, Matrix6<f64>) {
        let chain = &self.model.arms[self.arm.index()];
        let mut t = self.model.base[self.arm.index()];
        let mut axes = [Vector3::zeros(); 6];
        let mut origins = [Vector3::zeros(); 6];
        for (k, (j, qi)) in chain.iter().zip(q).enumerate() {
            t *= j.origin;
            axes[k] = t.rotation * j.axis.into_inner();
            origins[k] = t.translation.vector;
            t *= UnitQuaternion::from_axis_angle(&j.axis, *qi);
        }
        let tcp = t * self.tool;
        let p = tcp.translation.vector;
        let mut jac = Matrix6::zeros();
        for k in 0..6 {
            let v = axes[k].cross(&(p - origins[k]));
            jac.fixed_view_mut::<3, 1>(0, k).copy_from(&v);
            jac.fixed_view_mut::<3, 1>(3, k).copy_from(&(axes[k] * ROT_WEIGHT));
        }
        (tcp, jac)
    }

    fn error(target: &Isometry3<f64>, cur: &Isometry3<f64>) -> Vector6<f64> {
        let dp = target.translation.vector - cur.translation.vector;
        let dr = (target.rotation * cur.rotation.inverse()).scaled_axis() * ROT_WEIGHT;
        Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z)
    }

    /// Closed-form wrist roll: the joint-5 angle that best aligns the TCP frame with `target`
    /// given joints 0..4 of `q` (maximises tr(R(a, θ)ᵀ M)); wrapped into the limits when possible.
    pub fn wrist_roll(&self, q: &[f64; 6], target: &Isometry3<f64>) -> f64 {
        let chain = &self.model.arms[self.arm.index()];
        let mut t = self.model.base[self.arm.index()];
        for (j, qi) in chain.iter().zip(q).take(5) {
            t = t * j.origin * UnitQuaternion::from_axis_angle(&j.axis, *qi);
        }
        t *= chain[5].origin;
        let m = (t.rotation.inverse() * target.rotation * self.tool.rotation.inverse()).to_rotation_matrix();
        let m = m.matrix();
        let a = chain[5].axis.into_inner();
        let w = Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]);
        let theta = a.dot(&w).atan2(m.trace() - (a.transpose() * m * a)[0]);
        self.wrap_into_limits(5, theta, q[5])
    }

    /// `v + 2πk` inside joint `k`'s limits nearest to `near`, or `v` clamped when none is.
    fn wrap_into_limits(&self, k: usize, v: f64, near: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        let mut best: Option<f64> = None;
        for n in -2..=2 {
            let c = v + n as f64 * tau;
            if c >= self.lower[k] && c <= self.upper[k] && best.is_none_or(|b| (c - near).abs() < (b - near).abs()) {
                best = Some(c);
            }
        }
        best.unwrap_or_else(|| v.clamp(self.lower[k], self.upper[k]))
    }

    fn clamp(&self, q: &mut [f64; 6]) -> Option<usize> {
        let mut pinned = None;
        for (k, qk) in q.iter_mut().enumerate() {
            if *qk <= self.lower[k] {
                *qk = self.lower[k];
                pinned = Some(k);
            } else if *qk >= self.upper[k] {
                *qk = self.upper[k];
                pinned = Some(k);
            }
        }
        pinned
    }

    /// Levenberg–Marquardt descent from `seed` (projected onto the joint limits).
    fn descend(&self, target: &Isometry3<f64>, seed: &[f64; 6], roll_step: bool) -> Attempt {
        let mut q = *seed;
        self.clamp(&mut q);
        if roll_step {
            q[5] = self.wrist_roll(&q, target);
        }
        let (mut cur, mut jac) = self.fk_jac(&q);
        let mut e = Self::error(target, &cur);
        let mut cost = e.norm_squared();
        let mut lambda = 1e-3;
        let mut at_limit = None;
        // The residual and the normal equations of the current point, kept while steps are
        // rejected: a rejected step changes only the damping, so recomputing them gave the
        // same numbers (most iterations of a descent that does not converge are rejections).
        let mut residual = pose_residual(&cur, target);
        let mut normal: Option<(Matrix6<f64>, Vector6<f64>)> = None;
        for _ in 0..self.max_iters {
            let (dp, dr) = residual;
            if dp < self.tol_pos && dr < self.tol_rot {
                break;
            }
            let (jtj, g) = *normal.get_or_insert_with(|| (jac.transpose() * jac, jac.transpose() * e));
            let mut a = jtj;
            for k in 0..6 {
                a[(k, k)] += lambda * (jtj[(k, k)] + 1e-9);
            }
            let Some(delta) = super::cholesky::solve6(&a, &g) else {
                lambda *= 10.0;
                continue;
            };
            let mut qn = q;
            for k in 0..6 {
                qn[k] += delta[k];
            }
            let pinned = self.clamp(&mut qn);
            let (cn, jn) = self.fk_jac(&qn);
            let en = Self::error(target, &cn);
            let costn = en.norm_squared();
            if costn < cost {
                q = qn;
                cur = cn;
                jac = jn;
                e = en;
                cost = costn;
                at_limit = pinned;
                lambda = (lambda / 5.0).max(1e-12);
                residual = pose_residual(&cur, target);
                normal = None;
            } else {
                lambda *= 4.0;
                if lambda > 1e8 {
                    break;
                }
            }
        }
        let (pos, rot) = residual;
        Attempt { q, pos, rot, at_limit }
    }

    fn converged(&self, a: &Attempt) -> bool {
        a.pos < self.tol_pos.max(1e-12) * 10.0 && a.rot < self.tol_rot.max(1e-12) * 10.0
    }

    fn failure(&self, target: &Isometry3<f64>, best: Option<Attempt>, attempts: usize) -> RobotError {
        let t = target.translation.vector;
        let (pos, rot, lim) = match &best {
            Some(a) => (a.pos, a.rot, a.at_limit),
            None => (f64::INFINITY, f64::INFINITY, None),
        };
        RobotError::Unreachable {
            arm: self.arm.name().to_string(),
            target: [t.x, t.y, t.z],
            pos_residual: pos,
            rot_residual: rot,
            at_limit: lim.and_then(|k| {
                best.as_ref()
                    .map(|a| (self.model.arms[self.arm.index()][k].name.clone(), a.q[k]))
            }),
            attempts,
        }
    }

    /// The first solution any seed finds (fastest; no preference among branches).
    pub fn solve_any(&self, target: &Isometry3<f64>) -> Result<[f64; 6], RobotError> {
        let (sols, best, n) = self.run_seeds_until(target, None, true);
        sols.into_iter().next().ok_or_else(|| self.failure(target, best, n))
    }

    fn run_seeds(
        &self,
        target: &Isometry3<f64>,
        first: Option<&[Attempt; 2]>,
    ) -> (Vec<[f64; 6]>, Option<Attempt>, usize) {
        self.run_seeds_until(target, first, false)
    }

    /// Descents from the caller's seed (`first`: its two descents, already made), then from the
    /// solver's seeds in order: every distinct solution, the best failure and the number of
    /// descents. The solver's seeds' descents come from `seed_runs` when an earlier call made
    /// them: a descent is a pure function of its target, seed, roll and settings.
    fn run_seeds_until(
        &self,
        target: &Isometry3<f64>,
        first: Option<&[Attempt; 2]>,
        stop_at_first: bool,
    ) -> (Vec<[f64; 6]>, Option<Attempt>, usize) {
        let mut sols: Vec<[f64; 6]> = Vec::new();
        let mut best: Option<Attempt> = None;
        let mut n = 0;
        let main = 1 + RANDOM_SEEDS.min(self.seeds.len());
        let key = self.seed_key(target);
        let mut runs = self.seed_runs.lock().remove(&key).unwrap_or_default();
        let offset = first.is_some() as usize;
        'seeds: for i in 0..self.seeds.len() + offset {
            if i >= main + offset && !sols.is_empty() {
                break;
            }
            for r in 0..2 {
                n += 1;
                let a = match (first, i.checked_sub(offset)) {
                    (Some(f), None) => f[r].clone(),
                    (_, Some(k)) => {
                        // Made in order, so the next one missing is always at the end.
                        if 2 * k + r == runs.len() {
                            // Stopping at the first solution, only this one; else the main
                            // seeds at once, the extra ones a batch at a time (one thread
                            // makes no extra descent it does not need).
                            let batch = if self.threads > 1 { EXTRA_BATCH } else { 1 };
                            let upto = match (stop_at_first, k < main) {
                                (true, _) => 2 * k + r + 1,
                                (false, true) => 2 * main.min(self.seeds.len()),
                                (false, false) => 2 * (k + batch).min(self.seeds.len()),
                            };
                            self.descend_from_seeds(target, &mut runs, upto);
                        }
                        runs[2 * k + r].clone()
                    }
                    (None, None) => unreachable!("without a first seed every index is a seed's"),
                };
                if self.converged(&a) {
                    if !sols.iter().any(|o| (0..6).all(|k| (o[k] - a.q[k]).abs() < 1e-6)) {
                        sols.push(a.q);
                    }
                    if stop_at_first {
                        break 'seeds;
                    }
                } else if best
                    .as_ref()
                    .is_none_or(|b| a.pos + ROT_WEIGHT * a.rot < b.pos + ROT_WEIGHT * b.rot)
                {
                    best = Some(a);
                }
            }
        }
        self.seed_runs.lock().insert(key, runs);
        (sols, best, n)
    }

    /// The descents from the solver's seeds that `runs` lacks up to `upto` (seed `k`'s without
    /// the wrist roll at `2k`, with it at `2k + 1`), on [`IkSolver::threads`] threads: each
    /// makes a consecutive share, and the shares are appended in order, so `runs` is the same
    /// as made one after the other.
    fn descend_from_seeds(&self, target: &Isometry3<f64>, runs: &mut Vec<Attempt>, upto: usize) {
        let from = runs.len();
        let one = |i: usize| self.descend(target, &self.seeds[i / 2], i % 2 == 1);
        let threads = self.threads.clamp(1, (upto - from).max(1));
        if threads == 1 {
            runs.extend((from..upto).map(one));
            return;
        }
        let share = (upto - from).div_ceil(threads);
        let shares: Vec<Vec<Attempt>> = std::thread::scope(|s| {
            let made: Vec<_> = (from..upto)
                .step_by(share)
                .map(|a| s.spawn(move || (a..(a + share).min(upto)).map(one).collect::<Vec<_>>()))
                .collect();
            made.into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        });
        runs.extend(shares.into_iter().flatten());
    }

    /// The key of `target`'s descents in `seed_runs`.
    fn seed_key(&self, target: &Isometry3<f64>) -> SeedKey {
        let t = target.translation.vector;
        let r = target.rotation.coords;
        [
            t.x.to_bits(),
            t.y.to_bits(),
            t.z.to_bits(),
            r.x.to_bits(),
            r.y.to_bits(),
            r.z.to_bits(),
            r.w.to_bits(),
            self.max_iters as u64,
            self.tol_pos.to_bits(),
            self.tol_rot.to_bits(),
        ]
    }

    /// Every distinct solution the seeds find (possibly empty).
    pub fn solve_all(&self, target: &Isometry3<f64>) -> Vec<[f64; 6]> {
        self.run_seeds(target, None).0
    }

    /// A solution, preferring the largest joint margin (no previous configuration to follow).
    pub fn solve(&self, target: &Isometry3<f64>) -> Result<[f64; 6], RobotError> {
        let (sols, best, n) = self.run_seeds(target, None);
        sols.into_iter()
            .max_by(|a, b| {
                self.model
                    .joint_margin(self.arm, a)
                    .total_cmp(&self.model.joint_margin(self.arm, b))
            })
            .ok_or_else(|| self.failure(target, best, n))
    }

    /// The solution nearest to `prev` (branch continuity): a descent from `prev` is taken when it
    /// converges without any joint moving more than [`IkSolver::near_jump`]; otherwise every seed
    /// is tried and the nearest solution (max |Δq| + 0.1 Σ|Δq| smallest) wins.
    pub fn solve_near(&self, target: &Isometry3<f64>, prev: &[f64; 6]) -> Result<[f64; 6], RobotError> {
        self.solve_near_after(target, prev, None)
    }

    /// [`Self::solve_near`] given its first local descent (without the wrist roll) when the
    /// caller made it already.
    fn solve_near_after(
        &self,
        target: &Isometry3<f64>,
        prev: &[f64; 6],
        plain: Option<Attempt>,
    ) -> Result<[f64; 6], RobotError> {
        // Local descents from `prev` (as is, then with the closed-form wrist roll): the nearer
        // converged one is taken when no joint moved more than `near_jump`.
        let plain = plain.unwrap_or_else(|| self.descend(target, prev, false));
        let local = [plain, self.descend(target, prev, true)];
        let near = local
            .iter()
            .filter(|a| self.converged(a) && max_abs_diff(&a.q, prev) <= self.near_jump)
            .min_by(|x, y| weighted_dist(&x.q, prev).total_cmp(&weighted_dist(&y.q, prev)));
        if let Some(a) = near {
            return Ok(a.q);
        }
        // Every seed, `prev` first: its descents are the local ones.
        let (sols, best, n) = self.run_seeds(target, Some(&local));
        sols.into_iter()
            .min_by(|x, y| weighted_dist(x, prev).total_cmp(&weighted_dist(y, prev)))
            .ok_or_else(|| self.failure(target, best, n + 1))
    }

    /// [`Self::track`], and where that fails [`Self::solve_near`] (which starts with the same
    /// descent, made once here).
    pub fn track_or_near(&self, target: &Isometry3<f64>, prev: &[f64; 6]) -> Result<[f64; 6], RobotError> {
        let a = self.descend(target, prev, false);
        if self.converged(&a) {
            return Ok(a.q);
        }
        self.solve_near_after(target, prev, Some(a))
    }

    /// Only a local descent from `prev`, no other seed: for dense path following.
    pub fn track(&self, target: &Isometry3<f64>, prev: &[f64; 6]) -> Result<[f64; 6], RobotError> {
        let a = self.descend(target, prev, false);
        if self.converged(&a) {
            Ok(a.q)
        } else {
            Err(self.failure(target, Some(a), 1))
        }
    }
}

/// Largest absolute joint difference.
pub fn max_abs_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    (0..6).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

/// Joint distance used to rank branches: largest |Δq| plus a tenth of the sum (ties broken by the
/// total motion).
pub fn weighted_dist(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    let s: f64 = (0..6).map(|k| (a[k] - b[k]).abs()).sum();
    max_abs_diff(a, b) + 0.1 * s
}

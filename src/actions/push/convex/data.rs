//! One phase of a push as the programs see it: bodies, contacts and their geometry.

use super::*;

pub(super) const CACHE_CAP: usize = 1 << 16;
/// Lateral extension (in units of the phase's length scale) of the 3-D diagnostic program.
pub(super) const EXTEND: f64 = 2.0;
/// Bound on |t| (in units of the length scale) that keeps every program bounded.
pub(super) const T_CAP: f64 = 10.0;

/// Problem structure: dimension, phase sizes, variant.
pub(super) type SolverKey = (Dim, Vec<usize>, Variant);

thread_local! {
    pub(super) static LINE_CACHE: RefCell<HashMap<Vec<u64>, f64>> = RefCell::new(HashMap::new());
    pub(super) static VERDICT_CACHE: RefCell<HashMap<Vec<u64>, LineVerdict>> = RefCell::new(HashMap::new());
    pub(super) static SOLVERS: RefCell<HashMap<SolverKey, DefaultSolver<f64>>> = RefCell::new(HashMap::new());
    pub(super) static REUSE: RefCell<bool> = const { RefCell::new(true) };
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(super) enum Variant {
    /// Maximise the margin.
    Margin,
    /// Minimise the friction excess (slip diagnosis); segments and footprints relaxed.
    Slip,
}

/// One phase, normalised: positions relative to the front body's centre in units of `l0`.
pub(super) struct PhaseData<'a> {
    pub(super) model: &'a PushModel,
    pub(super) start: usize,
    pub(super) n: usize,
    pub(super) l0: f64,
    pub(super) origin: V2,
    /// Reference load of each contact of the phase (N): the normal force it carries in the 2-D
    /// statically determinate line.
    pub(super) r: Vec<f64>,
    /// Floor friction load of each body (N).
    pub(super) w: Vec<f64>,
    /// Weight of each body (N).
    pub(super) g: Vec<f64>,
    /// Shrunk friction coefficient of each contact.
    pub(super) mu: Vec<f64>,
}

impl<'a> PhaseData<'a> {
    pub(super) fn new(model: &'a PushModel, start: usize, opts: &CheckOptions) -> PhaseData<'a> {
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
    pub(super) fn with_l0(mut self, l0: f64) -> PhaseData<'a> {
        self.l0 = l0;
        self
    }
    pub(super) fn body(&self, i: usize) -> &Body {
        &self.model.bodies[self.start + i]
    }
    pub(super) fn contact(&self, j: usize) -> &Contact {
        &self.model.contacts[self.start + j]
    }
    /// Normalised position.
    pub(super) fn pos(&self, p: V2) -> V2 {
        [(p[0] - self.origin[0]) / self.l0, (p[1] - self.origin[1]) / self.l0]
    }
    /// Row scale of body `i`: the largest load acting on it.
    pub(super) fn scale(&self, i: usize, dim: Dim) -> f64 {
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
    pub(super) fn acting(&self, i: usize) -> impl Iterator<Item = (usize, f64)> {
        std::iter::once((i, 1.0)).chain((i > 0).then(|| (i - 1, -1.0)))
    }
}

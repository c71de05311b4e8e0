//! Robust push check: stable for every friction coefficient in given intervals and every centre
//! of friction in a given rectangle around each footprint centroid.
//!
//! Method: enumerate the vertices of the uncertainty set that can be worst, solve the nominal
//! check at each, report the minimum margin and the worst vertex.
//! * Contact friction (box–box, finger): the feasible set of contact forces grows with μ, so the
//!   lower end of each interval is the worst case — one value, no enumeration.
//! * Floor friction of each box: both ends of its interval (loads enter the line of action
//!   through their ratios, so neither end dominates).
//! * Centre of friction of each box: floor friction acts along `−u`, so only the lateral
//!   coordinate of its point of application (across `u`) changes any moment; the two corners of
//!   the region rectangle with the smallest and the largest lateral coordinate.
//! * The nominal point itself is always one of the cases, so the robust margin is never larger
//!   than the nominal one.
//!
//! Exactness: for a 2-D line every contact's line of action is a linear-fractional function of
//! the loads and a linear function of the lateral centres of friction, monotone in each
//! coordinate, so its extremes over a box are at vertices; the margin, a minimum of such
//! distances, is therefore minimised at a vertex — the enumeration is exact. In 3-D the same
//! vertices are used; `tests/push_stability.rs` samples interior points to check that none is
//! worse.

use serde::Serialize;

use super::convex::{self, CheckOptions, CheckResult, Dim};
use super::model::{dot, PushModel, V2};

/// Intervals of the uncertain parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UncertaintySet {
    /// Floor friction interval of each body.
    pub mu_floor: Vec<[f64; 2]>,
    /// Friction interval of each contact.
    pub mu_contact: Vec<[f64; 2]>,
    /// Half extents (m, along the body axes) of each body's centre-of-friction rectangle around
    /// its nominal centre of friction.
    pub cof: Vec<V2>,
}

impl UncertaintySet {
    /// No uncertainty: every interval collapsed on the nominal value.
    pub fn nominal(model: &PushModel) -> UncertaintySet {
        UncertaintySet {
            mu_floor: model.bodies.iter().map(|b| [b.mu_floor; 2]).collect(),
            mu_contact: model.contacts.iter().map(|c| [c.mu; 2]).collect(),
            cof: vec![[0.0; 2]; model.k()],
        }
    }

    /// `±frac` relative intervals around every friction coefficient and a centre-of-friction
    /// rectangle of `±frac` of each half extent.
    pub fn relative(model: &PushModel, frac: f64) -> UncertaintySet {
        let f = frac.max(0.0);
        UncertaintySet {
            mu_floor: model
                .bodies
                .iter()
                .map(|b| [b.mu_floor * (1.0 - f), b.mu_floor * (1.0 + f)])
                .collect(),
            mu_contact: model
                .contacts
                .iter()
                .map(|c| [c.mu * (1.0 - f).max(0.0), c.mu * (1.0 + f)])
                .collect(),
            cof: model.bodies.iter().map(|b| [b.half[0] * f, b.half[1] * f]).collect(),
        }
    }
}

/// One vertex of the uncertainty set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobustCase {
    /// Floor friction of each body.
    pub mu_floor: Vec<f64>,
    /// Friction of each contact.
    pub mu_contact: Vec<f64>,
    /// Centre of friction of each body (plane, m).
    pub cof: Vec<V2>,
    /// True for the nominal parameters.
    pub nominal: bool,
}

/// Result of a robust check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobustResult {
    /// The check at the worst case (its margin is the robust margin).
    pub result: CheckResult,
    /// The worst case.
    pub worst: RobustCase,
    /// Nominal margin, for comparison.
    pub nominal_margin: Option<f64>,
    /// Number of cases solved.
    pub cases: usize,
}

/// The model with the parameters of one case.
pub fn apply(model: &PushModel, case: &RobustCase) -> PushModel {
    let mut m = model.clone();
    for (b, (&mu, &cof)) in m.bodies.iter_mut().zip(case.mu_floor.iter().zip(&case.cof)) {
        b.mu_floor = mu;
        b.cof = cof;
    }
    for (c, &mu) in m.contacts.iter_mut().zip(&case.mu_contact) {
        c.mu = mu;
    }
    m
}

/// The cases enumerated (nominal first).
pub fn cases(model: &PushModel, set: &UncertaintySet) -> Vec<RobustCase> {
    let lateral = model.left();
    let nominal = RobustCase {
        mu_floor: model.bodies.iter().map(|b| b.mu_floor).collect(),
        mu_contact: model.contacts.iter().map(|c| c.mu).collect(),
        cof: model.bodies.iter().map(|b| b.cof).collect(),
        nominal: true,
    };
    let mu_contact: Vec<f64> = set.mu_contact.iter().map(|iv| iv[0].max(0.0)).collect();
    // Per body: the distinct (mu_floor, cof) choices.
    let choices: Vec<Vec<(f64, V2)>> = model
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let [lo, hi] = set.mu_floor[i];
            let mus: Vec<f64> = if hi > lo { vec![lo, hi] } else { vec![lo] };
            let [ra, rb] = set.cof[i];
            let [a, bb] = b.axes;
            let corners: Vec<V2> = [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
                .iter()
                .map(|&(sa, sb)| {
                    [
                        b.cof[0] + sa * ra * a[0] + sb * rb * bb[0],
                        b.cof[1] + sa * ra * a[1] + sb * rb * bb[1],
                    ]
                })
                .collect();
            let proj = |p: &V2| dot(*p, lateral);
            let lo_c = *corners
                .iter()
                .min_by(|p, q| proj(p).total_cmp(&proj(q)))
                .expect("corners");
            let hi_c = *corners
                .iter()
                .max_by(|p, q| proj(p).total_cmp(&proj(q)))
                .expect("corners");
            let cofs: Vec<V2> = if ra > 0.0 || rb > 0.0 {
                vec![lo_c, hi_c]
            } else {
                vec![b.cof]
            };
            mus.iter().flat_map(|&m| cofs.iter().map(move |&c| (m, c))).collect()
        })
        .collect();
    let mut out = vec![nominal];
    let mut idx = vec![0usize; choices.len()];
    loop {
        out.push(RobustCase {
            mu_floor: idx.iter().enumerate().map(|(i, &k)| choices[i][k].0).collect(),
            mu_contact: mu_contact.clone(),
            cof: idx.iter().enumerate().map(|(i, &k)| choices[i][k].1).collect(),
            nominal: false,
        });
        let mut i = 0;
        while i < idx.len() {
            idx[i] += 1;
            if idx[i] < choices[i].len() {
                break;
            }
            idx[i] = 0;
            i += 1;
        }
        if i == idx.len() {
            break;
        }
    }
    out
}

/// Robust check: the minimum over [`cases`].
pub fn check(model: &PushModel, set: &UncertaintySet, dim: Dim, opts: &CheckOptions) -> RobustResult {
    let all = cases(model, set);
    let n = all.len();
    let mut worst: Option<(CheckResult, RobustCase)> = None;
    let mut nominal_margin = None;
    for case in all {
        let r = convex::check(&apply(model, &case), dim, opts);
        if case.nominal {
            nominal_margin = r.margin;
        }
        // An unstable case beats a stable one (a phase may fail by its travel with a margin
        // that no longer counts), then the smaller margin.
        let rank = |r: &CheckResult| (r.stable, r.margin.unwrap_or(f64::NEG_INFINITY));
        let better = match &worst {
            None => true,
            Some((w, _)) => {
                let ((sr, mr), (sw, mw)) = (rank(&r), rank(w));
                (!sr && sw) || (sr == sw && mr < mw)
            }
        };
        if better {
            worst = Some((r, case));
        }
    }
    let (result, worst) = worst.expect("at least the nominal case");
    RobustResult {
        result,
        worst,
        nominal_margin,
        cases: n,
    }
}

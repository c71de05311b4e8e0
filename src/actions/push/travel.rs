//! Phases judged by their travel (`docs/push_stability.md` §5.4).
//!
//! A phase whose line of action leaves its contact does not stick: the box turns about the
//! contact's end. When the phase lasts only a known, short distance (the back box closing the
//! gap to the box in front of it), what matters is how far the box turns and drifts sideways
//! over that distance, not that it would turn forever. The rates come from the quasi-static
//! model of a box pushed at a point (Lynch, Maekawa & Tanie 1992) with the ellipsoidal limit
//! surface of uniform floor pressure: twist `(v_n, v_e, ω) ∝ (f_n, f_e, m / c²)`, `c` the
//! friction radius (mean distance of the footprint from its centre of friction).

use serde::Serialize;

use super::model::{dot, PushModel, V2};

/// How far a box turns and drifts over a phase of finite travel whose line of action leaves its
/// contact segment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TravelCheck {
    /// Gap the phase closes (m).
    pub travel: f64,
    /// Distance the pusher moves meanwhile (m): the gap over the box's forward speed per unit
    /// pusher speed (a turning box advances slower than the finger).
    pub pusher_travel: f64,
    /// The box that turns (body index).
    pub body: usize,
    /// The contact end it turns about (plane, m).
    pub pivot: V2,
    /// Whether the finger sticks at the pivot (else it slides along the face).
    pub sticking: bool,
    /// Rotation per metre of pusher travel (rad/m).
    pub rotation_rate: f64,
    /// Lateral drift of the centre of friction per metre of pusher travel (m/m).
    pub drift_rate: f64,
    /// Rotation over the phase (rad).
    pub rotation: f64,
    /// Lateral drift over the phase (m).
    pub drift: f64,
    /// `max(rotation / max_rotation, drift / max_drift)`: the phase passes iff ≤ 1.
    pub usage: f64,
    /// Whether the phase passes.
    pub passes: bool,
}

/// Friction radius `c` of a rectangle with half extents `half` under uniform pressure: the mean
/// distance of its points from the centre, `I(p, q) / (p q)` with
/// `I = ⅙ [2 p q d + p³ ln((q + d)/p) + q³ ln((p + d)/q)]`, `d = √(p² + q²)`.
pub fn friction_radius(half: V2) -> f64 {
    let (p, q) = (half[0].abs(), half[1].abs());
    let (lo, hi) = (p.min(q), p.max(q));
    if lo <= 1e-12 * hi.max(f64::MIN_POSITIVE) {
        // A segment: mean distance of its points from its middle.
        return hi / 2.0;
    }
    let d = p.hypot(q);
    let i = (2.0 * p * q * d + p.powi(3) * ((q + d) / p).ln() + q.powi(3) * ((p + d) / q).ln()) / 6.0;
    i / (p * q)
}

/// Quasi-static twist of a box pushed at the point `(x, y)` (relative to its centre of friction,
/// in the contact frame: `x` along the contact normal, `y` along the contact face) by a pusher
/// moving with unit velocity `(vpn, vpt)` in the same frame, friction `mu` at the point, friction
/// radius `c`. Returns `(v_n, v_e, ω, sticking)`, or `None` when the pusher cannot drive the box
/// forward (jamming).
pub fn point_push_twist(c: f64, x: f64, y: f64, vpn: f64, vpt: f64, mu: f64) -> Option<(f64, f64, f64, bool)> {
    let c2 = c * c;
    let d = c2 + x * x + y * y;
    // Sticking: the box's contact point moves with the pusher.
    let a = (vpn * (c2 + x * x) + x * y * vpt) / d;
    let b = (vpt * (c2 + y * y) + x * y * vpn) / d;
    if a > 0.0 && b.abs() <= mu * a {
        return Some((a, b, (x * b - y * a) / c2, true));
    }
    // Sliding: the force on the friction cone's edge on the side sticking would need; scaled so
    // the contact point keeps the pusher's normal speed.
    let s = mu * b.signum();
    let den = c2 + y * y - x * y * s;
    if den <= 0.0 || vpn <= 0.0 {
        return None;
    }
    let l = vpn * c2 / den;
    Some((l, l * s, l * (x * s - y) / c2, false))
}

/// Judge phase `start..k` of `model` (a single box, the last) moving `travel` metres with its
/// pusher contact's line of action beyond end `end` (0 = `p0`, 1 = `p1`).
pub fn judge(
    model: &PushModel,
    contact: usize,
    end: usize,
    travel: f64,
    max_rotation: f64,
    max_drift: f64,
) -> TravelCheck {
    let c = &model.contacts[contact];
    let body = &model.bodies[c.front];
    let pivot = if end == 0 { c.p0 } else { c.p1() };
    let r = [pivot[0] - body.cof[0], pivot[1] - body.cof[1]];
    let (n, e) = (c.normal, c.dir);
    let u = model.u;
    let radius = friction_radius(body.half);
    let twist = point_push_twist(radius, dot(r, n), dot(r, e), dot(u, n), dot(u, e), c.mu);
    let (rate, drift_rate, advance, sticking) = match twist {
        Some((vn, ve, w, st)) => {
            let v = [vn * n[0] + ve * e[0], vn * n[1] + ve * e[1]];
            (w.abs(), dot(v, model.left()).abs(), dot(v, u), st)
        }
        None => (f64::INFINITY, f64::INFINITY, 0.0, false),
    };
    // A box that barely advances never closes its gap within any sensible finger travel.
    let pusher_travel = if advance > 0.05 {
        travel / advance
    } else {
        f64::INFINITY
    };
    let (rotation, drift) = (rate * pusher_travel, drift_rate * pusher_travel);
    let usage = (rotation / max_rotation).max(drift / max_drift);
    TravelCheck {
        travel,
        pusher_travel,
        body: c.front,
        pivot,
        sticking,
        rotation_rate: rate,
        drift_rate,
        rotation,
        drift,
        usage,
        passes: usage <= 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn friction_radius_of_a_square_is_the_known_mean_distance() {
        // Mean distance from the centre of the unit square: (√2 + ln(1 + √2)) / 6 ≈ 0.38260.
        let exact = (2f64.sqrt() + (1.0 + 2f64.sqrt()).ln()) / 6.0;
        assert!((friction_radius([0.5, 0.5]) - exact).abs() < 1e-12);
        // Midpoint quadrature of a 3:1 rectangle agrees.
        let (p, q, n) = (0.03, 0.01, 400);
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let x = -p + (i as f64 + 0.5) * 2.0 * p / n as f64;
                let y = -q + (j as f64 + 0.5) * 2.0 * q / n as f64;
                sum += x.hypot(y);
            }
        }
        assert!((friction_radius([p, q]) - sum / (n * n) as f64).abs() < 1e-7);
        assert!((friction_radius([0.02, 0.0]) - 0.01).abs() < 1e-15);
    }

    #[test]
    fn a_centred_push_goes_straight_and_an_offset_one_turns_away() {
        let (vn, ve, w, st) = point_push_twist(0.03, -0.05, 0.0, 1.0, 0.0, 0.5).unwrap();
        assert!(st && (vn - 1.0).abs() < 1e-12 && ve.abs() < 1e-12 && w.abs() < 1e-12);
        // Pushed left of centre (y > 0) along +n: turns clockwise (ω < 0), slower than the finger.
        let (vn, _, w, st) = point_push_twist(0.03, -0.05, 0.02, 1.0, 0.0, 0.5).unwrap();
        assert!(st && w < 0.0 && vn < 1.0);
        // The sticking rate in closed form: |ω| = |y| / (c² + x² + y²).
        assert!((w.abs() - 0.02 / (0.0009 + 0.0025 + 0.0004)).abs() < 1e-12);
        // Without friction the finger slides and the box turns faster per unit push.
        let (_, _, w0, st0) = point_push_twist(0.03, -0.05, 0.02, 1.0, 0.0, 0.0).unwrap();
        assert!(!st0 && w0.abs() > w.abs());
        assert!((w0.abs() - 0.02 / (0.0009 + 0.0004)).abs() < 1e-12);
    }
}

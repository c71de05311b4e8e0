//! Polygon geometry of the scenario: edges, penetration, gaps and the contact between two bodies.

use super::*;

pub(super) fn translate(pts: &[V2], u: V2, s: f64) -> Vec<V2> {
    pts.iter().map(|p| [p[0] + s * u[0], p[1] + s * u[1]]).collect()
}

/// Outward unit normals of a convex polygon's edges (counter-clockwise vertices; a two-point
/// "polygon" is a segment with both normals).
pub(super) fn edges(poly: &[V2]) -> Vec<(V2, V2, V2)> {
    let n = poly.len();
    (0..n)
        .filter_map(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy);
            (l > 0.0).then(|| (a, b, [dy / l, -dx / l]))
        })
        .collect()
}

/// Penetration depth of two convex polygons (≤ 0 when they do not overlap), by separating axes.
pub(super) fn penetration(a: &[V2], b: &[V2]) -> f64 {
    let mut depth = f64::INFINITY;
    for (_, _, n) in edges(a).into_iter().chain(edges(b)) {
        let pa = a.iter().map(|p| dot(*p, n));
        let pb = b.iter().map(|p| dot(*p, n));
        let (amin, amax) = pa.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        let (bmin, bmax) = pb.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        depth = depth.min(amax.min(bmax) - amin.max(bmin));
    }
    depth
}

/// Whether segment `[p, q]` passes through the interior of a convex polygon (shrunk by the
/// tolerance), by Cyrus–Beck clipping.
pub(super) fn segment_enters(poly: &[V2], p: V2, q: V2) -> bool {
    let d = [q[0] - p[0], q[1] - p[1]];
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (a, _, n) in edges(poly) {
        // Inside: dot(x − a, n) ≤ −TOL.
        let num = -TOL - dot([p[0] - a[0], p[1] - a[1]], n);
        let den = dot(d, n);
        if den.abs() < 1e-18 {
            if num < 0.0 {
                return false;
            }
        } else if den > 0.0 {
            hi = hi.min(num / den);
        } else {
            lo = lo.max(num / den);
        }
        if lo > hi {
            return false;
        }
    }
    true
}

/// Parameter `s` at which the ray `p + s d` crosses segment `[a, b]`.
pub(super) fn ray_hit(p: V2, d: V2, a: V2, b: V2) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = cross(d, e);
    if den.abs() < 1e-15 {
        return None;
    }
    let ap = [a[0] - p[0], a[1] - p[1]];
    let s = cross(ap, e) / den;
    let r = cross(ap, d) / den;
    (-1e-12..=1.0 + 1e-12).contains(&r).then_some(s)
}

/// Distance `back` must travel along `u` to touch `front` (None if it never does).
pub(super) fn gap_along(front: &[V2], back: &[V2], u: V2) -> Option<f64> {
    let mut best: Option<f64> = None;
    let mut consider = |s: f64| {
        if s >= -TOL {
            best = Some(best.map_or(s, |b: f64| b.min(s)));
        }
    };
    for &v in back {
        for (a, b, _) in edges(front) {
            if let Some(s) = ray_hit(v, u, a, b) {
                consider(s);
            }
        }
    }
    let mu = [-u[0], -u[1]];
    for &v in front {
        for (a, b, _) in edges(back) {
            if let Some(s) = ray_hit(v, mu, a, b) {
                consider(s);
            }
        }
    }
    best
}

/// The contact of two touching convex polygons, as `(p0, dir, len, normal)` with the normal the
/// direction of the force on `front` (out of `back`, into `front`): a shared edge segment when
/// two anti-parallel edges coincide, else a vertex on an edge (a point contact).
pub(super) fn touching(front: &[V2], back: &[V2]) -> Option<(V2, V2, f64, V2)> {
    let ef = edges(front);
    let eb = edges(back);
    for &(a, b, na) in &ef {
        for &(c, d, nb) in &eb {
            if dot(na, nb) > -(1.0 - 1e-9) {
                continue;
            }
            if (dot([c[0] - a[0], c[1] - a[1]], na)).abs() > TOL {
                continue;
            }
            let t = [b[0] - a[0], b[1] - a[1]];
            let l = t[0].hypot(t[1]);
            let t = [t[0] / l, t[1] / l];
            let (s0, s1): (f64, f64) = (0.0, l);
            let (r0, r1) = {
                let x = dot([c[0] - a[0], c[1] - a[1]], t);
                let y = dot([d[0] - a[0], d[1] - a[1]], t);
                (x.min(y), x.max(y))
            };
            let lo = s0.max(r0);
            let hi = s1.min(r1);
            if hi - lo > TOL {
                return Some(([a[0] + lo * t[0], a[1] + lo * t[1]], t, hi - lo, [-na[0], -na[1]]));
            }
        }
    }
    let on_edge = |p: V2, a: V2, b: V2, n: V2| {
        let t = [b[0] - a[0], b[1] - a[1]];
        let l2 = dot(t, t);
        let r = dot([p[0] - a[0], p[1] - a[1]], t) / l2;
        (dot([p[0] - a[0], p[1] - a[1]], n)).abs() <= TOL && (-1e-9..=1.0 + 1e-9).contains(&r)
    };
    for &v in back {
        for &(a, b, na) in &ef {
            if on_edge(v, a, b, na) {
                let n = [-na[0], -na[1]];
                return Some((v, [-n[1], n[0]], 0.0, n));
            }
        }
    }
    for &v in front {
        for &(c, d, nb) in &eb {
            if on_edge(v, c, d, nb) {
                return Some((v, [-nb[1], nb[0]], 0.0, nb));
            }
        }
    }
    None
}

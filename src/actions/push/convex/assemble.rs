//! Assembling the 2-D and 3-D programs (force columns, friction cones, moment rows) of a phase.

use super::*;

/// Smallest friction coefficient used in a cone: keeps `f_n ≥ 0` implied by the cone rows.
pub(super) const MU_MIN: f64 = 1e-9;

/// 2-D LP. Columns: per phase, per contact `(f_n, f_t, m)`; then `t`; then (slip) `σ_j`.
/// Rows: 3 balance rows per body; 4 inequality rows per contact (two cone edges, two segment
/// ends); the cap on `t`; (slip) `σ ≥ 0` and `t ≥ −T`.
pub(super) fn assemble_2d(ds: &[PhaseData], variant: Variant, mr: &MarginRows) -> Program {
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
pub(super) fn col3_contact(off: usize, j: usize, corner: usize) -> usize {
    15 * off + 12 * j + 3 * corner
}

/// Column of the floor normal `N` of body `i` of a phase of `n` bodies; `P`, `Q` follow.
pub(super) fn col3_floor(off: usize, n: usize, i: usize) -> usize {
    15 * off + 12 * n + 3 * i
}

/// Lateral half extent added (normalised) to the footprints of the bodies a tipping program
/// does not judge: their floor moments become free, so another box's tipping (its own program)
/// cannot make this one infeasible.
pub(super) const RELAX: f64 = T_CAP;

/// 3-D SOCP, the tipping program of body `tip` of each phase. Columns: per phase, 4 corners ×
/// `(f_n, f_e, f_z)` per contact, then `(N, P, Q)` per body; then `t`. Rows: 6 balance rows per
/// body; 2 lateral rows per contact and 5 floor rows per body; the cap on `t`; 2 sign rows per
/// corner (vertical friction only where `tip` tipping would produce it); then one 3-dimensional
/// second-order cone per corner.
pub(super) fn assemble_3d(ds: &[PhaseData], ext: f64, mr: &MarginRows, tip: usize) -> Program {
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

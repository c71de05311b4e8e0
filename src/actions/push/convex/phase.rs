//! Deciding one phase: its program, and the contact and floor forces read back from the solution.

use super::*;

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
pub(super) fn phase_2d(d: &PhaseData) -> PhaseResult {
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
pub(super) fn contact_forces(d: &PhaseData, dim: Dim, x: &[f64], ext: f64) -> Vec<ContactForce> {
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
pub(super) fn floor_force(d: &PhaseData, x: &[f64], i: usize) -> FloorForce {
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

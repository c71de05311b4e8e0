//! The questions a caller asks: is a push stable, with what margin, for a line or a model.

use super::*;

pub(super) fn key(m: Option<f64>) -> f64 {
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
pub(super) fn judge_travel(
    model: &PushModel,
    p: &PhaseResult,
    travel: f64,
    dim: Dim,
    opts: &CheckOptions,
) -> Option<TravelCheck> {
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
pub(super) fn tip_margin(d: &PhaseData, i: usize) -> Option<(Vec<f64>, f64, bool)> {
    let one = std::slice::from_ref(d);
    match optimise(one, Dim::D3, 0.0, i) {
        Ok((x, t)) => Some((x, t, false)),
        Err(_) => optimise(one, Dim::D3, EXTEND, i).ok().map(|(x, t)| (x, t, true)),
    }
}
/// The clarabel 2-D margin of a planner line (see [`crate::actions::push::geometry_margin`]): every phase in
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

/// The planner's verdict on a line whose gaps are known (see
/// [`crate::actions::push::geometry_verdict`]), cached by every input.
///
/// A phase can only be excused by its travel when the back box closes a finite gap alone and
/// falls short of the required margin. Otherwise the verdict is the unlimited-travel margin of
/// [`line_margin_2d`], bit for bit, so lines the rule does not touch keep their margins. When it
/// may apply, the line is checked like a `push-check` scenario: [`check`] on the model with the
/// boxes' real depths and the finger's friction ([`model_of_travel_line`]), with the required
/// margin as the tolerance below which a phase is judged by its travel.
pub fn line_verdict_2d(line: &LineGeometry, t: &LineTravel) -> LineVerdict {
    let k = line.lateral.len();
    let flags: Vec<bool> = t.gaps.iter().map(|&g| g > crate::geometry::EPS).collect();
    let unlimited = line_margin_2d(line, &flags);
    let back_alone = k >= 2 && flags.get(k - 2).copied().unwrap_or(false);
    // A NaN margin is never "enough": it goes on to the full check, which reports it.
    if !back_alone || unlimited > t.min_margin {
        return LineVerdict {
            margin: unlimited,
            travel: None,
        };
    }
    let mut key: Vec<u64> = Vec::with_capacity(6 * k + 8);
    key.push(k as u64);
    for m in 0..k {
        key.extend([
            line.lateral[m][0].to_bits(),
            line.lateral[m][1].to_bits(),
            line.weight[m].to_bits(),
            t.depth.get(m).copied().unwrap_or(f64::NAN).to_bits(),
        ]);
    }
    key.extend(t.gaps.iter().map(|g| g.to_bits()));
    key.extend(
        [
            line.pusher[0],
            line.pusher[1],
            t.mu_finger,
            t.max_rotation,
            t.max_drift,
            t.min_margin,
        ]
        .map(f64::to_bits),
    );
    if let Some(v) = VERDICT_CACHE.with(|c| c.borrow().get(&key).cloned()) {
        return v;
    }
    let model = model_of_travel_line(line, t);
    let opts = CheckOptions {
        tol: t.min_margin,
        max_rotation: t.max_rotation,
        max_drift: t.max_drift,
        ..CheckOptions::default()
    };
    let r = check(&model, Dim::D2, &opts);
    let v = match r.phases.iter().find_map(|p| p.travel.clone()) {
        Some(tc) => LineVerdict {
            margin: r.margin.unwrap_or(f64::NEG_INFINITY),
            travel: Some(tc),
        },
        // Nothing judged by its travel: the unlimited rule's margin, as computed without it.
        None => LineVerdict {
            margin: unlimited,
            travel: None,
        },
    };
    VERDICT_CACHE.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() >= CACHE_CAP {
            c.clear();
        }
        c.insert(key, v.clone());
    });
    v
}

/// [`model_of_line`] with what the travel rule needs: each box's depth along `u` (the back box's
/// friction radius and the finger's lever arm about its centre), the finger's friction at the
/// back box, and each phase's travel (the gap in front of its front box; the last phase
/// unlimited). The boxes stand closed up, front box centred at the origin; the 2-D margins do not
/// depend on the depths (every contact normal is along `u`, so no tangential force and no lever
/// arm along `u` enters, §2), and box–box friction stays 1 for the same reason.
pub fn model_of_travel_line(line: &LineGeometry, t: &LineTravel) -> PushModel {
    let k = line.lateral.len();
    let flags: Vec<bool> = t.gaps.iter().map(|&g| g > crate::geometry::EPS).collect();
    let mut model = model_of_line(line, &flags);
    let mut x = 0.0;
    for m in 0..k {
        let depth = t.depth.get(m).copied().unwrap_or(0.0);
        if m > 0 {
            x -= (t.depth.get(m - 1).copied().unwrap_or(0.0) + depth) / 2.0;
        }
        let b = &mut model.bodies[m];
        b.centre[0] = x;
        b.cof[0] = x;
        b.half[0] = depth / 2.0;
        model.contacts[m].p0[0] = x - depth / 2.0;
    }
    if let Some(c) = model.contacts.last_mut() {
        c.mu = t.mu_finger;
    }
    model.phase_travel = model
        .phase_starts
        .iter()
        .map(|&s| if s == 0 { f64::INFINITY } else { t.gaps[s - 1] })
        .collect();
    model
}

/// Clear this thread's geometry caches and solver table (for benchmarks and tests).
pub fn clear_caches() {
    LINE_CACHE.with(|c| c.borrow_mut().clear());
    VERDICT_CACHE.with(|c| c.borrow_mut().clear());
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

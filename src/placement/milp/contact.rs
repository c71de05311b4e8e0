//! The contact stage: maximum contact length among minimum-area placements, by enumeration with the grid MILP for what it leaves open.

use super::*;

/// Second stage on the normal-pattern grid: maximise contact length inside extents `(w, d)`
/// with BL-stability as constraints. Boundaries are cut into segments between consecutive grid
/// coordinates; on each segment of each grid line, `L` (a footprint's low edge lies there) and
/// `R` (a footprint's high edge lies there) are sums of binaries, at most 1 by non-overlap, and
/// a contact variable `c ≤ L, c ≤ R` earns the segment length (walls earn `L` or `R` directly).
/// Exact: every BL-stable placement has grid coordinates.
pub(super) fn grid_contact_stage(
    inst: &Instance,
    fps: &[Footprints],
    (w, d): (f64, f64),
    warm: Option<&Placement>,
    time_left: f64,
    seed: u64,
    options: &[(String, String)],
) -> Result<Option<(Placement, bool, u64)>> {
    let mut cols = Cols {
        pv: ProblemVariables::new(),
        n: 0,
    };
    let Some(mut m) = GridModel::build(inst, fps, w, d, &mut cols) else {
        return Ok(None);
    };
    m.constraints.push(Expression::from(m.depth.0).leq(d));
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let (xs, ys) = GridModel::axes(fps, w, d);
    let dims = |g: usize, k: usize| fps[m.groups[g][0]][k].size;
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-7;
    let mut objective = Expression::from(0.0);
    // contact[(axis, line index, segment index)] = variable, for the BL-stability rows.
    let mut contact: std::collections::HashMap<(usize, usize, usize), Variable> = std::collections::HashMap::new();
    for axis in 0..2 {
        // axis 0: vertical lines x = const, segments along y; axis 1: horizontal lines.
        let (lines, segs, wall_hi) = if axis == 0 {
            (&xs, &ys, (w >= cw - EPS).then_some(cw))
        } else {
            (&ys, &xs, (d >= cd - EPS).then_some(cd))
        };
        for (li, &line) in lines.iter().enumerate() {
            for si in 0..segs.len().saturating_sub(1) {
                let (s0, s1) = (segs[si], segs[si + 1]);
                let mut lo_edge: Vec<Variable> = Vec::new();
                let mut hi_edge: Vec<Variable> = Vec::new();
                for &(g, k, x, y, v, _) in &m.vars {
                    let f = dims(g, k);
                    let (p0, ext, q0, len) = if axis == 0 {
                        (x, f[0], y, f[1])
                    } else {
                        (y, f[1], x, f[0])
                    };
                    if q0 <= s0 + 1e-9 && q0 + len >= s1 - 1e-9 {
                        if near(p0, line) {
                            lo_edge.push(v);
                        }
                        if near(p0 + ext, line) {
                            hi_edge.push(v);
                        }
                    }
                }
                let seg = s1 - s0;
                if line.abs() <= 1e-9 {
                    let e: Expression = lo_edge.iter().copied().sum();
                    objective += seg * e;
                } else if wall_hi.map(|h| near(line, h)).unwrap_or(false) {
                    let e: Expression = hi_edge.iter().copied().sum();
                    objective += seg * e;
                } else if !lo_edge.is_empty() && !hi_edge.is_empty() {
                    let (c, _) = cols.add(variable().min(0.0).max(1.0));
                    let l: Expression = lo_edge.iter().copied().sum();
                    let r: Expression = hi_edge.iter().copied().sum();
                    m.constraints.push((c - l).leq(0.0));
                    m.constraints.push((c - r).leq(0.0));
                    objective += seg * c;
                    contact.insert((axis, li, si), c);
                }
            }
        }
    }
    // BL-stability: a chosen footprint not on the low wall touches something along its low edge.
    for &(g, k, x, y, v, _) in &m.vars {
        let f = dims(g, k);
        for axis in 0..2 {
            let (p0, q0, len, lines, segs) = if axis == 0 {
                (x, y, f[1], &xs, &ys)
            } else {
                (y, x, f[0], &ys, &xs)
            };
            if p0.abs() <= 1e-9 {
                continue;
            }
            let Some(li) = lines.iter().position(|&l| near(l, p0)) else {
                continue;
            };
            let support: Expression = (0..segs.len().saturating_sub(1))
                .filter(|&si| q0 <= segs[si] + 1e-9 && q0 + len >= segs[si + 1] - 1e-9)
                .filter_map(|si| contact.get(&(axis, li, si)).copied())
                .sum();
            m.constraints.push((Expression::from(v) - support).leq(0.0));
        }
    }
    let init = warm.and_then(|p| m.initial(fps, p, cols.n)).map(|mut v| {
        // Contact variables start at 0; HiGHS repairs a partial start when it can.
        v.resize(cols.n, 0.0);
        v
    });
    let mut problem = cols.pv.maximise(objective).using(highs);
    for c in m.constraints.iter().cloned() {
        problem = problem.with(c);
    }
    let solved = run_highs(
        problem,
        &HighsRun {
            initial: init.as_deref(),
            time_left,
            seed,
            abs_gap: 1e-9,
            presolve: false,
            options,
        },
    )?;
    let Some(c) = solved.cols.as_deref() else {
        return Ok(None);
    };
    let q = m.extract(fps, inst.n(), c);
    if !q.violations(inst).is_empty() {
        return Ok(None);
    }
    Ok(Some((q, solved.status == HighsModelStatus::Optimal, solved.nodes)))
}

/// Second stage: maximise contact length inside the extents of `p`, BL-stable, warm-started
/// with `p`. Returns the placement, whether it is proven optimal, and HiGHS nodes.
///
/// Long on purpose: it writes one MILP in one pass over the objects (wall contacts, pair
/// contacts with their indicators, Bottom-Left stability, the warm start), as
/// [`super::model`] does for the area model; the pieces share the column bookkeeping.
pub(super) fn contact_stage(
    inst: &Instance,
    fps: &[Footprints],
    p: &Placement,
    time_left: f64,
    seed: u64,
    options: &[(String, String)],
) -> Result<Option<(Placement, bool, u64)>> {
    let (w, d) = p.extent();
    let (cw, cd) = (inst.container.width, inst.container.depth);
    let n = inst.n();
    let mut cols = Cols {
        pv: ProblemVariables::new(),
        n: 0,
    };
    let Some(mut m) = PlacementModel::build(inst, fps, w, d, &mut cols) else {
        return Ok(None);
    };
    m.constraints.push(Expression::from(m.depth.0).leq(d));
    let big = cw.max(cd);
    let eps = 1e-5;
    let mut objective = Expression::from(0.0);
    let mut init_extra: Vec<(usize, f64)> = Vec::new();
    // Wall contacts: left (x = 0), front (y = 0), right (x = cw), back (y = cd).
    let mut left_wall = Vec::new();
    let mut front_wall = Vec::new();
    for i in 0..n {
        let t = p.targets[i].rect;
        let walls: [(bool, bool); 4] = [
            (true, t.x0.abs() <= EPS),
            (true, t.y0.abs() <= EPS),
            (w >= cw - EPS, (t.x1 - cw).abs() <= EPS),
            (d >= cd - EPS, (t.y1 - cd).abs() <= EPS),
        ];
        for (side, (possible, now)) in walls.iter().enumerate() {
            if !possible {
                if side == 0 {
                    left_wall.push(None);
                }
                if side == 1 {
                    front_wall.push(None);
                }
                continue;
            }
            let (z, zc) = cols.add(variable().binary());
            init_extra.push((zc, if *now { 1.0 } else { 0.0 }));
            let wi = m.width(fps, i);
            let di = m.depth_of(fps, i);
            match side {
                0 => m.constraints.push(Expression::from(m.x[i].0).leq(big * (1.0 - z))),
                1 => m.constraints.push(Expression::from(m.y[i].0).leq(big * (1.0 - z))),
                2 => m.constraints.push((m.x[i].0 + wi).geq(cw - big * (1.0 - z))),
                _ => m.constraints.push((m.y[i].0 + di).geq(cd - big * (1.0 - z))),
            }
            // Contact length = the face length times z: u_k ≤ s_k, u_k ≤ z.
            for (k, Footprint { size: f, .. }) in fps[i].iter().enumerate() {
                let (u, uc) = cols.add(variable().min(0.0).max(1.0));
                let on = *now && (f[0] - t.width()).abs() <= EPS && (f[1] - t.depth()).abs() <= EPS;
                init_extra.push((uc, if on { 1.0 } else { 0.0 }));
                m.constraints.push(Expression::from(u).leq(m.s[i][k].0));
                m.constraints.push(Expression::from(u).leq(z));
                let len = if side % 2 == 0 { f[1] } else { f[0] };
                objective += len * u;
            }
            if side == 0 {
                left_wall.push(Some(z));
            }
            if side == 1 {
                front_wall.push(Some(z));
            }
        }
    }
    // Object contacts: touch[a][b][axis] = a's high face meets b's low face along axis.
    let mut supports_x: Vec<Vec<Variable>> = vec![Vec::new(); n];
    let mut supports_y: Vec<Vec<Variable>> = vec![Vec::new(); n];
    for a in 0..n {
        for b in 0..n {
            if a == b {
                continue;
            }
            for axis in [Axis2::X, Axis2::Y] {
                let (ta, tb) = (p.targets[a].rect, p.targets[b].rect);
                let now_touch = (ta.hi(axis) - tb.lo(axis)).abs() <= EPS;
                let now_ov = if now_touch {
                    ta.overlap_on(&tb, axis.other()).max(0.0)
                } else {
                    0.0
                };
                let (t, tc) = cols.add(variable().binary());
                let (ov, oc) = cols.add(variable().min(0.0).max(big));
                init_extra.push((tc, if now_touch && now_ov > eps { 1.0 } else { 0.0 }));
                init_extra.push((oc, if now_touch && now_ov > eps { now_ov } else { 0.0 }));
                // Along `axis`: positions p and extents l; across it: positions q and extents m.
                let (pa, pb, la, qa, qb, ma, mb) = match axis {
                    Axis2::X => (
                        m.x[a].0,
                        m.x[b].0,
                        m.width(fps, a),
                        m.y[a].0,
                        m.y[b].0,
                        m.depth_of(fps, a),
                        m.depth_of(fps, b),
                    ),
                    Axis2::Y => (
                        m.y[a].0,
                        m.y[b].0,
                        m.depth_of(fps, a),
                        m.x[a].0,
                        m.x[b].0,
                        m.width(fps, a),
                        m.width(fps, b),
                    ),
                };
                // Touch: pa + la = pb when t = 1.
                m.constraints.push((pa + la.clone() - pb).leq(big * (1.0 - t)));
                m.constraints.push((pb - pa - la).leq(big * (1.0 - t)));
                // Overlap along the other axis: ov ≤ min(qa+ma, qb+mb) − max(qa, qb), ov ≤ big·t.
                m.constraints.push((ov + qb - qa - ma.clone()).leq(big * (1.0 - t)));
                m.constraints.push((ov + qa - qb - mb.clone()).leq(big * (1.0 - t)));
                m.constraints.push((ov - ma).leq(0.0));
                m.constraints.push((ov - mb).leq(0.0));
                m.constraints.push(Expression::from(ov).leq(big * t));
                m.constraints.push((ov - eps * t).geq(0.0));
                objective += ov;
                match axis {
                    Axis2::X => supports_x[b].push(t),
                    Axis2::Y => supports_y[b].push(t),
                }
            }
        }
    }
    // BL-stability: each object touches the wall or an object on its −x and −y sides.
    for i in 0..n {
        let sx: Expression =
            supports_x[i].iter().copied().sum::<Expression>() + left_wall[i].map(Expression::from).unwrap_or_default();
        let sy: Expression =
            supports_y[i].iter().copied().sum::<Expression>() + front_wall[i].map(Expression::from).unwrap_or_default();
        m.constraints.push(sx.geq(1.0));
        m.constraints.push(sy.geq(1.0));
    }
    let ncols = cols.n;
    let mut init = initial_columns(fps, &m, p, ncols);
    init[m.depth.1] = d;
    for (c, v) in init_extra {
        init[c] = v;
    }
    let mut problem = cols.pv.maximise(objective).using(highs);
    for c in m.constraints.iter().cloned() {
        problem = problem.with(c);
    }
    let solved = run_highs(
        problem,
        &HighsRun {
            initial: Some(&init),
            time_left,
            seed,
            abs_gap: 1e-9,
            presolve: true,
            options,
        },
    )?;
    let Some(c) = solved.cols.as_deref() else {
        return Ok(None);
    };
    let q = extract(inst, fps, &m, c);
    let ok = q.violations(inst).is_empty() && q.occupied_area() <= p.occupied_area() + 1e-9;
    if !ok {
        return Ok(None);
    }
    let better = q.contact_length(inst) >= p.contact_length(inst) - 1e-9;
    let optimal = solved.status == HighsModelStatus::Optimal;
    Ok(Some((
        if better { q } else { p.clone() },
        optimal && better,
        solved.nodes,
    )))
}

//! Running HiGHS on a model: options, warm start, node count, and reading the placement back.

use super::*;

/// Outcome of one HiGHS run.
pub(super) struct Solved {
    pub(super) status: HighsModelStatus,
    pub(super) cols: Option<Vec<f64>>,
    pub(super) nodes: u64,
}

/// How to run HiGHS on one model.
pub(super) struct HighsRun<'a> {
    /// Solution to start from (column values).
    pub(super) initial: Option<&'a [f64]>,
    /// Seconds HiGHS may take.
    pub(super) time_left: f64,
    /// HiGHS's random seed.
    pub(super) seed: u64,
    /// `mip_abs_gap`.
    pub(super) abs_gap: f64,
    /// Presolve on.
    pub(super) presolve: bool,
    /// The user's extra options ([`MilpSettings::highs_options`]), set last.
    pub(super) options: &'a [(String, String)],
}

/// Solve `problem` with HiGHS. Every failure of HiGHS — an option it rejects, a run that returns
/// an error status — is [`Error::Solver`] naming what failed, never a model status: only a
/// model status HiGHS reports is read as a proof.
pub(super) fn run_highs(problem: good_lp::solvers::highs::HighsProblem, run: &HighsRun) -> Result<Solved> {
    let HighsRun {
        initial,
        time_left,
        seed,
        abs_gap,
        presolve,
        options,
    } = *run;
    let mut model = problem.try_into_inner().map_err(|e| Error::Solver {
        solver: "HiGHS".into(),
        reason: format!("could not build the model: {e}"),
    })?;
    model.make_quiet();
    model.set_option("time_limit", time_left.max(0.01));
    model.set_option("mip_rel_gap", 0.0);
    model.set_option("mip_abs_gap", abs_gap);
    model.set_option("random_seed", (seed % i32::MAX as u64) as i32);
    model.set_option("threads", 1);
    if !presolve {
        model.set_option("presolve", "off");
    }
    for (name, value) in options {
        // HiGHS parses the string into the option's type and checks its range itself.
        model
            .try_set_option(name.as_str(), value.as_str())
            .map_err(|_| Error::Solver {
                solver: "HiGHS".into(),
                reason: format!("option {name} = {value:?} rejected (status Error: unknown option or illegal value)"),
            })?;
    }
    if let Some(sol) = initial {
        model.set_solution(Some(sol), None, None, None);
    }
    let solved = model.try_solve().map_err(|e| Error::Solver {
        solver: "HiGHS".into(),
        reason: if options.is_empty() {
            format!("the run returned status {e:?}")
        } else {
            let set: Vec<String> = options.iter().map(|(n, v)| format!("{n} = {v:?}")).collect();
            format!("the run returned status {e:?} (extra options: {})", set.join(", "))
        },
    })?;
    let status = solved.status();
    let has_sol = solved.primal_solution_status() == highs::HighsSolutionStatus::Feasible;
    let cols = if has_sol {
        Some(solved.get_solution().columns().to_vec())
    } else {
        None
    };
    let nodes = mip_node_count(&solved);
    Ok(Solved { status, cols, nodes })
}

/// HiGHS's branch-and-bound node count (an int64 info value the `highs` crate does not read).
pub(super) fn mip_node_count(solved: &highs::SolvedModel) -> u64 {
    let mut v: i64 = 0;
    // SAFETY: `solved` owns a live HiGHS instance for the duration of the call, the name is a
    // NUL-terminated C string, and `v` is a valid, writable i64 as the C API requires.
    let status = unsafe { highs_sys::Highs_getInt64InfoValue(solved.as_ptr(), c"mip_node_count".as_ptr(), &mut v) };
    if status == highs_sys::STATUS_OK {
        v.max(0) as u64
    } else {
        0
    }
}

/// Read a placement from a solved column vector.
pub(super) fn extract(inst: &Instance, fps: &[Footprints], m: &PlacementModel, cols: &[f64]) -> Placement {
    let targets = (0..inst.n())
        .map(|i| {
            let k = m.s[i]
                .iter()
                .enumerate()
                .max_by(|a, b| cols[a.1 .1].total_cmp(&cols[b.1 .1]))
                .map(|(k, _)| k)
                .expect("at least one orientation");
            let Footprint {
                size: f,
                orientation: q,
                height: h,
            } = fps[i][k];
            // Snap to the 0.1 µm grid: MILP solutions carry solver tolerances.
            let snap = |v: f64| (v * 1e7).round() / 1e7;
            Target {
                orientation: q,
                rect: Rect::new(snap(cols[m.x[i].1]).max(0.0), snap(cols[m.y[i].1]).max(0.0), f[0], f[1]),
                height: h,
            }
        })
        .collect();
    Placement { targets }
}

/// Column vector of a known placement for the model (warm start).
pub(super) fn initial_columns(fps: &[Footprints], m: &PlacementModel, p: &Placement, ncols: usize) -> Vec<f64> {
    let mut v = vec![0.0; ncols];
    for (i, t) in p.targets.iter().enumerate() {
        for ((_, c), Footprint { size: f, .. }) in m.s[i].iter().zip(&fps[i]) {
            if (f[0] - t.rect.width()).abs() <= EPS && (f[1] - t.rect.depth()).abs() <= EPS {
                v[*c] = 1.0;
                break;
            }
        }
        v[m.x[i].1] = t.rect.x0;
        v[m.y[i].1] = t.rect.y0;
    }
    for (i, j, b) in &m.pairs {
        let (a, c) = (p.targets[*i].rect, p.targets[*j].rect);
        let rel = [
            a.x1 <= c.x0 + EPS,
            c.x1 <= a.x0 + EPS,
            a.y1 <= c.y0 + EPS,
            c.y1 <= a.y0 + EPS,
        ];
        for k in 0..4 {
            if let (Some((_, col)), true) = (b[k], rel[k]) {
                v[col] = 1.0;
                break;
            }
        }
    }
    v[m.depth.1] = p.extent().1;
    v
}

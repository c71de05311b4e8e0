//! The exact placement: the area stage, then the contact stage, with the report of both.

use super::*;

/// Slide every object down and left until none moves: the result is BL-stable and its extents
/// are no larger.
pub fn compact(p: &Placement) -> Placement {
    let mut t = p.targets.clone();
    for _ in 0..10_000 {
        let mut moved = false;
        let mut order: Vec<usize> = (0..t.len()).collect();
        order.sort_by(|&a, &b| (t[a].rect.y0 + t[a].rect.x0).total_cmp(&(t[b].rect.y0 + t[b].rect.x0)));
        for &i in &order {
            let r = t[i].rect;
            let down = t
                .iter()
                .enumerate()
                .filter(|(j, o)| *j != i && o.rect.overlap_on(&r, Axis2::X) > EPS && o.rect.y1 <= r.y0 + EPS)
                .map(|(_, o)| o.rect.y1)
                .fold(0.0, f64::max);
            let r2 = Rect::new(r.x0, down, r.width(), r.depth());
            let left = t
                .iter()
                .enumerate()
                .filter(|(j, o)| *j != i && o.rect.overlap_on(&r2, Axis2::Y) > EPS && o.rect.x1 <= r2.x0 + EPS)
                .map(|(_, o)| o.rect.x1)
                .fold(0.0, f64::max);
            let r3 = Rect::new(left, down, r.width(), r.depth());
            if (r3.x0 - r.x0).abs() > EPS || (r3.y0 - r.y0).abs() > EPS {
                t[i].rect = r3;
                moved = true;
            }
        }
        if !moved {
            break;
        }
    }
    Placement { targets: t }
}

/// Minimise the occupied area exactly (then maximise contact). `warm` only seeds the
/// incumbent: an empty or invalid warm placement changes nothing but speed.
pub fn solve(
    inst: &Instance,
    warm: &PlacementResult,
    settings: &MilpSettings,
    stop: &dyn Terminator,
) -> Result<PlacementResult> {
    solve_report(inst, warm, settings, stop).map(|(r, _)| r)
}

/// What [`solve_report`] did besides its result.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MilpReport {
    /// Proven lower bound and incumbent area over time.
    pub trace: Vec<BoundPoint>,
    /// Seconds in the area stage (boxes by area, exact packing search).
    pub area_stage_s: f64,
    /// Seconds in the contact stage (enumeration, then HiGHS).
    pub contact_stage_s: f64,
    /// Enclosing boxes decided, and how many of them needed the exact search.
    pub boxes: u64,
    /// Boxes decided by the exact search rather than by bounds or dominance.
    pub boxes_searched: u64,
    /// Seconds of the contact stage spent enumerating packings.
    pub contact_enumeration_s: f64,
    /// Seconds of the contact stage spent in HiGHS (the grid or disjunctive contact MILP).
    pub contact_milp_s: f64,
    /// Extents whose contact optimum the enumeration proved.
    pub contact_proofs_by_enumeration: u64,
    /// Extents whose contact optimum HiGHS proved.
    pub contact_proofs_by_milp: u64,
    /// The area is proven minimal.
    pub area_optimal: bool,
    /// The contact length is proven maximal among area-optimal placements.
    pub contact_optimal: bool,
    /// An upper bound on the contact length (m) of every BL-stable placement of the optimal
    /// area: the contact found when the contact stage proved it, else what the searches
    /// stopped early can still promise (the bounds of the parts they did not finish). `None`
    /// when the area is not proven minimal, when boxes of that area were left undecided, or
    /// without a contact stage.
    pub contact_upper_bound: Option<f64>,
}

/// [`solve`], with the bound-over-time trace and the cost of each stage.
pub fn solve_report(
    inst: &Instance,
    warm: &PlacementResult,
    settings: &MilpSettings,
    stop: &dyn Terminator,
) -> Result<(PlacementResult, MilpReport)> {
    solve_listen(inst, warm, settings, stop, &mut Silent)
}

/// [`solve_report`], telling `listener` how the search goes: [`crate::control::Event::Progress`]
/// with the nodes so far (the warm start's included), the incumbent's occupied area (m²) and the
/// proven lower bound on it, at most one per [`crate::control::PROGRESS_INTERVAL`], from inside
/// the packing searches of both stages. The bound only rises and never passes the incumbent.
///
/// Long on purpose: the area stage, then one contact stage per optimal extent (enumeration
/// first, a MILP with what is left), under one deadline, one node meter and one report. Each
/// part is a call ([`area::solve`], [`area::max_contact`], `grid_contact_stage`,
/// `contact_stage`); what stays here is the budget and the bookkeeping between them.
pub fn solve_listen(
    inst: &Instance,
    warm: &PlacementResult,
    settings: &MilpSettings,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> Result<(PlacementResult, MilpReport)> {
    settings.check_highs_options("<settings>", "highs_options")?;
    let start = Instant::now();
    let left = |s: &MilpSettings| s.time_limit - start.elapsed().as_secs_f64();
    let fps = footprints(inst);
    let progress = Progress::new(listener, warm.nodes);
    // Every search polls this now and then: the place to send a progress event.
    let halt = || {
        progress.tick();
        stop.should_stop() || left(settings) <= 0.0
    };
    let warm_p = (!warm.placement.targets.is_empty()).then_some(&warm.placement);
    let search_master = |items: &[Item], w: f64, d: f64, stop: &dyn Fn() -> bool| {
        let base = progress.nodes.get();
        let (r, n) = crate::placement::opp::decide_metered(items, w, d, stop, Some(&progress.nodes), settings.threads);
        progress.reach_nodes(base + n);
        Ok((r, n))
    };
    let highs_master = |items: &[Item], w: f64, d: f64, stop: &dyn Fn() -> bool| {
        let (r, n) = benders::decide_benders(items, w, d, stop, &|| left(settings), &settings.highs_options)?;
        progress.reach_nodes(progress.nodes.get() + n);
        Ok((r, n))
    };
    let decider: &area::Decider = match settings.area_master {
        AreaMaster::Search => &search_master,
        AreaMaster::Highs => &highs_master,
    };
    // Without a warm start, a quarter of the limit may go to finding any packing at all.
    let area_opts = area::AreaOptions {
        contact: settings.contact_stage,
        start,
        budget_first_s: settings.time_limit * 0.25,
        decider,
        on_bound: &|lb, inc| progress.set(lb, inc),
    };
    let area = area::solve(inst, &fps, warm_p, &area_opts, &halt)?;
    let area_stage_s = start.elapsed().as_secs_f64();
    let mut report = MilpReport {
        trace: area.trace.clone(),
        area_stage_s,
        boxes: area.boxes,
        boxes_searched: area.boxes_searched,
        area_optimal: area.optimal,
        ..MilpReport::default()
    };
    if area.infeasible {
        return Err(Error::Infeasible {
            reason: format!(
                "the objects fit in no box inside the {} × {} container: every enclosing box was refuted by bounds or an exhaustive search ({} boxes)",
                inst.container.width, inst.container.depth, area.boxes
            ),
        });
    }
    let Some(mut best) = area.best.clone() else {
        return Err(Error::Stopped {
            stage: "placement (milp)".into(),
            limit: crate::status::Limit::Time,
            nodes: area.nodes,
            elapsed_s: area_stage_s,
            min_actions: None,
        });
    };
    let best_area = best.occupied_area();
    let area_optimal = area.optimal;
    let ties_closed = area.ties_closed;
    let lower_bound = area.lower_bound;
    let solutions = area.solutions;
    let mut milps = 0u64;
    let mut nodes = warm.nodes + area.nodes;
    // Every object's footprints closed under swapping x and y: a placement transposes.
    let transposable = fps.iter().all(|o| {
        o.iter().all(|Footprint { size: f, .. }| {
            o.iter()
                .any(|Footprint { size: g, .. }| (g[0] - f[1]).abs() <= EPS && (g[1] - f[0]).abs() <= EPS)
        })
    });
    let mut contact_optimal = false;
    // The contact stage keeps the area: its events show the area's incumbent and bound.
    progress.reach_nodes(nodes);
    progress.set(if area_optimal { best_area } else { lower_bound }, Some(best_area));
    if settings.contact_stage && left(settings) > 0.0 && !stop.should_stop() {
        // Every distinct extent pair reaching the optimal area gets its own contact stage.
        let mut extents: Vec<(f64, f64)> = Vec::new();
        for p in &solutions {
            let e = p.extent();
            if e.0 * e.1 <= best_area + AREA_TOL
                && !extents
                    .iter()
                    .any(|f| (f.0 - e.0).abs() <= 1e-9 && (f.1 - e.1).abs() <= 1e-9)
            {
                extents.push(e);
            }
        }
        let mut all_optimal = area_optimal && ties_closed;
        let mut best_contact = best.contact_length(inst);
        // The most contact the extents' unfinished searches can still hold.
        let mut open = f64::NEG_INFINITY;
        // An extent that gets no search at all still has its bound from the split alone.
        let bound_only = |e: (f64, f64)| area::max_contact(inst, &fps, e, f64::INFINITY, &|| true, None, 1).3;
        // The high walls earn contact only where the extent reaches them; with those matched,
        // the contact stage of `(d, w)` is the transpose of that of `(w, d)`.
        let (cw, cd) = (inst.container.width, inst.container.depth);
        let walls_transpose =
            |(w, d): (f64, f64)| (w >= cw - EPS) == (w >= cd - EPS) && (d >= cd - EPS) == (d >= cw - EPS);
        let mut done: Vec<((f64, f64), bool)> = Vec::new();
        for e in extents {
            if left(settings) <= 0.0 || stop.should_stop() {
                all_optimal = false;
                open = open.max(bound_only(e));
                continue;
            }
            // A transposed extent already solved has the same optimum, reached by the transposed
            // placement; that ties with a contact already taken into `best_contact`, and only a
            // strictly larger one replaces `best`, so the stage would change nothing.
            if transposable && walls_transpose(e) {
                if let Some(&(_, opt)) = done
                    .iter()
                    .find(|(f, _)| (f.0 - e.1).abs() <= 1e-9 && (f.1 - e.0).abs() <= 1e-9)
                {
                    all_optimal &= opt;
                    continue;
                }
            }
            let warm_p = solutions.iter().find(|p| {
                let f = p.extent();
                (f.0 - e.0).abs() <= 1e-9 && (f.1 - e.1).abs() <= 1e-9
            });
            // Enumeration first: in a box of the optimal area packings are few. The MILP gets
            // what remains of the contact budget.
            let deadline = match settings.contact_budget {
                ContactBudget::Rest => f64::INFINITY,
                ContactBudget::AreaTime => area_stage_s.max(1.0),
                ContactBudget::Seconds(s) => s,
            };
            let contact_left = || (deadline - (start.elapsed().as_secs_f64() - area_stage_s)).min(left(settings));
            // The enumeration may take what is left but 1 s, which the MILP gets: the
            // enumeration made every contact proof measured, HiGHS none and it never raised
            // the contact found (docs/algorithms.md, *Budget*); a flat 10 % cost N = 21's
            // squares their proof in some runs. HiGHS may still raise the contact elsewhere.
            // With less than 10 s left it gets nothing: HiGHS asks its time limit only between
            // LP solves, and the grid model's root LP overran smaller budgets by most of a
            // second (the generated seed-29 instance at `--time-limit 1`: 0.74 s of 0.09 s).
            let reserve = if contact_left() >= 10.0 { 1.0 } else { 0.0 };
            let enum_end = start.elapsed().as_secs_f64() + contact_left() - reserve;
            let halt_enum = || {
                progress.tick();
                stop.should_stop() || contact_left() <= 0.0 || start.elapsed().as_secs_f64() >= enum_end
            };
            let t_enum = Instant::now();
            let meter = Some(&progress.nodes);
            let (enum_best, complete, n_enum, enum_open) =
                area::max_contact(inst, &fps, e, best_contact, &halt_enum, meter, settings.threads);
            report.contact_enumeration_s += t_enum.elapsed().as_secs_f64();
            report.contact_proofs_by_enumeration += complete as u64;
            nodes += n_enum;
            progress.reach_nodes(nodes);
            if let Some(p) = &enum_best {
                let c = p.contact_length(inst);
                if c > best_contact + 1e-9 && p.occupied_area() <= best_area + 1e-12 {
                    best = p.clone();
                    best_contact = c;
                }
            }
            if complete {
                done.push((e, true));
                continue;
            }
            // A stop asked (not the limit) ends the stage here too: HiGHS would not hear it.
            if contact_left() <= 0.0 || stop.should_stop() {
                all_optimal = false;
                open = open.max(enum_open);
                continue;
            }
            let warm_p = enum_best.as_ref().or(warm_p);
            let t_milp = Instant::now();
            let res = if GridModel::size(inst, &fps, e.0, e.1) <= settings.grid_max_nnz {
                grid_contact_stage(
                    inst,
                    &fps,
                    e,
                    warm_p,
                    contact_left(),
                    settings.seed,
                    &settings.highs_options,
                )?
            } else if let Some(wp) = warm_p {
                contact_stage(inst, &fps, wp, contact_left(), settings.seed, &settings.highs_options)?
            } else {
                None
            };
            milps += 1;
            report.contact_milp_s += t_milp.elapsed().as_secs_f64();
            match res {
                Some((p, opt, n2)) => {
                    nodes += n2;
                    progress.reach_nodes(nodes);
                    report.contact_proofs_by_milp += opt as u64;
                    all_optimal &= opt;
                    if !opt {
                        open = open.max(enum_open);
                    }
                    done.push((e, opt));
                    let c = p.contact_length(inst);
                    if c > best_contact + 1e-9 && p.occupied_area() <= best_area + 1e-12 {
                        best = p;
                        best_contact = c;
                    }
                }
                None => {
                    all_optimal = false;
                    open = open.max(enum_open);
                }
            }
        }
        contact_optimal = all_optimal;
        if area_optimal && ties_closed {
            report.contact_upper_bound = Some(if contact_optimal {
                best_contact
            } else {
                best_contact.max(open)
            });
        }
    }
    debug_assert!(is_bl_stable(&best.targets));
    report.contact_stage_s = start.elapsed().as_secs_f64() - area_stage_s;
    report.contact_optimal = contact_optimal;
    let status = if area_optimal && contact_optimal {
        PlacementStatus::Optimal
    } else {
        PlacementStatus::Feasible
    };
    let result = PlacementResult {
        placement: best,
        status,
        lower_bound: if area_optimal { best_area } else { lower_bound },
        solver: "milp".into(),
        time_s: start.elapsed().as_secs_f64() + warm.time_s,
        nodes,
        subproblems: milps,
    };
    Ok((result, report))
}

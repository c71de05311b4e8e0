//! Hand variants of an action (the gripper turned by π) and the choice between them.

use super::*;

/// Plan one variant of an action for `arm` from `start` with the hand in `start_hand`.
pub(super) fn plan_variant(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    specs: Vec<Spec>,
    start: &[f64; 6],
    start_hand: Hand,
) -> Result<Motion, RobotError> {
    let mut q = *start;
    let mut segments = Vec::new();
    let mut key_q = Vec::new();
    let mut min_clear = f64::INFINITY;
    let mut cost = 0.0;
    let name = action_label(ctx.inst, action);
    for (k, sp) in specs.iter().enumerate() {
        let hand = if k == 0 {
            start_hand
        } else {
            Hand {
                opening: specs[k - 1].opening,
                held: specs[k - 1].held,
            }
        };
        let what = format!("{name}, move to {}", sp.label);
        let from = solver.fk(&q);
        let legs: Legs = match sp.mv {
            Move::Line => {
                let tol = if ctx.fast_ik {
                    PREDICATE_LINE_TOLERANCE
                } else {
                    LINE_TOLERANCE
                };
                let p = line_memo(ctx, solver, &q, &from, &sp.target, &what, tol)?;
                check_samples(ctx, solver, action, k, &hand, &densify(&p), &what, &mut min_clear, 0.0)?;
                vec![p]
            }
            Move::Joint => joint_move(ctx, solver, action, k, &hand, &q, &sp.target, &what, &mut min_clear)?,
        };
        for path in &legs {
            for w in path.windows(2) {
                cost += (0..6).map(|j| (w[1][j] - w[0][j]).abs()).sum::<f64>();
            }
        }
        q = *legs.last().and_then(|l| l.last()).expect("non-empty");
        key_q.push(q);
        segments.push(legs);
    }
    let margin = key_q
        .iter()
        .map(|q| ctx.inst.robot.model.joint_margin(solver.arm(), q))
        .fold(f64::INFINITY, f64::min);
    Ok(Motion {
        segments,
        key_q,
        specs,
        cost: cost - 0.5 * margin.min(0.5),
        clearance: min_clear,
    })
}

/// Hand turned by π (at the table, in the container) in each variant of an action.
pub(super) fn hand_variants(action: &Action) -> &'static [[bool; 2]] {
    match action {
        Action::Place { .. } => &[[false, false], [false, true], [true, false], [true, true]],
        Action::Push { .. } => &[[false, false], [true, false]],
    }
}

/// The hand variants of `action` (turned by 0 or π at the table and in the container) that are
/// kinematically feasible from `start`, ranked by joint motion (least first), and the first error
/// when some were not.
pub(super) fn rank_variants(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    start: &[f64; 6],
    start_hand: Hand,
    notes: &mut Vec<String>,
) -> (Vec<(f64, [bool; 2])>, Option<RobotError>) {
    let flips = hand_variants(action);
    let mut ranked: Vec<(f64, [bool; 2])> = Vec::new();
    let mut first_err: Option<RobotError> = None;
    let free = Ctx {
        inst: ctx.inst,
        placement: ctx.placement,
        statics: Vec::new(),
        at: ctx.at.clone(),
        other: Vec::new(),
        scope: Scope::Kinematic,
        fast_ik: ctx.fast_ik,
        memo: ctx.memo,
    };
    for f in flips {
        let mut n = Vec::new();
        let sp = specs(ctx.inst, ctx.placement, action, *f, &mut n);
        if notes.is_empty() {
            notes.extend(n);
        }
        match plan_variant(&free, solver, action, sp, start, start_hand) {
            Ok(m) => ranked.push((m.cost, *f)),
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    (ranked, first_err)
}

/// Plan the best variant: the cheap kinematic pass ranks the variants by joint motion, the full
/// pass then takes the first (least motion) variant that is collision-free.
pub(super) fn plan_action(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    start: &[f64; 6],
    start_hand: Hand,
    notes: &mut Vec<String>,
) -> Result<Motion, RobotError> {
    let (ranked, first_err) = rank_variants(ctx, solver, action, start, start_hand, notes);
    let mut errs: Vec<String> = Vec::new();
    for (_, f) in &ranked {
        let sp = specs(ctx.inst, ctx.placement, action, *f, &mut Vec::new());
        match plan_variant(ctx, solver, action, sp, start, start_hand) {
            Ok(m) => return Ok(m),
            Err(e) => {
                let e = e.to_string();
                if !errs.contains(&e) {
                    errs.push(e);
                }
            }
        }
    }
    match (errs.len(), first_err) {
        (0, e) => Err(e.expect("at least one variant")),
        // Every hand variant failed: say why each did, not just the first.
        (1, _) => Err(RobotError::Other(errs.remove(0))),
        _ => Err(RobotError::Other(format!(
            "every hand variant failed: {}",
            errs.join("; ")
        ))),
    }
}

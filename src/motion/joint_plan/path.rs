//! Paths of one arm: straight Cartesian lines, joint-space moves and their collision samples.

use super::*;

/// The motion of one action variant.
#[derive(Debug, Clone)]
pub(super) struct Motion {
    /// Legs (each from rest to rest) per segment; segment k ends at key pose k.
    pub(super) segments: Vec<Legs>,
    pub(super) key_q: Vec<[f64; 6]>,
    pub(super) specs: Vec<Spec>,
    pub(super) cost: f64,
    pub(super) clearance: f64,
}

pub(super) fn lerp(a: &[f64; 6], b: &[f64; 6], u: f64) -> [f64; 6] {
    std::array::from_fn(|k| a[k] + u * (b[k] - a[k]))
}

pub(super) fn interp_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    a.lerp_slerp(b, s)
}

/// Distance from `p` to the segment a–b.
pub fn line_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let u = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * u)).norm()
}

/// Follow the straight line a → b from configuration `q0` (at a), within position tolerance `tol`
/// (the predicate only needs to know that the line can be followed, not the fine waypoints the
/// joint plan emits).
pub(super) fn follow_line_tol(
    solver: &IkSolver,
    q0: &[f64; 6],
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    what: &str,
    tol: f64,
) -> Result<Vec<[f64; 6]>, RobotError> {
    let len = (b.translation.vector - a.translation.vector).norm();
    let ang = a.rotation.angle_to(&b.rotation);
    let n = (len / 0.01).max(ang / 0.05).ceil().max(1.0) as usize;
    let mut out = vec![*q0];
    let mut worst = (0.0f64, 0.0f64);
    for i in 1..=n {
        let s0 = (i - 1) as f64 / n as f64;
        let s1 = i as f64 / n as f64;
        refine(solver, a, b, s0, s1, &mut out, 0, what, &mut worst, tol)?;
    }
    Ok(out)
}

/// [`follow_line_tol`] through the context's memo (a pure function of its inputs, so a hit is
/// the same answer). The predicate only asks whether a line can be followed, so it shares a
/// line between actions whatever the move is called; the joint plan keeps the error, which
/// names the move, so its key holds the name too.
pub(super) fn line_memo(
    ctx: &Ctx,
    solver: &IkSolver,
    q0: &[f64; 6],
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    what: &str,
    tol: f64,
) -> Result<Vec<[f64; 6]>, RobotError> {
    IkMemo::get(
        ctx.memo,
        || {
            let mut k = key_bits(2, solver.arm(), &[a, b], Some(q0), &[tol]);
            if !ctx.fast_ik {
                k.extend(what.bytes().map(u64::from));
            }
            k
        },
        || follow_line_tol(solver, q0, a, b, what, tol),
    )
}

/// [`IkSolver::solve_near`] through the context's memo. The hand variants of an action share
/// their table half, and the joint plan's kinematic ranking pass solves the same poses as its
/// full pass: without the memo each repeat costs a descent from every IK seed.
pub(super) fn near_memo(
    ctx: &Ctx,
    solver: &IkSolver,
    target: &Isometry3<f64>,
    q: &[f64; 6],
) -> Result<[f64; 6], RobotError> {
    IkMemo::get(
        ctx.memo,
        || key_bits(3, solver.arm(), &[target], Some(q), &[]),
        || solver.solve_near(target, q).map(|q| vec![q]),
    )
    .map(|v| v[0])
}

#[allow(clippy::too_many_arguments)]
pub(super) fn refine(
    solver: &IkSolver,
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    s0: f64,
    s1: f64,
    out: &mut Vec<[f64; 6]>,
    depth: usize,
    what: &str,
    worst: &mut (f64, f64),
    tol: f64,
) -> Result<(), RobotError> {
    let q0 = *out.last().expect("starts with q0");
    let target = interp_pose(a, b, s1);
    let q1 = solver.track_or_near(&target, &q0)?;
    let jump = max_abs_diff(&q0, &q1);
    let (pa, pb) = (a.translation.vector, b.translation.vector);
    // Position off the line, and orientation off the interpolated one: a held box reaches
    // ~0.05 m from the TCP, so a turn of ROT_TOLERANCE moves its corners by < 0.03 mm.
    let (mut dev, mut rot) = (0.0f64, 0.0f64);
    for u in [0.25, 0.5, 0.75] {
        let f = solver.fk(&lerp(&q0, &q1, u));
        dev = dev.max(line_distance(&f.translation.vector, &pa, &pb));
        let want = interp_pose(a, b, s0 + u * (s1 - s0));
        rot = rot.max(f.rotation.angle_to(&want.rotation));
    }
    if jump > MAX_LINE_STEP || dev > tol || rot > ROT_TOLERANCE * tol / LINE_TOLERANCE {
        worst.0 = worst.0.max(dev);
        worst.1 = worst.1.max(jump);
        if depth >= 14 {
            return Err(RobotError::Path {
                what: what.to_string(),
                deviation: worst.0,
                limit: tol,
                jump: worst.1,
            });
        }
        let sm = 0.5 * (s0 + s1);
        refine(solver, a, b, s0, sm, out, depth + 1, what, worst, tol)?;
        refine(solver, a, b, sm, s1, out, depth + 1, what, worst, tol)?;
    } else {
        out.push(q1);
    }
    Ok(())
}

/// Collision check of configurations `qs` of `arm` with hand `hand` during segment `seg`; the
/// robot's parts grown by `margin` (0 for straight lines, which may touch; [`JOINT_MOVE_MARGIN`]
/// for joint-space moves).
#[allow(clippy::too_many_arguments)]
pub(super) fn check_samples(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    seg: usize,
    hand: &Hand,
    qs: &[[f64; 6]],
    what: &str,
    min_clear: &mut f64,
    margin: f64,
) -> Result<(), RobotError> {
    if ctx.scope == Scope::Kinematic {
        return Ok(());
    }
    let moving = matches!(action, Action::Push { .. }) && seg == 2;
    let fixed_obs = if moving {
        Vec::new()
    } else {
        ctx.obstacles(action, seg, None)
    };
    let samples = Samples {
        ctx,
        solver,
        action,
        seg,
        hand,
        qs,
        fixed_obs: &fixed_obs,
        moving,
        margin,
    };
    // The predicate checks the same lines for many actions (the table half of a place is the
    // same for every release mode, and for both hand turns in the container), so its answers
    // are memoised by everything the check reads. It keeps no clearance.
    let hit = match ctx.memo.filter(|_| ctx.scope == Scope::StaticLines && !moving) {
        Some(memo) => {
            let skipped = match action {
                Action::Push { objects, .. } if seg >= 2 => Some(objects.as_slice()),
                _ => None,
            };
            let key = check_key(solver.arm(), hand, margin, qs, &fixed_obs, skipped);
            IkMemo::check(memo, key, || samples.first_hit(None))
        }
        // Only the joint plan reports clearances; the distance queries cost more than the
        // boolean test they follow.
        None => samples.first_hit((ctx.scope == Scope::Full).then_some(min_clear)),
    };
    match hit {
        None => Ok(()),
        Some((part, obstacle, tcp)) => Err(RobotError::Collision {
            what: what.to_string(),
            part,
            obstacle,
            tcp,
        }),
    }
}

/// The inputs of one [`check_samples`].
struct Samples<'c> {
    ctx: &'c Ctx<'c>,
    solver: &'c IkSolver<'c>,
    action: &'c Action,
    seg: usize,
    hand: &'c Hand,
    qs: &'c [[f64; 6]],
    /// The obstacles unless they move with the TCP (`moving`: a push's pushed objects).
    fixed_obs: &'c [Obstacle],
    moving: bool,
    margin: f64,
}

impl Samples<'_> {
    /// The first sample's first collision, lowering `min_clear` (when given) to the clearance
    /// of the samples before it.
    fn first_hit(&self, mut min_clear: Option<&mut f64>) -> Option<Hit> {
        let (ctx, solver, action, seg) = (self.ctx, self.solver, self.action, self.seg);
        let model = &ctx.inst.robot.model;
        let skip = Ctx::skip(action, seg);
        for (k, q) in self.qs.iter().enumerate() {
            let parts = robot_parts(model, ctx.inst, solver.arm(), q, self.hand);
            let grown_parts;
            let tested = if self.margin > 0.0 {
                grown_parts = grown(&parts, self.margin);
                &grown_parts
            } else {
                &parts
            };
            // Only a push's moving obstacles and the error need the TCP: most samples spare it.
            let tcp = || solver.fk(q).translation.vector;
            let moved_obs;
            let obs = if self.moving {
                moved_obs = ctx.obstacles(action, seg, Some(&tcp()));
                &moved_obs
            } else {
                self.fixed_obs
            };
            if let Some((p, o)) = first_collision(tested, obs, &skip) {
                let tcp = tcp();
                return Some((p.name.clone(), o.name.clone(), [tcp.x, tcp.y, tcp.z]));
            }
            // Clearance report on a subset of samples (it is slower than the boolean test).
            if let Some(mc) = min_clear.as_deref_mut() {
                if k % 8 == 0 || k + 1 == self.qs.len() {
                    *mc = mc.min(clearance(&parts, obs, &skip));
                }
            }
        }
        None
    }
}

/// Dense samples of a waypoint path for collision checks: every waypoint and intermediate
/// configurations no more than [`COLLISION_STEP`] apart.
pub(super) fn densify(path: &[[f64; 6]]) -> Vec<[f64; 6]> {
    let mut out = vec![path[0]];
    for w in path.windows(2) {
        let n = (max_abs_diff(&w[0], &w[1]) / COLLISION_STEP).ceil().max(1.0) as usize;
        for i in 1..=n {
            out.push(lerp(&w[0], &w[1], i as f64 / n as f64));
        }
    }
    out
}

/// Extra height of the last resort in [`joint_move`] above the transfer height (m): open fingers
/// turning between two poses near a wall can dip below its top in a joint move at transfer
/// height, and a straight line may not be followable through the turn.
const HIGH_TRANSFER_LIFT: f64 = 0.10;

/// A move to `target` in joint space; where that collides, a straight line. Where that collides
/// too, the move is made at a clear height instead: straight up from the start to that height
/// (if below it), a joint move (or a line) to the target raised to that height, and straight
/// down to the target (if below it). The clear heights tried are the transfer height and
/// [`HIGH_TRANSFER_LIFT`] above it. Returns the legs.
#[allow(clippy::too_many_arguments)]
pub(super) fn joint_move(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    seg: usize,
    hand: &Hand,
    q: &[f64; 6],
    target: &Isometry3<f64>,
    what: &str,
    min_clear: &mut f64,
) -> Result<Legs, RobotError> {
    let check = |p: &[[f64; 6]], mc: &mut f64, margin: f64| {
        check_samples(ctx, solver, action, seg, hand, &densify(p), what, mc, margin)
    };
    let from = solver.fk(q);
    // The predicate only needs some branch at the target (the joint move is not checked); the
    // nearest one costs a search over every IK seed when the move is long.
    let qt = if ctx.fast_ik {
        IkMemo::get(
            ctx.memo,
            || key_bits(1, solver.arm(), &[target], None, &[]),
            || solver.solve_any(target).map(|q| vec![q]),
        )?[0]
    } else {
        near_memo(ctx, solver, target, q)?
    };
    let joint = vec![*q, qt];
    if ctx.scope != Scope::Full {
        return Ok(vec![joint]);
    }
    let joint_err = match check(&joint, min_clear, JOINT_MOVE_MARGIN) {
        Ok(()) => return Ok(vec![joint]),
        Err(e) => e,
    };
    if let Ok(line) = line_memo(ctx, solver, q, &from, target, what, LINE_TOLERANCE) {
        if check(&line, min_clear, 0.0).is_ok() {
            return Ok(vec![line]);
        }
    }
    let zt = crate::motion::keypoints::transfer_z(ctx.inst);
    for h in [zt, zt + HIGH_TRANSFER_LIFT] {
        if let Some(legs) = move_at_height(ctx, solver, q, &from, target, h, what, &check, min_clear) {
            return Ok(legs);
        }
    }
    Err(joint_err)
}

/// A collision check of a sampled path (path, smallest clearance so far, margin).
type SampleCheck<'a> = dyn Fn(&[[f64; 6]], &mut f64, f64) -> Result<(), RobotError> + 'a;

/// The legs of a move from `from` (configuration `q`) to `target` made at height `h`: up, across
/// (joint move, else a line), down; `None` when a leg cannot be followed or collides, or when
/// neither end is below `h` (then this is the direct move, already tried).
#[allow(clippy::too_many_arguments)]
fn move_at_height(
    ctx: &Ctx,
    solver: &IkSolver,
    q: &[f64; 6],
    from: &Isometry3<f64>,
    target: &Isometry3<f64>,
    h: f64,
    what: &str,
    check: &SampleCheck,
    min_clear: &mut f64,
) -> Option<Legs> {
    let raise = |p: &Isometry3<f64>| {
        let mut up = *p;
        up.translation.vector.z = h;
        up
    };
    let (rise_start, descend) = (
        from.translation.vector.z < h - 1e-6,
        target.translation.vector.z < h - 1e-6,
    );
    if !rise_start && !descend {
        return None;
    }
    let mut legs = Vec::new();
    let (mut q1, mut p1) = (*q, *from);
    if rise_start {
        let up = raise(from);
        let rise = line_memo(ctx, solver, q, from, &up, what, LINE_TOLERANCE).ok()?;
        check(&rise, min_clear, 0.0).ok()?;
        q1 = *rise.last().expect("non-empty");
        p1 = up;
        legs.push(rise);
    }
    let top = if descend { raise(target) } else { *target };
    let across = {
        let qt = near_memo(ctx, solver, &top, &q1).ok()?;
        let joint = vec![q1, qt];
        if check(&joint, min_clear, JOINT_MOVE_MARGIN).is_ok() {
            joint
        } else {
            let line = line_memo(ctx, solver, &q1, &p1, &top, what, LINE_TOLERANCE).ok()?;
            check(&line, min_clear, 0.0).ok()?;
            line
        }
    };
    let q2 = *across.last().expect("non-empty");
    legs.push(across);
    if descend {
        let down = line_memo(ctx, solver, &q2, &top, target, what, LINE_TOLERANCE).ok()?;
        check(&down, min_clear, 0.0).ok()?;
        legs.push(down);
    }
    Some(legs)
}

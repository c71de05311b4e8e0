//! Reachability as the planner asks it: arms that can do an action, and the objects in the way.

use super::*;

/// Short label of an action (`place 1a`, `push 2a+4a`).
pub fn action_label(inst: &Instance, action: &Action) -> String {
    let ids: Vec<&str> = action.objects().iter().map(|&i| inst.objects[i].id.as_str()).collect();
    match action {
        Action::Place { .. } => format!("place {}", ids.join("+")),
        Action::Push { .. } => format!("push {}", ids.join("+")),
    }
}

/// The action with another executing arm.
pub fn with_arm(action: &Action, arm: Arm) -> Action {
    let mut a = action.clone();
    match &mut a {
        Action::Place { arm: x, .. } | Action::Push { arm: x, .. } => *x = arm,
    }
    a
}

/// What the action planner needs to know about one action for its own arm (see
/// [`action_reach`]).
#[derive(Debug, Clone)]
pub struct Reach {
    /// Joint path length from home of the cheapest feasible hand variant (rad), minus half its
    /// smallest joint margin at the key poses (capped at 0.5 rad).
    pub cost: f64,
    /// For every feasible hand variant, the other objects that block it while they are still on
    /// the table (the open fingers, the hand or the held object would hit them during the grasp or
    /// the lift). Empty for pushes.
    pub table_blockers: Vec<Vec<usize>>,
    /// Every feasible hand variant found, with what can block it where the objects are.
    variants: Vec<Variant>,
    /// The objects the action moves: the pushed line touches the pusher on purpose, and the
    /// predicate already checks the back object where the push finds it.
    moved: Vec<usize>,
    /// (variant, object, footprint bits) → whether the variant's low parts hit the object
    /// there: the sequencers ask about the same few footprints millions of times.
    hits: RefCell<HashMap<PackedKey, bool>>,
}

/// (hand variant, object, bits of its footprint) of a packed-object query.
type PackedKey = (usize, usize, [u64; 4]);

/// One feasible hand variant of an action, as the predicate asks it in a state.
#[derive(Debug, Clone)]
struct Variant {
    /// Objects that block it while still on the table.
    table: Vec<usize>,
    /// The arm's link parts (hand housing, wrist, links; not the fingers or the held object)
    /// at the samples of the action's straight lines that come down below the top of the
    /// tallest object in the container ([`low_parts`]): only these can hit an object already
    /// packed. Empty in any cell whose objects stay below the hand, such as the default one
    /// (the housing is at least 0.105 m above the floor, the objects at most 0.10 m tall).
    low: Vec<Part>,
}

impl Reach {
    /// Whether some hand variant is free, given which objects are still on the table; objects
    /// in the container are not looked at (see [`Self::free_in`]).
    pub fn free_when(&self, on_table: impl Fn(usize) -> bool) -> bool {
        self.variants.iter().any(|v| !v.table.iter().any(|&j| on_table(j)))
    }

    /// Whether some hand variant is free, given where the objects are: `at(j)` is `None` for
    /// an object still on the table, else its footprint in the container (C). Objects in the
    /// container stand at their target heights.
    pub fn free_in(&self, inst: &Instance, placement: &Placement, at: impl Fn(usize) -> Option<Rect>) -> bool {
        self.variants.iter().enumerate().any(|(k, v)| {
            !v.table.iter().any(|&j| at(j).is_none()) && (v.low.is_empty() || !self.packed_hit(inst, placement, k, &at))
        })
    }

    /// Whether the low parts of variant `k` hit an object in the container (not one the action
    /// moves).
    fn packed_hit(
        &self,
        inst: &Instance,
        placement: &Placement,
        k: usize,
        at: &impl Fn(usize) -> Option<Rect>,
    ) -> bool {
        (0..inst.n()).filter(|j| !self.moved.contains(j)).any(|j| {
            let Some(rect) = at(j) else {
                return false;
            };
            let key = (k, j, [rect.x0, rect.y0, rect.x1, rect.y1].map(f64::to_bits));
            if let Some(&hit) = self.hits.borrow().get(&key) {
                return hit;
            }
            let o = object_in_container(inst, j, &rect, placement.targets[j].height);
            let hit = first_collision(&self.variants[k].low, std::slice::from_ref(&o), |_, _| false).is_some();
            self.hits.borrow_mut().insert(key, hit);
            hit
        })
    }

    /// Whether some hand variant has parts low enough to hit a packed object.
    pub fn reaches_down(&self) -> bool {
        self.variants.iter().any(|v| !v.low.is_empty())
    }
}

/// The link parts of the arm along the straight lines of `m` that come below `z_top` (world):
/// the only parts of this motion that can hit an object packed in the container. The fingers
/// and the held object are left out: near packed objects they are judged by the action's own
/// slab rules ([`crate::actions::Layout::check`]), with the heights of both.
fn low_parts(ctx: &Ctx, solver: &IkSolver, m: &Motion, z_top: f64) -> Vec<Part> {
    let inst = ctx.inst;
    let hand = Hand {
        opening: 0.0,
        held: None,
    };
    let down = -Vector3::z();
    let links = |q: &[f64; 6]| {
        robot_parts(&inst.robot.model, inst, solver.arm(), q, &hand)
            .into_iter()
            .filter(|p| p.kind == PartKind::Link)
    };
    let bottom = |p: &Part| -p.solid.support_extent(&p.pose, &down);
    // The straight lines run between key poses with the tool held top-down, so the hand only
    // translates along them and its lowest point moves linearly between the key poses' (the
    // links above it stay higher). Looking at the key poses first spares the samples in every
    // cell whose objects stay below the hand, such as the default one; LOW_MARGIN covers the
    // lines' tolerances many times over.
    const LOW_MARGIN: f64 = 0.02;
    let lowest = m
        .key_q
        .iter()
        .flat_map(links)
        .map(|p| bottom(&p))
        .fold(f64::INFINITY, f64::min);
    if lowest - LOW_MARGIN >= z_top {
        return Vec::new();
    }
    let mut out = Vec::new();
    for (spec, legs) in m.specs.iter().zip(&m.segments) {
        // Joint-space moves are the joint plan's (they depend on where the arm comes from).
        if spec.mv != Move::Line {
            continue;
        }
        for leg in legs {
            for q in densify(leg) {
                out.extend(links(&q).filter(|p| bottom(p) < z_top));
            }
        }
    }
    out
}

/// Top of the tallest object in the container (world z, m), when every object is at its
/// target height.
fn packed_top(inst: &Instance, placement: &Placement) -> f64 {
    let h = placement.targets.iter().map(|t| t.height).fold(0.0, f64::max);
    inst.container.to_world([0.0, 0.0, h]).z
}

/// Objects still on the table (other than the picked one) that collide with the grasp and lift
/// lines of a place motion.
pub(super) fn blockers_of(ctx: &Ctx, solver: &IkSolver, action: &Action, m: &Motion) -> Vec<usize> {
    let Action::Place { object, .. } = action else {
        return Vec::new();
    };
    let inst = ctx.inst;
    let here = &inst.objects[*object].table;
    let near: Vec<(usize, Obstacle)> = (0..inst.n())
        .filter(|&j| j != *object)
        .filter(|&j| {
            let c = &inst.objects[j].table;
            (c.x - here.x).hypot(c.y - here.y) < 0.25
        })
        .map(|j| (j, object_on_table(inst, j)))
        .collect();
    let mut out = Vec::new();
    for seg in 1..=2 {
        let hand = Hand {
            opening: m.specs[seg - 1].opening,
            held: m.specs[seg - 1].held,
        };
        for leg in &m.segments[seg] {
            for q in densify(leg) {
                let parts = robot_parts(&inst.robot.model, inst, solver.arm(), &q, &hand);
                for (j, o) in &near {
                    if !out.contains(j) && first_collision(&parts, std::slice::from_ref(o), |_, _| false).is_some() {
                        out.push(*j);
                    }
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// The action planner's predicate for `action` with its own arm, from the arm's home pose: every
/// key pose reachable within the joint limits and every straight line followable, in some hand
/// orientation, and the straight lines of that variant free of the fixed cell (walls, floor
/// plate, table). Objects in the container are the finger and pusher slabs' job
/// ([`crate::actions::Layout::check`]); objects on the table are returned as blockers.
/// `None` when no hand variant passes.
pub fn action_reach(inst: &Instance, placement: &Placement, action: &Action) -> Option<Reach> {
    action_reach_memo(inst, placement, action, &RefCell::new(IkMemo::default()), false)
}

/// [`action_reach`] sharing IK results with earlier queries of the same instance (the memo must
/// not be shared across instances with different robots). With `first_free`, stops at the first
/// hand variant without table blockers: feasibility is then settled, but `cost` is that
/// variant's, not the least.
pub fn action_reach_memo(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    memo: &RefCell<IkMemo>,
    first_free: bool,
) -> Option<Reach> {
    let arm = action.arm();
    if !inst.robot.arms.contains(&arm) {
        return None;
    }
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: vec![ObjAt::Table; inst.n()],
        // The joint plan parks an idle arm at home when it is in the way, so the other arm at
        // home is part of the fixed cell.
        other: idle_arm(inst, arm.other(), &inst.robot.home[arm.other().index()], 0.0),
        scope: Scope::StaticLines,
        fast_ik: true,
        memo: Some(memo),
    };
    let solver = IkSolver::new(&inst.robot.model, arm, &inst.robot.tcp_offset);
    let home = inst.robot.home[arm.index()];
    let hand = Hand {
        opening: 0.0,
        held: None,
    };
    let mut cost = f64::INFINITY;
    let mut table_blockers = Vec::new();
    let mut variants = Vec::new();
    let z_top = packed_top(inst, placement);
    for f in hand_variants(action) {
        let sp = specs(inst, placement, action, *f, &mut Vec::new());
        if let Ok(m) = plan_variant(&ctx, &solver, action, sp, &home, hand) {
            cost = cost.min(m.cost);
            let b = blockers_of(&ctx, &solver, action, &m);
            let low = low_parts(&ctx, &solver, &m, z_top);
            // A variant that packed objects may block does not settle feasibility.
            let free = b.is_empty() && low.is_empty();
            if !table_blockers.contains(&b) {
                table_blockers.push(b.clone());
            }
            variants.push(Variant { table: b, low });
            if free && first_free {
                break;
            }
        }
    }
    cost.is_finite().then_some(Reach {
        cost,
        table_blockers,
        variants,
        moved: action.objects(),
        hits: RefCell::new(HashMap::new()),
    })
}

/// Whether the action's arm can execute `action` when no other object is in the way (see
/// [`action_reach`]); table blockers are ignored here.
pub fn action_reachable(inst: &Instance, placement: &Placement, action: &Action) -> bool {
    action_reach(inst, placement, action).is_some()
}

/// The allowed arms that can execute `action` (each tried in place of the action's own arm).
pub fn arms_reaching(inst: &Instance, placement: &Placement, action: &Action) -> Vec<Arm> {
    inst.robot
        .arms
        .iter()
        .copied()
        .filter(|a| action_reachable(inst, placement, &with_arm(action, *a)))
        .collect()
}

/// The arm that executes `action` best: among the allowed arms that pass [`action_reach`], the
/// one with the least joint motion from its home pose (joint path length in rad, minus half the
/// smallest joint margin at the key poses, capped at 0.5 rad). `None` when no arm reaches.
pub fn select_arm(inst: &Instance, placement: &Placement, action: &Action) -> Option<Arm> {
    inst.robot
        .arms
        .iter()
        .filter_map(|a| action_reach(inst, placement, &with_arm(action, *a)).map(|r| (*a, r.cost)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(a, _)| a)
}

/// What an action does to the objects.
pub(super) fn apply(at: &mut [ObjAt], placement: &Placement, action: &Action) {
    match action {
        Action::Place { object, mode, .. } => at[*object] = ObjAt::Floor(release_rect(placement, *object, mode)),
        Action::Push { objects, .. } => {
            for &i in objects {
                at[i] = ObjAt::Floor(placement.targets[i].rect);
            }
        }
    }
}

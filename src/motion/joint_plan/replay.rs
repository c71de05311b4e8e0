//! The hand, held objects and idle arm along a recorded plan, for the verifier.

use super::*;

/// The hand during segment `seg` of `action` (segment k ends at key pose k), given the openings
/// recorded at the key poses and the opening before the action.
pub(crate) fn segment_hand(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    seg: usize,
    openings: &[f64],
    before: f64,
) -> Hand {
    if seg == 0 {
        return Hand {
            opening: before,
            held: None,
        };
    }
    let opening = openings.get(seg - 1).copied().unwrap_or(before);
    let held = match action {
        Action::Place {
            object,
            mode,
            grasp_axis,
            ..
        } => match seg {
            2 | 3 => {
                let (_, closing, other, height, _) = table_grasp(inst, placement, *object, *grasp_axis);
                Some(Held {
                    object: *object,
                    closing,
                    other,
                    height,
                })
            }
            4 => {
                let rel = release_rect(placement, *object, mode);
                Some(Held {
                    object: *object,
                    closing: rel.extent(*grasp_axis),
                    other: rel.extent(grasp_axis.other()),
                    height: placement.targets[*object].height,
                })
            }
            _ => None,
        },
        Action::Push { .. } => None,
    };
    Hand { opening, held }
}

/// The first collision of `arm` at `q` with hand `hand` during segment `seg` of `action` (or of
/// an idle move when `action` is `None`), objects placed as in `at`, the other arm's parts in
/// `other`: (robot part, obstacle).
#[allow(clippy::too_many_arguments)]
pub(crate) fn collision_at(
    inst: &Instance,
    placement: &Placement,
    at: &[ObjAt],
    action: Option<&Action>,
    seg: usize,
    hand: &Hand,
    arm: Arm,
    q: &[f64; 6],
    other: &[Obstacle],
) -> Option<(String, String)> {
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: at.to_vec(),
        other: other.to_vec(),
        scope: Scope::Full,
        fast_ik: false,
        memo: None,
    };
    let idle = Action::Push {
        objects: vec![],
        push_dir: PushDir::MinusX,
        distance: 0.0,
        pusher_at: 0.0,
        arm,
    };
    let (action, seg) = match action {
        Some(a) => (a, seg),
        None => (&idle, 0),
    };
    let parts = robot_parts(&inst.robot.model, inst, arm, q, hand);
    let tcp = inst.robot.model.tcp_position(arm, q, &inst.robot.tcp_offset);
    let obs = ctx.obstacles(action, seg, Some(&tcp));
    first_collision(&parts, &obs, Ctx::skip(action, seg)).map(|(p, o)| (p.name.clone(), o.name.clone()))
}

/// Apply an action's effect on object positions (for replays).
pub(crate) fn apply_action(at: &mut [ObjAt], placement: &Placement, action: &Action) {
    apply(at, placement, action)
}

/// The idle arm's parts as obstacles.
pub(crate) fn idle_arm(inst: &Instance, arm: Arm, q: &[f64; 6], opening: f64) -> Vec<Obstacle> {
    arm_as_obstacles(
        robot_parts(&inst.robot.model, inst, arm, q, &Hand { opening, held: None }),
        arm,
    )
}

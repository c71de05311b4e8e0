//! Key poses of an action: the grasp on the table, the release footprint and the pose specs.

use super::*;

/// The yaw, closing extent, other extent and height of a top-down grasp of `object` on the table
/// along the body axis that is the closing axis at its target; and whether the object changes its
/// up axis between table and target (a top-down pick cannot do that).
pub(super) fn table_grasp(
    inst: &Instance,
    placement: &Placement,
    object: usize,
    grasp_axis: Axis2,
) -> (f64, f64, f64, f64, bool) {
    let o = &inst.objects[object];
    let t = &placement.targets[object];
    let others = |a: BodyAxis| match a {
        BodyAxis::X => (BodyAxis::Y, BodyAxis::Z),
        BodyAxis::Y => (BodyAxis::X, BodyAxis::Z),
        BodyAxis::Z => (BodyAxis::X, BodyAxis::Y),
    };
    let (b, c) = others(t.orientation.up);
    let g = match (grasp_axis, t.orientation.yaw90) {
        (Axis2::X, false) | (Axis2::Y, true) => b,
        _ => c,
    };
    let (bt, ct) = others(o.table.up);
    let s = o.size;
    let h = s[o.table.up.index()];
    if g == bt {
        (
            o.table.yaw,
            s[bt.index()],
            s[ct.index()],
            h,
            t.orientation.up != o.table.up,
        )
    } else if g == ct {
        (
            o.table.yaw + FRAC_PI_2,
            s[ct.index()],
            s[bt.index()],
            h,
            t.orientation.up != o.table.up,
        )
    } else if s[bt.index()] <= s[ct.index()] {
        (o.table.yaw, s[bt.index()], s[ct.index()], h, true)
    } else {
        (o.table.yaw + FRAC_PI_2, s[ct.index()], s[bt.index()], h, true)
    }
}

/// Release footprint of a place.
pub(super) fn release_rect(placement: &Placement, object: usize, mode: &PlaceMode) -> Rect {
    let t = placement.targets[object].rect;
    match mode {
        PlaceMode::Direct => t,
        PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
    }
}

pub(super) fn axis_yaw(inst: &Instance, a: Axis2) -> f64 {
    inst.container.yaw
        + match a {
            Axis2::X => 0.0,
            Axis2::Y => FRAC_PI_2,
        }
}

/// Key pose specs of `action` with the hand turned by π where `flip` says so.
pub(super) fn specs(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    flip: [bool; 2],
    notes: &mut Vec<String>,
) -> Vec<Spec> {
    let kps = action_keypoints(inst, placement, action);
    let g = &inst.gripper;
    let pose = |k: usize, yaw: f64| top_down_pose(&Vector3::from(kps[k].position), yaw);
    let turn = |f: bool| if f { PI } else { 0.0 };
    match action {
        Action::Place {
            object,
            mode,
            grasp_axis,
            ..
        } => {
            let (yaw_t, closing_t, other_t, h_t, reoriented) = table_grasp(inst, placement, *object, *grasp_axis);
            if reoriented {
                notes.push(format!(
                    "object {} changes its up axis between the table and its target: a top-down pick cannot turn \
                     it over; the joint plan assumes the cell's regrasp (robot.regrasp{}) has it in its target \
                     orientation when it is lowered into the container (the regrasp itself is not planned)",
                    inst.objects[*object].id,
                    if inst.robot.regrasp {
                        " = true"
                    } else {
                        " is false: not executable"
                    }
                ));
            }
            let rel = release_rect(placement, *object, mode);
            let closing_r = rel.extent(*grasp_axis);
            let other_r = rel.extent(grasp_axis.other());
            let h_r = placement.targets[*object].height;
            let yaw_r = axis_yaw(inst, *grasp_axis) + turn(flip[1]);
            let yaw_t = yaw_t + turn(flip[0]);
            let open = |w: f64| (w + 2.0 * g.release_clearance).min(g.max_opening.max(w));
            let held_t = Held {
                object: *object,
                closing: closing_t,
                other: other_t,
                height: h_t,
            };
            let held_r = Held {
                object: *object,
                closing: closing_r,
                other: other_r,
                height: h_r,
            };
            let mk = |k: usize, yaw: f64, opening: f64, held: Option<Held>, mv: Move| Spec {
                label: kps[k].label.clone(),
                target: pose(k, yaw),
                opening,
                held,
                mv,
            };
            vec![
                mk(0, yaw_t, open(closing_t), None, Move::Joint),
                mk(1, yaw_t, closing_t, Some(held_t), Move::Line),
                mk(2, yaw_t, closing_t, Some(held_t), Move::Line),
                mk(3, yaw_r, closing_r, Some(held_r), Move::Joint),
                mk(4, yaw_r, open(closing_r), None, Move::Line),
                mk(5, yaw_r, open(closing_r), None, Move::Line),
            ]
        }
        Action::Push { push_dir, .. } => {
            let yaw = axis_yaw(inst, push_dir.axis()) + turn(flip[0]);
            let mv = [Move::Joint, Move::Line, Move::Line, Move::Line];
            (0..kps.len())
                .map(|k| Spec {
                    label: kps[k].label.clone(),
                    target: pose(k, yaw),
                    opening: 0.0,
                    held: None,
                    mv: mv[k.min(3)],
                })
                .collect()
        }
    }
}

/// World point → container frame C (x, y).
pub(super) fn to_container(inst: &Instance, p: &Vector3<f64>) -> [f64; 2] {
    let c = &inst.container;
    let (s, co) = c.yaw.sin_cos();
    let (u, v) = (p.x - c.center[0], p.y - c.center[1]);
    [co * u + s * v + c.width / 2.0, -s * u + co * v + c.depth / 2.0]
}

/// Footprints of a pushed line when the pusher's front face is at `face` along the push axis:
/// objects (front to back, released footprints `rel`) move only when pushed.
pub(super) fn pushed_rects(rel: &[Rect], dir: PushDir, face: f64) -> Vec<Rect> {
    let axis = dir.axis();
    let mut drive = face;
    let mut out = vec![rel[0]; rel.len()];
    for k in (0..rel.len()).rev() {
        let hi = rel[k].hi(axis).min(drive);
        let r = rel[k].moved(dir, rel[k].hi(axis) - hi);
        drive = r.lo(axis);
        out[k] = r;
    }
    out
}

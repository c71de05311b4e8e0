//! The verifier's own gripper geometry: finger slabs, pusher slabs and the obstacles they can hit.
//!
//! Deliberately written from the documented geometry (SPEC §5, `actions` module docs) rather
//! than by calling the planner's slab functions, so that a mistake there shows up here.

use crate::geometry::{Axis2, Box3, PushDir, Rect};
use crate::instance::{Gripper, Instance};

/// A rectangle given by its interval along `a` and along the other axis.
fn rect_on(a: Axis2, a0: f64, a1: f64, b0: f64, b1: f64) -> Rect {
    match a {
        Axis2::X => Rect {
            x0: a0,
            x1: a1,
            y0: b0,
            y1: b1,
        },
        Axis2::Y => Rect {
            x0: b0,
            x1: b1,
            y0: a0,
            y1: a1,
        },
    }
}

/// Top of every slab: well above the walls and any object in the container.
pub(super) fn slab_top(inst: &Instance) -> f64 {
    inst.container.wall_height + 1.0
}

/// The two finger slabs of a grasp of footprint `r` (height `h`) closing along `axis`:
/// `finger_thickness + release_clearance` deep beside each face, `finger_width` wide centred on
/// the face, from `h − grasp_depth` (not below the floor) up to `top`.
pub(super) fn finger_slabs(g: &Gripper, r: &Rect, h: f64, axis: Axis2, top: f64) -> [Box3; 2] {
    let depth = g.finger_thickness + g.release_clearance;
    let lat = axis.other();
    let mid = (r.lo(lat) + r.hi(lat)) / 2.0;
    let (b0, b1) = (mid - g.finger_width / 2.0, mid + g.finger_width / 2.0);
    let z0 = (h - g.grasp_depth).max(0.0);
    let lo = rect_on(axis, r.lo(axis) - depth, r.lo(axis), b0, b1);
    let hi = rect_on(axis, r.hi(axis), r.hi(axis) + depth, b0, b1);
    [Box3::extrude(&lo, z0, top), Box3::extrude(&hi, z0, top)]
}

/// The closed-finger pusher behind footprint `back` for a push along `dir` (pushes go toward −x
/// or −y, so "behind" is the +axis side): `finger_thickness + extra` deep, `finger_width` wide
/// centred at lateral coordinate `at`, from the push height up to `top`.
pub(super) fn pusher_slab(g: &Gripper, back: &Rect, dir: PushDir, at: f64, extra: f64, top: f64) -> Box3 {
    let axis = dir.axis();
    let face = back.hi(axis);
    let r = rect_on(
        axis,
        face,
        face + g.finger_thickness + extra,
        at - g.finger_width / 2.0,
        at + g.finger_width / 2.0,
    );
    Box3::extrude(&r, g.push_height, top)
}

/// Smallest box containing both.
pub(super) fn hull(a: &Box3, b: &Box3) -> Box3 {
    Box3 {
        min: [0, 1, 2].map(|k| a.min[k].min(b.min[k])),
        max: [0, 1, 2].map(|k| a.max[k].max(b.max[k])),
    }
}

/// Names of the four container walls, in the order of [`crate::instance::Container::walls`].
pub(super) const WALL_NAMES: [&str; 4] = [
    "the left wall (x = 0)",
    "the right wall (x = width)",
    "the front wall (y = 0)",
    "the back wall (y = depth)",
];

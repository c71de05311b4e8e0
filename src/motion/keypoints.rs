//! Cartesian TCP key points of each action (world frame) and the gripper travel they imply.
//!
//! Place: above the table pose, grasp, above it, above the release pose, release, above it.
//! Push: above the push start, down behind the line, along the push, up. Moves between key
//! points are straight lines; travel is the length of these polylines for both arms, from the
//! home pose back to home.

use crate::actions::{Action, PlaceMode};
use crate::geometry::Arm;
use crate::geometry::{Orientation, PushDir, Rect};
use crate::instance::Instance;
use crate::placement::Placement;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A labelled TCP position.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KeyPoint {
    /// What the point is (`pre-grasp`, `grasp`, …).
    pub label: String,
    /// World position (m).
    pub position: [f64; 3],
}

/// Height of transfer moves: above the container walls and every object on the table.
pub fn transfer_z(inst: &Instance) -> f64 {
    let wall_top = inst.container.floor_z + inst.container.wall_height;
    let table_top = inst
        .objects
        .iter()
        .map(|o| inst.robot.table_z + o.table_footprint().1)
        .fold(f64::NEG_INFINITY, f64::max);
    wall_top.max(table_top) + inst.robot.transfer_clearance
}

fn kp(label: &str, v: Vector3<f64>) -> KeyPoint {
    KeyPoint {
        label: label.into(),
        position: [v.x, v.y, v.z],
    }
}

/// Key points of one action.
pub fn action_keypoints(inst: &Instance, placement: &Placement, action: &Action) -> Vec<KeyPoint> {
    let zt = transfer_z(inst);
    let g = &inst.gripper;
    match action {
        Action::Place { object, mode, .. } => {
            let o = &inst.objects[*object];
            let h_table = Orientation {
                up: o.table.up,
                yaw90: false,
            }
            .dims(o.size)
            .1;
            let pick = Vector3::new(o.table.x, o.table.y, inst.robot.table_z + h_table - g.grasp_depth);
            let t = placement.targets[*object];
            let rel: Rect = match mode {
                PlaceMode::Direct => t.rect,
                PlaceMode::Indirect { push_dir, offset } => t.rect.moved(*push_dir, -offset),
            };
            let c = rel.center();
            let release = inst.container.to_world([c[0], c[1], t.height - g.grasp_depth]);
            vec![
                kp("pre-grasp", Vector3::new(pick.x, pick.y, zt)),
                kp("grasp", pick),
                kp("lift", Vector3::new(pick.x, pick.y, zt)),
                kp("pre-place", Vector3::new(release.x, release.y, zt)),
                kp("release", release),
                kp("retreat", Vector3::new(release.x, release.y, zt)),
            ]
        }
        Action::Push {
            objects,
            push_dir,
            distance,
            pusher_at,
            ..
        } => {
            let back = *objects.last().expect("a push moves at least one object");
            let tr = placement.targets[back].rect;
            let half_t = g.finger_thickness / 2.0;
            let (start, end) = match push_dir {
                PushDir::MinusX => (
                    [tr.x1 + distance + g.release_clearance + half_t, *pusher_at],
                    [tr.x1 + half_t, *pusher_at],
                ),
                PushDir::MinusY => (
                    [*pusher_at, tr.y1 + distance + g.release_clearance + half_t],
                    [*pusher_at, tr.y1 + half_t],
                ),
            };
            let s = inst.container.to_world([start[0], start[1], g.push_height]);
            let e = inst.container.to_world([end[0], end[1], g.push_height]);
            vec![
                kp("above-push", Vector3::new(s.x, s.y, zt)),
                kp("push-start", s),
                kp("push-end", e),
                kp("push-retreat", Vector3::new(e.x, e.y, zt)),
            ]
        }
    }
}

/// Length of the polyline from `from` through `points`; returns it and the last point.
pub fn path_length(from: &Vector3<f64>, points: &[KeyPoint]) -> (f64, Vector3<f64>) {
    let mut len = 0.0;
    let mut cur = *from;
    for p in points {
        let v = Vector3::from(p.position);
        len += (v - cur).norm();
        cur = v;
    }
    (len, cur)
}

/// Arm that picks an object: the allowed arm on the object's side of the robot (y ≥ 0 → left),
/// else the other allowed arm.
pub fn pick_arm(inst: &Instance, object: usize) -> Arm {
    let pref = if inst.objects[object].table.y >= 0.0 {
        Arm::Left
    } else {
        Arm::Right
    };
    if inst.robot.arms.contains(&pref) {
        pref
    } else {
        inst.robot.arms[0]
    }
}

/// Total TCP travel of both arms executing `actions` in order, from home back to home.
pub fn total_travel(inst: &Instance, placement: &Placement, actions: &[Action]) -> f64 {
    let mut pos = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    let mut used = [false; 2];
    let mut total = 0.0;
    for a in actions {
        let k = a.arm().index();
        let (len, end) = path_length(&pos[k], &action_keypoints(inst, placement, a));
        total += len;
        pos[k] = end;
        used[k] = true;
    }
    for arm in [Arm::Left, Arm::Right] {
        if used[arm.index()] {
            total += (inst.robot.home_tcp(arm) - pos[arm.index()]).norm();
        }
    }
    total
}

/// Arms that may push a line whose back object is `back`, in order of preference: the arm that
/// picked it (its hand is already over the container), then the other allowed arm. Pushes
/// happen inside the container, which both arms reach, so either may be the one that can.
pub fn push_arms(inst: &Instance, back: usize) -> Vec<Arm> {
    let first = pick_arm(inst, back);
    let mut arms = vec![first];
    if inst.robot.arms.contains(&first.other()) {
        arms.push(first.other());
    }
    arms
}

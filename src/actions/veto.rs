//! Actions a physics replay rejected, each in the neighbourhood it was tried in.
//!
//! The push rules are quasi-static and see the line, the finger, the floor and the faces beside
//! the line ([`super::push::side`]); a replay in a physics engine sees everything. When it moves
//! a box out of tolerance, the planner records the action together with the state of every box
//! near it, and the sequencers treat that action as infeasible whenever the same neighbourhood
//! recurs (`docs/push_stability.md` §13). Elsewhere the action stays allowed: a neighbourhood is
//! what the replay's outcome depends on.

use super::{Action, Layout, ObjState};
use crate::geometry::Rect;

/// How far (m) from an action's footprints a box counts as its neighbour: a finger's width,
/// more than any contact or finger slab of the action reaches.
pub const NEIGHBOURHOOD: f64 = 0.02;

/// One rejected action and the neighbourhood it was rejected in.
#[derive(Debug, Clone, PartialEq)]
pub struct Veto {
    /// The action (its arm included: the finger's path is the same for either arm, but a
    /// veto stays exactly as specific as the replay that found it).
    pub action: Action,
    /// Every other box in the container near the action, with its state, by index.
    pub neighbourhood: Vec<(usize, ObjState)>,
    /// What the replay saw, for messages.
    pub reason: String,
}

impl Veto {
    /// The veto of `action` in `layout`'s state.
    pub fn new(layout: &Layout, action: &Action, reason: String) -> Veto {
        Veto {
            action: action.clone(),
            neighbourhood: layout.neighbourhood(action),
            reason,
        }
    }

    /// Whether this veto rejects `action` in `layout`'s state.
    pub fn rejects(&self, layout: &Layout, action: &Action) -> bool {
        let same = match (&self.action, action) {
            (
                Action::Place {
                    object: a,
                    mode: ma,
                    grasp_axis: ga,
                    ..
                },
                Action::Place {
                    object: b,
                    mode: mb,
                    grasp_axis: gb,
                    ..
                },
            ) => a == b && ga == gb && same_mode(ma, mb),
            (
                Action::Push {
                    objects: a,
                    push_dir: da,
                    distance: xa,
                    ..
                },
                Action::Push {
                    objects: b,
                    push_dir: db,
                    distance: xb,
                    ..
                },
            ) => a == b && da == db && (xa - xb).abs() <= crate::geometry::EPS,
            _ => false,
        };
        // A push's neighbourhood holds the line's own releases too. States are compared to the
        // geometric tolerance: a search may rebuild a release from its offset step.
        let here = layout.neighbourhood(action);
        same && here.len() == self.neighbourhood.len()
            && here
                .iter()
                .zip(&self.neighbourhood)
                .all(|((i, a), (j, b))| i == j && same_state(a, b))
    }
}

fn same_mode(a: &super::PlaceMode, b: &super::PlaceMode) -> bool {
    use super::PlaceMode::*;
    match (a, b) {
        (Direct, Direct) => true,
        (
            Indirect {
                push_dir: da,
                offset: oa,
            },
            Indirect {
                push_dir: db,
                offset: ob,
            },
        ) => da == db && (oa - ob).abs() <= crate::geometry::EPS,
        _ => false,
    }
}

fn same_state(a: &ObjState, b: &ObjState) -> bool {
    use crate::geometry::EPS;
    match (a, b) {
        (
            ObjState::Released {
                rect: ra,
                push_dir: da,
                offset: oa,
            },
            ObjState::Released {
                rect: rb,
                push_dir: db,
                offset: ob,
            },
        ) => {
            da == db
                && (oa - ob).abs() <= EPS
                && [ra.x0 - rb.x0, ra.y0 - rb.y0, ra.x1 - rb.x1, ra.y1 - rb.y1]
                    .iter()
                    .all(|d| d.abs() <= EPS)
        }
        _ => a == b,
    }
}

impl Layout<'_> {
    /// Every box in the container other than the ones `action` moves, within
    /// [`NEIGHBOURHOOD`] of the footprints the action's boxes occupy from start to end, and
    /// the line's own releases (a push's outcome depends on its gaps), by index.
    pub fn neighbourhood(&self, action: &Action) -> Vec<(usize, ObjState)> {
        let moved = action.objects();
        let reach: Vec<Rect> = moved
            .iter()
            .map(|&i| {
                let target = self.placement.targets[i].rect;
                let r = match action {
                    Action::Place { mode, .. } => self.release_rect(i, mode),
                    Action::Push { .. } => self.rect_of(i).map_or(target, |r| r.union(&target)),
                };
                Rect {
                    x0: r.x0 - NEIGHBOURHOOD,
                    y0: r.y0 - NEIGHBOURHOOD,
                    x1: r.x1 + NEIGHBOURHOOD,
                    y1: r.y1 + NEIGHBOURHOOD,
                }
            })
            .collect();
        (0..self.state.len())
            .filter_map(|j| {
                if moved.contains(&j) {
                    return matches!(action, Action::Push { .. }).then_some((j, self.state[j]));
                }
                let r = self.rect_of(j)?;
                reach.iter().any(|n| n.overlaps(&r)).then_some((j, self.state[j]))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Arm, Axis2, PushDir};
    use crate::instance::InstanceBuilder;

    #[test]
    fn a_veto_rejects_its_action_only_in_its_neighbourhood() {
        // Three boxes in a row along x; box 2 far to the right.
        let inst = InstanceBuilder::new("veto")
            .container(0.3, 0.2, 0.1, 0.01, [0.3, 0.0])
            .friction(0.35, 0.4, 0.6)
            .kind("k", [0.04, 0.04, 0.03], 0.05)
            .object("a", "k", [0.2, 0.2], crate::instance::Orientations::Upright)
            .object("b", "k", [0.2, 0.25], crate::instance::Orientations::Upright)
            .object("c", "k", [0.2, 0.3], crate::instance::Orientations::Upright)
            .build()
            .expect("a valid instance");
        let target = |rect| crate::placement::Target {
            orientation: crate::geometry::Orientation {
                up: crate::geometry::BodyAxis::Z,
                yaw90: false,
            },
            rect,
            height: 0.03,
        };
        let placement = crate::placement::Placement {
            targets: vec![
                target(Rect::new(0.0, 0.0, 0.04, 0.04)),
                target(Rect::new(0.0, 0.04, 0.04, 0.04)),
                target(Rect::new(0.2, 0.0, 0.04, 0.04)),
            ],
        };
        let place = |object| Action::Place {
            object,
            mode: super::super::PlaceMode::Indirect {
                push_dir: PushDir::MinusX,
                offset: 0.015,
            },
            grasp_axis: Axis2::Y,
            arm: Arm::Left,
        };
        let push = Action::Push {
            objects: vec![0],
            push_dir: PushDir::MinusX,
            distance: 0.015,
            pusher_at: 0.02,
            arm: Arm::Left,
        };
        let mut layout = Layout::new(&inst, &placement);
        layout.apply(&place(0));
        let veto = Veto::new(&layout, &push, "test".into());
        assert!(veto.rejects(&layout, &push));
        // The same push by the other arm is the same push.
        let other_arm = Action::Push {
            objects: vec![0],
            push_dir: PushDir::MinusX,
            distance: 0.015,
            pusher_at: 0.02,
            arm: Arm::Right,
        };
        assert!(veto.rejects(&layout, &other_arm));
        // A box far away changes nothing; a neighbour released beside the line does.
        let mut far = layout.clone();
        far.apply(&place(2));
        assert!(veto.rejects(&far, &push));
        let mut near = layout.clone();
        near.apply(&place(1));
        assert!(!veto.rejects(&near, &push));
    }
}

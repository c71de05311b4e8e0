//! Side contacts of a push: the faces a pushed box slides along, and whether they hold.
//!
//! The line checks ([`super::line_verdict`]) see the pushed boxes, the finger and the floor. A
//! dense container adds faces *beside* the line, parallel to the push: a neighbour, a wall, or
//! one on each side (a slot). At zero nominal clearance their normal force is statically
//! indeterminate — any release error of half a millimetre or half a degree makes corner meet
//! face — so their friction, up to `μ_obj` times whatever the finger presses into them, can act
//! (docs/push_stability.md §12):
//!
//! * **A neighbour that nothing holds against the push is dragged.** Its floor friction
//!   `μ_floor m g` is all that keeps it, while the normal force of a wedged contact grows with
//!   the push force. A box released for a later push (a gap ahead of it) and a box whose face
//!   ahead touches no chain of held boxes down to a wall are such neighbours.
//! * **A box between faces on both sides can wedge.** With one face on each side, the two
//!   normal forces can balance each other with no upper bound (the planar peg-in-hole jam: a
//!   box turned by `θ` in a slot of clearance `c` touches both faces once `L sin θ ≥ c`, and
//!   friction on both faces can then resist the push with any force the finger applies). Whether
//!   it does depends on the turn, which the finger's flat face removes before the box enters;
//!   measured, rejecting every slot costs plans and buys no replay that passes, so it is an
//!   option (`planner.forbid_slots`), and the physics replay judges slots.
//! * **A neighbour held against the push is safe.** A wall or a held box cannot move along the
//!   push: the pushed box is only aligned by it.
//!
//! A face beside a box counts when the lateral gap is below the clearance and the box's sweep
//! (release to target) runs along it for a positive length.

use crate::geometry::{Axis2, PushDir, Rect, EPS};

/// A box in the container that a push does not move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Standing {
    /// Object index.
    pub object: usize,
    /// Its footprint now.
    pub rect: Rect,
    /// At its target (`false`: released, waiting for its push, with a gap ahead of it).
    pub at_target: bool,
}

/// Why a push's side contacts make it fail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SideFailure {
    /// `moving` slides along `neighbour`, which nothing holds against the push.
    Drags {
        /// The pushed object.
        moving: usize,
        /// The object it would drag.
        neighbour: usize,
    },
    /// `moving` slides between faces on both of its sides.
    Wedged {
        /// The pushed object.
        moving: usize,
    },
}

/// The boxes of `standing` that are held against a push along `dir`: at their target, with the
/// face ahead of them touching (over a positive length) the wall or a held box.
pub fn held_against(floor: &Rect, standing: &[Standing], dir: PushDir) -> Vec<bool> {
    let a = dir.axis();
    let lat = a.other();
    let mut held = vec![false; standing.len()];
    // A chain runs toward the wall: settle boxes in order of their face ahead, nearest first.
    let mut order: Vec<usize> = (0..standing.len()).filter(|&k| standing[k].at_target).collect();
    order.sort_by(|&p, &q| standing[p].rect.lo(a).total_cmp(&standing[q].rect.lo(a)));
    for (n, &k) in order.iter().enumerate() {
        let r = standing[k].rect;
        held[k] = (r.lo(a) - floor.lo(a)).abs() <= EPS
            || order[..n].iter().any(|&j| {
                held[j] && (standing[j].rect.hi(a) - r.lo(a)).abs() <= EPS && standing[j].rect.overlap_on(&r, lat) > EPS
            });
    }
    held
}

/// How side contacts are judged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideRule {
    /// Lateral gap (m) below which a face beside a sweep is a side contact
    /// (`planner.side_clearance`).
    pub clearance: f64,
    /// Count every box at its target as held (see [`side_failure`]).
    pub assume_held: bool,
    /// Reject a box with side contacts on both sides (`planner.forbid_slots`, default off:
    /// measured, it leaves dense placements without a plan and buys no replay that passes;
    /// docs/push_stability.md §12).
    pub forbid_slots: bool,
}

/// The first side contact that makes pushing `moving` (object, sweep from release to target)
/// along `dir` fail, with `standing` the other boxes in the container and `floor` the
/// container's floor (its walls are the faces beyond it); `None` when every side holds.
///
/// `rule.assume_held` counts every box at its target as held. Bounds that reason about one
/// neighbour at a time need it: whether a box is held depends on the others, and a box that
/// more boxes can only hold must not be read as a blocker for good. With it the predicate is
/// monotone — more boxes in the container never turn a failure into a success.
pub fn side_failure(
    floor: &Rect,
    moving: &[(usize, Rect)],
    standing: &[Standing],
    dir: PushDir,
    rule: &SideRule,
) -> Option<SideFailure> {
    let SideRule {
        clearance, assume_held, ..
    } = *rule;
    let a = dir.axis();
    let lat: Axis2 = a.other();
    let mut held: Option<Vec<bool>> = None;
    for &(i, sweep) in moving {
        // Faces beside the sweep: below (toward lower lateral values) and above.
        let mut below = sweep.lo(lat) - floor.lo(lat) < clearance;
        let mut above = floor.hi(lat) - sweep.hi(lat) < clearance;
        for (k, s) in standing.iter().enumerate() {
            if moving.iter().any(|m| m.0 == s.object) || sweep.overlap_on(&s.rect, a) <= EPS {
                continue;
            }
            let gap_below = sweep.lo(lat) - s.rect.hi(lat);
            let gap_above = s.rect.lo(lat) - sweep.hi(lat);
            let side = if (-EPS..clearance).contains(&gap_below) {
                &mut below
            } else if (-EPS..clearance).contains(&gap_above) {
                &mut above
            } else {
                continue;
            };
            *side = true;
            let is_held = if assume_held {
                s.at_target
            } else {
                held.get_or_insert_with(|| held_against(floor, standing, dir))[k]
            };
            if !is_held {
                return Some(SideFailure::Drags {
                    moving: i,
                    neighbour: s.object,
                });
            }
        }
        if below && above && rule.forbid_slots {
            return Some(SideFailure::Wedged { moving: i });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floor() -> Rect {
        Rect::new(0.0, 0.0, 0.3, 0.2)
    }
    fn at(object: usize, x: f64, y: f64, w: f64, d: f64, at_target: bool) -> Standing {
        Standing {
            object,
            rect: Rect::new(x, y, w, d),
            at_target,
        }
    }

    fn rule(forbid_slots: bool) -> SideRule {
        SideRule {
            clearance: 1e-3,
            assume_held: false,
            forbid_slots,
        }
    }

    #[test]
    fn a_chain_to_the_wall_holds_and_a_gap_breaks_it() {
        let s = [
            at(0, 0.0, 0.0, 0.05, 0.05, true),
            at(1, 0.05, 0.0, 0.05, 0.05, true),
            at(2, 0.101, 0.0, 0.05, 0.05, true),
            at(3, 0.0, 0.1, 0.05, 0.05, false),
        ];
        assert_eq!(
            held_against(&floor(), &s, PushDir::MinusX),
            vec![true, true, false, false]
        );
        // Along −y the first row stands on the wall; the released box does not count.
        assert_eq!(
            held_against(&floor(), &s, PushDir::MinusY),
            vec![true, true, true, false]
        );
    }

    #[test]
    fn sliding_along_a_released_box_drags_it_and_along_a_held_one_does_not() {
        // Box 9 pushed along −x in the row above y = 0.05, beside box 1 (held) or box 3 (released).
        let sweep = Rect::new(0.05, 0.05, 0.08, 0.05);
        let held = [at(0, 0.0, 0.0, 0.05, 0.05, true), at(1, 0.05, 0.0, 0.05, 0.05, true)];
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &held, PushDir::MinusX, &rule(false)),
            None
        );
        let free = [at(3, 0.07, 0.0, 0.05, 0.05, false)];
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &free, PushDir::MinusX, &rule(false)),
            Some(SideFailure::Drags {
                moving: 9,
                neighbour: 3
            })
        );
        // With 2 mm between them the released box is not touched.
        let apart = [at(3, 0.07, 0.0, 0.05, 0.048, false)];
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &apart, PushDir::MinusX, &rule(false)),
            None
        );
    }

    #[test]
    fn a_slot_is_found_whatever_holds_its_faces() {
        // Between the wall y = 0 and a held box above: a slot.
        let sweep = Rect::new(0.05, 0.0, 0.08, 0.05);
        let above = [at(0, 0.0, 0.05, 0.1, 0.05, true)];
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &above, PushDir::MinusX, &rule(true)),
            Some(SideFailure::Wedged { moving: 9 })
        );
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &above, PushDir::MinusX, &rule(false)),
            None
        );
        // Along the wall alone it only aligns.
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &[], PushDir::MinusX, &rule(false)),
            None
        );
        // A box ahead of the sweep, not beside it, is no side.
        let ahead = [at(0, 0.0, 0.0, 0.05, 0.1, true)];
        assert_eq!(
            side_failure(&floor(), &[(9, sweep)], &ahead, PushDir::MinusX, &rule(false)),
            None
        );
    }
}

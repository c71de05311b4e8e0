//! The context of planning one action, and the memo of inverse-kinematics results.

use super::*;
use crate::geometry::parry_bridge::Solid;

/// The context of planning one action.
pub(super) struct Ctx<'a> {
    pub(super) inst: &'a Instance,
    pub(super) placement: &'a Placement,
    pub(super) statics: Vec<Obstacle>,
    /// Objects before the action.
    pub(super) at: Vec<ObjAt>,
    /// The idle arm as obstacles.
    pub(super) other: Vec<Obstacle>,
    /// Which collisions to check.
    pub(super) scope: Scope,
    /// Joint moves go to any IK branch at the target, not the nearest (the predicate).
    pub(super) fast_ik: bool,
    /// Memo of IK results shared between the predicate's queries (see [`IkMemo`]).
    pub(super) memo: Option<&'a RefCell<IkMemo>>,
}

/// IK results by their exact inputs, for one instance: the reachability predicate's (actions of
/// one object share their table half, pre-grasp, grasp, lift: the same poses for every release
/// mode, and an unreachable pose costs a search over every IK seed, so repeating it per mode
/// dominated the predicate's time) and the joint plan's. Each entry is what the call computes
/// from its key, so a hit changes no answer.
#[derive(Debug, Default)]
pub struct IkMemo {
    map: HashMap<Vec<u64>, Result<Vec<[f64; 6]>, RobotError>>,
    /// Collision checks of the predicate's straight lines by their exact inputs (see
    /// [`check_key`]): the first collision's part, obstacle and TCP, or none.
    checks: HashMap<Vec<u64>, Option<Hit>>,
}

/// A collision found by a sample check: part, obstacle, TCP (the error without its move name).
pub(super) type Hit = (String, String, [f64; 3]);

/// Everything a collision check of sampled configurations reads besides the instance: arm,
/// hand, margin, the samples, the obstacles (name, kind, solid and pose of each) and which pairs
/// are skipped (the pusher on the pushed objects, from the segment on).
pub(super) fn check_key(
    arm: Arm,
    hand: &Hand,
    margin: f64,
    qs: &[[f64; 6]],
    obstacles: &[Obstacle],
    skipped: Option<&[usize]>,
) -> Vec<u64> {
    let mut k = vec![arm.index() as u64, hand.opening.to_bits(), margin.to_bits()];
    match hand.held {
        None => k.push(0),
        Some(h) => k.extend([
            1,
            h.object as u64,
            h.closing.to_bits(),
            h.other.to_bits(),
            h.height.to_bits(),
        ]),
    }
    match skipped {
        None => k.push(0),
        Some(objects) => {
            k.extend([1, objects.len() as u64]);
            k.extend(objects.iter().map(|&i| i as u64));
        }
    }
    k.push(qs.len() as u64);
    k.extend(qs.iter().flatten().map(|x| x.to_bits()));
    k.push(obstacles.len() as u64);
    for o in obstacles {
        k.push(o.name.len() as u64);
        k.extend(o.name.bytes().map(u64::from));
        k.push(match o.kind {
            ObstacleKind::Wall(w) => w as u64,
            ObstacleKind::Floor => 100,
            ObstacleKind::Table => 101,
            ObstacleKind::Object(i) => 1000 + i as u64,
            ObstacleKind::OtherArm => 102,
        });
        let solid: Vec<f64> = match o.solid {
            Solid::Cuboid { half } => vec![0.0, half.x, half.y, half.z],
            Solid::Cylinder { radius, half_length } => vec![1.0, radius, half_length],
            Solid::Capsule { a, b, radius } => vec![2.0, a.x, a.y, a.z, b.x, b.y, b.z, radius],
            Solid::Ball { radius } => vec![3.0, radius],
        };
        k.extend(solid.iter().map(|x| x.to_bits()));
        k.extend(o.pose.translation.vector.iter().map(|x| x.to_bits()));
        k.extend(o.pose.rotation.coords.iter().map(|x| x.to_bits()));
    }
    k
}

impl IkMemo {
    /// The memoised result with key `key()`, else `f`'s, remembered (nothing without a memo).
    pub(super) fn get(
        cell: Option<&RefCell<IkMemo>>,
        key: impl FnOnce() -> Vec<u64>,
        f: impl FnOnce() -> Result<Vec<[f64; 6]>, RobotError>,
    ) -> Result<Vec<[f64; 6]>, RobotError> {
        let Some(cell) = cell else {
            return f();
        };
        let k = key();
        if let Some(v) = cell.borrow().map.get(&k) {
            return v.clone();
        }
        let v = f();
        cell.borrow_mut().map.insert(k, v.clone());
        v
    }

    /// The memoised answer of the check with key `key`, else `f`'s, remembered.
    pub(super) fn check(cell: &RefCell<IkMemo>, key: Vec<u64>, f: impl FnOnce() -> Option<Hit>) -> Option<Hit> {
        if let Some(v) = cell.borrow().checks.get(&key) {
            return v.clone();
        }
        let v = f();
        cell.borrow_mut().checks.insert(key, v.clone());
        v
    }
}

/// Exact bits of a pose, a configuration and a few more numbers, as a memo key.
pub(super) fn key_bits(tag: u64, arm: Arm, poses: &[&Isometry3<f64>], q: Option<&[f64; 6]>, extra: &[f64]) -> Vec<u64> {
    let mut k = vec![tag, arm.index() as u64];
    for p in poses {
        k.extend(p.translation.vector.iter().map(|x| x.to_bits()));
        k.extend(p.rotation.coords.iter().map(|x| x.to_bits()));
    }
    if let Some(q) = q {
        k.extend(q.iter().map(|x| x.to_bits()));
    }
    k.extend(extra.iter().map(|x| x.to_bits()));
    k
}

/// Which collisions a [`Ctx`] checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scope {
    /// None: kinematics only (ranking hand variants).
    Kinematic,
    /// The reachability predicate: the straight lines of the action (descents, lifts, releases,
    /// retreats, the push) against the fixed cell (walls, floor plate, table). Joint-space moves
    /// depend on where the arm comes from and the objects on the state, so they are left to the
    /// joint plan (objects on the table are handled as pick blockers).
    StaticLines,
    /// Everything: the joint plan.
    Full,
}

impl Ctx<'_> {
    pub(super) fn object_obstacle(&self, i: usize, at: ObjAt) -> Obstacle {
        match at {
            ObjAt::Table => object_on_table(self.inst, i),
            ObjAt::Floor(r) => object_in_container(self.inst, i, &r, self.placement.targets[i].height),
        }
    }

    /// Obstacles during segment `seg` of `action` (before the TCP-dependent push motion).
    pub(super) fn obstacles(&self, action: &Action, seg: usize, tcp: Option<&Vector3<f64>>) -> Vec<Obstacle> {
        let mut out = self.statics.clone();
        if self.scope == Scope::StaticLines {
            out.extend(self.other.iter().cloned());
            // A push's back object is where the action says (its target moved back by the push
            // distance) whatever the state: the pusher descends behind it and drives it, and a
            // hand housing hanging below its top hits it.
            if let Action::Push {
                objects,
                push_dir,
                distance,
                ..
            } = action
            {
                let back = *objects.last().expect("a push moves an object");
                let rel = [self.placement.targets[back].rect.moved(*push_dir, -distance)];
                let now = match (seg, tcp) {
                    (0 | 1, _) => rel[0],
                    (2, Some(p)) => {
                        let c = to_container(self.inst, p);
                        let face = c[push_dir.axis().index()] - self.inst.gripper.finger_thickness / 2.0;
                        pushed_rects(&rel, *push_dir, face)[0]
                    }
                    _ => self.placement.targets[back].rect,
                };
                out.push(self.object_obstacle(back, ObjAt::Floor(now)));
            }
            return out;
        }
        out.extend(self.other.iter().cloned());
        let n = self.inst.n();
        match action {
            Action::Place { object, mode, .. } => {
                for i in 0..n {
                    if i == *object {
                        match seg {
                            0 | 1 => out.push(self.object_obstacle(i, self.at[i])),
                            5.. => {
                                out.push(self.object_obstacle(i, ObjAt::Floor(release_rect(self.placement, i, mode))))
                            }
                            _ => {}
                        }
                    } else {
                        out.push(self.object_obstacle(i, self.at[i]));
                    }
                }
            }
            Action::Push { objects, push_dir, .. } => {
                let rel: Vec<Rect> = objects
                    .iter()
                    .map(|&i| match self.at[i] {
                        ObjAt::Floor(r) => r,
                        ObjAt::Table => self.placement.targets[i].rect,
                    })
                    .collect();
                let now: Vec<Rect> = match (seg, tcp) {
                    (0 | 1, _) => rel.clone(),
                    (2, Some(p)) => {
                        let c = to_container(self.inst, p);
                        let face = c[push_dir.axis().index()] - self.inst.gripper.finger_thickness / 2.0;
                        pushed_rects(&rel, *push_dir, face)
                    }
                    _ => objects.iter().map(|&i| self.placement.targets[i].rect).collect(),
                };
                for i in 0..n {
                    match objects.iter().position(|&j| j == i) {
                        Some(k) => out.push(self.object_obstacle(i, ObjAt::Floor(now[k]))),
                        None => out.push(self.object_obstacle(i, self.at[i])),
                    }
                }
            }
        }
        out
    }

    /// Pairs that are allowed to touch beyond the tolerance: the pusher on the pushed line.
    /// ([`check_key`] holds what this reads: change both together.)
    pub(super) fn skip(action: &Action, seg: usize) -> impl Fn(&Part, &Obstacle) -> bool + '_ {
        move |p: &Part, o: &Obstacle| match (action, o.kind) {
            (Action::Push { objects, .. }, ObstacleKind::Object(i)) => {
                p.kind == PartKind::Finger && seg >= 2 && objects.contains(&i)
            }
            _ => false,
        }
    }
}

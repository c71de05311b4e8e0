//! Reachability as a planner predicate: [`super::joint_plan::action_reach`] (inverse kinematics of
//! every key pose and collision checks of the straight lines against the fixed cell, a few to
//! tens of ms) memoised per action, since it does not depend on where the other objects are;
//! the objects on the table that block a pick are checked against the state on every query, and
//! so are the objects already packed, in a cell where the hand comes down among them.
//!
//! The planners ask millions of times for a few hundred distinct actions, so a hit must be
//! cheap: the memo hashes the action's fields directly (no formatted string per call) and
//! compares whole actions on a hash match, so two actions never share an answer by accident.

use super::joint_plan::{action_reach_memo, IkMemo, Reach};
use crate::actions::{Action, Layout, ObjState, PlaceMode};
use crate::instance::Instance;
use crate::placement::Placement;
use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Action hash → the actions with that hash and their answers.
type ReachMemo = HashMap<u64, Vec<(Action, Option<Reach>)>, BuildHasherDefault<IdentityHasher>>;
/// Memoised "some arm can execute this action" for one instance and placement.
pub struct ReachCache<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    /// Action hash → the actions with that hash and their answers (almost always one).
    memo: RefCell<ReachMemo>,
    /// IK results shared between actions (see [`IkMemo`]).
    ik: RefCell<IkMemo>,
}

/// The keys are already well-mixed hashes: use them as they are.
#[derive(Default)]
struct IdentityHasher(u64);

impl Hasher for IdentityHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 << 8) | u64::from(*b);
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = v;
    }
}

/// A 64-bit hash of every field of an action (f64 fields by bit pattern).
fn action_hash(a: &Action) -> u64 {
    // FxHash-style mixing: multiply-rotate per word. Collisions are resolved by comparing the
    // actions, so the hash only has to spread, not to be unique.
    let mut h: u64 = 0;
    let mut mix = |w: u64| h = (h.rotate_left(5) ^ w).wrapping_mul(0x517c_c1b7_2722_0a95);
    match a {
        Action::Place {
            object,
            mode,
            grasp_axis,
            arm,
        } => {
            mix(1);
            mix(*object as u64);
            match mode {
                PlaceMode::Direct => mix(2),
                PlaceMode::Indirect { push_dir, offset } => {
                    mix(3 + *push_dir as u64);
                    mix(offset.to_bits());
                }
            }
            mix(*grasp_axis as u64);
            mix(*arm as u64);
        }
        Action::Push {
            objects,
            push_dir,
            distance,
            pusher_at,
            arm,
        } => {
            mix(7);
            for &o in objects {
                mix(o as u64);
            }
            mix(u64::MAX);
            mix(*push_dir as u64);
            mix(distance.to_bits());
            mix(pusher_at.to_bits());
            mix(*arm as u64);
        }
    }
    // splitmix64's finaliser: the multiply above only carries low bits upward, and the map
    // indexes buckets by the low bits.
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    h ^ (h >> 31)
}

impl<'a> ReachCache<'a> {
    /// An empty cache.
    pub fn new(inst: &'a Instance, placement: &'a Placement) -> Self {
        ReachCache {
            inst,
            placement,
            memo: RefCell::new(HashMap::default()),
            ik: RefCell::new(IkMemo::default()),
        }
    }

    fn with<T>(&self, a: &Action, f: impl FnOnce(Option<&Reach>) -> T) -> T {
        let k = action_hash(a);
        if let Some(bucket) = self.memo.borrow().get(&k) {
            if let Some((_, v)) = bucket.iter().find(|(b, _)| b == a) {
                return f(v.as_ref());
            }
        }
        let v = action_reach_memo(self.inst, self.placement, a, &self.ik, true);
        let out = f(v.as_ref());
        self.memo.borrow_mut().entry(k).or_default().push((a.clone(), v));
        out
    }

    /// Whether the action's arm reaches all its key poses with its straight lines free of the
    /// fixed cell, ignoring objects on the table.
    pub fn ok(&self, a: &Action) -> bool {
        self.with(a, |r| r.is_some())
    }

    /// [`Self::ok`], and in `state` some hand variant is blocked neither by an object still on
    /// the table nor by one already in the container.
    pub fn ok_when(&self, a: &Action, state: &[ObjState]) -> bool {
        self.with(a, |r| {
            r.is_some_and(|r| {
                if !r.reaches_down() {
                    return r.free_when(|j| state[j] == ObjState::Table);
                }
                r.free_in(self.inst, self.placement, |j| match state[j] {
                    ObjState::Table => None,
                    ObjState::Released { rect, .. } => Some(rect),
                    ObjState::Done => Some(self.placement.targets[j].rect),
                })
            })
        })
    }

    /// Per hand variant found, the objects that block it while still on the table (an empty
    /// set when some variant is free; the search stops at the first free one); `None` when the
    /// action is unreachable whatever is on the table.
    pub fn table_blockers(&self, a: &Action) -> Option<Vec<Vec<usize>>> {
        self.with(a, |r| r.map(|r| r.table_blockers.clone()))
    }

    /// [`Self::ok_when`] in the state of `layout`.
    pub fn ok_in(&self, a: &Action, layout: &Layout) -> bool {
        self.ok_when(a, &layout.state)
    }
}

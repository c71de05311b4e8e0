//! Reachability as a planner predicate: [`super::motion::action_reach`] (inverse kinematics
//! of every key pose and collision checks of the straight lines against the fixed cell, a few
//! ms) memoised per action, since it does not depend on where the other objects are; the
//! objects on the table that block a pick are checked against the state on every query.

use super::motion::{action_reach_memo, IkMemo, Reach};
use crate::actions::{Action, Layout, ObjState};
use crate::instance::Instance;
use crate::placement::Placement;
use std::cell::RefCell;
use std::collections::HashMap;

/// Memoised "some arm can execute this action" for one instance and placement.
pub struct ReachCache<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    memo: RefCell<HashMap<String, Option<Reach>>>,
    ik: RefCell<IkMemo>,
}

impl<'a> ReachCache<'a> {
    /// An empty cache.
    pub fn new(inst: &'a Instance, placement: &'a Placement) -> Self {
        ReachCache {
            inst,
            placement,
            memo: RefCell::new(HashMap::new()),
            ik: RefCell::new(IkMemo::default()),
        }
    }

    fn with<T>(&self, a: &Action, f: impl FnOnce(Option<&Reach>) -> T) -> T {
        let k = format!("{a:?}");
        if let Some(v) = self.memo.borrow().get(&k) {
            return f(v.as_ref());
        }
        let v = action_reach_memo(self.inst, self.placement, a, &self.ik, true);
        let out = f(v.as_ref());
        self.memo.borrow_mut().insert(k, v);
        out
    }

    /// Whether the action's arm reaches all its key poses with its straight lines free of the
    /// fixed cell, ignoring objects on the table.
    pub fn ok(&self, a: &Action) -> bool {
        self.with(a, |r| r.is_some())
    }

    /// [`Self::ok`], and no object still on the table (in `layout`) blocks the pick.
    pub fn ok_in(&self, a: &Action, layout: &Layout) -> bool {
        self.with(a, |r| {
            r.is_some_and(|r| r.free_when(|j| layout.state[j] == ObjState::Table))
        })
    }
}

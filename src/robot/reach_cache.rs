//! Reachability as a planner predicate: [`super::motion::action_reachable`] (inverse kinematics
//! of every key pose, about 1 ms) memoised per action, since it does not depend on where the
//! other objects are.

use crate::actions::Action;
use crate::instance::Instance;
use crate::placement::Placement;
use std::cell::RefCell;
use std::collections::HashMap;

/// Memoised "some arm can execute this action" for one instance and placement.
pub struct ReachCache<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    memo: RefCell<HashMap<String, bool>>,
}

impl<'a> ReachCache<'a> {
    /// An empty cache.
    pub fn new(inst: &'a Instance, placement: &'a Placement) -> Self {
        ReachCache {
            inst,
            placement,
            memo: RefCell::new(HashMap::new()),
        }
    }

    /// Whether the action's arm reaches all its key poses.
    pub fn ok(&self, a: &Action) -> bool {
        let k = format!("{a:?}");
        if let Some(v) = self.memo.borrow().get(&k) {
            return *v;
        }
        let v = super::motion::action_reachable(self.inst, self.placement, a);
        self.memo.borrow_mut().insert(k, v);
        v
    }
}

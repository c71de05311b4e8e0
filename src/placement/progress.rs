//! Progress events of the exact placement ([`Event::Progress`] with [`Stage::Placement`]): nodes so
//! far, the incumbent's occupied area and the proven lower bound on it, at most one per
//! [`crate::control::PROGRESS_INTERVAL`], sent from the searches' stop polls.

use crate::control::{Event, Listener, Stage, Ticker};
use std::cell::{Cell, RefCell};

/// What the exact placement has reached, and the listener it tells. Shared by reference with the
/// stop closures (which are `Fn`), hence the cells.
pub(crate) struct Progress<'a> {
    listener: RefCell<&'a mut dyn Listener>,
    ticker: Cell<Ticker>,
    /// Search nodes so far: those of finished searches plus the running search's count at its
    /// last stop poll (a search's meter, [`super::opp::Search::metered`]).
    pub(crate) nodes: Cell<u64>,
    incumbent: Cell<Option<f64>>,
    bound: Cell<Option<f64>>,
}

impl<'a> Progress<'a> {
    /// Nothing reached yet; `nodes` starts the count (the warm start's nodes).
    pub(crate) fn new(listener: &'a mut dyn Listener, nodes: u64) -> Self {
        Progress {
            listener: RefCell::new(listener),
            ticker: Cell::new(Ticker::new()),
            nodes: Cell::new(nodes),
            incumbent: Cell::new(None),
            bound: Cell::new(None),
        }
    }

    /// Record a proven lower bound and the incumbent's area (m²). Both come from the area
    /// stage, whose bound only rises and never passes its incumbent; the event keeps the
    /// largest bound seen so that a rounding difference can never show it falling.
    pub(crate) fn set(&self, bound: f64, incumbent: Option<f64>) {
        if bound.is_finite() {
            self.bound.set(Some(self.bound.get().map_or(bound, |b| b.max(bound))));
        }
        if incumbent.is_some() {
            self.incumbent.set(incumbent);
        }
    }

    /// Raise the node count to `n` (a count only grows).
    pub(crate) fn reach_nodes(&self, n: u64) {
        self.nodes.set(self.nodes.get().max(n));
    }

    /// Send an event if one is due: a clock read otherwise, so every stop poll may call it.
    pub(crate) fn tick(&self) {
        let mut t = self.ticker.get();
        let due = t.due();
        self.ticker.set(t);
        if due {
            self.listener.borrow_mut().event(&Event::Progress {
                stage: Stage::Placement,
                nodes: self.nodes.get(),
                incumbent: self.incumbent.get(),
                bound: self.bound.get(),
            });
        }
    }
}

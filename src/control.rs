//! Run control passed into long runs: when to stop ([`Terminator`]) and whom to tell ([`Listener`]).

use crate::status::Status;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Decides when a long-running solver must stop and return its best result so far.
pub trait Terminator {
    /// True once the run must stop.
    fn should_stop(&self) -> bool;
}

/// Stops after a wall-clock duration.
#[derive(Debug, Clone, Copy)]
pub struct TimeLimit {
    start: Instant,
    limit: Duration,
}

impl TimeLimit {
    /// A limit of `seconds` from now.
    pub fn new(seconds: f64) -> TimeLimit {
        TimeLimit {
            start: Instant::now(),
            limit: Duration::from_secs_f64(seconds.max(0.0)),
        }
    }
    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

impl Terminator for TimeLimit {
    fn should_stop(&self) -> bool {
        self.start.elapsed() >= self.limit
    }
}

/// Stops when the caller says so: a flag shared with another thread (a Ctrl+C handler, a GUI
/// button, a cell controller's abort).
#[derive(Debug, Clone, Default)]
pub struct CancelFlag(Arc<AtomicBool>);

impl CancelFlag {
    /// A flag that is not set.
    pub fn new() -> CancelFlag {
        CancelFlag::default()
    }
    /// Ask the run to stop; it returns its best result so far.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }
    /// True once [`cancel`](Self::cancel) was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

impl Terminator for CancelFlag {
    fn should_stop(&self) -> bool {
        self.is_cancelled()
    }
}

/// Never stops.
#[derive(Debug, Clone, Copy, Default)]
pub struct Never;

impl Terminator for Never {
    fn should_stop(&self) -> bool {
        false
    }
}

/// Stops when either of two terminators does: a stage's own deadline and the caller's.
pub(crate) struct Either<'a>(pub &'a dyn Terminator, pub &'a dyn Terminator);

impl Terminator for Either<'_> {
    fn should_stop(&self) -> bool {
        self.0.should_stop() || self.1.should_stop()
    }
}

/// A stage of a planning run, as progress events name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Orientations and footprints in the container.
    Placement,
    /// Actions and their order.
    Sequence,
    /// Joint trajectories of the actions.
    Motion,
}

impl Stage {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Placement => "placement",
            Stage::Sequence => "sequence",
            Stage::Motion => "motion",
        }
    }
}

/// What a run reports while it works.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum Event {
    /// A stage starts, with the seconds it may use at most.
    StageStarted {
        /// The stage.
        stage: Stage,
        /// Its time budget (s).
        budget_s: f64,
    },
    /// A stage ends.
    StageFinished {
        /// The stage.
        stage: Stage,
        /// What it proved.
        status: Status,
        /// Its wall-clock time (s).
        time_s: f64,
        /// Search nodes (placement: branch-and-bound nodes or Bottom-Left orders; sequence: A*
        /// expansions or paper candidates); docs/formats.md.
        nodes: u64,
        /// Its objective, when it has a solution (placement: occupied area, m²; sequence:
        /// number of actions).
        objective: Option<f64>,
        /// Its proven lower bound on that objective, when it has one.
        bound: Option<f64>,
    },
    /// A search inside a stage is under way: at most one every [`PROGRESS_INTERVAL`], from the
    /// sequencers (A* and the paper's, [`crate::sequence::paper::solve_with`]), the exact
    /// placement (both of its stages; Bottom-Left reports only its stage's start and finish)
    /// and the joint plan ([`crate::plan::build_plan_with`]).
    Progress {
        /// The stage.
        stage: Stage,
        /// Search nodes so far, never decreasing (sequence: A* expansions, 0 while A* still
        /// proves its lower bound on the number of actions, before the main search; the paper
        /// sequencer's assignments of Algorithm 1, then plus its depth-first nodes; placement:
        /// nodes of the packing searches and HiGHS, the warm start's included; motion: actions
        /// whose joint trajectories are planned).
        nodes: u64,
        /// The best solution's objective so far, when there is one (sequence: number of
        /// actions; placement: occupied area, m², also during the contact stage, which keeps
        /// it).
        incumbent: Option<f64>,
        /// The proven lower bound on that objective so far (it only rises, and never passes
        /// the incumbent).
        bound: Option<f64>,
    },
}

/// Least time between two [`Event::Progress`] of one search: often enough for a live display,
/// rarely enough that building and handing over an event costs nothing measurable.
pub const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

/// Decides when a search may send its next [`Event::Progress`]: a clock read per call, so a
/// search can ask at every node.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Ticker {
    next: Instant,
}

impl Ticker {
    /// The first event is due one interval from now: a search that ends sooner sends none.
    pub(crate) fn new() -> Ticker {
        Ticker {
            next: Instant::now() + PROGRESS_INTERVAL,
        }
    }
    /// True at most once per [`PROGRESS_INTERVAL`].
    pub(crate) fn due(&mut self) -> bool {
        let now = Instant::now();
        if now < self.next {
            return false;
        }
        self.next = now + PROGRESS_INTERVAL;
        true
    }
}

/// Receives progress events from a run ([`crate::plan::optimize_with`]): every stage's start
/// and finish, and [`Event::Progress`] from inside a search at most every
/// [`PROGRESS_INTERVAL`].
pub trait Listener {
    /// Called at every event, on the planning thread, which waits for it: keep it quick.
    fn event(&mut self, event: &Event);
}

/// Ignores every event.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Listener for Silent {
    fn event(&mut self, _event: &Event) {}
}

/// Collects every event (for tests and for callers that report afterwards).
#[derive(Debug, Clone, Default)]
pub struct Recorder(pub Vec<Event>);

impl Listener for Recorder {
    fn event(&mut self, event: &Event) {
        self.0.push(event.clone());
    }
}

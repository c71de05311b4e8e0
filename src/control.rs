//! Run control passed into long runs: when to stop ([`Terminator`]) and whom to tell ([`Listener`]).

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

/// Receives progress messages from long runs.
pub trait Listener {
    /// A stage reports progress.
    fn progress(&self, stage: &str, message: &str);
}

/// Ignores every message.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Listener for Silent {
    fn progress(&self, _stage: &str, _message: &str) {}
}

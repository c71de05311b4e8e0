//! Library errors: bad input (naming file, field and reason) versus planning failures.
//!
//! A solver that stops early is *not* an error: it returns a result whose status says so.

use crate::status::{Limit, Status};
use std::path::PathBuf;

/// Everything that can go wrong in pushpack.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input (instance, plan or scenario file) is invalid.
    #[error("{file}: field `{field}`: {reason}")]
    Input {
        /// The file the value came from (or `<memory>`).
        file: String,
        /// Dotted path of the offending field, e.g. `objects[2].size[1]`.
        field: String,
        /// Why the value is rejected.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The path involved.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// A search hit its node or time limit before it had found any plan. Nothing is proven:
    /// a larger limit may find one. (A search stopped *with* a plan is not an error; its
    /// result carries the status.)
    #[error(
        "{stage} stopped by its {limit} after {nodes} nodes ({elapsed_s:.1} s) before any plan was found{}",
        min_actions_note(.min_actions)
    )]
    Stopped {
        /// The stage that stopped (`"sequence (astar)"`, `"sequence (paper)"`).
        stage: String,
        /// What stopped it.
        limit: Limit,
        /// Nodes expanded before the stop.
        nodes: u64,
        /// Seconds spent in the stage.
        elapsed_s: f64,
        /// The fewest actions any plan needs, as proven before the stop (A* only).
        min_actions: Option<usize>,
    },
    /// A solver library failed (it neither solved nor proved anything): never a proof of
    /// infeasibility.
    #[error("{solver} failed: {reason}")]
    Solver {
        /// The library (`"HiGHS"`).
        solver: String,
        /// What it reported.
        reason: String,
    },
    /// The instance is valid, but no plan satisfying every constraint exists within the search.
    #[error("no feasible plan: {reason}")]
    Infeasible {
        /// What made it infeasible.
        reason: String,
    },
}

impl Error {
    /// Shorthand for an [`Error::Input`].
    pub fn input(file: impl Into<String>, field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Input {
            file: file.into(),
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// The outcome of a run that ended without a solution for a reason that is a status, not a
    /// fault: a limit stopped it ([`Status::TimeLimit`], [`Status::NodeLimit`]) or it proved
    /// that none exists ([`Status::Infeasible`]). `None` for real errors.
    pub fn status(&self) -> Option<Status> {
        match self {
            Error::Infeasible { .. } => Some(Status::Infeasible),
            Error::Stopped { limit, .. } => Some(limit.without_solution()),
            _ => None,
        }
    }

    /// True when the error is caused by bad input (the CLI exits with code 2).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Input { .. } | Error::Io { .. })
    }
}

/// The proven bound of an [`Error::Stopped`], as a clause of its message.
fn min_actions_note(min_actions: &Option<usize>) -> String {
    min_actions.map_or(String::new(), |n| {
        format!("; proven: every plan needs at least {n} actions")
    })
}

/// Result alias used across the crate.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    /// A HiGHS failure is a fault: it carries no status (so no stage, plan file, CLI line or
    /// benchmark row can read it as `infeasible`), and it is not bad input (exit code 1, not 2).
    /// `tests/placement_solver_errors.rs` provokes real HiGHS failures through the placement.
    #[test]
    fn a_solver_failure_is_an_error_never_a_status() {
        let e = Error::Solver {
            solver: "HiGHS".into(),
            reason: "kError".into(),
        };
        assert_eq!(e.status(), None);
        assert!(!e.is_input());
        assert!(!e.to_string().contains("infeasible") && !e.to_string().contains("no feasible plan"));
        let proven = Error::Infeasible { reason: "x".into() };
        assert_eq!(proven.status(), Some(Status::Infeasible));
    }
}

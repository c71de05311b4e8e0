//! The one outcome vocabulary of every stage, of `plan.json`, of the CLI and of benchmark rows.
//!
//! A status says what a result *proves*, in the spirit of Clarabel's `SolverStatus` and OMPL's
//! `PlannerStatus`. Errors (bad input, a solver that fails) are never statuses: they are
//! [`crate::Error`]s, so that a crashed solver can never be read as "infeasible".
//!
//! | status | solution | what is proven |
//! |---|---|---|
//! | `optimal` | yes | a lower bound meets the objective (the bound is reported next to it) |
//! | `feasible` | yes | a lower bound below the objective (bound and gap reported) |
//! | `heuristic` | yes | nothing: the method proves no bound (Bottom-Left, the paper's sequencer) |
//! | `time_limit` | no | nothing: the time limit stopped the run before any solution |
//! | `node_limit` | no | nothing: a node or candidate cap stopped it before any solution |
//! | `cancelled` | no | nothing: the caller cancelled the run before any solution |
//! | `infeasible` | no | no solution exists (within the stage's model) |
//!
//! A run that stopped early *with* a solution is `feasible` (or `heuristic`), and records which
//! [`Limit`] stopped it next to the status.

use serde::{Deserialize, Serialize};
use std::fmt;

/// What a stage, or a whole run, proved about its result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A solution whose objective meets a proven lower bound.
    Optimal,
    /// A solution with a proven lower bound that does not meet it (bound and gap reported).
    Feasible,
    /// A solution from a method that proves no bound.
    Heuristic,
    /// No solution: the time limit stopped the run first.
    TimeLimit,
    /// No solution: a node or candidate cap stopped the run first (more time would not help).
    NodeLimit,
    /// No solution: the run was cancelled first.
    Cancelled,
    /// Proven: no solution exists.
    Infeasible,
}

impl Status {
    /// Every status, in the order of the table above.
    pub const ALL: [Status; 7] = [
        Status::Optimal,
        Status::Feasible,
        Status::Heuristic,
        Status::TimeLimit,
        Status::NodeLimit,
        Status::Cancelled,
        Status::Infeasible,
    ];

    /// True when the result includes a solution.
    pub fn has_solution(self) -> bool {
        matches!(self, Status::Optimal | Status::Feasible | Status::Heuristic)
    }

    /// True when the status is a proof: of optimality, or of infeasibility.
    pub fn is_proven(self) -> bool {
        matches!(self, Status::Optimal | Status::Infeasible)
    }

    /// The name used in files and on the command line (`optimal`, `time_limit`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Optimal => "optimal",
            Status::Feasible => "feasible",
            Status::Heuristic => "heuristic",
            Status::TimeLimit => "time_limit",
            Status::NodeLimit => "node_limit",
            Status::Cancelled => "cancelled",
            Status::Infeasible => "infeasible",
        }
    }

    /// The status of a whole run from its stages' statuses, in pipeline order: the weakest
    /// claim wins. A run is `optimal` only when every stage is (lexicographically: the
    /// placement is optimal, and the sequence is optimal *for that placement*); any heuristic
    /// stage makes it `heuristic`; a stage without a solution decides it.
    pub fn combine(stages: &[Status]) -> Status {
        if let Some(s) = stages.iter().find(|s| !s.has_solution()) {
            return *s;
        }
        if stages.contains(&Status::Heuristic) {
            Status::Heuristic
        } else if stages.iter().all(|s| *s == Status::Optimal) {
            Status::Optimal
        } else {
            Status::Feasible
        }
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What stopped a run before it finished its proof.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Limit {
    /// The time limit.
    Time,
    /// A node cap.
    Nodes,
    /// The paper sequencer's cap on the candidates of Algorithm 1, which it holds in memory
    /// (`sequence::paper::MAX_CANDIDATES`).
    Candidates,
    /// The caller's cancel flag.
    Cancel,
}

impl std::fmt::Display for Limit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Limit::Time => "time limit",
            Limit::Nodes => "node limit",
            Limit::Candidates => "candidate limit",
            Limit::Cancel => "cancel flag",
        })
    }
}

impl Limit {
    /// The status of a run this limit stopped before it had any solution.
    pub fn without_solution(self) -> Status {
        match self {
            Limit::Time => Status::TimeLimit,
            Limit::Nodes | Limit::Candidates => Status::NodeLimit,
            Limit::Cancel => Status::Cancelled,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_serde() {
        for s in Status::ALL {
            let j = serde_json::to_string(&s).unwrap();
            assert_eq!(j, format!("\"{}\"", s.as_str()));
            assert_eq!(serde_json::from_str::<Status>(&j).unwrap(), s);
        }
    }

    #[test]
    fn a_run_is_only_as_proven_as_its_weakest_stage() {
        use Status::*;
        assert_eq!(Status::combine(&[Optimal, Optimal]), Optimal);
        assert_eq!(Status::combine(&[Optimal, Feasible]), Feasible);
        assert_eq!(Status::combine(&[Optimal, Heuristic]), Heuristic);
        assert_eq!(Status::combine(&[Heuristic, Optimal]), Heuristic);
        assert_eq!(Status::combine(&[Feasible, Heuristic]), Heuristic);
        assert_eq!(Status::combine(&[Optimal, TimeLimit]), TimeLimit);
        assert_eq!(Status::combine(&[Optimal, Infeasible]), Infeasible);
        assert!(!Heuristic.is_proven() && Optimal.is_proven() && Infeasible.is_proven());
    }
}

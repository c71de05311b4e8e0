//! Planner specs (`milp+astar+no-direct`): parsing, canonical names and the plan options they set.

use crate::error::{Error, Result};
use crate::plan::{PlacementSolver, PlanOptions, Sequencer};
use std::fmt;

/// One planner configuration of a benchmark: placement solver, sequencer and ablations.
///
/// Grammar: `PLACEMENT+SEQUENCER[+ABLATION]...` with PLACEMENT `bl|milp`, SEQUENCER
/// `paper|astar`, ABLATION `no-direct|no-multi-push` (each at most once, any order). The
/// canonical name lists ablations in that fixed order, so `bl+paper+no-multi-push+no-direct`
/// and `bl+paper+no-direct+no-multi-push` are the same planner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlannerSpec {
    /// Placement solver.
    pub placement: PlacementSolver,
    /// Sequencer.
    pub sequencer: Sequencer,
    /// Forbid direct placing.
    pub no_direct: bool,
    /// Forbid multi-object pushes.
    pub no_multi_push: bool,
}

impl PlannerSpec {
    /// Parse one spec; errors name `field` (e.g. `--planners`) and the offending part.
    pub fn parse(text: &str, field: &str) -> Result<PlannerSpec> {
        let bad = |reason: String| Error::input("<command line>", field, reason);
        let parts: Vec<&str> = text.trim().split('+').map(str::trim).collect();
        if parts.len() < 2 {
            return Err(bad(format!(
                "planner {text:?} must be PLACEMENT+SEQUENCER[+ABLATION...], e.g. milp+astar or bl+paper+no-direct"
            )));
        }
        let placement = match parts[0] {
            "bl" => PlacementSolver::Bl,
            "milp" => PlacementSolver::Milp,
            p => {
                return Err(bad(format!(
                    "planner {text:?}: placement must be bl or milp, got {p:?}"
                )))
            }
        };
        let sequencer = match parts[1] {
            "paper" => Sequencer::Paper,
            "astar" => Sequencer::Astar,
            s => {
                return Err(bad(format!(
                    "planner {text:?}: sequencer must be paper or astar, got {s:?}"
                )))
            }
        };
        let mut spec = PlannerSpec {
            placement,
            sequencer,
            no_direct: false,
            no_multi_push: false,
        };
        for a in &parts[2..] {
            let flag = match *a {
                "no-direct" => &mut spec.no_direct,
                "no-multi-push" => &mut spec.no_multi_push,
                other => {
                    return Err(bad(format!(
                        "planner {text:?}: ablation must be no-direct or no-multi-push, got {other:?}"
                    )))
                }
            };
            if *flag {
                return Err(bad(format!("planner {text:?}: ablation {a:?} given twice")));
            }
            *flag = true;
        }
        Ok(spec)
    }

    /// Parse a comma-separated list, dropping repeats (first occurrence keeps its place).
    pub fn parse_list(text: &str, field: &str) -> Result<Vec<PlannerSpec>> {
        let mut out: Vec<PlannerSpec> = Vec::new();
        for t in text.split(',').filter(|t| !t.trim().is_empty()) {
            let s = PlannerSpec::parse(t, field)?;
            if !out.contains(&s) {
                out.push(s);
            }
        }
        if out.is_empty() {
            return Err(Error::input("<command line>", field, "no planner given"));
        }
        Ok(out)
    }

    /// The same planner without ablations (the "full method" of the paper's Table II).
    pub fn base(&self) -> PlannerSpec {
        PlannerSpec {
            no_direct: false,
            no_multi_push: false,
            ..*self
        }
    }

    /// Plan options for `inst`: the instance's own settings with this planner and `time_limit`.
    pub fn options(&self, inst: &crate::instance::Instance, time_limit: f64) -> PlanOptions {
        let mut o = PlanOptions::from_instance(inst);
        o.placement = self.placement;
        o.sequencer = self.sequencer;
        o.no_direct = self.no_direct;
        o.no_multi_push = self.no_multi_push;
        o.time_limit = time_limit;
        o
    }
}

impl fmt::Display for PlannerSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = match self.placement {
            PlacementSolver::Bl => "bl",
            PlacementSolver::Milp => "milp",
        };
        let s = match self.sequencer {
            Sequencer::Paper => "paper",
            Sequencer::Astar => "astar",
        };
        write!(f, "{p}+{s}")?;
        if self.no_direct {
            write!(f, "+no-direct")?;
        }
        if self.no_multi_push {
            write!(f, "+no-multi-push")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_prints_canonical_names() {
        for (text, canon) in [
            ("bl+paper", "bl+paper"),
            ("milp+astar", "milp+astar"),
            (
                " milp + astar + no-multi-push + no-direct ",
                "milp+astar+no-direct+no-multi-push",
            ),
            ("bl+astar+no-multi-push", "bl+astar+no-multi-push"),
        ] {
            assert_eq!(PlannerSpec::parse(text, "--planners").unwrap().to_string(), canon);
        }
        let l = PlannerSpec::parse_list("bl+paper,milp+astar,bl+paper", "--planners").unwrap();
        assert_eq!(l.len(), 2);
        assert_eq!(l[1].base().to_string(), "milp+astar");
    }

    #[test]
    fn rejects_bad_specs_naming_the_part() {
        for (text, needle) in [
            ("bl", "PLACEMENT+SEQUENCER"),
            ("lp+paper", "placement must be"),
            ("bl+dfs", "sequencer must be"),
            ("bl+paper+fast", "ablation must be"),
            ("bl+paper+no-direct+no-direct", "given twice"),
            ("", "PLACEMENT+SEQUENCER"),
        ] {
            let e = PlannerSpec::parse(text, "--planners").unwrap_err();
            assert!(e.is_input() && e.to_string().contains(needle), "{text:?}: {e}");
        }
        assert!(PlannerSpec::parse_list(",,", "--planners").is_err());
    }
}

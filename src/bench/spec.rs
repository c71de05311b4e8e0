//! Planner specs (`milp+astar+no-direct`): parsing, canonical names and the plan options they set.

use crate::error::{Error, Result};
use crate::plan::{PlacementSolver, PlanOptions, Sequencer};
use std::fmt;

/// One planner configuration of a benchmark: placement solver, sequencer and ablations.
///
/// Grammar: `PLACEMENT+SEQUENCER[+OPTION]...` with PLACEMENT `bl|milp`, SEQUENCER
/// `paper|astar`, OPTION an ablation `no-direct|no-multi-push`, `no-physics`, `altN` (N ≥ 1: up to N
/// alternative Bottom-Left placements when one is proven to have no plan,
/// [`PlanOptions::placement_alternatives`]) or `threadsN` (N ≥ 1 threads for the exact
/// placement's box searches and the inverse kinematics, [`PlanOptions::threads`]; the plan is
/// the same, only the times change), each at most once, in any order. The canonical
/// name lists them in that fixed order, so `bl+paper+no-multi-push+no-direct` and
/// `bl+paper+no-direct+no-multi-push` are the same planner.
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
    /// Alternative placements allowed (`altN`; 0 when absent).
    pub placement_alternatives: usize,
    /// A packing-only study (`packing-only`): robot issues do not make a plan invalid
    /// ([`PlanOptions::packing_only`]). Written right after the sequencer in the canonical
    /// name, so that the ablation variants of a packing-only planner extend its name.
    pub packing_only: bool,
    /// Replay each plan in the physics engine (`simulate`) and fill the `sim_*` columns. Not an
    /// ablation: the plan is the same with or without it.
    pub simulate: bool,
    /// No physics replay (`no-physics`): neither in the search nor in the verifier, so no plan
    /// counts as executable ([`PlanOptions::physics`]). For measuring what the replay costs.
    pub no_physics: bool,
    /// Threads of one run (`threadsN`; 1 when absent, and `threads1` is the same planner). Not
    /// an ablation either: the same plan on any number. With `--jobs J`, J × N threads run at
    /// once.
    pub threads: usize,
}

impl PlannerSpec {
    /// Parse one spec; errors name `field` (e.g. `--planners`) and the offending part.
    pub fn parse(text: &str, field: &str) -> Result<PlannerSpec> {
        let bad = |reason: String| Error::input("<command line>", field, reason);
        let parts: Vec<&str> = text.trim().split('+').map(str::trim).collect();
        if parts.len() < 2 {
            return Err(bad(format!(
                "planner {text:?} must be PLACEMENT+SEQUENCER[+OPTION...], e.g. milp+astar, bl+paper+no-direct or bl+astar+alt5"
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
            placement_alternatives: 0,
            packing_only: false,
            simulate: false,
            no_physics: false,
            threads: 1,
        };
        // The numbered options, `altN` and `threadsN`: each N >= 1, each at most once.
        let (mut alternatives, mut threads) = (None, None);
        for a in &parts[2..] {
            let numbered = [
                ("alt", "alternatives", &mut alternatives),
                ("threads", "threads", &mut threads),
            ]
            .into_iter()
            .find_map(|(prefix, what, slot)| a.strip_prefix(prefix).map(|n| (prefix, what, slot, n)));
            if let Some((prefix, what, slot, n)) = numbered {
                let n: usize = n.parse().ok().filter(|&n| n >= 1).ok_or_else(|| {
                    bad(format!(
                        "planner {text:?}: {a:?} must be {prefix}N with an integer N >= 1"
                    ))
                })?;
                if slot.replace(n).is_some() {
                    return Err(bad(format!("planner {text:?}: {what} given twice")));
                }
                continue;
            }
            let flag = match *a {
                "packing-only" => &mut spec.packing_only,
                "no-direct" => &mut spec.no_direct,
                "no-multi-push" => &mut spec.no_multi_push,
                "simulate" => &mut spec.simulate,
                "no-physics" => &mut spec.no_physics,
                other => {
                    return Err(bad(format!(
                        "planner {text:?}: option must be packing-only, no-direct, no-multi-push, simulate, no-physics, altN or threadsN, got {other:?}"
                    )))
                }
            };
            if *flag {
                return Err(bad(format!("planner {text:?}: ablation {a:?} given twice")));
            }
            *flag = true;
        }
        spec.placement_alternatives = alternatives.unwrap_or(0);
        spec.threads = threads.unwrap_or(1);
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

    /// The same planner without ablations (the "full method" of the paper's Table II); it
    /// keeps `altN`, which is not an ablation.
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
        o.placement_alternatives = self.placement_alternatives;
        o.packing_only = self.packing_only;
        o.threads = self.threads;
        o.physics = !self.no_physics;
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
        if self.packing_only {
            write!(f, "+packing-only")?;
        }
        if self.no_direct {
            write!(f, "+no-direct")?;
        }
        if self.no_multi_push {
            write!(f, "+no-multi-push")?;
        }
        if self.placement_alternatives > 0 {
            write!(f, "+alt{}", self.placement_alternatives)?;
        }
        if self.simulate {
            write!(f, "+simulate")?;
        }
        if self.no_physics {
            write!(f, "+no-physics")?;
        }
        if self.threads > 1 {
            write!(f, "+threads{}", self.threads)?;
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
            ("bl+astar+alt5+no-direct", "bl+astar+no-direct+alt5"),
            ("milp+astar+threads2+packing-only", "milp+astar+packing-only+threads2"),
            ("milp+astar+threads1", "milp+astar"),
        ] {
            assert_eq!(PlannerSpec::parse(text, "--planners").unwrap().to_string(), canon);
        }
        let l = PlannerSpec::parse_list("bl+paper,milp+astar,bl+paper", "--planners").unwrap();
        assert_eq!(l.len(), 2);
        assert_eq!(l[1].base().to_string(), "milp+astar");
        let a = PlannerSpec::parse("bl+astar+no-direct+alt3", "--planners").unwrap();
        assert_eq!(a.base().to_string(), "bl+astar+alt3");
        let inst = crate::instance::Instance::parse(
            &crate::instance::generate::to_toml(
                &crate::instance::generate::random_instance(&crate::instance::generate::GenerateParams::new(3, 1, 0))
                    .unwrap(),
            ),
            false,
            "<test>",
            None,
        )
        .unwrap();
        assert_eq!(a.options(&inst, 5.0).placement_alternatives, 3);
        assert_eq!(a.options(&inst, 5.0).threads, 1);
        let t = PlannerSpec::parse("milp+astar+threads2", "--planners").unwrap();
        assert_eq!(t.options(&inst, 5.0).threads, 2);
        assert_eq!(t.base().to_string(), "milp+astar+threads2");
        // The same planner on one thread is the one without the option.
        let l = PlannerSpec::parse_list("milp+astar,milp+astar+threads1,milp+astar+threads2", "--planners").unwrap();
        assert_eq!(l.len(), 2);
    }

    #[test]
    fn rejects_bad_specs_naming_the_part() {
        for (text, needle) in [
            ("bl", "PLACEMENT+SEQUENCER"),
            ("lp+paper", "placement must be"),
            ("bl+dfs", "sequencer must be"),
            ("bl+paper+fast", "option must be"),
            ("bl+astar+alt0", "altN with an integer N >= 1"),
            ("bl+astar+altx", "altN with an integer N >= 1"),
            ("bl+astar+alt2+alt3", "alternatives given twice"),
            ("bl+paper+no-direct+no-direct", "given twice"),
            ("milp+astar+threads0", "threadsN with an integer N >= 1"),
            ("milp+astar+threads", "threadsN with an integer N >= 1"),
            ("milp+astar+threads2+threads3", "threads given twice"),
            ("", "PLACEMENT+SEQUENCER"),
        ] {
            let e = PlannerSpec::parse(text, "--planners").unwrap_err();
            assert!(e.is_input() && e.to_string().contains(needle), "{text:?}: {e}");
        }
        assert!(PlannerSpec::parse_list(",,", "--planners").is_err());
    }
}

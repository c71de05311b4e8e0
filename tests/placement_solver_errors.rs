//! A HiGHS failure in the exact placement is an error (`Error::Solver`, naming HiGHS, what failed
//! and its status), never "infeasible": provoked for real through the documented pass-through of
//! HiGHS options (`MilpSettings::highs_options`, `place --highs-option`), with the HiGHS master
//! of the area stage, which calls HiGHS for every box it decides.

use pushpack::control::TimeLimit;
use pushpack::error::Error;
use pushpack::instance::generate::consecutive_squares_toml;
use pushpack::instance::Instance;
use pushpack::placement::{milp, PlacementResult, PlacementStatus};

/// Squares 1…5 with the HiGHS master and no warm start: the first packing is looked for by
/// HiGHS, so every run below calls HiGHS.
fn run(options: &[(&str, &str)]) -> pushpack::error::Result<PlacementResult> {
    let inst = Instance::parse(&consecutive_squares_toml(5, None), false, "<squares>", None).unwrap();
    let s = milp::MilpSettings {
        time_limit: 60.0,
        area_master: milp::AreaMaster::Highs,
        highs_options: options.iter().map(|(n, v)| (n.to_string(), v.to_string())).collect(),
        ..Default::default()
    };
    milp::solve(&inst, &PlacementResult::empty("none", 0.0), &s, &TimeLimit::new(60.0))
}

/// The reason of an `Error::Solver` from HiGHS; any other outcome fails the test.
fn solver_reason(r: pushpack::error::Result<PlacementResult>) -> String {
    match r {
        Err(e @ Error::Solver { .. }) => {
            assert_eq!(e.status(), None, "a solver failure carries no status");
            assert!(!e.is_input(), "a solver failure is not bad input");
            let Error::Solver { solver, reason } = e else {
                unreachable!()
            };
            assert_eq!(solver, "HiGHS");
            reason
        }
        other => panic!("expected Error::Solver, got {other:?}"),
    }
}

#[test]
fn an_accepted_option_changes_nothing_proven() {
    // The pass-through works: an option HiGHS accepts leaves the proof (A038666(5) = 60).
    let r = run(&[("mip_heuristic_effort", "0.1")]).unwrap();
    assert_eq!(r.status, PlacementStatus::Optimal);
    assert!((r.placement.occupied_area() / 4e-6 - 60.0).abs() < 1e-6);
}

#[test]
fn an_option_value_highs_rejects_is_a_solver_error() {
    // mip_heuristic_effort lies in [0, 1]: HiGHS itself refuses -1 (pushpack does not check it).
    let reason = solver_reason(run(&[("mip_heuristic_effort", "-1")]));
    assert!(
        reason.contains("mip_heuristic_effort") && reason.contains("status Error"),
        "{reason}"
    );
    // An option HiGHS does not know.
    let reason = solver_reason(run(&[("no_such_highs_option", "1")]));
    assert!(reason.contains("no_such_highs_option"), "{reason}");
}

#[test]
fn a_highs_run_that_fails_is_a_solver_error_not_infeasible() {
    // HiGHS accepts the name, then its run fails reading the file: Highs_run returns kError.
    let missing = std::env::temp_dir().join("pushpack-no-such-dir/no-such-solution.sol");
    let reason = solver_reason(run(&[("read_solution_file", missing.to_str().unwrap())]));
    assert!(reason.contains("status Error"), "{reason}");
}

#[test]
fn options_that_would_change_a_proof_are_bad_input() {
    for (name, value) in [
        ("mip_rel_gap", "0.5"),
        ("objective_bound", "-1"),
        ("mip_feasibility_tolerance", "0.1"),
        ("Bad Name", "1"),
    ] {
        match run(&[(name, value)]) {
            Err(Error::Input { field, reason, .. }) => {
                assert_eq!(field, "highs_options");
                assert!(reason.contains(name), "{reason}");
            }
            other => panic!("{name}: expected Error::Input, got {other:?}"),
        }
    }
}

/// `place --highs-option`: a failing HiGHS run exits 3 with "HiGHS failed" and the status on
/// stderr, never "infeasible" or "no feasible plan"; a forbidden or malformed option exits 2
/// naming `--highs-option`.
#[test]
fn place_cli_reports_a_highs_failure_as_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("squares5.toml");
    std::fs::write(&file, consecutive_squares_toml(5, None)).unwrap();
    let missing = dir.path().join("missing/no.sol");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "place",
            file.to_str().unwrap(),
            "--solver",
            "milp",
            "--area-master",
            "highs",
        ];
        args.extend_from_slice(extra);
        std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
            .args(&args)
            .output()
            .expect("run pushpack")
    };
    let opt = format!("read_solution_file={}", missing.display());
    let out = run(&["--highs-option", &opt]);
    let err = String::from_utf8_lossy(&out.stderr).to_lowercase();
    assert_eq!(
        out.status.code(),
        Some(3),
        "a solver failure has its own exit code: {err}"
    );
    assert!(err.contains("highs failed") && err.contains("status error"), "{err}");
    assert!(!err.contains("infeasible") && !err.contains("no feasible"), "{err}");
    for bad in ["mip_rel_gap=0.5", "output_flag"] {
        let out = run(&["--highs-option", bad]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("--highs-option"), "{bad}: {err}");
    }
    // Without the option the same command succeeds.
    assert_eq!(run(&[]).status.code(), Some(0));
}

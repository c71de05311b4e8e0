//! Exact placement on consecutive squares (OEIS A038666), in loose and tight containers, with
//! and without a warm start, and on instances proven infeasible; their contact optima against
//! those an independent solver proved.

use pushpack::control::TimeLimit;
use pushpack::error::Error;
use pushpack::geometry::Rect;
use pushpack::instance::generate::consecutive_squares_toml;
use pushpack::instance::Instance;
use pushpack::placement::{milp, PlacementResult, PlacementStatus};

fn no_warm() -> PlacementResult {
    PlacementResult::empty("none", 0.0)
}

fn settings() -> milp::MilpSettings {
    milp::MilpSettings {
        time_limit: 120.0,
        contact_stage: true,
        seed: 1,
        ..Default::default()
    }
}

/// Area in units² (2 mm squares).
fn units(a: f64) -> f64 {
    a / 4e-6
}

#[test]
fn consecutive_squares_reach_a038666() {
    // OEIS A038666, n = 1 … 9.
    let known = [1.0, 6.0, 15.0, 35.0, 60.0, 99.0, 154.0, 210.0, 300.0];
    for (k, &want) in known.iter().enumerate() {
        let n = k as u32 + 1;
        let inst = Instance::parse(&consecutive_squares_toml(n, None), false, "<squares>", None).unwrap();
        let r = milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
        assert!(r.placement.violations(&inst).is_empty(), "n = {n}");
        assert_eq!(r.status, PlacementStatus::Optimal, "n = {n}");
        assert!(
            (units(r.placement.occupied_area()) - want).abs() < 1e-6,
            "n = {n}: {}",
            units(r.placement.occupied_area())
        );
    }
}

/// The bug: Bottom-Left finds nothing in the tight 14 × 15 container, which must not
/// make the exact solver report infeasibility; with or without a warm start the answer is the
/// same optimum.
#[test]
fn tight_container_is_solved_with_or_without_warm_start() {
    let inst = Instance::parse(&consecutive_squares_toml(8, Some((14, 15))), false, "<squares>", None).unwrap();
    let (r, _) = pushpack::plan::solve_placement_report(&inst, pushpack::plan::PlacementSolver::Milp, 1, 20, 120.0)
        .expect("a packing exists");
    assert!(r.placement.violations(&inst).is_empty());
    assert_eq!(r.status, PlacementStatus::Optimal);
    assert!((units(r.placement.occupied_area()) - 210.0).abs() < 1e-6);
    let r2 = milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
    assert_eq!(r2.status, PlacementStatus::Optimal);
    assert!((r2.placement.occupied_area() - r.placement.occupied_area()).abs() < 1e-12);
    assert!((r2.placement.contact_length(&inst) - r.placement.contact_length(&inst)).abs() < 1e-9);
}

/// A warm start that is invalid (here: the right number of targets, all at the origin) is
/// ignored: same area, same contact, same status as a good one.
#[test]
fn a_bad_warm_start_does_not_change_the_answer() {
    let inst = Instance::parse(&consecutive_squares_toml(6, None), false, "<squares>", None).unwrap();
    let good = pushpack::placement::bl::solve(&inst, 1, 20, &TimeLimit::new(10.0)).unwrap();
    let mut bad = good.clone();
    for t in &mut bad.placement.targets {
        t.rect = pushpack::geometry::Rect::new(0.0, 0.0, t.rect.width(), t.rect.depth());
    }
    let a = milp::solve(&inst, &good, &settings(), &TimeLimit::new(120.0)).unwrap();
    let b = milp::solve(&inst, &bad, &settings(), &TimeLimit::new(120.0)).unwrap();
    let c = milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
    for r in [&b, &c] {
        assert_eq!(r.status, a.status);
        assert!((r.placement.occupied_area() - a.placement.occupied_area()).abs() < 1e-12);
        assert!((r.placement.contact_length(&inst) - a.placement.contact_length(&inst)).abs() < 1e-9);
    }
}

/// Squares 1 … 8 have total area 204 but fit no 13 × 16 box (208): the solver proves it and
/// says so as infeasibility, not as a stop or a solver failure.
#[test]
fn infeasible_container_is_proven() {
    let inst = Instance::parse(&consecutive_squares_toml(8, Some((13, 16))), false, "<squares>", None).unwrap();
    match milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)) {
        Err(Error::Infeasible { reason }) => assert!(reason.contains("fit in no box"), "{reason}"),
        other => panic!("expected a proof of infeasibility, got {other:?}"),
    }
}

/// The area stage with the HiGHS master (Benders decomposition) reaches the same optima, finds
/// the tight packing without a warm start, and proves the 13 × 16 box infeasible.
#[test]
fn highs_master_reaches_the_same_optima_and_proofs() {
    let highs = milp::MilpSettings {
        area_master: milp::AreaMaster::Highs,
        ..settings()
    };
    for (n, want) in [(5u32, 60.0), (7, 154.0), (8, 210.0)] {
        let inst = Instance::parse(&consecutive_squares_toml(n, None), false, "<squares>", None).unwrap();
        let r = milp::solve(&inst, &no_warm(), &highs, &TimeLimit::new(120.0)).unwrap();
        assert!(r.placement.violations(&inst).is_empty(), "n = {n}");
        assert_eq!(r.status, PlacementStatus::Optimal, "n = {n}");
        assert!((units(r.placement.occupied_area()) - want).abs() < 1e-6, "n = {n}");
    }
    let tight = Instance::parse(&consecutive_squares_toml(8, Some((14, 15))), false, "<squares>", None).unwrap();
    let r = milp::solve(&tight, &no_warm(), &highs, &TimeLimit::new(120.0)).unwrap();
    assert!(r.placement.violations(&tight).is_empty());
    assert!((units(r.placement.occupied_area()) - 210.0).abs() < 1e-6);
    let too_small = Instance::parse(&consecutive_squares_toml(8, Some((13, 16))), false, "<squares>", None).unwrap();
    assert!(matches!(
        milp::solve(&too_small, &no_warm(), &highs, &TimeLimit::new(120.0)),
        Err(Error::Infeasible { .. })
    ));
}

/// Stopped at once: a placement (the warm start's) and a valid bound, not an error.
#[test]
fn stopped_search_reports_incumbent_and_bound() {
    let inst = Instance::parse(&consecutive_squares_toml(14, None), false, "<squares>", None).unwrap();
    let warm = pushpack::placement::bl::solve(&inst, 1, 5, &TimeLimit::new(10.0)).unwrap();
    let s = milp::MilpSettings {
        time_limit: 0.0,
        ..settings()
    };
    let r = milp::solve(&inst, &warm, &s, &TimeLimit::new(0.0)).unwrap();
    assert!(r.placement.violations(&inst).is_empty());
    assert!(r.lower_bound <= r.placement.occupied_area() + 1e-12);
    // A038666(14) = 1035: the bound never passes the optimum.
    assert!(units(r.lower_bound) <= 1035.0 + 1e-6);
}

/// `place --solver milp --area-master highs --contact-budget area` runs the HiGHS master with the
/// old contact budget and reaches the same proven optimum as the default, and `--threads 2` the
/// same placement; the exact solver's options without `--solver milp`, a bad budget or no
/// threads are bad input (exit 2, the option named).
#[test]
fn place_cli_takes_the_exact_solvers_master_and_contact_budget() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
            .args(args)
            .current_dir(root)
            .output()
            .expect("run pushpack")
    };
    let inst = "instances/paper/exp2_8objects.toml";
    let json = |args: &[&str]| -> serde_json::Value {
        let out = run(args);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let default = json(&["place", inst, "--solver", "milp", "--json"]);
    let highs = json(&[
        "place",
        inst,
        "--solver",
        "milp",
        "--area-master",
        "highs",
        "--contact-budget",
        "area",
        "--json",
    ]);
    for v in [&default, &highs] {
        assert_eq!(v["status"], "optimal", "{v}");
    }
    let area = |v: &serde_json::Value| v["objective"]["occupied_area"].as_f64().unwrap();
    assert!((area(&default) - area(&highs)).abs() < 1e-12);
    // Two threads: the very same placement.
    let two = json(&["place", inst, "--solver", "milp", "--threads", "2", "--json"]);
    assert_eq!(two["placement"], default["placement"], "{two}");
    assert_eq!(two["status"], "optimal", "{two}");
    for (args, flag) in [
        (vec!["place", inst, "--area-master", "highs"], "--area-master"),
        (vec!["place", inst, "--threads", "2"], "--threads"),
        (vec!["place", inst, "--solver", "milp", "--threads", "0"], "--threads"),
        (
            vec!["plan", inst, "--threads", "0", "--out", "/nonexistent/never"],
            "--threads",
        ),
        (
            vec!["place", inst, "--solver", "milp", "--contact-budget", "soon"],
            "--contact-budget",
        ),
        (
            vec!["place", inst, "--solver", "milp", "--contact-budget=-1"],
            "--contact-budget",
        ),
    ] {
        let out = run(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(flag), "{args:?}: {stderr}");
    }
}

/// A contact stage stopped before it could finish still says how much contact it could not
/// rule out: with no time for it (`--contact-budget 0`), the report's upper bound is at least
/// the contact that the full run proves optimal, and the full run's bound is its contact. On
/// instances whose area stage finds less contact than the optimum, so that the bound must come
/// from the stopped search and not from the placement found.
#[test]
fn a_stopped_contact_stage_bounds_the_contact_it_did_not_prove() {
    let squares = |n| Instance::parse(&consecutive_squares_toml(n, None), false, "<squares>", None).unwrap();
    let files = [
        "instances/random/n12/n12_k4_s0001.toml",
        "instances/random/n12/n12_k4_s0003.toml",
    ];
    let mut cases: Vec<(String, Instance)> = (9..=11).map(|n| (format!("squares 1…{n}"), squares(n))).collect();
    cases.extend(files.iter().map(|f| (f.to_string(), Instance::load(f).unwrap())));
    let mut below = 0;
    for (what, inst) in &cases {
        let (full, rep) = milp::solve_report(inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
        let optimum = full.placement.contact_length(inst);
        assert!(rep.area_optimal && rep.contact_optimal, "{what}");
        assert_eq!(
            rep.contact_upper_bound,
            Some(optimum),
            "{what}: the proven optimum is its own bound"
        );
        let none = milp::MilpSettings {
            contact_budget: milp::ContactBudget::Seconds(0.0),
            ..settings()
        };
        let (stopped, rep) = milp::solve_report(inst, &no_warm(), &none, &TimeLimit::new(120.0)).unwrap();
        assert!(stopped.placement.violations(inst).is_empty(), "{what}");
        assert!(rep.area_optimal && !rep.contact_optimal, "{what}: {rep:?}");
        let found = stopped.placement.contact_length(inst);
        let bound = rep
            .contact_upper_bound
            .unwrap_or_else(|| panic!("{what}: no contact bound"));
        assert!(
            bound >= optimum - 1e-9 && bound >= found,
            "{what}: bound {bound}, found {found}, optimum {optimum}"
        );
        below += (found < optimum - 1e-9) as usize;
    }
    assert!(below >= 2, "only {below} instances stopped below the optimum");
}

/// A stop asked in the contact stage ends it with the best placement so far and its bound:
/// HiGHS, which would not hear the stop, does not get the rest of the time limit. n20_k4_s0017
/// proves its area at once (5 ms) and takes 0.4 s (release build, one thread) to prove its
/// contact, longer with this profile's debug assertions, so a stop at 0.3 s comes in the
/// contact stage's enumeration.
#[test]
fn a_stop_in_the_contact_stage_runs_no_milp() {
    let inst = Instance::load("instances/random/n20/n20_k4_s0017.toml").unwrap();
    let (r, rep) = milp::solve_report(&inst, &no_warm(), &settings(), &TimeLimit::new(0.3)).unwrap();
    assert!(r.placement.violations(&inst).is_empty());
    assert!(
        rep.area_optimal && !rep.contact_optimal,
        "the stop came in the contact stage: {rep:?}"
    );
    assert_eq!((r.subproblems, rep.contact_milp_s), (0, 0.0), "{rep:?}");
    let bound = rep.contact_upper_bound.expect("a bound on the contact not proven");
    assert!(bound >= r.placement.contact_length(&inst));
}

/// Contact length in units (2 mm squares).
fn contact_units(inst: &Instance, r: &PlacementResult) -> f64 {
    r.placement.contact_length(inst) / 0.002
}

/// The contact stage's optima agree with OR-Tools CP-SAT's, which proved them with its own
/// model (NoOverlap2D, touch literals, BL-stability as clauses) for N = 8 … 15
/// (`scripts/cpsat_squares.py 8 15 --contact`, docs/benchmarks.md, *Against CP-SAT*): an
/// independent check of the contact enumeration, as A038666 is of the area stage.
#[test]
fn consecutive_squares_contact_matches_an_independent_solver() {
    let proven_by_cp_sat = [
        (8u32, 68.0),
        (9, 89.0),
        (10, 108.0),
        (11, 125.0),
        (12, 153.0),
        (13, 175.0),
        (14, 201.0),
        (15, 231.0),
    ];
    for (n, want) in proven_by_cp_sat {
        let inst = Instance::parse(&consecutive_squares_toml(n, None), false, "<squares>", None).unwrap();
        let r = milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
        assert!(r.placement.violations(&inst).is_empty(), "n = {n}");
        assert_eq!(r.status, PlacementStatus::Optimal, "n = {n}");
        assert!(
            (contact_units(&inst, &r) - want).abs() < 1e-6,
            "n = {n}: {}",
            contact_units(&inst, &r)
        );
    }
}

/// SPEC §4 asks for BL-stable placements, and the contact optimum is over those only: squares
/// 1 … 16 in their optimal box 56 × 27 have a packing of contact 261 with square 2 over a gap
/// (CP-SAT's, without the BL-stability constraint), which the placement check rejects; the
/// solver's proven optimum is 260, and CP-SAT with the constraint finds 260 too.
#[test]
fn contact_optimum_is_over_bl_stable_placements() {
    let inst = Instance::parse(&consecutive_squares_toml(16, None), false, "<squares>", None).unwrap();
    let r = milp::solve(&inst, &no_warm(), &settings(), &TimeLimit::new(120.0)).unwrap();
    assert!(r.placement.violations(&inst).is_empty());
    assert_eq!(r.status, PlacementStatus::Optimal);
    assert!((units(r.placement.occupied_area()) - 1512.0).abs() < 1e-6);
    assert!(
        (contact_units(&inst, &r) - 260.0).abs() < 1e-6,
        "{}",
        contact_units(&inst, &r)
    );

    // (x, y) of squares 1 … 16 in units, CP-SAT's packing without BL-stability.
    let at = [
        (22, 19),
        (38, 13),
        (38, 7),
        (41, 7),
        (23, 15),
        (22, 20),
        (38, 0),
        (14, 19),
        (14, 10),
        (13, 0),
        (45, 0),
        (28, 15),
        (0, 0),
        (0, 13),
        (23, 0),
        (40, 11),
    ];
    let mut hanging = r.clone();
    for (t, (x, y)) in hanging.placement.targets.iter_mut().zip(at) {
        t.rect = Rect::new(
            f64::from(x) * 0.002,
            f64::from(y) * 0.002,
            t.rect.width(),
            t.rect.depth(),
        );
    }
    assert!((units(hanging.placement.occupied_area()) - 1512.0).abs() < 1e-6);
    assert!(
        (contact_units(&inst, &hanging) - 261.0).abs() < 1e-6,
        "{}",
        contact_units(&inst, &hanging)
    );
    let v = hanging.placement.violations(&inst);
    assert_eq!(v.len(), 1, "{v:?}");
    assert!(v[0].contains("not BL-stable (nothing on its -y side)"), "{v:?}");
}

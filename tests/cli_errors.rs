//! Errors that name the fix, through the built binary: a plan whose recorded instance path
//! does not resolve from the working directory points to `--instance FILE`, and a plan and an
//! instance given the wrong way round are named as such instead of a parser's message.

mod common;

use pushpack::plan::{optimize, PlanOptions};
use std::path::Path;
use std::process::Output;

fn run_in(dir: &Path, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// A plan of exp1 in `dir/plan.json` that records its instance by the relative path a run
/// from the repository's top level would have recorded.
fn plan_with_relative_source(dir: &Path) -> std::path::PathBuf {
    let inst = common::load("paper/exp1_4objects.toml");
    let mut plan = optimize(&inst, &PlanOptions::from_instance(&inst)).expect("plans").plan;
    plan.instance.source = "instances/paper/exp1_4objects.toml".into();
    let p = dir.join("plan.json");
    plan.save(&p).unwrap();
    p
}

#[test]
fn an_instance_path_that_does_not_resolve_here_suggests_instance() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_with_relative_source(dir.path());
    let plan = plan.to_str().unwrap();
    let out = dir.path().join("out");
    for args in [
        vec!["render", plan, "--out", out.to_str().unwrap()],
        vec!["simulate", plan],
    ] {
        let r = run_in(dir.path(), &args);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains("instance.source"), "{stderr}");
        assert!(stderr.contains("instances/paper/exp1_4objects.toml"), "{stderr}");
        assert!(stderr.contains("--instance FILE"), "{stderr}");
    }
    // The suggested fix works.
    let file = common::bundled("paper/exp1_4objects.toml");
    let r = run_in(
        dir.path(),
        &["render", plan, "--instance", &file, "--out", out.to_str().unwrap()],
    );
    assert_eq!(r.status.code(), Some(0), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(out.join("placement.svg").exists());
}

#[test]
fn swapped_plan_and_instance_are_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan_with_relative_source(dir.path());
    let plan = plan.to_str().unwrap();
    let inst = common::bundled("paper/exp1_4objects.toml");
    let check = |args: &[&str], want: &[&str]| {
        let r = run_in(dir.path(), args);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {stderr}");
        for w in want {
            assert!(stderr.contains(w), "{args:?}: {w:?} not in {stderr}");
        }
        assert!(!stderr.contains("field ``"), "{stderr}");
    };
    // verify takes INSTANCE PLAN.
    check(
        &["verify", plan, &inst],
        &[
            &inst,
            "looks like an instance file",
            "like a plan",
            "swapped",
            "verify INSTANCE PLAN",
        ],
    );
    // A plan where the instance goes, and an instance where the plan goes.
    check(
        &["simulate", plan, "--instance", plan],
        &["looks like a plan, not an instance"],
    );
    check(
        &["render", &inst],
        &["looks like an instance file, not a plan", "--instance FILE"],
    );
    // A broken plan that is no instance keeps the parser's own message.
    let broken = dir.path().join("broken.json");
    std::fs::write(&broken, "{\"format_version\": 2}").unwrap();
    let r = run_in(dir.path(), &["render", broken.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{stderr}");
    assert!(!stderr.contains("looks like"), "{stderr}");
}

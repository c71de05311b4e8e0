//! The benchmark harness end to end, through the built binary: generate a tiny set, run it
//! interrupted (deterministically with --max-runs plus a torn last line, and with a real kill),
//! resume, shard and merge, report. No assertion depends on timing.

use pushpack::bench::row::{read_jsonl, ResultRow, RunStatus};
use pushpack::instance::Instance;
use pushpack::plan::Plan;
use pushpack::report::load_rows;
use pushpack::status::Status;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const EXE: &str = env!("CARGO_BIN_EXE_pushpack");
/// Packing-only: the generated sets allow any orientation, which a top-down pick cannot run.
const PLANNERS: &str = "bl+paper+packing-only,bl+paper+packing-only+no-direct";

fn run(args: &[&str]) -> Output {
    Command::new(EXE).args(args).output().expect("binary runs")
}

fn ok(args: &[&str]) -> Output {
    let o = run(args);
    assert!(
        o.status.success(),
        "pushpack {args:?} failed: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// Three instances of three objects (two kinds) in `dir/tiny`.
fn tiny_set(dir: &Path) -> PathBuf {
    let set = dir.join("tiny");
    ok(&[
        "generate",
        "--objects",
        "3",
        "--kinds",
        "2",
        "--count",
        "3",
        "--seed",
        "5",
        "--out",
        set.to_str().unwrap(),
    ]);
    set
}

fn bench(set: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "bench",
        set.to_str().unwrap(),
        "--planners",
        PLANNERS,
        "--jobs",
        "2",
        "--time-limit",
        "60",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    run(&args)
}

fn expected_keys(set: &Path) -> BTreeSet<(String, String)> {
    let mut keys = BTreeSet::new();
    for i in 5..8 {
        let p = set.join(format!("n03_k2_s{i:04}.toml")).display().to_string();
        for pl in PLANNERS.split(',') {
            keys.insert((p.clone(), pl.to_string()));
        }
    }
    keys
}

/// Rows of a result file, checking there is exactly one per expected key.
fn rows_exactly(file: &Path, set: &Path) -> Vec<ResultRow> {
    let (rows, _) = read_jsonl(file).unwrap();
    let keys: Vec<_> = rows.iter().map(ResultRow::key).collect();
    let unique: BTreeSet<_> = keys.iter().cloned().collect();
    assert_eq!(keys.len(), unique.len(), "repeated rows in {}", file.display());
    assert_eq!(unique, expected_keys(set), "lost or extra rows in {}", file.display());
    rows
}

fn without_timing(rows: &[ResultRow]) -> Vec<serde_json::Value> {
    let mut v: Vec<_> = rows.iter().map(ResultRow::without_timing).collect();
    v.sort_by_key(|r| r.to_string());
    v
}

/// Every row solved, and the plan it describes re-made in process passes the verifier.
fn check_rows_solved(rows: &[ResultRow]) {
    for r in rows {
        assert!(r.status.status().is_some_and(|s| s.has_solution()), "{r:?}");
        assert_eq!(r.verify.as_deref(), Some("valid"), "{r:?}");
    }
    // The harness ran `verify` in the child; check one plan independently here too.
    let r = &rows[0];
    let inst = Instance::load(&r.instance).unwrap();
    let spec = pushpack::bench::spec::PlannerSpec::parse(&r.planner, "planner").unwrap();
    let out = pushpack::plan::optimize(&inst, &spec.options(&inst, 60.0)).unwrap();
    let text = serde_json::to_string(&out.plan).unwrap();
    let plan: Plan = serde_json::from_str(&text).unwrap();
    assert!(pushpack::verify::verify(&inst, &plan).is_valid());
    assert_eq!(Some(plan.metrics.seq_len), r.seq_len, "same inputs, same plan");
}

#[test]
fn interrupted_batch_resumes_without_repeating_or_losing_rows_and_shards_merge() {
    let dir = tempfile::tempdir().unwrap();
    let set = tiny_set(dir.path());

    // Reference: one uninterrupted run.
    let full = dir.path().join("full");
    assert!(bench(&set, &full, &[]).status.success());
    let reference = rows_exactly(&full.join("results.jsonl"), &set);
    check_rows_solved(&reference);
    let csv = std::fs::read_to_string(full.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "header + 6 rows");

    // Interrupted deterministically: two runs, then a row torn by a kill in mid-write.
    let part = dir.path().join("part");
    assert!(bench(&set, &part, &["--max-runs", "2"]).status.success());
    let jsonl = part.join("results.jsonl");
    assert_eq!(read_jsonl(&jsonl).unwrap().0.len(), 2);
    let torn = &reference[5].to_json_line()[..60];
    let mut text = std::fs::read_to_string(&jsonl).unwrap();
    text.push_str(torn);
    std::fs::write(&jsonl, text).unwrap();
    // Without --resume the existing results are refused (bad input, exit 2).
    assert_eq!(bench(&set, &part, &[]).status.code(), Some(2));
    let o = bench(&set, &part, &["--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("2 already done, 4 run now"));
    let resumed = rows_exactly(&jsonl, &set);
    assert_eq!(without_timing(&resumed), without_timing(&reference));
    let csv = std::fs::read_to_string(part.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 7, "the CSV is rebuilt from the JSON Lines record");
    // Resuming a finished batch runs nothing.
    let o = bench(&set, &part, &["--resume"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("6 already done, 0 run now"));
    assert_eq!(read_jsonl(&jsonl).unwrap().0.len(), 6);

    // Two shards merged equal the unsharded run.
    let sharded = dir.path().join("sharded");
    for k in ["0/2", "1/2"] {
        assert!(bench(&set, &sharded, &["--shard", k]).status.success());
    }
    let s0 = read_jsonl(&sharded.join("results.shard-0-of-2.jsonl")).unwrap().0;
    let s1 = read_jsonl(&sharded.join("results.shard-1-of-2.jsonl")).unwrap().0;
    assert_eq!((s0.len(), s1.len()), (3, 3));
    let merged = load_rows(std::slice::from_ref(&sharded)).unwrap();
    assert_eq!(merged.duplicates, 0);
    assert_eq!(without_timing(&merged.rows), without_timing(&reference));

    // Report over the shards and the full run: duplicates are dropped, files are written.
    let rep = dir.path().join("report");
    let o = ok(&[
        "report",
        sharded.to_str().unwrap(),
        full.to_str().unwrap(),
        "--out",
        rep.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("summary.md"));
    let md = std::fs::read_to_string(rep.join("summary.md")).unwrap();
    assert!(
        md.contains("12 rows") || md.contains("6 rows from 3 file(s), 6 duplicate"),
        "{md}"
    );
    assert!(md.contains("| tiny | 3 | bl+paper+packing-only | 3 | 100 % |"), "{md}");
    assert!(md.contains("Table II"), "{md}");
    assert!(md.contains("## Confidence intervals"), "{md}");
    let per = std::fs::read_to_string(rep.join("per_instance.md")).unwrap();
    assert_eq!(per.lines().filter(|l| l.starts_with("| tiny |")).count(), 3, "{per}");
    // No planner proved anything optimal: no scatter against an optimum.
    assert!(!rep.join("scatter.svg").exists());
    for f in [
        "time_vs_objects.svg",
        "cactus.svg",
        "ratios.svg",
        "table2_bl_paper_packing-only.svg",
    ] {
        let svg = std::fs::read_to_string(rep.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(svg.contains("<svg") && svg.contains("bl+paper"), "{f}");
    }
}

#[test]
fn killed_batch_resumes_to_the_full_set() {
    let dir = tempfile::tempdir().unwrap();
    let set = tiny_set(dir.path());
    let out = dir.path().join("out");
    let jsonl = out.join("results.jsonl");
    // SIGKILL to the harness process only: the run in flight is orphaned and its row is lost
    // with the harness, which is the case resume must handle.
    let mut child = Command::new(EXE)
        .args([
            "bench",
            set.to_str().unwrap(),
            "--planners",
            PLANNERS,
            "--jobs",
            "1",
            "--time-limit",
            "60",
        ])
        .arg("--out")
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait (by polling the file, not by a timed assertion) until a row has landed or the batch ended.
    loop {
        let rows = if jsonl.exists() {
            read_jsonl(&jsonl).unwrap().0.len()
        } else {
            0
        };
        if rows >= 1 || child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    let before = read_jsonl(&jsonl).unwrap().0.len();
    assert!((1..=6).contains(&before));
    let o = bench(&set, &out, &["--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows_exactly(&jsonl, &set);
    assert!(rows.iter().all(|r| r.status.status().is_some_and(|s| s.has_solution())));
}

#[test]
fn bad_input_exits_2_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_str().unwrap();
    for (args, needle) in [
        (vec!["bench", "instances/paper", "--planners", "bl+foo"], "--planners"),
        (
            vec!["bench", "instances/paper", "--planners", "bl+paper", "--shard", "2/2"],
            "--shard",
        ),
        (
            vec!["bench", "instances/paper", "--planners", "bl+paper", "--jobs", "0"],
            "--jobs",
        ),
        (
            // More runs than cores would shrink every time limit silently.
            vec!["bench", "instances/paper", "--planners", "bl+paper", "--jobs", "100000"],
            "--jobs",
        ),
        (
            vec![
                "bench",
                "instances/paper",
                "--planners",
                "bl+paper",
                "--time-limit",
                "0",
            ],
            "--time-limit",
        ),
        (vec!["bench", "no/such/dir", "--planners", "bl+paper"], "no/such/dir"),
        (
            vec!["bench", "instances/invalid/nan_size.toml", "--planners", "bl+paper"],
            "nan_size.toml",
        ),
        (
            vec!["generate", "--objects", "30", "--kinds", "2", "--out", d],
            "--objects",
        ),
        (
            vec![
                "generate",
                "--objects",
                "4",
                "--kinds",
                "2",
                "--size-range",
                "0.03",
                "--out",
                d,
            ],
            "--size-range",
        ),
        (vec!["report", d], "no *.jsonl"),
    ] {
        let o = run(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn a_node_limit_stop_is_recorded_as_node_limit_not_timeout() {
    // The paper sequencer with a one-node limit stops before it has any plan; a 60 s time limit
    // is nowhere near, so `timeout` would send a reader to the wrong knob.
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("limited");
    std::fs::create_dir_all(&set).unwrap();
    let text = std::fs::read_to_string("instances/paper/exp2_8objects.toml").unwrap();
    let text = text.replace("[planner]\nseed = 1\n", "[planner]\nseed = 1\nmax_nodes = 1\n");
    assert!(
        text.contains("max_nodes = 1"),
        "the paper instance's [planner] table moved"
    );
    std::fs::write(set.join("exp2_one_node.toml"), text).unwrap();
    let out = dir.path().join("out");
    let o = ok(&[
        "bench",
        set.to_str().unwrap(),
        "--planners",
        "bl+paper",
        "--time-limit",
        "60",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (rows, _) = read_jsonl(&out.join("results.jsonl")).unwrap();
    assert_eq!(rows.len(), 1, "{}", String::from_utf8_lossy(&o.stdout));
    assert_eq!(rows[0].status, RunStatus::Planner(Status::NodeLimit), "{:?}", rows[0]);
    assert!(
        rows[0].error.as_deref().unwrap_or("").contains("node limit"),
        "{:?}",
        rows[0]
    );
    let rep = dir.path().join("rep");
    ok(&["report", out.to_str().unwrap(), "--out", rep.to_str().unwrap()]);
    let md = std::fs::read_to_string(rep.join("summary.md")).unwrap();
    assert!(md.contains("| node limit |"), "{md}");
    // Result files from before the status existed said `timeout`; they read back as node_limit.
    let old = dir.path().join("old.jsonl");
    let line = std::fs::read_to_string(out.join("results.jsonl")).unwrap();
    assert!(line.contains("\"status\":\"node_limit\""), "{line}");
    std::fs::write(
        &old,
        line.replace("\"status\":\"node_limit\"", "\"status\":\"timeout\""),
    )
    .unwrap();
    let (rows, _) = read_jsonl(&old).unwrap();
    assert_eq!(rows[0].status, RunStatus::Planner(Status::NodeLimit));
}

/// A mixed run of a heuristic and the exact pipeline on the same instances: only the pipeline
/// whose every stage proves its result may call a row optimal; the rows keep the placement
/// even when a later stage has nothing, and say which machine and how many jobs ran them.
#[test]
fn no_heuristic_row_is_reported_optimal() {
    use pushpack::bench::run::run_in_process;
    use pushpack::bench::spec::PlannerSpec;
    for rel in ["paper/exp1_4objects.toml", "paper/exp2_8objects.toml"] {
        let path = format!("{}/instances/{rel}", env!("CARGO_MANIFEST_DIR"));
        let inst = pushpack::instance::Instance::load(&path).unwrap();
        for planner in ["bl+paper", "milp+paper", "bl+astar", "milp+astar"] {
            let spec = PlannerSpec::parse(planner, "planner").unwrap();
            let r = run_in_process(&path, &inst, &spec, 60.0);
            assert!(r.solved(), "{rel} {planner}: {r:?}");
            let heuristic = planner.contains("paper") || planner.starts_with("bl");
            if heuristic {
                assert_eq!(r.status, RunStatus::Planner(Status::Heuristic), "{rel} {planner}");
                assert!(!r.proven());
            } else {
                assert_eq!(r.status, RunStatus::Planner(Status::Optimal), "{rel} {planner}");
                assert!(r.proven());
            }
            assert!(r.robot_time_s.is_some_and(|t| t > 0.0), "{rel} {planner}");
            assert!(r.cpu_model.is_some() || !cfg!(target_os = "linux"));
        }
    }
}

//! The plans of every committed paper and example instance, as `pushpack plan` writes them, are
//! the ones recorded in `tests/golden/`. A refactoring that changes no algorithm must leave them
//! identical; a change that is meant to alter plans updates the records in the same commit and
//! says why (`PUSHPACK_BLESS=1 cargo test --profile checked --test golden_plans` rewrites them).
//!
//! What is compared is what a plan *is*: the targets, the actions with their key poses, the
//! metrics, the placement's figures and a fingerprint of every joint trajectory. Timings, the tool
//! version, the options echo and the status words are left out, so that the report format can
//! evolve without hiding a change of plan.

use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Relative tolerance of number comparisons: far below anything a plan change produces, above the
/// last-bit noise a reordered floating-point sum could introduce.
const REL_TOL: f64 = 1e-9;

fn instances() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("instances");
    let mut v: Vec<PathBuf> = ["paper", "examples"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root.join(d)).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("toml" | "json")))
        .collect();
    v.sort();
    v
}

/// A trajectory reduced to its identity: times, key-pose joints and weighted sums of every point,
/// so that a change of any joint value at any point changes the record.
fn trajectory_fingerprint(t: &Value) -> Value {
    let points = t["points"].as_array().cloned().unwrap_or_default();
    let mut pos_sum = 0.0;
    let mut vel_sum = 0.0;
    let mut t_sum = 0.0;
    for (i, p) in points.iter().enumerate() {
        let w = (i + 1) as f64;
        t_sum += w * p["t"].as_f64().unwrap();
        for (j, q) in p["positions"].as_array().unwrap().iter().enumerate() {
            pos_sum += w * (j + 1) as f64 * q.as_f64().unwrap();
        }
        if let Some(vs) = p["velocities"].as_array() {
            for (j, q) in vs.iter().enumerate() {
                vel_sum += w * (j + 1) as f64 * q.as_f64().unwrap();
            }
        }
    }
    let key_poses: Vec<Value> = t["key_poses"]
        .as_array()
        .map(|k| {
            k.iter()
                .map(|kp| json!({"label": kp["label"], "joints": kp["joints"], "t": kp["t"], "opening": kp["opening"]}))
                .collect()
        })
        .unwrap_or_default();
    json!({
        "action": t["action"], "label": t["label"], "arm": t["arm"],
        "t_start": t["t_start"], "t_end": t["t_end"],
        "n_points": points.len(), "t_sum": t_sum, "position_sum": pos_sum, "velocity_sum": vel_sum,
        "key_poses": key_poses,
    })
}

fn canonical(plan: &Value) -> Value {
    let mut placement = Map::new();
    for k in ["occupied_area", "lower_bound", "contact_length"] {
        placement.insert(k.into(), plan["placement"][k].clone());
    }
    let trajectories: Vec<Value> = plan["trajectories"]
        .as_array()
        .map(|ts| ts.iter().map(trajectory_fingerprint).collect())
        .unwrap_or_default();
    json!({
        "placement": placement,
        "placements": plan["placements"],
        "actions": plan["actions"],
        "metrics": plan["metrics"],
        "trajectories": trajectories,
    })
}

/// Differences between two canonical plans, as JSON paths.
fn diff(path: &str, a: &Value, b: &Value, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            if (x - y).abs() > REL_TOL * x.abs().max(y.abs()).max(1.0) {
                out.push(format!("{path}: recorded {x}, now {y}"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            for k in x.keys().chain(y.keys().filter(|k| !x.contains_key(*k))) {
                diff(
                    &format!("{path}.{k}"),
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                    out,
                );
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (p, q)) in x.iter().zip(y).enumerate() {
                diff(&format!("{path}[{i}]"), p, q, out);
            }
        }
        _ if a == b => {}
        _ => out.push(format!("{path}: recorded {}, now {}", short(a), short(b))),
    }
}

fn short(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 120 {
        format!("{}…", &s[..120])
    } else {
        s
    }
}

#[test]
fn plans_of_the_committed_paper_and_example_instances_are_the_recorded_ones() {
    let golden_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let bless = std::env::var_os("PUSHPACK_BLESS").is_some();
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    let list = instances();
    assert!(
        list.len() >= 7,
        "expected the 2 paper and 5 example instances, found {list:?}"
    );
    for inst in &list {
        let stem = inst.file_stem().unwrap().to_string_lossy().to_string();
        let out = tmp.path().join(&stem);
        let run = Command::new(env!("CARGO_BIN_EXE_pushpack"))
            .arg("plan")
            .arg(inst)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let plan_path = out.join("plan.json");
        assert!(
            plan_path.exists(),
            "{stem}: no plan.json (exit {:?})\n{}",
            run.status.code(),
            String::from_utf8_lossy(&run.stderr)
        );
        let plan: Value = serde_json::from_str(&std::fs::read_to_string(&plan_path).unwrap()).unwrap();
        let now = canonical(&plan);
        let record = golden_dir.join(format!("{stem}.json"));
        if bless {
            std::fs::create_dir_all(&golden_dir).unwrap();
            std::fs::write(&record, serde_json::to_string_pretty(&now).unwrap() + "\n").unwrap();
            continue;
        }
        let text = std::fs::read_to_string(&record)
            .unwrap_or_else(|e| panic!("{}: {e} (record it with PUSHPACK_BLESS=1)", record.display()));
        let recorded: Value = serde_json::from_str(&text).unwrap();
        let mut d = Vec::new();
        diff(&stem, &recorded, &now, &mut d);
        if !d.is_empty() {
            d.truncate(20);
            failures.push(d.join("\n"));
        }
    }
    assert!(
        failures.is_empty(),
        "plans differ from tests/golden:\n{}",
        failures.join("\n\n")
    );
}

#[test]
fn the_comparison_catches_a_changed_joint_value() {
    let plan = json!({
        "placement": {"occupied_area": 1.0, "lower_bound": 1.0, "contact_length": 0.5},
        "placements": [], "actions": [], "metrics": {"seq_len": 0},
        "trajectories": [{"action": 0, "label": "a", "arm": "left", "t_start": 0.0, "t_end": 1.0,
            "points": [{"t": 0.0, "positions": [0.1, 0.2]}, {"t": 1.0, "positions": [0.3, 0.4]}],
            "key_poses": []}],
    });
    let mut changed = plan.clone();
    changed["trajectories"][0]["points"][1]["positions"][0] = json!(0.3001);
    let mut d = Vec::new();
    diff("p", &canonical(&plan), &canonical(&changed), &mut d);
    assert_eq!(d.len(), 1, "{d:?}");
    let mut same = Vec::new();
    diff("p", &canonical(&plan), &canonical(&plan.clone()), &mut same);
    assert!(same.is_empty());
}

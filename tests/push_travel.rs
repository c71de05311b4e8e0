//! Phases judged by their travel (`docs/push_stability.md` §5.4) and the `push-check` nits of
//! issue 25 (size limits, friction use without friction).

use std::process::Command;

use pushpack::actions::push::{self, check_scenario, load_scenario, parse_scenario, travel, FailureKind};
use serde_json::{json, Value};

fn pushes(name: &str) -> String {
    format!("{}/instances/pushes/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn with_gap(gap: f64) -> Value {
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(pushes("short_phase_passes.json")).unwrap()).unwrap();
    v["boxes"][1]["pose"][0] = json!(0.15 + gap);
    v["pusher"]["point"][0] = json!(0.20 + gap);
    v
}

/// The closed form of the example: back box 100 × 100 mm (friction radius `c` of the square),
/// pushed at the finger's edge 20 mm off its centre line, 50 mm behind its centre, finger sticks
/// (`|x y| / (c² + x²) = 0.25 < μ`): it turns `|y| / (c² + x² + y²)` per metre of finger travel and
/// advances `(c² + x²) / (c² + x² + y²)` per metre, so closing a gap `g` takes `g / advance` of
/// finger travel.
fn closed_form_rotation(gap: f64) -> f64 {
    let c = travel::friction_radius([0.05, 0.05]);
    let (x, y) = (0.05f64, 0.02f64);
    let d = c * c + x * x + y * y;
    y / d * gap / ((c * c + x * x) / d)
}

#[test]
fn a_short_phase_passes_and_a_long_one_fails_by_the_rotation_over_its_travel() {
    let short = check_scenario(&load_scenario(pushes("short_phase_passes.json")).unwrap());
    assert!(short.stable(), "{short}");
    let t = short.phases[0]
        .travel
        .as_ref()
        .expect("phase 1 is judged by its travel");
    assert!((t.travel - 0.0002).abs() < 1e-9);
    assert!(t.sticking);
    assert!((t.rotation - closed_form_rotation(0.0002)).abs() < 1e-9, "{t:?}");
    assert!(t.rotation.to_degrees() < 0.07 && t.passes && t.usage < 0.1, "{t:?}");
    // Phase 1 alone would rotate forever (margin −20 mm) but no longer sets the push's margin:
    // the closed-up line does (10 mm), and the report says so.
    assert!((short.phases[0].margin.unwrap() + 0.02).abs() < 1e-7);
    assert!((short.margin.unwrap() - 0.01).abs() < 1e-7, "{short}");
    assert_eq!(short.limiting_phase, Some(2));
    assert!(short.to_string().contains("judged by its travel"), "{short}");

    let long = check_scenario(&load_scenario(pushes("long_phase_turns.json")).unwrap());
    assert!(!long.stable(), "{long}");
    let t = long.phases[0].travel.as_ref().expect("phase 1 is judged by its travel");
    assert!((t.rotation - closed_form_rotation(0.01)).abs() < 1e-9, "{t:?}");
    assert!((2.5..3.5).contains(&t.rotation.to_degrees()), "{t:?}");
    assert!(!t.passes && t.usage > 2.0);
    assert_eq!(long.limiting_phase, Some(1));
    let f = long.failure.as_ref().expect("failure");
    assert_eq!((f.phase, f.kind), (1, FailureKind::Rotate));
    assert!(
        f.detail.contains("turns") && f.detail.contains("10.000 mm gap"),
        "{}",
        f.detail
    );
    assert!((long.margin.unwrap() + 0.02).abs() < 1e-7, "{long}");
}

#[test]
fn the_travel_rule_switches_where_the_rotation_reaches_the_limit() {
    // Rotation grows linearly with the gap; with the default 1° the switch is at the gap whose
    // closed-form rotation is 1° (drift is smaller here: |x y| < |y| c-terms, checked below).
    let limit = push::MAX_ROTATION;
    let g_star = 0.0002 * limit / closed_form_rotation(0.0002);
    assert!((0.002..0.006).contains(&g_star), "{g_star}");
    for (f, stable) in [(0.9, true), (0.99, true), (1.01, false), (1.5, false)] {
        let r = check_scenario(&parse_scenario(&with_gap(g_star * f).to_string(), "<test>").unwrap());
        assert_eq!(r.stable(), stable, "gap {} mm: {r}", g_star * f * 1e3);
        let t = r.phases[0].travel.as_ref().unwrap();
        assert!(t.drift < t.rotation * 0.06, "{t:?}");
    }
    // A tighter tolerance from the file moves the switch.
    let mut v = with_gap(g_star * 0.5);
    assert!(check_scenario(&parse_scenario(&v.to_string(), "<test>").unwrap()).stable());
    v["max_rotation"] = json!(limit * 0.4);
    assert!(!check_scenario(&parse_scenario(&v.to_string(), "<test>").unwrap()).stable());
}

#[test]
fn slip_tipping_and_unbounded_phases_are_not_excused_by_travel() {
    // The closed-up line (the last phase) lasts the whole push: never judged by travel.
    let r = check_scenario(&load_scenario(pushes("pair_3d_not_lenient.json")).unwrap());
    assert!(!r.stable() && r.phases.iter().all(|p| p.travel.is_none()), "{r}");
    // A short phase that slips is still a failure (no margin at all).
    let mut v = with_gap(0.0002);
    v["push_dir"] = json!([-1.0, -0.5]);
    v["pusher"]["normal"] = json!([-1.0, 0.0]);
    v["friction"]["mu_finger"] = json!(0.1);
    if let Ok(s) = parse_scenario(&v.to_string(), "<test>") {
        let r = check_scenario(&s);
        if r.phases[0].margin.is_none() {
            assert!(r.phases[0].travel.is_none() && !r.stable(), "{r}");
        }
    }
    // Robust mode: the worst case is an unstable one whenever any is.
    let mut v = with_gap(0.004);
    v["mode"] = json!("robust");
    v["robust"] = json!({ "cof_region": [0.01, 0.01] });
    let r = check_scenario(&parse_scenario(&v.to_string(), "<test>").unwrap());
    let mut nominal = v.clone();
    nominal["mode"] = json!("2d");
    let n = check_scenario(&parse_scenario(&nominal.to_string(), "<test>").unwrap());
    assert!(!r.stable() || n.stable(), "robust stable but nominal not:\n{r}\n{n}");
}

fn push_check(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .arg("push-check")
        .args(args)
        .output()
        .expect("run pushpack")
}

#[test]
fn push_check_rejects_boxes_smaller_than_instance_files_accept_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(pushes("single_centred.json")).unwrap()).unwrap();
    v["boxes"][0]["size"][0] = json!(1e-12);
    let path = dir.path().join("tiny_box.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let out = push_check(&[&path.display().to_string()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(stderr.contains("tiny_box.json"), "{stderr}");
    assert!(stderr.contains("boxes[0].size[0]"), "{stderr}");
    assert!(stderr.contains("at least 0.0001 m"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn push_check_without_finger_friction_prints_no_absurd_percentages() {
    let dir = tempfile::tempdir().unwrap();
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(pushes("single_centred.json")).unwrap()).unwrap();
    v["friction"]["mu_finger"] = json!(0.0);
    let path = dir.path().join("no_finger_friction.json");
    std::fs::write(&path, v.to_string()).unwrap();
    for mode in ["2d", "3d"] {
        v["mode"] = json!(mode);
        std::fs::write(&path, v.to_string()).unwrap();
        let out = push_check(&[&path.display().to_string()]);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(matches!(out.status.code(), Some(0 | 1)), "{mode}: {text}");
        assert!(text.contains("friction use n/a (μ = 0)"), "{mode}: {text}");
        for part in text.split("friction use ").skip(1) {
            let word = part.split_whitespace().next().unwrap_or("");
            if let Some(p) = word.strip_suffix('%') {
                let p: f64 = p.parse().unwrap_or_else(|_| panic!("{mode}: {word}"));
                assert!((0.0..=100.0).contains(&p), "{mode}: friction use {p}%\n{text}");
            }
        }
        let out = push_check(&[&path.display().to_string(), "--json"]);
        let js: Value = serde_json::from_slice(&out.stdout).unwrap();
        let c = &js["phases"][0]["contacts"][0];
        assert!(c["friction_use"].is_null(), "{mode}: {c}");
    }
}

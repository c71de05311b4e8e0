//! Phases judged by their travel (`docs/push_stability.md` §5.4) and the `push-check` nits of
//! issue 25 (size limits, friction use without friction).

mod common;

use std::process::Command;

use pushpack::actions::push::{self, check_scenario, load_scenario, parse_scenario, travel, FailureKind};
use pushpack::geometry::{BodyAxis, Orientation, Rect};
use pushpack::instance::Instance;
use pushpack::placement::{Placement, PlacementResult, Target};
use pushpack::plan::{sequence_placement, PlanOptions, Sequencer};
use pushpack::verify::verify;
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

// ---------------------------------------------------------------------------------------------
// The planner's rule (`push::geometry_verdict`, used by `Layout::check` and the verifier) is the
// push-check rule on the same line.

/// The line of `short_phase_passes.json` as the planner sees it: lateral intervals (y), friction
/// weights `μ m`, the finger, and the gap in front of the back box.
fn planner_line(gap: f64, min_margin: f64) -> (push::LineGeometry, push::LineTravel) {
    (
        push::LineGeometry {
            lateral: vec![[-0.01, 0.09], [-0.05, 0.05]],
            weight: vec![0.5 * 1.5, 0.5 * 0.5],
            pusher: [0.02, 0.04],
        },
        push::LineTravel {
            gaps: vec![gap],
            depth: vec![0.1, 0.1],
            mu_finger: 0.5,
            max_rotation: push::MAX_ROTATION,
            max_drift: push::MAX_DRIFT,
            min_margin,
        },
    )
}

#[test]
fn the_planner_judges_the_issue_lines_by_their_travel_as_push_check_does() {
    for (file, gap, stable) in [
        ("short_phase_passes.json", 0.0002, true),
        ("long_phase_turns.json", 0.01, false),
    ] {
        let report = check_scenario(&load_scenario(pushes(file)).unwrap());
        let want = report.phases[0].travel.as_ref().unwrap();
        // With push-check's own tolerance and with the planner's default 2 mm.
        for min_margin in [push::MARGIN_TOL, 0.002] {
            let (line, travel) = planner_line(gap, min_margin);
            let v = push::geometry_verdict(&line, &travel);
            assert_eq!(v.accepted(min_margin), stable, "{file}: {v:?}");
            let t = v.travel.as_ref().expect("judged by its travel");
            assert_eq!(t.passes, stable);
            assert!((t.rotation - closed_form_rotation(gap)).abs() < 1e-9, "{t:?}");
            for (a, b) in [
                (t.rotation, want.rotation),
                (t.drift, want.drift),
                (t.usage, want.usage),
                (t.pusher_travel, want.pusher_travel),
            ] {
                assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{file}: {t:?} vs {want:?}");
            }
            assert!(
                (v.margin - report.margin.unwrap()).abs() < 1e-7,
                "{file}: {v:?}\n{report}"
            );
            // Judged as if the phase lasted forever, both lines fail: the back box alone pushed
            // 20 mm beyond the finger's edge.
            let flags = [true];
            assert!((push::geometry_margin(&line, &flags) + 0.02).abs() < 1e-7);
        }
    }
}

/// A small deterministic generator (SplitMix64), so the random lines are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

#[test]
fn the_planner_and_push_check_agree_on_random_lines_with_gaps() {
    let mut rng = Rng(25);
    let (mut compared, mut passed_by_travel, mut failed_by_travel) = (0, 0, 0);
    for case in 0..400 {
        let k = 2 + (rng.next() * 2.0) as usize;
        let mut width = vec![];
        let mut centre: Vec<f64> = vec![];
        for m in 0..k {
            let w = rng.range(0.03, 0.12);
            let c = if m == 0 {
                0.0
            } else {
                centre[m - 1] + rng.range(-0.4, 0.4) * w.min(width[m - 1])
            };
            width.push(w);
            centre.push(c);
        }
        let depth: Vec<f64> = (0..k).map(|_| rng.range(0.02, 0.12)).collect();
        let mass: Vec<f64> = (0..k).map(|_| rng.range(0.05, 2.0)).collect();
        let gaps: Vec<f64> = (1..k)
            .map(|_| {
                if rng.next() < 0.3 {
                    0.0
                } else {
                    rng.range(0.0001, 0.015)
                }
            })
            .collect();
        // The finger overlaps the back box by at least 1 mm.
        let (back_c, back_w) = (centre[k - 1], width[k - 1]);
        let reach = back_w / 2.0 + 0.01 - 0.001;
        let at = back_c + rng.range(-reach, reach);
        let mu_finger = rng.range(0.05, 1.0);
        let min_margin = if case % 2 == 0 { push::MARGIN_TOL } else { 0.002 };

        let line = push::LineGeometry {
            lateral: (0..k)
                .map(|m| [centre[m] - width[m] / 2.0, centre[m] + width[m] / 2.0])
                .collect(),
            weight: mass.iter().map(|m| 0.5 * m).collect(),
            pusher: [at - 0.01, at + 0.01],
        };
        let travel = push::LineTravel {
            gaps: gaps.clone(),
            depth: depth.clone(),
            mu_finger,
            max_rotation: push::MAX_ROTATION,
            max_drift: push::MAX_DRIFT,
            min_margin,
        };
        let v = push::geometry_verdict(&line, &travel);

        // The same line as a push-check file, pushed along −x, gaps between the boxes.
        let mut x = 0.0;
        let mut boxes = vec![];
        for m in 0..k {
            if m > 0 {
                x += (depth[m - 1] + depth[m]) / 2.0 + gaps[m - 1];
            }
            boxes.push(json!({
                "id": format!("b{m}"), "size": [depth[m], width[m], 0.05], "mass": mass[m], "pose": [x, centre[m], 0.0]
            }));
        }
        let file = json!({
            "mode": "2d", "push_dir": "-x",
            "friction": { "mu_floor": 0.5, "mu_obj": 0.5, "mu_finger": mu_finger },
            "boxes": boxes,
            "pusher": { "point": [x + depth[k - 1] / 2.0 + 0.001, at], "width": 0.02, "height": 0.005 },
            "min_margin": min_margin,
        });
        let r = check_scenario(&parse_scenario(&file.to_string(), "<random>").unwrap());
        let judged = r.phases.iter().find_map(|p| p.travel.as_ref());
        let near_edge = (v.margin - min_margin).abs() < 1e-6
            || judged.is_some_and(|t| (t.usage - 1.0).abs() < 1e-6)
            || v.travel.as_ref().is_some_and(|t| (t.usage - 1.0).abs() < 1e-6);
        if near_edge {
            continue;
        }
        compared += 1;
        assert_eq!(v.accepted(min_margin), r.stable(), "case {case}: {v:?}\n{r}\n{file}");
        assert!((v.margin - r.margin.unwrap()).abs() < 1e-7, "case {case}: {v:?}\n{r}");
        match (&v.travel, judged) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                assert_eq!(a.passes, b.passes, "case {case}");
                assert_eq!(a.sticking, b.sticking, "case {case}");
                for (p, q) in [(a.rotation, b.rotation), (a.drift, b.drift), (a.usage, b.usage)] {
                    assert!((p - q).abs() <= 1e-9 * (1.0 + q.abs()), "case {case}: {a:?} vs {b:?}");
                }
                if a.passes {
                    passed_by_travel += 1;
                } else {
                    failed_by_travel += 1;
                }
            }
            _ => panic!("case {case}: planner {:?}, push-check {:?}\n{r}", v.travel, judged),
        }
    }
    eprintln!("{compared} lines compared: {passed_by_travel} passed by their travel, {failed_by_travel} failed it");
    // The comparison covers lines the rule lets through and lines it rejects.
    assert!(compared >= 390, "{compared}");
    assert!(
        passed_by_travel >= 10 && failed_by_travel >= 10,
        "{passed_by_travel} passed, {failed_by_travel} failed"
    );
}

// ---------------------------------------------------------------------------------------------
// A plan that needs the rule.

/// Front `f` (40 × 80 mm, 0.7 kg) and back `b` (40 × 50 mm, 0.3 kg) in a −x line along the −y
/// wall. With direct places forbidden (the paper's ablation) both are released and pushed. `b`
/// cannot start touching `f`: the wall takes its −y finger and `f` its −x finger, so it starts at
/// least one `min_offset` (15 mm) behind `f` and closes that gap alone. The finger centred on
/// the pair's friction centroid (y = 0.0355) leaves `b`'s centre line (y = 0.025) 0.5 mm beyond
/// its edge: judged as if that phase lasted forever the pair cannot be pushed together (four
/// actions); over 15 mm `b` turns about 0.6° (three actions).
const NEEDS_THE_RULE: &str = r#"
name = "needs-the-travel-rule"
[container]
width = 0.20
depth = 0.20
wall_height = 0.10
wall_thickness = 0.01
center = [0.30, 0.0]
[friction]
mu_floor = 0.5
mu_obj = 0.5
mu_finger = 0.6
[gripper]
finger_thickness = 0.01
finger_width = 0.02
finger_length = 0.06
max_opening = 0.09
grasp_depth = 0.015
release_clearance = 0.005
[planner]
no_direct = true
[[kinds]]
name = "wide"
size = [0.04, 0.08, 0.05]
mass = 0.7
[[kinds]]
name = "narrow"
size = [0.04, 0.05, 0.05]
mass = 0.3
[[objects]]
id = "f"
kind = "wide"
x = 0.22
y = 0.27
[[objects]]
id = "b"
kind = "narrow"
x = 0.32
y = 0.30
"#;

fn needs_the_rule_placement(inst: &Instance) -> PlacementResult {
    let up = Orientation {
        up: BodyAxis::Z,
        yaw90: false,
    };
    let corner = |id: &str| if id == "b" { (0.04, 0.0) } else { (0.0, 0.0) };
    let targets = inst
        .objects
        .iter()
        .map(|o| {
            let (fp, h) = up.dims(o.size);
            let (x, y) = corner(&o.id);
            Target {
                orientation: up,
                rect: Rect::new(x, y, fp[0], fp[1]),
                height: h,
            }
        })
        .collect();
    let placement = Placement { targets };
    common::hand_result(inst, placement)
}

fn plan_packing(inst: &Instance) -> pushpack::plan::PlanOutcome {
    plan_packing_with(inst, Sequencer::Astar)
}

fn plan_packing_with(inst: &Instance, sequencer: Sequencer) -> pushpack::plan::PlanOutcome {
    let mut opts = PlanOptions::from_instance(inst);
    opts.packing_only = true;
    opts.sequencer = sequencer;
    let out = sequence_placement(inst, &opts, needs_the_rule_placement(inst)).unwrap();
    let r = verify(inst, &out.plan);
    assert!(r.is_valid(), "{r}");
    out
}

#[test]
fn a_plan_that_needs_the_travel_rule_is_produced_and_verified() {
    let inst = Instance::parse(NEEDS_THE_RULE, false, "needs_the_rule.toml", None).unwrap();
    let out = plan_packing(&inst);
    let pair = out
        .plan
        .actions
        .iter()
        .find(|e| e.kind == "push" && e.objects == ["f", "b"])
        .unwrap_or_else(|| panic!("f and b are pushed together: {:#?}", out.plan.actions));
    let t = pair
        .travel_phase
        .as_ref()
        .expect("b's phase alone is judged by its travel");
    assert_eq!(t.object, "b");
    assert!((t.gap - inst.gripper.min_offset).abs() < 1e-9, "{t:?}");
    assert!((0.4..0.8).contains(&t.rotation.to_degrees()) && t.usage < 0.8, "{t:?}");
    // The recorded margin is the closed-up pair's (the finger's half width), not b's −0.5 mm.
    assert!((pair.margin.unwrap() - 0.01).abs() < 1e-6, "{:?}", pair.margin);

    // With a rotation limit below what b turns, the pair cannot go together and the plan needs
    // one more action (f and b pushed one after the other).
    assert_eq!(out.plan.metrics.seq_len, 3, "{:#?}", out.plan.actions);
    let mut strict = inst.clone();
    strict.settings.max_push_rotation = 0.1f64.to_radians();
    let without = plan_packing(&strict);
    assert!(without.plan.actions.iter().all(|e| e.travel_phase.is_none()));
    assert_eq!(
        without.plan.metrics.seq_len,
        out.plan.metrics.seq_len + 1,
        "{:#?}",
        without.plan.actions
    );

    // The paper's sequencer releases the line staggered by one `min_offset` and checks it with
    // that gap: it pushes the pair together too, with the same travel phase.
    let paper = plan_packing_with(&inst, Sequencer::Paper);
    let pair = paper
        .plan
        .actions
        .iter()
        .find(|e| e.kind == "push" && e.objects == ["f", "b"])
        .unwrap_or_else(|| panic!("paper: f and b are pushed together: {:#?}", paper.plan.actions));
    assert_eq!(pair.travel_phase.as_ref(), Some(t));
    let paper_strict = plan_packing_with(&strict, Sequencer::Paper);
    assert!(paper_strict.plan.actions.iter().all(|e| e.travel_phase.is_none()));
}

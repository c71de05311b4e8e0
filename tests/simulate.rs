//! The physics replay (`pushpack simulate`): first checked against the closed forms of
//! docs/push_stability.md on single pushes, then run on whole plans of the bundled instances.

mod common;

use pushpack::actions::push::analytic::{single_box_margin, topple_height, two_box_friction_threshold};
use pushpack::simulate::line::{push_line, FloorBox, Pusher};
use pushpack::simulate::{simulate, SimOptions};
use pushpack::{optimize, verify, Plan, PlanOptions};

fn opts() -> SimOptions {
    SimOptions::from_instance(&common::load("paper/exp1_4objects.toml"))
}

/// A 6 × 6 × 3 cm box centred at (0.1, 0), pushed 5 cm along −x by a plate 2 cm wide whose
/// centre is `offset` off the box's centre line: (rotation, lateral drift at the end).
fn single_push(offset: f64) -> (f64, f64) {
    let b = FloorBox {
        centre: [0.1, 0.0],
        size: [0.06, 0.06, 0.03],
        mass: 0.05,
        mu: [0.4, 0.4, 0.5],
        yaw: 0.0,
    };
    let x0 = 0.1 + 0.03 + 0.005 + 0.0005;
    let p = Pusher {
        half: [0.005, 0.01, 0.03],
        path: [[x0, offset], [x0 - 0.05, offset]],
        tip_height: 0.005,
    };
    let m = push_line(&[b], &p, &opts());
    (m[0].max_rotation, m[0].end.translation.vector.y.abs())
}

#[test]
fn a_centred_push_goes_straight() {
    let (rot, drift) = single_push(0.0);
    assert!(rot.to_degrees() < 0.05, "turned {:.3}°", rot.to_degrees());
    assert!(drift < 2e-5, "drifted {:.4} mm", drift * 1e3);
}

#[test]
fn a_push_turns_the_box_only_when_its_line_of_action_leaves_the_finger() {
    // The closed form's margin is finger/2 − |offset| (10 mm − |offset|): positive = sticks.
    for (offset, sticks) in [(0.005, true), (0.009, true), (0.011, false), (0.016, false)] {
        assert_eq!(single_box_margin(0.06, 0.02, offset) > 0.0, sticks);
        let (rot, _) = single_push(offset);
        if sticks {
            assert!(
                rot.to_degrees() < 0.05,
                "offset {offset}: turned {:.3}°",
                rot.to_degrees()
            );
        } else {
            assert!(
                rot.to_degrees() > 1.0,
                "offset {offset}: turned only {:.3}°",
                rot.to_degrees()
            );
        }
    }
}

#[test]
fn a_tall_box_tips_above_the_closed_form_height_and_slides_below_it() {
    // 2 cm deep along the push, 10 cm tall; μ_floor 0.8, μ_finger 0.3.
    let th = topple_height(0.02, 0.8, 0.3);
    for (factor, tips) in [(0.5, false), (0.85, false), (1.15, true), (1.6, true)] {
        let b = FloorBox {
            centre: [0.1, 0.0],
            size: [0.02, 0.06, 0.10],
            mass: 0.05,
            mu: [0.8, 0.4, 0.3],
            yaw: 0.0,
        };
        let x0 = 0.1 + 0.01 + 0.005 + 0.0005;
        let p = Pusher {
            half: [0.005, 0.01, 0.03],
            path: [[x0, 0.0], [x0 - 0.03, 0.0]],
            tip_height: factor * th,
        };
        let tilt = push_line(&[b], &p, &opts())[0].max_tilt.to_degrees();
        if tips {
            assert!(tilt > 45.0, "fingertip at {factor} × {th:.4} m: tilted only {tilt:.2}°");
        } else {
            assert!(tilt < 0.1, "fingertip at {factor} × {th:.4} m: tilted {tilt:.2}°");
        }
    }
}

#[test]
fn two_offset_boxes_slip_apart_below_the_friction_threshold_and_stay_together_above_it() {
    // Boxes 4 cm deep, centroids 12 mm apart across the push, pushed along the line through
    // both centroids: the contact force leans atan(12/40) from the contact normal.
    let (d, e) = (0.04, 0.012);
    let threshold = two_box_friction_threshold(d, e);
    let n = d.hypot(e);
    let u = [-d / n, -e / n];
    for (factor, slips) in [(0.5, true), (1.5, false)] {
        let mu = factor * threshold;
        let bx = |c: [f64; 2]| FloorBox {
            centre: c,
            size: [d, 0.06, 0.03],
            mass: 0.05,
            mu: [0.4, mu, 1.0],
            yaw: 0.0,
        };
        let s = [0.1 + d + d / 2.0 + 0.0055, e * 1.5];
        let p = Pusher {
            half: [0.005, 0.01, 0.03],
            path: [s, [s[0] + 0.05 * u[0], s[1] + 0.05 * u[1]]],
            tip_height: 0.005,
        };
        let m = push_line(&[bx([0.1, 0.0]), bx([0.1 + d, e])], &p, &opts());
        let lateral = m[1].end.translation.vector.y - m[0].end.translation.vector.y;
        let slip = (e - lateral).abs();
        if slips {
            assert!(slip > 3e-3, "μ = {mu:.3}: slipped only {:.2} mm", slip * 1e3);
        } else {
            assert!(slip < 1e-4, "μ = {mu:.3}: slipped {:.2} mm", slip * 1e3);
        }
    }
}

fn planned(rel: &str) -> (pushpack::Instance, Plan) {
    let inst = common::load(rel);
    let out = optimize(&inst, &PlanOptions::from_instance(&inst)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    let report = verify(&inst, &out.plan);
    assert!(report.is_valid(), "{rel}: {report}");
    (inst, out.plan)
}

#[test]
fn every_bundled_plan_ends_with_every_box_at_its_target() {
    for rel in [
        "examples/two_boxes.toml",
        "examples/row_of_three.json",
        "examples/mixed_5.toml",
        "examples/upright_only.toml",
        "paper/exp1_4objects.toml",
        "paper/exp2_8objects.toml",
    ] {
        let (inst, plan) = planned(rel);
        let s = simulate(&inst, &plan, &SimOptions::from_instance(&inst)).unwrap();
        assert_eq!(s.actions.len(), plan.actions.len());
        assert_eq!(s.boxes.len(), inst.objects.len());
        for b in &s.boxes {
            assert!(b.placed && b.ok, "{rel}: {b:?}\n{s}");
            // Far inside the 1 mm tolerance: contacts stiff enough that a pushed line does
            // not stay compressed (docs/simulate.md, "Settings").
            assert!(b.position_error_mm < 0.1, "{rel}: {b:?}\n{s}");
        }
        assert!(s.ok, "{rel}:\n{s}");
    }
}

#[test]
fn the_replay_is_deterministic() {
    let (inst, plan) = planned("paper/exp1_4objects.toml");
    let o = SimOptions::from_instance(&inst);
    let (mut a, mut b) = (simulate(&inst, &plan, &o).unwrap(), simulate(&inst, &plan, &o).unwrap());
    a.wall_s = 0.0;
    b.wall_s = 0.0;
    assert_eq!(a, b);
}

#[test]
fn a_push_moved_to_the_edge_of_its_box_turns_it_out_of_tolerance() {
    // The same plan with one push's finger moved 1 mm inside the back box's edge: its line
    // of action leaves the finger, which the verifier rejects by the rules and the replay
    // must see happen.
    for rel in [
        "examples/row_of_three.json",
        "paper/exp1_4objects.toml",
        "paper/exp2_8objects.toml",
    ] {
        let (inst, mut plan) = planned(rel);
        let Some(k) = plan.actions.iter().position(|a| a.kind == "push") else {
            continue;
        };
        let back = plan.actions[k].objects.last().unwrap().clone();
        let t = plan.placements.iter().find(|p| p.object == back).unwrap();
        let lo = if plan.actions[k].push_dir == Some(pushpack::geometry::PushDir::MinusX) {
            t.y
        } else {
            t.x
        };
        plan.actions[k].pusher_at = Some(lo + 0.001);
        assert!(
            !verify(&inst, &plan).is_valid(),
            "{rel}: the verifier accepted the moved finger"
        );
        let s = simulate(&inst, &plan, &SimOptions::from_instance(&inst)).unwrap();
        assert!(
            !s.ok,
            "{rel}: a push 1 mm from the box's edge kept every box in tolerance\n{s}"
        );
        assert!(!s.actions[k].ok, "{rel}: step {} within tolerance\n{s}", k + 1);
        return;
    }
    panic!("no bundled plan has a push");
}

#[test]
fn options_out_of_range_are_input_errors() {
    let (inst, plan) = planned("examples/two_boxes.toml");
    for bad in [0.0, -1.0, f64::NAN] {
        let o = SimOptions {
            dt: bad,
            ..SimOptions::from_instance(&inst)
        };
        let e = simulate(&inst, &plan, &o).unwrap_err();
        assert!(
            matches!(e, pushpack::Error::Input { .. }) && e.to_string().contains("dt"),
            "{e}"
        );
    }
}

fn cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run pushpack")
}

#[test]
fn cli_simulate_and_verify_simulate_report_and_exit_by_the_verdict() {
    let (inst, plan) = planned("examples/row_of_three.json");
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.json");
    plan.save(&good).unwrap();
    let inst_path = common::bundled("examples/row_of_three.json");
    let good = good.display().to_string();

    let out = cli(&["simulate", &good, "--instance", &inst_path, "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["ok"], true);
    assert_eq!(v["boxes"].as_array().unwrap().len(), inst.objects.len());

    let out = cli(&["verify", &inst_path, &good, "--simulate"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("simulation: every box within tolerance"));

    // The finger of the first push moved to 1 mm inside the back box's edge.
    let mut bad = plan.clone();
    let k = bad.actions.iter().position(|a| a.kind == "push").expect("a push");
    let back = bad.actions[k].objects.last().unwrap().clone();
    let t = bad.placements.iter().find(|p| p.object == back).unwrap();
    let lo = if bad.actions[k].push_dir == Some(pushpack::geometry::PushDir::MinusX) {
        t.y
    } else {
        t.x
    };
    bad.actions[k].pusher_at = Some(lo + 0.001);
    let bad_path = dir.path().join("bad.json");
    bad.save(&bad_path).unwrap();
    let out = cli(&["simulate", &bad_path.display().to_string(), "--instance", &inst_path]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("OUT OF TOLERANCE"));

    for (flag, value) in [("--dt", "0"), ("--push-speed", "-1"), ("--dt", "NaN")] {
        let arg = format!("{flag}={value}");
        let out = cli(&["simulate", &good, "--instance", &inst_path, &arg]);
        assert_eq!(out.status.code(), Some(2), "{arg}");
        assert!(String::from_utf8_lossy(&out.stderr).contains(flag), "{arg}");
    }
    let out = cli(&["simulate", "does/not/exist.json"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_verdict_uses_the_instances_push_tolerances() {
    let (inst, plan) = planned("examples/row_of_three.json");
    let o = SimOptions::from_instance(&inst);
    assert_eq!(o.tolerances.max_rotation, inst.settings.max_push_rotation);
    assert_eq!(o.tolerances.max_drift, inst.settings.max_push_drift);
    assert!(simulate(&inst, &plan, &o).unwrap().ok);
    // A micrometre is tighter than the replay's own contact slop: the same plan fails.
    let tight = SimOptions {
        tolerances: pushpack::simulate::Tolerances {
            max_rotation: o.tolerances.max_rotation,
            max_drift: 1e-6,
        },
        ..o
    };
    let s = simulate(&inst, &plan, &tight).unwrap();
    assert!(!s.ok && s.boxes.iter().any(|b| !b.ok), "{s}");
}

#[test]
fn a_sweep_replays_under_six_distinct_settings() {
    let (inst, plan) = planned("examples/two_boxes.toml");
    let base = SimOptions::from_instance(&inst);
    let runs = pushpack::simulate::sweep::sweep(&inst, &plan, &base).unwrap();
    assert_eq!(runs.len(), 6);
    let settings: std::collections::BTreeSet<_> = runs.iter().map(|r| r.setting.clone()).collect();
    assert_eq!(settings.len(), 6, "{settings:?}");
    assert_eq!(runs[0].report.steps, simulate(&inst, &plan, &base).unwrap().steps);
    // Half the step: about twice the steps.
    let ratio = runs[1].report.steps as f64 / runs[0].report.steps as f64;
    assert!((ratio - 2.0).abs() < 0.05, "{ratio}");
    assert!(
        runs.iter().all(|r| r.report.ok),
        "{}",
        pushpack::simulate::sweep::sweep_table(&runs)
    );
}

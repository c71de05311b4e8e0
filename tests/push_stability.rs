//! Push stability: the clarabel checks (2-D LP, 3-D SOCP, robust) against the closed forms of
//! `docs/push_stability.md` and the paper's analytic condition (the oracle).

use pushpack::actions::push::{
    self, analytic, check_scenario, convex, load_scenario, parse_scenario, robust, CheckOptions, Dim, FailureKind,
    LineGeometry, Mode, MARGIN_TOL,
};
use serde_json::{json, Value};

/// splitmix64: deterministic, no extra crates.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn pushes(name: &str) -> String {
    format!("{}/instances/pushes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Scenario JSON of one box pushed along −x, footprint `[0.02, 0.08] × [0.01, 0.05]`.
fn single_box(mode: &str, pusher_y: f64, width: f64) -> Value {
    json!({
        "mode": mode,
        "push_dir": "-x",
        "friction": { "mu_floor": 0.35, "mu_obj": 0.3, "mu_finger": 0.5 },
        "boxes": [ { "id": "b1", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.05, 0.03, 0.0] } ],
        "pusher": { "point": [0.09, pusher_y], "width": width, "height": 0.005 }
    })
}

fn check(v: &Value) -> push::PushReport {
    let s = parse_scenario(&v.to_string(), "<test>").unwrap_or_else(|e| panic!("{e}\n{v}"));
    check_scenario(&s)
}

#[test]
fn centred_single_push_is_stable_with_positive_margin() {
    for mode in ["2d", "3d"] {
        let r = check(&single_box(mode, 0.03, 0.02));
        assert!(r.stable(), "{r}");
        let m = r.margin.expect("margin");
        assert!(
            (m - 0.01).abs() < 1e-7,
            "{mode}: margin {m}, expected half the finger width 0.01"
        );
        assert!(r.failure.is_none());
        // The certificate: the finger carries the box's floor friction, along the push, through
        // the centroid. In 3-D the planar part sets this margin (the box is far from tipping),
        // so its certificate has no vertical friction either; the floor reaction comes from the
        // box's own tipping program.
        let c = &r.phases[0].contacts[0];
        let load = 0.35 * 0.05 * 9.81;
        assert_eq!(c.force.force[2], 0.0);
        if mode == "3d" {
            assert!(r.phases[0].floor[0].floor.footprint_margin > 0.01, "{r}");
        }
        assert!(
            (c.force.force[0] + load).abs() < 1e-6 * load,
            "{mode}: {:?} vs {load}",
            c.force.force
        );
        assert!(c.force.force[1].abs() < 1e-6);
        assert!(
            (c.force.point[1] - 0.03).abs() < 1e-7,
            "line of action through the centroid"
        );
    }
    // The planner's contract path agrees.
    let line = LineGeometry {
        lateral: vec![[0.01, 0.05]],
        weight: vec![0.35 * 0.05],
        pusher: [0.02, 0.04],
    };
    assert!((push::geometry_margin(&line, &[]) - 0.01).abs() < 1e-7);
}

#[test]
fn margin_shrinks_monotonically_off_centre_and_vanishes_at_the_closed_form() {
    let (face, finger) = (0.04, 0.02);
    let mut last = f64::INFINITY;
    let mut k = 0;
    while k <= 16 {
        let off = 0.001 * k as f64;
        let r = check(&single_box("2d", 0.03 + off, finger));
        let m = r.margin.expect("margin");
        let closed = analytic::single_box_margin(face, finger, off);
        assert!(
            (m - closed).abs() < 1e-7,
            "offset {off}: margin {m}, closed form {closed}"
        );
        assert!(m < last - 5e-4, "offset {off}: margin {m} did not shrink from {last}");
        assert_eq!(r.stable(), closed > MARGIN_TOL, "offset {off}: {r}");
        last = m;
        k += 1;
    }
    // Zero exactly where the line of action reaches the finger's edge: offset = finger/2.
    let at = check(&single_box("2d", 0.03 + finger / 2.0, finger));
    assert!(at.margin.expect("margin").abs() < 1e-8 && !at.stable());
    assert_eq!(at.failure.as_ref().map(|f| f.kind), Some(FailureKind::Rotate));
    assert!(check(&single_box("2d", 0.03 + finger / 2.0 - 1e-4, finger)).stable());
    assert!(!check(&single_box("2d", 0.03 + finger / 2.0 + 1e-4, finger)).stable());
    // Off-centre pushes fail the same way in 3-D (low fingertip: no toppling).
    assert!(!check(&single_box("3d", 0.03 + finger / 2.0 + 1e-4, finger)).stable());
    assert!(check(&single_box("3d", 0.03 + finger / 2.0 - 1e-4, finger)).stable());
}

/// Two boxes `depth` deep, `width` wide, the back one offset by `offset` sideways, pushed along
/// the line through both centroids; the finger flat on the back face where that line leaves it.
fn offset_pair(mu_obj: f64, mu_finger: f64, offset: f64, dir_along_centres: bool) -> Value {
    let (depth, width) = (0.06, 0.05);
    let u = if dir_along_centres {
        json!([-depth, -offset])
    } else {
        json!("-x")
    };
    let py = if dir_along_centres { 1.5 * offset } else { offset / 2.0 };
    json!({
        "mode": "2d",
        "push_dir": u,
        "friction": { "mu_floor": 0.35, "mu_obj": mu_obj, "mu_finger": mu_finger },
        "boxes": [
            { "id": "b1", "size": [depth, width, 0.04], "mass": 0.1, "pose": [0.0, 0.0, 0.0] },
            { "id": "b2", "size": [depth, width, 0.04], "mass": 0.1, "pose": [depth, offset, 0.0] }
        ],
        "pusher": { "point": [1.5 * depth, py], "width": 0.02, "height": 0.005, "normal": [-1.0, 0.0] }
    })
}

#[test]
fn two_offset_boxes_fail_below_the_derived_friction_and_pass_above() {
    let (depth, offset) = (0.06, 0.02);
    let star = analytic::two_box_friction_threshold(depth, offset);
    assert!((star - 1.0 / 3.0).abs() < 1e-12);
    let threshold = star / (1.0 - push::CONE_SHRINK);
    for f in [0.5, 0.9, 0.99, 0.999] {
        let r = check(&offset_pair(threshold * f, 1.0, offset, true));
        assert!(!r.stable(), "mu_obj = {} below {threshold}: {r}", threshold * f);
        assert!(r.margin.is_none());
        let fail = r.failure.expect("failure");
        assert_eq!(fail.kind, FailureKind::Slip);
        assert_eq!(fail.at, "b2 → b1");
    }
    for f in [1.001, 1.01, 1.5, 3.0] {
        let r = check(&offset_pair(threshold * f, 1.0, offset, true));
        assert!(r.stable(), "mu_obj = {} above {threshold}: {r}", threshold * f);
        // Friction decides; the margin is the pusher's segment margin (10 mm), whatever μ.
        assert!((r.margin.unwrap() - 0.01).abs() < 1e-7, "{r}");
        let c = &r.phases[0].contacts[0];
        assert!((c.force.tangential[0].abs() / c.force.normal - star).abs() < 1e-6);
    }
    // The finger contact has the same threshold.
    assert!(!check(&offset_pair(1.0, threshold * 0.99, offset, true)).stable());
    assert!(check(&offset_pair(1.0, threshold * 1.01, offset, true)).stable());
    // Pushed straight along −x instead, friction plays no part: the front box's own centroid
    // line must cross the overlap [δ − w/2, w/2]; here it does (margin 5 mm) for any μ.
    for mu in [0.0, 0.1, 1.0] {
        let r = check(&offset_pair(mu, mu, offset, false));
        assert!(r.stable(), "{r}");
        assert!((r.margin.unwrap() - 0.005).abs() < 1e-7, "{r}");
    }
}

/// Random line geometry (front to back), sometimes with non-overlapping faces.
fn random_line(rng: &mut Rng) -> (LineGeometry, Vec<bool>) {
    let k = 1 + rng.below(3);
    let mut lateral = Vec::new();
    let mut lo = rng.range(-0.05, 0.05);
    for _ in 0..k {
        let w = rng.range(0.02, 0.1);
        lateral.push([lo, lo + w]);
        lo += rng.range(-0.8, 0.8) * w;
    }
    let weight = (0..k).map(|_| rng.range(0.01, 0.5)).collect();
    let back = lateral[k - 1];
    let fw = rng.range(0.005, 0.04);
    let c = rng.range(back[0] - 0.01, back[1] + 0.01);
    let gaps = (0..k - 1).map(|_| rng.below(2) == 1).collect();
    (
        LineGeometry {
            lateral,
            weight,
            pusher: [c - fw / 2.0, c + fw / 2.0],
        },
        gaps,
    )
}

#[test]
fn clarabel_agrees_with_the_paper_on_random_lines() {
    let mut rng = Rng(20240607);
    let (mut compared, mut stable, mut unstable) = (0, 0, 0);
    for case in 0..1200 {
        let (line, gaps) = random_line(&mut rng);
        let oracle = analytic::geometry_margin(&line, &gaps);
        let ours = push::geometry_margin(&line, &gaps);
        // The oracle applies everywhere here (faces normal to the push, uniform pressure);
        // skip only the knife edge where the decision is numerically ambiguous.
        if oracle.abs() <= 2.0 * MARGIN_TOL {
            continue;
        }
        compared += 1;
        assert!(
            (ours - oracle).abs() < 1e-8,
            "case {case}: clarabel {ours} vs paper {oracle}\n{line:?} gaps {gaps:?}"
        );
        assert_eq!(ours > MARGIN_TOL, oracle > MARGIN_TOL, "case {case}");
        if oracle > 0.0 {
            stable += 1;
        } else {
            unstable += 1;
        }
    }
    assert!(compared >= 1000, "only {compared} cases compared");
    assert!(
        stable > 200 && unstable > 200,
        "{stable} stable / {unstable} unstable: not a balanced sample"
    );
}

/// The same random lines through the general scenario path: boxes with depths, the whole line
/// turned by a random yaw and pushed along its own axis, contacts found geometrically.
#[test]
fn scenario_geometry_agrees_with_the_paper_under_rotation() {
    let mut rng = Rng(77);
    let mut compared = 0;
    for case in 0..300 {
        let (line, gaps) = random_line(&mut rng);
        let oracle = analytic::geometry_margin(&line, &gaps);
        // Boxes that do not overlap sideways never meet: not a line (the scenario rejects it).
        let apart = (0..line.lateral.len()).any(|m| {
            let behind = line.lateral.get(m + 1).copied().unwrap_or(line.pusher);
            line.lateral[m][1].min(behind[1]) - line.lateral[m][0].max(behind[0]) < 1e-4
        });
        if oracle.abs() <= 1e-5 || apart {
            continue;
        }
        let yaw = rng.range(-3.1, 3.1);
        let (c, s) = (yaw.cos(), yaw.sin());
        // Local frame: push along −x', lateral y'. Box m spans x' ∈ [x_m, x_m + d_m].
        let rot = |x: f64, y: f64| [c * x - s * y, s * x + c * y];
        let mut x = 0.0;
        let mut boxes = Vec::new();
        for (m, lat) in line.lateral.iter().enumerate() {
            let d = rng.range(0.02, 0.08);
            let gap = if m > 0 && gaps[m - 1] {
                rng.range(0.002, 0.02)
            } else {
                0.0
            };
            x += gap;
            let p = rot(x + d / 2.0, (lat[0] + lat[1]) / 2.0);
            boxes.push(json!({
                "id": format!("b{m}"),
                "size": [d, lat[1] - lat[0], 0.04],
                "mass": line.weight[m] / 0.4,
                "pose": [p[0], p[1], yaw]
            }));
            x += d;
        }
        let p = rot(x + rng.range(0.0, 0.01), (line.pusher[0] + line.pusher[1]) / 2.0);
        let v = json!({
            "mode": "2d",
            "push_dir": [-c, -s],
            "friction": { "mu_floor": 0.4, "mu_obj": 0.3, "mu_finger": 0.5 },
            "boxes": boxes,
            "pusher": { "point": p, "width": line.pusher[1] - line.pusher[0], "height": 0.005 }
        });
        let r = check(&v);
        let m = r.margin.expect("2-D lines along the face normals always have forces");
        assert!(
            (m - oracle).abs() < 1e-7,
            "case {case}: scenario {m} vs paper {oracle}\n{v}\n{r}"
        );
        assert_eq!(r.stable(), oracle > MARGIN_TOL);
        compared += 1;
    }
    assert!(compared > 150, "only {compared} compared");
}

fn tall_box(height: f64, mode: &str) -> Value {
    json!({
        "mode": mode,
        "push_dir": "-x",
        "friction": { "mu_floor": 0.5, "mu_obj": 0.3, "mu_finger": 0.3 },
        "boxes": [ { "id": "tall", "size": [0.03, 0.05, 0.20], "mass": 0.2, "pose": [0.0, 0.0, 0.0] } ],
        "pusher": { "point": [0.015, 0.0], "width": 0.02, "height": height }
    })
}

#[test]
fn tall_narrow_box_topples_when_pushed_high_and_not_when_pushed_low() {
    let mu_f = 0.3 * (1.0 - push::CONE_SHRINK);
    let z_star = analytic::topple_height(0.03, 0.5, mu_f);
    assert!((z_star - 0.034275).abs() < 1e-9);
    let high = check(&tall_box(0.06, "3d"));
    assert!(!high.stable(), "{high}");
    let f = high.failure.as_ref().expect("failure");
    assert_eq!(f.kind, FailureKind::Tip);
    assert_eq!(f.at, "tall");
    assert!(f.detail.contains("front edge"), "{}", f.detail);
    let low = check(&tall_box(0.01, "3d"));
    assert!(low.stable(), "{low}");
    // The planar model cannot see it.
    assert!(check(&tall_box(0.06, "2d")).stable());
    // Where tipping decides, the 3-D margin is the closed-form distance of the floor's centre
    // of pressure from the front edge, and it crosses zero at the toppling height.
    for z in [0.025, 0.03, 0.034, 0.0345, 0.04, 0.06] {
        let m = check(&tall_box(z, "3d")).margin.expect("margin");
        let closed = analytic::topple_margin(0.03, 0.5, mu_f, z);
        assert!(
            (m - closed).abs() < 1e-6,
            "z = {z}: 3-D margin {m}, closed form {closed}"
        );
        assert_eq!(m > MARGIN_TOL, z < z_star);
    }
    // The floor reaction of the certificate: normal ≥ m g (the finger presses down), centre of
    // pressure toward the front edge.
    let r = check(&tall_box(0.03, "3d"));
    let fl = &r.phases[0].floor[0];
    assert!(fl.floor.normal >= 0.2 * 9.81 - 1e-9);
    assert!(fl.floor.cop[0] < -0.01, "{:?}", fl.floor.cop);
}

#[test]
fn a_tall_box_behind_a_low_one_tips_only_when_pushed_high() {
    let v = |z: f64| {
        json!({
            "mode": "3d",
            "push_dir": "-x",
            "friction": { "mu_floor": 0.5, "mu_obj": 0.3, "mu_finger": 0.3 },
            "boxes": [
                { "id": "low",  "size": [0.06, 0.05, 0.02], "mass": 0.3, "pose": [0.0, 0.0, 0.0] },
                { "id": "tall", "size": [0.03, 0.05, 0.20], "mass": 0.1, "pose": [0.045, 0.0, 0.0] }
            ],
            "pusher": { "point": [0.06, 0.0], "width": 0.02, "height": z }
        })
    };
    assert!(check(&v(0.005)).stable());
    let r = check(&v(0.08));
    assert!(!r.stable(), "{r}");
    assert_eq!(r.failure.as_ref().map(|f| f.at.as_str()), Some("tall"));
}

#[test]
fn every_phase_of_a_multi_object_push_is_checked() {
    let r = check_scenario(&load_scenario(pushes("back_box_alone_fails.json")).unwrap());
    assert!(!r.stable(), "{r}");
    assert_eq!(r.phases.len(), 2);
    assert_eq!(r.phases[0].moving, vec!["back"]);
    assert_eq!(r.phases[1].moving, vec!["front", "back"]);
    assert!(
        r.phases[1].margin.unwrap() > 0.005,
        "the closed-up line alone would be stable"
    );
    let f = r.failure.unwrap();
    assert_eq!((f.phase, f.kind), (1, FailureKind::Rotate));
    // The same boxes released touching: one phase, stable.
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(pushes("back_box_alone_fails.json")).unwrap()).unwrap();
    v["boxes"][1]["pose"][0] = json!(0.075);
    v["pusher"]["point"][0] = json!(0.10);
    let r = check(&v);
    assert!(r.stable() && r.phases.len() == 1, "{r}");
    // Three staggered boxes: three phases.
    let r = check_scenario(&load_scenario(pushes("three_box_staggered.json")).unwrap());
    assert!(r.stable(), "{r}");
    assert_eq!(r.phases.len(), 3);
    assert!(
        (r.gaps[1] - 0.01).abs() < 1e-9 && (r.gaps[2] - 0.01).abs() < 1e-9,
        "{:?}",
        r.gaps
    );
}

#[test]
fn robust_mode_is_never_more_permissive_than_nominal() {
    let mut rng = Rng(99);
    let opts = CheckOptions::default();
    let mut strictly_worse = 0;
    for case in 0..60 {
        let (line, gaps) = random_line(&mut rng);
        let model = convex::model_of_line(&line, &gaps);
        let frac = rng.range(0.0, 0.3);
        let set = robust::UncertaintySet::relative(&model, frac);
        let nominal = convex::check(&model, Dim::D2, &opts);
        let rob = robust::check(&model, &set, Dim::D2, &opts);
        let (n, r) = (nominal.margin.unwrap(), rob.result.margin.unwrap());
        assert!(r <= n + 1e-12, "case {case}: robust {r} > nominal {n}");
        assert!(!rob.result.stable || nominal.stable);
        if r < n - 1e-6 {
            strictly_worse += 1;
        }
        // Interior points of the uncertainty set are never worse than the vertices (exact in 2-D).
        for _ in 0..5 {
            let mut case_ = robust::cases(&model, &set)[0].clone();
            for (i, b) in model.bodies.iter().enumerate() {
                case_.mu_floor[i] = rng.range(set.mu_floor[i][0], set.mu_floor[i][1]);
                case_.cof[i][1] = b.cof[1] + rng.range(-1.0, 1.0) * set.cof[i][1];
            }
            let m = convex::margin(&robust::apply(&model, &case_), Dim::D2, &opts).unwrap();
            assert!(
                m >= r - 1e-9,
                "case {case}: interior point {m} below the robust margin {r}"
            );
        }
    }
    assert!(
        strictly_worse > 20,
        "uncertainty should usually cost margin ({strictly_worse})"
    );
    // The example: nominally stable, robustly not.
    let s = load_scenario(pushes("robust_off_centre.json")).unwrap();
    let r = check_scenario(&s);
    assert!(!r.stable(), "{r}");
    let rb = r.robust.as_ref().unwrap();
    assert!((rb.nominal_margin.unwrap() - 0.002).abs() < 1e-7);
    assert!((r.margin.unwrap() + 0.001).abs() < 1e-7, "{r}");
    let mut nominal = s.clone();
    nominal.mode = Mode::D2;
    assert!(check_scenario(&nominal).stable());
}

#[test]
fn robust_3d_is_never_more_permissive_and_vertices_cover_the_interior() {
    let mut rng = Rng(5);
    let opts = CheckOptions::default();
    for case in 0..12 {
        let z = rng.range(0.005, 0.05);
        let y = rng.range(-0.008, 0.008);
        let mut v = tall_box(z, "3d");
        v["pusher"]["point"][1] = json!(y);
        let s = parse_scenario(&v.to_string(), "<test>").unwrap();
        let set = robust::UncertaintySet::relative(&s.model, 0.15);
        let nominal = convex::margin(&s.model, Dim::D3, &opts).unwrap();
        let rob = robust::check(&s.model, &set, Dim::D3, &opts);
        let r = rob.result.margin.unwrap();
        assert!(r <= nominal + 1e-9, "case {case}: robust {r} > nominal {nominal}");
        for _ in 0..4 {
            let mut c = robust::cases(&s.model, &set)[0].clone();
            c.mu_floor[0] = rng.range(set.mu_floor[0][0], set.mu_floor[0][1]);
            c.mu_contact[0] = rng.range(set.mu_contact[0][0], set.mu_contact[0][1]);
            c.cof[0][0] += rng.range(-1.0, 1.0) * set.cof[0][0];
            c.cof[0][1] += rng.range(-1.0, 1.0) * set.cof[0][1];
            let m = convex::margin(&robust::apply(&s.model, &c), Dim::D3, &opts).unwrap();
            assert!(
                m >= r - 1e-7,
                "case {case}: interior point {m} below the robust margin {r}"
            );
        }
    }
}

#[test]
fn example_scenarios_decide_as_documented() {
    let expect = [
        ("single_centred.json", true),
        ("single_off_centre.json", false),
        ("offset_pair_oblique.json", true),
        ("offset_pair_low_friction.json", false),
        ("three_box_staggered.json", true),
        ("back_box_alone_fails.json", false),
        ("tall_box_pushed_high.json", false),
        ("tall_box_pushed_low.json", true),
        ("tall_pushes_short.json", true),
        ("robust_off_centre.json", false),
        ("yawed_pair_mm.json", true),
        ("pair_3d_not_lenient.json", false),
        ("short_phase_passes.json", true),
        ("long_phase_turns.json", false),
    ];
    let dir = format!("{}/instances/pushes", env!("CARGO_MANIFEST_DIR"));
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let Some(&(_, stable)) = expect.iter().find(|(f, _)| *f == name) else {
            panic!("{name}: add it to this table");
        };
        let r = check_scenario(&load_scenario(&path).unwrap_or_else(|e| panic!("{e}")));
        assert_eq!(r.stable(), stable, "{name}\n{r}");
        assert_eq!(r.failure.is_none(), stable);
        // Display and JSON both render.
        let text = r.to_string();
        assert!(text.contains(if stable { "STABLE" } else { "UNSTABLE" }));
        let js = serde_json::to_value(&r).unwrap();
        assert_eq!(js["verdict"], if stable { "stable" } else { "unstable" });
        assert!(js["phases"].as_array().is_some_and(|p| !p.is_empty()));
        n += 1;
    }
    assert_eq!(n, expect.len());
    // The yawed pair in millimetres is the same push as an axis-aligned one in metres.
    let r = check_scenario(&load_scenario(pushes("yawed_pair_mm.json")).unwrap());
    assert!((r.margin.unwrap() - 0.01).abs() < 1e-7, "{r}");
}

#[test]
fn bad_scenarios_name_the_field() {
    let base = single_box("2d", 0.03, 0.02);
    let cases: Vec<(Value, &str)> = vec![
        (
            {
                let mut v = base.clone();
                v["boxes"][0]["size"][1] = json!(-0.04);
                v
            },
            "boxes[0].size[1]",
        ),
        (
            {
                let mut v = base.clone();
                v["boxes"][0]["mass"] = json!(0.0);
                v
            },
            "boxes[0].mass",
        ),
        (
            {
                let mut v = base.clone();
                v["friction"]["mu_floor"] = json!(0.0);
                v
            },
            "friction.mu_floor",
        ),
        (
            {
                let mut v = base.clone();
                v["friction"]["mu_obj"] = json!(-1.0);
                v
            },
            "friction.mu_obj",
        ),
        (
            {
                let mut v = base.clone();
                v["mode"] = json!("4d");
                v
            },
            "mode",
        ),
        (
            {
                let mut v = base.clone();
                v["push_dir"] = json!("up");
                v
            },
            "push_dir",
        ),
        (
            {
                let mut v = base.clone();
                v["push_dir"] = json!([0.0, 0.0]);
                v
            },
            "push_dir",
        ),
        (
            {
                let mut v = base.clone();
                v["pusher"]["height"] = json!(0.05);
                v
            },
            "pusher.height",
        ),
        (
            {
                let mut v = base.clone();
                v["pusher"]["width"] = json!(0.0);
                v
            },
            "pusher.width",
        ),
        (
            {
                let mut v = base.clone();
                v["pusher"]["point"] = json!([0.05, 0.03]);
                v
            },
            "pusher.point",
        ),
        (
            {
                let mut v = base.clone();
                v["pusher"]["point"] = json!([0.0, 0.03]);
                v
            },
            "pusher.point",
        ),
        (
            {
                let mut v = base.clone();
                v["colour"] = json!("red");
                v
            },
            "colour",
        ),
        (
            {
                let mut v = base.clone();
                v.as_object_mut().unwrap().remove("pusher");
                v
            },
            "pusher",
        ),
        (
            {
                let mut v = base.clone();
                v["mode"] = json!("robust");
                v
            },
            "robust",
        ),
        (
            {
                let mut v = base.clone();
                v["mode"] = json!("robust");
                v["robust"] = json!({"mu_floor": [0.4, 0.5]});
                v
            },
            "robust.mu_floor",
        ),
        (
            {
                let mut v = base.clone();
                v["units"] = json!("inch");
                v
            },
            "units",
        ),
        (
            {
                let mut v = base.clone();
                v["boxes"] = json!([
                    { "id": "a", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.05, 0.03, 0.0] },
                    { "id": "b", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.07, 0.03, 0.0] }
                ]);
                v
            },
            "boxes[1].pose",
        ),
        (
            {
                let mut v = base.clone();
                v["boxes"] = json!([
                    { "id": "a", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.05, 0.03, 0.0] },
                    { "id": "a", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.15, 0.03, 0.0] }
                ]);
                v
            },
            "boxes[1].id",
        ),
        (
            {
                // Listed back to front: the second box never meets the first along −x.
                let mut v = base.clone();
                v["boxes"] = json!([
                    { "id": "a", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.05, 0.03, 0.0] },
                    { "id": "b", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [-0.05, 0.03, 0.0] }
                ]);
                v
            },
            "boxes[1].pose",
        ),
        (
            {
                // Smaller than any instance file accepts (MIN_EDGE = 0.1 mm).
                let mut v = base.clone();
                v["boxes"][0]["size"][0] = json!(1e-12);
                v
            },
            "boxes[0].size[0]",
        ),
        (
            {
                let mut v = base.clone();
                v["units"] = json!("mm");
                v["boxes"][0]["size"] = json!([60.0, 0.05, 30.0]);
                v["boxes"][0]["pose"] = json!([50.0, 30.0, 0.0]);
                v["pusher"] = json!({ "point": [90.0, 30.0], "width": 20.0, "height": 5.0 });
                v
            },
            "boxes[0].size[1]",
        ),
        (
            {
                let mut v = base.clone();
                v["pusher"]["width"] = json!(1e-9);
                v
            },
            "pusher.width",
        ),
        (
            {
                let mut v = base.clone();
                v["max_rotation"] = json!(-0.1);
                v
            },
            "max_rotation",
        ),
        (
            {
                let mut v = base.clone();
                v["max_drift"] = json!(0.0);
                v
            },
            "max_drift",
        ),
    ];
    for (v, field) in cases {
        match parse_scenario(&v.to_string(), "bad.json") {
            Ok(_) => panic!("accepted a bad scenario (expected an error at {field}): {v}"),
            Err(e) => {
                assert!(e.is_input(), "{e}");
                match &e {
                    pushpack::Error::Input { file, field: f, .. } => {
                        assert_eq!(file, "bad.json");
                        assert_eq!(f, field, "{e}");
                    }
                    other => panic!("{other}"),
                }
            }
        }
    }
    assert!(parse_scenario("{ not json", "x.json").is_err_and(|e| e.to_string().contains("<syntax>")));
    assert!(load_scenario(pushes("missing.json")).is_err_and(|e| e.is_input()));
}

#[test]
fn the_planner_margin_is_the_clarabel_margin_in_every_mode() {
    // Same line through the contract (2-D) and the full model in 3-D: for a low fingertip and
    // flat boxes, 3-D adds nothing, so both agree.
    let inst = pushpack::instance::Instance::load(format!(
        "{}/instances/paper/exp1_4objects.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let stop = pushpack::control::TimeLimit::new(30.0);
    let placement = pushpack::placement::bl::solve(&inst, 1, 8, &stop).unwrap().placement;
    let mut checked = 0;
    for dir in pushpack::geometry::PushDir::ALL {
        for i in 0..inst.n() {
            let line = [i];
            let at = push::centred_pusher(&inst, &placement, &line, dir);
            let m2 = push::line_margin(&inst, &placement, &line, dir, at, &[]);
            let oracle = analytic::geometry_margin(&push::line_geometry(&inst, &placement, &line, dir, at), &[]);
            assert!((m2 - oracle).abs() < 1e-8);
            let m3 = push::line_margin_mode(&inst, &placement, &line, dir, at, &[], Mode::D3, 0.0);
            assert!(m3 <= m2 + 1e-7, "3-D may only be stricter: {m3} vs {m2}");
            let mr = push::line_margin_mode(&inst, &placement, &line, dir, at, &[], Mode::Robust, 0.1);
            assert!(mr <= m2 + 1e-12);
            checked += 1;
        }
    }
    assert!(checked > 0);
    // Lines of two and three boxes: every ordered chain of objects whose faces overlap sideways,
    // back ones behind front ones along the push (released apart: one phase per gap, and also
    // closed up). 3-D and robust-3-D may only be stricter than 2-D and robust 2-D.
    let lat_of = |i: usize, dir: pushpack::geometry::PushDir| {
        let r = placement.targets[i].rect;
        let lat = dir.axis().other();
        [r.lo(lat), r.hi(lat)]
    };
    let along = |i: usize, dir: pushpack::geometry::PushDir| {
        let r = placement.targets[i].rect;
        let u = dir.unit()[dir.axis().index()];
        u * r.center()[dir.axis().index()]
    };
    let mut multi = 0;
    let mut stricter = 0;
    for dir in pushpack::geometry::PushDir::ALL {
        let n = inst.n();
        let mut lines: Vec<Vec<usize>> = Vec::new();
        for a in 0..n {
            for b in 0..n {
                let ok = |f: usize, bk: usize| {
                    let (x, y) = (lat_of(f, dir), lat_of(bk, dir));
                    f != bk && x[1].min(y[1]) - x[0].max(y[0]) > 0.01 && along(bk, dir) < along(f, dir) - 1e-6
                };
                if !ok(a, b) {
                    continue;
                }
                lines.push(vec![a, b]);
                for c in 0..n {
                    if c != a && ok(b, c) {
                        lines.push(vec![a, b, c]);
                    }
                }
            }
        }
        for line in &lines {
            let at = push::centred_pusher(&inst, &placement, line, dir);
            for gap in [false, true] {
                let gaps = vec![gap; line.len() - 1];
                let m2 = push::line_margin(&inst, &placement, line, dir, at, &gaps);
                let oracle = analytic::geometry_margin(&push::line_geometry(&inst, &placement, line, dir, at), &gaps);
                assert!((m2 - oracle).abs() < 1e-8, "{line:?}: {m2} vs paper {oracle}");
                let mode = |m: Mode| push::line_margin_mode(&inst, &placement, line, dir, at, &gaps, m, 0.1);
                let (m3, mr, mr3) = (mode(Mode::D3), mode(Mode::Robust), mode(Mode::Robust3d));
                assert!(m3 <= m2 + 1e-7, "{line:?} {dir:?}: 3-D {m3} > 2-D {m2}");
                assert!(mr <= m2 + 1e-12, "{line:?} {dir:?}: robust {mr} > 2-D {m2}");
                assert!(mr3 <= mr + 1e-7, "{line:?} {dir:?}: robust3d {mr3} > robust {mr}");
                assert!(mr3 <= m3 + 1e-7, "{line:?} {dir:?}: robust3d {mr3} > 3-D {m3}");
                if m3 < m2 - 1e-6 {
                    stricter += 1;
                }
                multi += 1;
            }
        }
    }
    assert!(multi >= 10, "only {multi} multi-box lines");
    eprintln!("{multi} multi-box lines, 3-D stricter than 2-D on {stricter}");
}

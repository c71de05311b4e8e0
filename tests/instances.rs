//! The bundled instance files: every valid one loads (and the examples plan and verify), every
//! file in `instances/invalid/` is rejected for exactly the reason it was written for — by the
//! library and by `pushpack validate` — and `units` scales lengths and nothing else.

use pushpack::error::Error;
use pushpack::instance::Instance;
use pushpack::plan::{optimize, PlanOptions};
use pushpack::robot::NEXTAGE_INITIAL_POSE_DEG;
use pushpack::robot::{Arm, RobotModel, DEFAULT_TCP_OFFSET};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Instance files (`.toml`, `.json`) of one `instances/` folder, sorted.
fn instance_files(folder: &str) -> Vec<PathBuf> {
    let dir = root().join("instances").join(folder);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("toml" | "json")))
        .collect();
    files.sort();
    files
}

fn file_name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// Every invalid file: (file name, the exact `field` of the error, a substring of its reason).
/// The reason pins the failure down where several faults share a field (e.g. `objects[0]`).
const INVALID: &[(&str, &str, &str)] = &[
    ("area_exceeds_floor.toml", "objects", "exceeds the container floor"),
    ("bad_arm.toml", "robot.arms[1]", "\"middle\""),
    ("bad_format_version.toml", "format_version", "only version 1"),
    ("bad_orientations.toml", "objects[0].orientations", "\"sideways\""),
    ("bad_units.toml", "units", "\"inch\""),
    ("bad_up_axis.toml", "objects[0].up", "\"w\""),
    ("duplicate_id.toml", "objects[1].id", "duplicate object id"),
    ("duplicate_kind.toml", "kinds[1].name", "duplicate kind name"),
    ("grasp_deeper_than_fingers.toml", "gripper.grasp_depth", "finger_length"),
    ("home_out_of_limits.toml", "robot.home.left", "LARM_JOINT2"),
    ("infinite_value.toml", "container.depth", "finite"),
    (
        "min_offset_too_small.toml",
        "gripper.min_offset",
        "finger_thickness + release_clearance",
    ),
    ("missing_field.toml", "friction.mu_obj", "missing field"),
    ("missing_section.toml", "gripper", "missing field"),
    ("model_broken.toml", "robot.model", "does not parse"),
    ("model_missing.toml", "robot.model", "not found"),
    ("model_without_arms.toml", "robot.model", "LARM_JOINT0 missing"),
    ("nan_in_json.json", "container.width", "expected value"),
    ("nan_size.toml", "kinds[0].size[0]", "finite"),
    ("negative_friction.toml", "friction.mu_floor", ">= 0"),
    ("negative_size.toml", "kinds[0].size[1]", "> 0"),
    ("no_objects.toml", "objects", "at least one object"),
    (
        "object_too_large.toml",
        "objects[0].kind",
        "none of its allowed orientations",
    ),
    ("on_container.toml", "objects[0]", "on top of the container"),
    ("overlap_on_table.toml", "objects[1]", "overlaps object \"a\""),
    ("syntax_error.json", "<syntax>", "line"),
    ("syntax_error.toml", "<syntax>", "line"),
    ("time_limit_too_large.toml", "planner.time_limit", "at most"),
    (
        "offset_steps_too_large.toml",
        "planner.max_offset_steps",
        "must be 1..=100",
    ),
    ("sample_dt_too_large.toml", "planner.sample_dt", "at most 1 s"),
    ("packing_only_not_bool.toml", "planner.packing_only", "invalid type"),
    ("too_low_to_grasp.toml", "objects[0]", "cannot be picked up"),
    ("under_home_hand.toml", "objects[0]", "under the left hand"),
    ("unknown_field.json", "friction.mu_table", "unknown field"),
    ("unknown_field.toml", "colour", "unknown field"),
    ("unknown_field_nested.toml", "objects[1].weight", "unknown field"),
    ("unknown_kind.toml", "objects[1].kind", "unknown kind \"brick\""),
    ("unreachable_start.toml", "objects[0]", "out of reach"),
    ("wrong_type.toml", "kinds[0].mass", "invalid type"),
    ("zero_bl_orders.toml", "planner.bl_orders", ">= 1"),
    ("speed_scale_above_one.toml", "robot.speed_scale", "must be in (0, 1]"),
    (
        "push_rotation_too_large.toml",
        "planner.max_push_rotation_deg",
        "at most 5 degrees",
    ),
    ("negative_push_drift.toml", "planner.max_push_drift", "must be > 0"),
    ("zero_size.toml", "kinds[0].size[2]", "> 0"),
];

fn expected(name: &str) -> (&'static str, &'static str) {
    INVALID
        .iter()
        .find(|(f, _, _)| *f == name)
        .map(|(_, field, reason)| (*field, *reason))
        .unwrap_or_else(|| panic!("instances/invalid/{name} has no entry in the INVALID table of this test"))
}

fn approx(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

fn approx_all(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| approx(*x, *y))
}

// ---------------------------------------------------------------------------------------------
// Valid files.

#[test]
fn paper_and_example_instances_load() {
    let mut n = 0;
    for folder in ["paper", "examples"] {
        for p in instance_files(folder) {
            let inst = Instance::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(inst.n() >= 2, "{}", p.display());
            assert_eq!(inst.source, p.display().to_string());
            assert_eq!(inst.digest.len(), 64);
            n += 1;
        }
    }
    assert!(
        n >= 7,
        "expected the 2 paper instances and at least 5 examples, found {n}"
    );
}

#[test]
fn examples_plan_and_the_plans_verify() {
    for p in instance_files("examples") {
        let inst = Instance::load(&p).unwrap();
        let out =
            optimize(&inst, &PlanOptions::from_instance(&inst)).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let plan = &out.plan;
        assert_eq!(plan.placements.len(), inst.n(), "{}", p.display());
        assert!(plan.metrics.seq_len >= inst.n(), "{}", p.display());
        assert_eq!(plan.actions.len(), plan.metrics.seq_len, "{}", p.display());
        let report = pushpack::verify::verify(&inst, plan);
        assert!(report.is_valid(), "{}: {report}", p.display());
    }
}

/// The examples sit in the default work cell (docs/robot.md, "The work cell") with boxes in the
/// arms' table zones.
#[test]
fn examples_use_the_default_work_cell() {
    for p in instance_files("examples") {
        let inst = Instance::load(&p).unwrap();
        let c = &inst.container;
        let what = p.display();
        assert!(
            approx_all(&[c.width, c.depth, c.wall_height], &[0.30, 0.20, 0.10]),
            "{what}"
        );
        assert!(approx_all(&c.center, &[0.30, 0.0]) && c.yaw == 0.0, "{what}");
        let t = pushpack::robot::DEFAULT_TABLE_Z;
        assert!(approx(inst.robot.table_z, t) && approx(c.floor_z, t), "{what}");
        for o in &inst.objects {
            let (x, y) = (o.table.x, o.table.y);
            assert!((0.20..=0.35).contains(&x), "{what}: {} x = {x}", o.id);
            assert!((0.20..=0.40).contains(&y.abs()), "{what}: {} y = {y}", o.id);
        }
    }
}

#[test]
fn defaults_are_applied() {
    let inst = Instance::load(root().join("instances/examples/two_boxes.toml")).unwrap();
    let g = &inst.gripper;
    assert!(approx(g.min_offset, g.finger_thickness + g.release_clearance));
    assert!(approx(g.push_height, 0.005));
    let r = &inst.robot;
    assert_eq!(r.model_path, "<bundled>");
    assert_eq!(r.model, RobotModel::bundled());
    assert_eq!(r.tcp_offset, DEFAULT_TCP_OFFSET);
    assert_eq!(r.arms, vec![Arm::Left, Arm::Right]);
    assert_eq!(r.home, NEXTAGE_INITIAL_POSE_DEG.map(|a| a.map(f64::to_radians)));
    assert!(approx(r.table_z, pushpack::robot::DEFAULT_TABLE_Z));
    assert!(approx(r.transfer_clearance, 0.08));
    assert!(approx(r.speed_scale, 0.9));
    assert!(approx(inst.container.floor_z, r.table_z));
    assert_eq!(inst.container.yaw, 0.0);
    assert_eq!(inst.settings, pushpack::instance::Settings::default());
    assert_eq!(inst.name, "two-boxes");
    for o in &inst.objects {
        assert_eq!(o.table.yaw, 0.0);
        assert_eq!(o.table.up, pushpack::geometry::BodyAxis::Z);
        assert_eq!((o.mu_floor, o.mu_obj, o.mu_finger), (0.35, 0.4, 0.6));
    }
}

/// Every `[planner]` key reaches the one options tree of a run, and the defaults of the keys a
/// file leaves out are the stages' own.
#[test]
fn planner_table_fills_plan_options() {
    use pushpack::motion::TrajectoryOptions;
    use pushpack::plan::PlanOptions;
    use pushpack::sequence::astar::AstarSettings;
    let text = std::fs::read_to_string(root().join("instances/examples/two_boxes.toml")).unwrap();
    let plain = Instance::parse(&text, false, "<two_boxes>", None).unwrap();
    let o = PlanOptions::from_instance(&plain);
    assert!(!o.packing_only);
    assert_eq!(o.astar, AstarSettings::default());
    assert_eq!(
        o.trajectory,
        TrajectoryOptions {
            velocity_scale: plain.robot.speed_scale,
            ..TrajectoryOptions::default()
        }
    );
    let tuned = text.replace(
        "[[kinds]]",
        "[planner]\npacking_only = true\nmax_offset_steps = 5\ndive_nodes = 7\njoint_acceleration = 2.5\nsample_dt = 0.05\n\n[[kinds]]",
    );
    let inst = Instance::parse(&tuned, false, "<tuned>", None).unwrap();
    let o = PlanOptions::from_instance(&inst);
    assert!(o.packing_only);
    assert_eq!((o.astar.max_offset_steps, o.astar.dive_nodes), (5, 7));
    assert!(!o.astar.trace && !o.astar.profile);
    assert_eq!((o.trajectory.acceleration, o.trajectory.sample_dt), (2.5, 0.05));
    // The plan records them, and older plans without them read as the defaults.
    let json = serde_json::to_value(&o).unwrap();
    assert_eq!(json["astar"]["max_offset_steps"], 5);
    assert_eq!(json["trajectory"]["sample_dt"], 0.05);
    let mut old = json.clone();
    old.as_object_mut().unwrap().remove("astar");
    old.as_object_mut().unwrap().remove("trajectory");
    let back: PlanOptions = serde_json::from_value(old).unwrap();
    assert_eq!(back.astar, AstarSettings::default());
    assert_eq!(back.trajectory, TrajectoryOptions::default());
}

#[test]
fn upright_only_keeps_the_table_up_axis() {
    let inst = Instance::load(root().join("instances/examples/upright_only.toml")).unwrap();
    for o in &inst.objects {
        assert!(!o.orientations.is_empty());
        assert!(
            o.orientations.iter().all(|q| q.up == o.table.up),
            "{}: {:?}",
            o.id,
            o.orientations
        );
    }
    assert_eq!(inst.robot.arms, vec![Arm::Left]);
    // Without orientations the default follows the gripper (upright, no regrasp); "any" allows
    // more than the upright pair for the same box.
    let text = std::fs::read_to_string(root().join("instances/examples/two_boxes.toml")).unwrap();
    let default = Instance::parse(&text, false, "two_boxes.toml", None).unwrap();
    assert_eq!(default.objects[0].orientations.len(), 2);
    let any = Instance::parse(
        &text.replace("y = 0.28\n", "y = 0.28\norientations = \"any\"\n"),
        false,
        "t",
        None,
    )
    .unwrap();
    assert!(any.objects[0].orientations.len() > 2);
    let regrasp = text.replace("[[kinds]]", "[robot]\nregrasp = true\n\n[[kinds]]");
    let regrasp = Instance::parse(&regrasp, false, "t", None).unwrap();
    assert!(
        regrasp.objects[0].orientations.len() > 2,
        "with a regrasp the default is any"
    );
}

#[test]
fn relative_model_paths_resolve_against_the_instance_file_then_the_working_directory() {
    // mixed_5.toml says `model = "../../models/nextage_open.urdf"`, relative to itself.
    let inst = Instance::load(root().join("instances/examples/mixed_5.toml")).unwrap();
    assert!(
        inst.robot.model_path.ends_with("nextage_open.urdf"),
        "{}",
        inst.robot.model_path
    );
    assert_eq!(inst.robot.model, RobotModel::bundled());
    // Without a base directory the path is taken relative to the working directory, which for
    // `cargo test` is the crate root.
    let text = std::fs::read_to_string(root().join("instances/examples/mixed_5.toml"))
        .unwrap()
        .replace("../../models/nextage_open.urdf", "models/nextage_open.urdf");
    let inst = Instance::parse(&text, false, "<memory>", None).unwrap();
    assert_eq!(inst.robot.model, RobotModel::bundled());
    // The same relative path does not resolve from the instance's folder, nor from the crate root.
    let text = text.replace("models/nextage_open.urdf", "nextage_open.urdf");
    let e = Instance::parse(&text, false, "x.toml", Some(&root().join("instances/examples"))).unwrap_err();
    assert!(
        matches!(&e, Error::Input { field, .. } if field == "robot.model"),
        "{e}"
    );
}

#[test]
fn json_and_toml_share_one_schema() {
    // Round-trip the JSON example through the serde file type into TOML: same instance.
    let p = root().join("instances/examples/row_of_three.json");
    let a = Instance::load(&p).unwrap();
    let toml_text = toml::to_string(&a.file).expect("the file type serialises to TOML");
    let b = Instance::parse(&toml_text, false, "<memory>.toml", None).unwrap_or_else(|e| panic!("{e}\n{toml_text}"));
    assert_eq!(a.container, b.container);
    assert_eq!(a.kinds, b.kinds);
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.gripper, b.gripper);
    assert_eq!(a.settings, b.settings);
    // And a TOML example through JSON.
    let p = root().join("instances/examples/mixed_5.toml");
    let a = Instance::load(&p).unwrap();
    let json_text = serde_json::to_string_pretty(&a.file).unwrap();
    let b =
        Instance::parse(&json_text, true, "<memory>.json", p.parent()).unwrap_or_else(|e| panic!("{e}\n{json_text}"));
    assert_eq!(a.container, b.container);
    assert_eq!(a.objects, b.objects);
    assert_eq!(a.gripper, b.gripper);
    assert_eq!(a.settings, b.settings);
}

// ---------------------------------------------------------------------------------------------
// Invalid files.

#[test]
fn every_invalid_file_is_listed_and_every_listed_file_exists() {
    let names: Vec<String> = instance_files("invalid").iter().map(|p| file_name(p)).collect();
    for n in &names {
        expected(n);
    }
    for (f, _, _) in INVALID {
        assert!(
            names.iter().any(|n| n == f),
            "instances/invalid/{f} is listed but missing"
        );
    }
    // Each TOML file says at the top what is wrong with it.
    for p in instance_files("invalid") {
        if p.extension().unwrap() == "toml" {
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(
                text.starts_with("# INVALID: "),
                "{} lacks its header comment",
                p.display()
            );
        }
    }
}

#[test]
fn invalid_instances_are_rejected_with_the_field_and_the_file() {
    let files = instance_files("invalid");
    assert!(files.len() >= 20);
    for p in files {
        let name = file_name(&p);
        let (want_field, want_reason) = expected(&name);
        let err = match Instance::load(&p) {
            Ok(_) => panic!("{name}: loaded, but must be rejected ({want_field}: {want_reason})"),
            Err(e) => e,
        };
        let path = p.display().to_string();
        match &err {
            Error::Input { file, field, reason } => {
                assert_eq!(file, &path, "{name}");
                assert_eq!(field, want_field, "{name}: wrong field; the error was: {err}");
                assert!(
                    reason.contains(want_reason),
                    "{name}: reason lacks {want_reason:?}; the error was: {err}"
                );
            }
            other => panic!("{name}: expected Error::Input, got {other:?}"),
        }
        let msg = err.to_string();
        assert!(
            msg.starts_with(&format!("{path}: field `{want_field}`: ")),
            "{name}: message format: {msg}"
        );
        assert!(err.is_input());
    }
}

fn validate_cli(path: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args(["validate", &path.display().to_string()])
        .current_dir(root())
        .output()
        .expect("run pushpack")
}

#[test]
fn cli_validate_rejects_invalid_files_with_exit_code_2() {
    for p in instance_files("invalid") {
        let name = file_name(&p);
        let (want_field, _) = expected(&name);
        let out = validate_cli(&p);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{name}: exit status {:?}, stderr: {stderr}",
            out.status
        );
        assert!(
            stderr.contains(want_field),
            "{name}: stderr lacks the field {want_field:?}: {stderr}"
        );
        assert!(stderr.contains(&name), "{name}: stderr lacks the file name: {stderr}");
    }
}

#[test]
fn cli_validate_accepts_valid_files_with_exit_code_0() {
    for folder in ["paper", "examples"] {
        for p in instance_files(folder) {
            let out = validate_cli(&p);
            assert_eq!(
                out.status.code(),
                Some(0),
                "{}: exit status {:?}, stderr: {}",
                p.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

#[test]
fn cli_validate_reports_a_missing_file_as_bad_input() {
    let out = validate_cli(&root().join("instances/examples/does_not_exist.toml"));
    assert_eq!(out.status.code(), Some(2));
}

fn cli(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run pushpack")
}

/// Time limits too large for a deadline (they used to panic converting to a `Duration`), not
/// positive, or not numbers: exit 2 with the flag named, for every command that takes one.
#[test]
fn cli_rejects_bad_time_limits_with_exit_code_2() {
    let inst = "instances/examples/two_boxes.toml";
    let out_dir = std::env::temp_dir().join("pushpack-bad-time-limit");
    let out_dir = out_dir.display().to_string();
    for value in ["1e20", "1e300", "inf", "NaN", "-1", "0"] {
        // `--flag=value`, so that clap takes "-1" as the value, not as another flag.
        let (tl, hl) = (format!("--time-limit={value}"), format!("--hard-limit={value}"));
        let cases: [(Vec<&str>, &str); 4] = [
            (vec!["plan", inst, "--out", &out_dir, &tl], "--time-limit"),
            (vec!["place", inst, "--solver", "milp", &tl], "--time-limit"),
            (
                vec!["bench", inst, "--planners", "bl+paper", "--out", &out_dir, &tl],
                "--time-limit",
            ),
            (
                vec![
                    "bench",
                    inst,
                    "--planners",
                    "bl+paper",
                    "--out",
                    &out_dir,
                    "--time-limit",
                    "1",
                    &hl,
                ],
                "--hard-limit",
            ),
        ];
        for (args, flag) in cases {
            let out = cli(&args);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(
                out.status.code(),
                Some(2),
                "{args:?}: {:?}, stderr: {stderr}",
                out.status
            );
            assert!(stderr.contains(flag), "{args:?}: stderr lacks {flag}: {stderr}");
            assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        }
    }
}

/// A reader that goes away (`pushpack push-check FILE | head -1`) ends the command quietly, as
/// with any Unix filter: no panic message. The writer starts after the reader has exited.
#[cfg(unix)]
#[test]
fn cli_ends_quietly_when_its_reader_goes_away() {
    let exe = env!("CARGO_BIN_EXE_pushpack");
    let script = "set -o pipefail; { sleep 0.3; \"$0\" push-check instances/pushes/three_box_staggered.json --json; \
                  \"$0\" validate instances/examples/two_boxes.toml; } | true";
    let out = Command::new("bash")
        .args(["-c", script, exe])
        .current_dir(root())
        .output()
        .expect("run bash");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "stderr: {stderr}");
    assert!(!stderr.contains("Broken pipe"), "stderr: {stderr}");
}

// ---------------------------------------------------------------------------------------------
// Units.

/// Every geometric quantity of two instances agrees (relative 1e-12).
fn assert_same_geometry(a: &Instance, b: &Instance) {
    let (ca, cb) = (&a.container, &b.container);
    assert!(
        approx_all(
            &[
                ca.width,
                ca.depth,
                ca.wall_height,
                ca.wall_thickness,
                ca.center[0],
                ca.center[1],
                ca.yaw,
                ca.floor_z
            ],
            &[
                cb.width,
                cb.depth,
                cb.wall_height,
                cb.wall_thickness,
                cb.center[0],
                cb.center[1],
                cb.yaw,
                cb.floor_z
            ]
        ),
        "container {ca:?} vs {cb:?}"
    );
    assert_eq!(a.kinds.len(), b.kinds.len());
    for (ka, kb) in a.kinds.iter().zip(&b.kinds) {
        assert_eq!(ka.name, kb.name);
        assert!(approx_all(&ka.size, &kb.size), "{ka:?} vs {kb:?}");
        assert_eq!(ka.mass, kb.mass, "masses are never scaled");
    }
    assert_eq!(a.objects.len(), b.objects.len());
    for (oa, ob) in a.objects.iter().zip(&b.objects) {
        assert_eq!(oa.id, ob.id);
        assert_eq!(oa.kind, ob.kind);
        assert!(approx_all(&oa.size, &ob.size));
        assert!(
            approx_all(&[oa.table.x, oa.table.y], &[ob.table.x, ob.table.y]),
            "{oa:?} vs {ob:?}"
        );
        assert_eq!(oa.table.yaw, ob.table.yaw, "angles are never scaled");
        assert_eq!(oa.table.up, ob.table.up);
        assert_eq!(oa.orientations, ob.orientations);
        assert_eq!(
            (oa.mass, oa.mu_floor, oa.mu_obj, oa.mu_finger),
            (ob.mass, ob.mu_floor, ob.mu_obj, ob.mu_finger)
        );
    }
    let (ga, gb) = (&a.gripper, &b.gripper);
    assert!(
        approx_all(
            &[
                ga.finger_thickness,
                ga.finger_width,
                ga.finger_length,
                ga.max_opening,
                ga.grasp_depth,
                ga.release_clearance,
                ga.min_offset,
                ga.push_height
            ],
            &[
                gb.finger_thickness,
                gb.finger_width,
                gb.finger_length,
                gb.max_opening,
                gb.grasp_depth,
                gb.release_clearance,
                gb.min_offset,
                gb.push_height
            ]
        ),
        "gripper {ga:?} vs {gb:?}"
    );
    let (ra, rb) = (&a.robot, &b.robot);
    assert!(approx_all(&ra.tcp_offset, &rb.tcp_offset));
    assert!(approx_all(
        &[ra.table_z, ra.transfer_clearance],
        &[rb.table_z, rb.transfer_clearance]
    ));
    assert_eq!(ra.home, rb.home, "joint angles are never scaled");
    assert_eq!(ra.arms, rb.arms);
    let (sa, sb) = (&a.settings, &b.settings);
    assert!(approx(sa.min_push_margin, sb.min_push_margin));
    assert!(approx(sa.max_push_drift, sb.max_push_drift));
    assert_eq!(sa.max_push_rotation, sb.max_push_rotation, "angles are never scaled");
    assert_eq!(sa.time_limit, sb.time_limit, "seconds are never scaled");
    assert_eq!(
        (sa.seed, sa.bl_orders, sa.max_nodes, sa.no_direct, sa.no_multi_push),
        (sb.seed, sb.bl_orders, sb.max_nodes, sb.no_direct, sb.no_multi_push)
    );
}

#[test]
fn mm_file_equals_its_metre_twin() {
    // mm_units.toml is mixed_5.toml in millimetres, with every optional length field set.
    let m = Instance::load(root().join("instances/examples/mixed_5.toml")).unwrap();
    let mm = Instance::load(root().join("instances/examples/mm_units.toml")).unwrap();
    assert_same_geometry(&m, &mm);
    assert!(approx(mm.container.width, 0.30));
    assert!(approx(mm.settings.min_push_margin, 0.002));
    assert!(approx(mm.robot.tcp_offset[0], -0.30));
}

/// A small cell written with every length multiplied by `k`.
fn scaled_cell(units: &str, k: f64) -> String {
    let l = |v: f64| format!("{:?}", v * k);
    format!(
        r#"units = "{units}"
[container]
width = {w}
depth = {d}
wall_height = {h}
wall_thickness = {t}
center = [{cx}, {cy}]
yaw = 0.1
floor_z = {fz}
[friction]
mu_floor = 0.3
mu_obj = 0.5
mu_finger = 0.7
[gripper]
finger_thickness = {ft}
finger_width = {fw}
finger_length = {fl}
max_opening = {mo}
grasp_depth = {gd}
release_clearance = {rc}
min_offset = {mof}
push_height = {ph}
[robot]
tcp_offset = [{tx}, {ty}, {tz}]
table_z = {tbz}
transfer_clearance = {tc}
[planner]
time_limit = 12.5
min_push_margin = {pm}
max_push_drift = {pd}
max_push_rotation_deg = 2.5
[[kinds]]
name = "k"
size = [{s0}, {s1}, {s2}]
mass = 0.125
[[objects]]
id = "o1"
kind = "k"
x = {x1}
y = {y1}
yaw = 0.7
[[objects]]
id = "o2"
kind = "k"
x = {x2}
y = {y2}
"#,
        w = l(0.30),
        d = l(0.20),
        h = l(0.10),
        t = l(0.012),
        cx = l(0.30),
        cy = l(0.0),
        fz = l(-0.299),
        ft = l(0.011),
        fw = l(0.021),
        fl = l(0.061),
        mo = l(0.091),
        gd = l(0.014),
        rc = l(0.004),
        mof = l(0.02),
        ph = l(0.006),
        tx = l(-0.3),
        ty = l(0.001),
        tz = l(-0.002),
        tbz = l(-0.3),
        tc = l(0.07),
        pm = l(0.003),
        pd = l(0.0015),
        s0 = l(0.055),
        s1 = l(0.045),
        s2 = l(0.035),
        x1 = l(0.24),
        y1 = l(0.27),
        x2 = l(0.24),
        y2 = l(-0.3),
    )
}

#[test]
fn units_scale_every_length_and_nothing_else() {
    let m = Instance::parse(&scaled_cell("m", 1.0), false, "m.toml", None).unwrap();
    let cm = Instance::parse(&scaled_cell("cm", 100.0), false, "cm.toml", None).unwrap();
    let mm = Instance::parse(&scaled_cell("mm", 1000.0), false, "mm.toml", None).unwrap();
    assert_same_geometry(&m, &cm);
    assert_same_geometry(&m, &mm);
    assert!(approx(mm.container.wall_thickness, 0.012));
    assert!(approx(mm.gripper.min_offset, 0.02));
    assert_eq!(mm.container.yaw, 0.1);
    assert_eq!(mm.objects[0].table.yaw, 0.7);
    assert_eq!(mm.kinds[0].mass, 0.125);
    assert_eq!(mm.settings.time_limit, 12.5);
    assert!(approx(mm.settings.max_push_drift, 0.0015));
    assert!(approx(mm.settings.max_push_rotation, 2.5f64.to_radians()));
    // Omitted, the travel tolerances are the push model's defaults.
    let plain = Instance::load(root().join("instances/examples/two_boxes.toml")).unwrap();
    assert_eq!(plain.settings.max_push_rotation, pushpack::actions::push::MAX_ROTATION);
    assert_eq!(plain.settings.max_push_drift, pushpack::actions::push::MAX_DRIFT);
    // No `units` at all means metres.
    let none = scaled_cell("m", 1.0).replacen("units = \"m\"\n", "", 1);
    let none = Instance::parse(&none, false, "none.toml", None).unwrap();
    assert_same_geometry(&m, &none);
}

#[test]
fn units_apply_before_validation() {
    // 50 mm boxes are fine; the same numbers read as metres are far too big for the container.
    let text = scaled_cell("mm", 1000.0);
    assert!(Instance::parse(&text, false, "mm.toml", None).is_ok());
    let as_metres = text.replacen("units = \"mm\"", "units = \"m\"", 1);
    let e = Instance::parse(&as_metres, false, "m.toml", None).unwrap_err();
    assert!(matches!(e, Error::Input { .. }), "{e}");
}

// ---------------------------------------------------------------------------------------------
// Parser error paths not covered by a file.

fn field_of(text: &str, json: bool) -> String {
    match Instance::parse(text, json, "t", None) {
        Err(Error::Input { field, .. }) => field,
        Err(e) => panic!("unexpected error {e:?}"),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

#[test]
fn serde_errors_name_the_field() {
    assert_eq!(field_of("", false), "container");
    assert_eq!(field_of("", true), "<syntax>");
    assert_eq!(field_of("{}", true), "container");
    assert_eq!(field_of("[1, 2]", true), "[1]");
    assert_eq!(field_of(r#"{"container": {"width": 1e400}}"#, true), "container.width");
    assert_eq!(field_of(r#"{"container": {"width": 1 "depth": 2}}"#, true), "<syntax>");
    assert_eq!(field_of("container = 3", false), "container");
    assert_eq!(field_of("[container]\nwidth = 1\nwidth = 2", false), "<syntax>");
    assert_eq!(field_of("format_version = -1", false), "format_version");
    // Odd unknown keys are quoted, so the field is never blank.
    assert_eq!(field_of(r#"{"  ": 1}"#, true), r#""  ""#);
    assert_eq!(field_of(r#""" = 1"#, false), r#""""#);
}

//! Pictures: the SVG files exist, are well-formed, and show every object and every action.

use pushpack::instance::Instance;
use pushpack::plan::{optimize, Plan, PlanOptions};
use pushpack::render::render;
use std::path::{Path, PathBuf};

const PAPER: [&str; 2] = [
    "instances/paper/exp1_4objects.toml",
    "instances/paper/exp2_8objects.toml",
];
const FILES: [&str; 4] = ["placement.svg", "storyboard.svg", "swept.svg", "view.html"];

fn plan_for(inst: &Instance) -> Plan {
    optimize(inst, &PlanOptions::from_instance(inst)).unwrap().plan
}

/// Check that `text` is one `<svg>` element with balanced tags (XML declaration and comments
/// allowed), and return the text content of every element.
fn check_well_formed(name: &str, text: &str) -> Vec<String> {
    let body = text.trim_start();
    assert!(
        body.starts_with("<?xml") || body.starts_with("<svg"),
        "{name}: does not start with <?xml or <svg"
    );
    assert!(text.trim_end().ends_with("</svg>"), "{name}: does not end with </svg>");
    let mut stack: Vec<String> = Vec::new();
    let mut contents = Vec::new();
    let mut rest = text;
    let mut roots = 0;
    while let Some(open) = rest.find('<') {
        let between = &rest[..open];
        if stack.is_empty() {
            assert!(between.trim().is_empty(), "{name}: text outside the root: {between:?}");
        } else if !between.trim().is_empty() {
            assert!(escaped(between), "{name}: unescaped text {between:?}");
            contents.push(between.to_string());
        }
        rest = &rest[open..];
        if rest.starts_with("<!--") {
            let end = rest
                .find("-->")
                .unwrap_or_else(|| panic!("{name}: unterminated comment"));
            assert!(!rest[4..end].contains("--"), "{name}: `--` inside a comment");
            rest = &rest[end + 3..];
            continue;
        }
        let close = rest.find('>').unwrap_or_else(|| panic!("{name}: unterminated tag"));
        let tag = &rest[1..close];
        rest = &rest[close + 1..];
        assert!(!tag.contains('<'), "{name}: `<` inside a tag: {tag:?}");
        if tag.starts_with('?') {
            assert!(stack.is_empty() && roots == 0, "{name}: misplaced declaration");
            continue;
        }
        assert_eq!(tag.matches('"').count() % 2, 0, "{name}: unbalanced quotes in <{tag}>");
        if let Some(closing) = tag.strip_prefix('/') {
            let top = stack
                .pop()
                .unwrap_or_else(|| panic!("{name}: </{closing}> without an opening tag"));
            assert_eq!(top, closing.trim(), "{name}: </{closing}> closes <{top}>");
        } else {
            let elem = tag
                .split_whitespace()
                .next()
                .unwrap_or("")
                .trim_end_matches('/')
                .to_string();
            assert!(!elem.is_empty(), "{name}: empty tag");
            if stack.is_empty() {
                roots += 1;
                assert_eq!(elem, "svg", "{name}: root element is <{elem}>");
            }
            if !tag.ends_with('/') {
                stack.push(elem);
            }
        }
    }
    assert!(stack.is_empty(), "{name}: unclosed elements {stack:?}");
    assert_eq!(roots, 1, "{name}: {roots} root elements");
    assert!(rest.trim().is_empty(), "{name}: trailing text");
    contents
}

/// No `<` or `>` and every `&` starts an entity.
fn escaped(text: &str) -> bool {
    !text.contains('>')
        && text.match_indices('&').all(|(i, _)| {
            ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;", "&#"]
                .iter()
                .any(|e| text[i..].starts_with(e))
        })
}

fn render_to(inst: &Instance, plan: &Plan, dir: &Path) -> Vec<PathBuf> {
    let files = render(inst, plan, dir).unwrap();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, FILES, "render returns the files it wrote");
    for f in &files {
        assert!(f.is_file(), "{} missing", f.display());
        assert!(f.starts_with(dir));
    }
    files
}

#[test]
fn paper_plans_render_to_well_formed_svg_showing_every_object_and_action() {
    for path in PAPER {
        let inst = Instance::load(path).unwrap();
        let plan = plan_for(&inst);
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("pictures"); // created by render
        let files = render_to(&inst, &plan, &out);
        // The SVGs; view.html has its own tests (tests/view.rs).
        for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "svg")) {
            let name = format!("{path}: {}", f.file_name().unwrap().to_string_lossy());
            let text = std::fs::read_to_string(f).unwrap();
            let contents = check_well_formed(&name, &text);
            let words: Vec<&str> = contents
                .iter()
                .flat_map(|c| c.split(|ch: char| !ch.is_alphanumeric()))
                .collect();
            for o in &inst.objects {
                assert!(words.contains(&o.id.as_str()), "{name}: object {} is not shown", o.id);
            }
        }
        let story = std::fs::read_to_string(&files[1]).unwrap();
        for k in 1..=plan.actions.len() {
            assert!(story.contains(&format!(">step {k}: ")), "{path}: no panel for step {k}");
        }
        assert!(!story.contains(&format!(">step {}: ", plan.actions.len() + 1)));
        // Fingers that pass above a lower neighbour carry both heights (exp2's steps 7 and 8
        // release next to a 4 cm box with the fingertips at 4.5 cm).
        for mark in story.match_indices('\u{2191}') {
            let text: String = story[mark.0..].chars().take_while(|c| *c != '<').collect();
            let h: Vec<f64> = text[3..].split(" over ").map(|v| v.trim().parse().unwrap()).collect();
            assert!(h[0] >= h[1], "{path}: fingertips above the box they pass: {text}");
        }
        if path.contains("exp2") {
            assert_eq!(story.matches("\u{2191}4.5 over 4.0").count(), 2, "{path}");
        }
        let placement = std::fs::read_to_string(&files[0]).unwrap();
        let area = plan.placement.occupied_area * 1e4;
        assert!(
            placement.contains(&format!("occupied area {area:.1}")),
            "{path}: the title states the occupied area"
        );
        assert!(
            placement.contains("contact length"),
            "{path}: the title states the contact length"
        );
    }
}

/// The page y of C's origin and of C's y = depth in placement.svg: C's y must point up.
#[test]
fn placement_has_y_pointing_up() {
    let inst = Instance::load(PAPER[0]).unwrap();
    let plan = plan_for(&inst);
    let tmp = tempfile::tempdir().unwrap();
    let files = render_to(&inst, &plan, tmp.path());
    let text = std::fs::read_to_string(&files[0]).unwrap();
    // Tick labels of the y axis are right-aligned texts "0" and the depth in cm.
    let tick_y = |label: &str| -> f64 {
        text.lines()
            .filter(|l| {
                l.starts_with("<text") && l.contains("text-anchor=\"end\"") && l.ends_with(&format!(">{label}</text>"))
            })
            .map(|l| {
                let v = l.split("y=\"").nth(1).unwrap().split('"').next().unwrap();
                v.parse::<f64>().unwrap()
            })
            .next()
            .unwrap_or_else(|| panic!("no y tick {label}"))
    };
    let depth_cm = format!("{:.0}", inst.container.depth * 100.0);
    assert!(
        tick_y("0") > tick_y(&depth_cm),
        "y = 0 must be below y = depth on the page"
    );
}

#[test]
fn special_characters_in_ids_are_escaped() {
    let text = std::fs::read_to_string(PAPER[0])
        .unwrap()
        .replace("id = \"1a\"", "id = \"a&b<c>\"");
    let inst = Instance::parse(&text, false, "escaped.toml", Some(Path::new("instances/paper"))).unwrap();
    let plan = plan_for(&inst);
    let tmp = tempfile::tempdir().unwrap();
    for f in render_to(&inst, &plan, tmp.path()) {
        let svg = std::fs::read_to_string(&f).unwrap();
        if f.extension().is_some_and(|e| e == "html") {
            // In the page's JSON, `<` is escaped so that no id can end the script.
            assert!(svg.contains("a&b\\u003cc>"), "{}: id not escaped", f.display());
            assert!(!svg.contains("a&b<c>"));
            continue;
        }
        check_well_formed(&f.display().to_string(), &svg);
        assert!(svg.contains("a&amp;b&lt;c&gt;"), "{}: id not escaped", f.display());
        assert!(!svg.contains("a&b<c>"));
    }
}

#[test]
fn a_plan_for_another_instance_is_an_error_not_a_picture() {
    let inst = Instance::load(PAPER[0]).unwrap();
    let mut plan = plan_for(&inst);
    plan.actions[0].objects[0] = "no-such-box".into();
    let tmp = tempfile::tempdir().unwrap();
    let err = render(&inst, &plan, tmp.path()).unwrap_err();
    assert!(err.to_string().contains("no-such-box"), "{err}");
    assert!(!tmp.path().join("placement.svg").exists());
}

/// A run whose sequence stage finds no plan still leaves its placement (JSON and picture) and
/// says so, and a plan.json left by an earlier run is flagged as not this run's.
#[test]
fn plan_without_a_sequence_still_writes_its_placement() {
    use pushpack::placement::PlacementResult;
    use pushpack::plan::{solve_placement, PlacementSolver};
    // A* proves at its root that this Bottom-Left placement has no plan (the objects on the table
    // block each other's picks for good), so the run fails at once and deterministically.
    let file = "instances/random/n20/n20_k4_s0005.toml";
    let inst = Instance::load(file).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("plan.json"), "{}").unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pushpack"))
        .args(["plan", file, "--placement", "bl", "--time-limit", "30", "--out"])
        .arg(tmp.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "a run without a plan fails: {stderr}");
    assert!(stderr.contains("no feasible plan"), "{stderr}");
    assert!(stderr.contains("placement.json"), "{stderr}");
    assert!(
        stderr.contains("is from an earlier run"),
        "the stale plan.json is flagged: {stderr}"
    );
    assert!(
        stderr.contains("--placement-alternatives"),
        "the way out is named: {stderr}"
    );

    let json = std::fs::read_to_string(tmp.path().join("placement.json")).unwrap();
    let written: PlacementResult = serde_json::from_str(&json).unwrap();
    let again = solve_placement(
        &inst,
        PlacementSolver::Bl,
        inst.settings.seed,
        inst.settings.bl_orders,
        30.0,
    )
    .unwrap();
    assert_eq!(written.placement, again.placement, "the file holds the run's placement");
    assert_eq!(written.placement.targets.len(), inst.n());

    let svg = std::fs::read_to_string(tmp.path().join("placement.svg")).unwrap();
    let texts = check_well_formed("placement.svg", &svg).join(" ");
    for o in &inst.objects {
        assert!(texts.contains(&o.id), "placement.svg shows {}", o.id);
    }
    assert!(!tmp.path().join("storyboard.svg").exists());
}

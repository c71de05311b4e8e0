//! Property tests of the instance loader: random, broken and nonsensical instance files — in TOML
//! and JSON — never panic and are either accepted (with every invariant holding) or rejected with
//! an `Error::Input` that names a field and a reason; random small valid instances in the default
//! work cell load and plan (or are reported infeasible), and every plan passes the verifier.
//!
//! Case counts are modest so that `cargo test` stays fast; raise them with `PROPTEST_CASES`.

use proptest::prelude::*;
use pushpack::error::Error;
use pushpack::instance::Instance;
use pushpack::plan::{optimize, PlacementSolver, PlanOptions};
use std::path::PathBuf;

// ---------------------------------------------------------------------------------------------
// A tiny document tree that can hold what serde_json::Value cannot (NaN, ±inf), written out as
// TOML (one `key = inline value` line per top-level key) or as JSON.

#[derive(Debug, Clone)]
enum Node {
    Num(f64),
    Int(i64),
    Str(String),
    Bool(bool),
    Arr(Vec<Node>),
    Tab(Vec<(String, Node)>),
}

use Node::*;

fn quote(s: &str) -> String {
    // JSON string escapes (\" \\ \n \t \uXXXX) are valid TOML basic-string escapes too.
    serde_json::to_string(s).unwrap()
}

fn float_token(v: f64, json: bool) -> String {
    match (v.is_nan(), v.is_infinite(), json) {
        (true, _, false) => "nan".into(),
        (true, _, true) => "NaN".into(),
        (_, true, false) => if v > 0.0 { "inf" } else { "-inf" }.into(),
        (_, true, true) => if v > 0.0 { "1e999" } else { "-Infinity" }.into(),
        // Debug formatting always has a '.' or an exponent, so it stays a float in TOML.
        _ => format!("{v:?}"),
    }
}

fn emit(n: &Node, json: bool) -> String {
    match n {
        Num(v) => float_token(*v, json),
        Int(i) => i.to_string(),
        Str(s) => quote(s),
        Bool(b) => b.to_string(),
        Arr(items) => format!(
            "[{}]",
            items.iter().map(|i| emit(i, json)).collect::<Vec<_>>().join(", ")
        ),
        Tab(entries) => {
            let sep = if json { ": " } else { " = " };
            let body: Vec<String> = entries
                .iter()
                .map(|(k, v)| format!("{}{sep}{}", quote(k), emit(v, json)))
                .collect();
            format!("{{{}}}", body.join(", "))
        }
    }
}

/// The whole document: JSON as one value; TOML as top-level `key = value` lines (a non-table
/// root becomes a single key, which the schema rejects).
fn document(root: &Node, json: bool) -> String {
    if json {
        return emit(root, true);
    }
    match root {
        Tab(entries) => entries
            .iter()
            .map(|(k, v)| format!("{} = {}\n", quote(k), emit(v, false)))
            .collect(),
        other => format!("root = {}\n", emit(other, false)),
    }
}

fn tab(entries: Vec<(&str, Node)>) -> Node {
    Tab(entries.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
}

fn nums(v: &[f64]) -> Node {
    Arr(v.iter().map(|x| Num(*x)).collect())
}

/// A valid instance in the default work cell (two boxes, every section present).
fn template() -> Node {
    tab(vec![
        ("format_version", Int(1)),
        ("name", Str("fuzz".into())),
        ("units", Str("m".into())),
        (
            "container",
            tab(vec![
                ("width", Num(0.30)),
                ("depth", Num(0.20)),
                ("wall_height", Num(0.10)),
                ("wall_thickness", Num(0.01)),
                ("center", nums(&[0.30, 0.0])),
                ("yaw", Num(0.0)),
            ]),
        ),
        (
            "friction",
            tab(vec![
                ("mu_floor", Num(0.35)),
                ("mu_obj", Num(0.4)),
                ("mu_finger", Num(0.6)),
            ]),
        ),
        (
            "gripper",
            tab(vec![
                ("finger_thickness", Num(0.01)),
                ("finger_width", Num(0.02)),
                ("finger_length", Num(0.06)),
                ("max_opening", Num(0.09)),
                ("grasp_depth", Num(0.015)),
                ("release_clearance", Num(0.005)),
                ("min_offset", Num(0.02)),
                ("push_height", Num(0.005)),
            ]),
        ),
        (
            "robot",
            tab(vec![
                ("arms", Arr(vec![Str("left".into()), Str("right".into())])),
                ("table_z", Num(-0.30)),
                ("tcp_offset", nums(&[-0.30, 0.0, 0.0])),
                ("transfer_clearance", Num(0.08)),
                (
                    "home",
                    tab(vec![
                        ("left", nums(&[0.010472, 0.0, -1.745329, -0.26529, 0.164061, -0.055851])),
                        ("right", nums(&[-0.010472, 0.0, -1.745329, 0.26529, 0.164061, 0.055851])),
                    ]),
                ),
            ]),
        ),
        (
            "planner",
            tab(vec![
                ("seed", Int(1)),
                ("bl_orders", Int(8)),
                ("time_limit", Num(10.0)),
                ("max_nodes", Int(10000)),
                ("min_push_margin", Num(0.002)),
                ("max_push_rotation_deg", Num(1.0)),
                ("max_push_drift", Num(0.001)),
                ("no_direct", Bool(false)),
                ("no_multi_push", Bool(false)),
            ]),
        ),
        (
            "kinds",
            Arr(vec![
                tab(vec![
                    ("name", Str("a".into())),
                    ("size", nums(&[0.06, 0.04, 0.03])),
                    ("mass", Num(0.05)),
                ]),
                tab(vec![
                    ("name", Str("b".into())),
                    ("size", nums(&[0.05, 0.05, 0.04])),
                    ("mass", Num(0.07)),
                    ("mu_floor", Num(0.45)),
                ]),
            ]),
        ),
        (
            "objects",
            Arr(vec![
                tab(vec![
                    ("id", Str("o1".into())),
                    ("kind", Str("a".into())),
                    ("x", Num(0.25)),
                    ("y", Num(0.28)),
                    ("yaw", Num(0.0)),
                    ("up", Str("z".into())),
                    ("orientations", Str("any".into())),
                ]),
                tab(vec![
                    ("id", Str("o2".into())),
                    ("kind", Str("b".into())),
                    ("x", Num(0.25)),
                    ("y", Num(-0.28)),
                ]),
            ]),
        ),
    ])
}

// ---------------------------------------------------------------------------------------------
// Mutations of the tree.

/// One step into a node: a table key (by index) or an array element.
type Path = Vec<usize>;

fn children_mut(n: &mut Node) -> Vec<&mut Node> {
    match n {
        Arr(items) => items.iter_mut().collect(),
        Tab(entries) => entries.iter_mut().map(|(_, v)| v).collect(),
        _ => Vec::new(),
    }
}

fn collect(n: &Node, path: &mut Path, out: &mut Vec<(Path, &'static str)>) {
    let kind = match n {
        Num(_) => "num",
        Int(_) => "int",
        Str(_) => "str",
        Bool(_) => "bool",
        Arr(_) => "arr",
        Tab(_) => "tab",
    };
    out.push((path.clone(), kind));
    let kids: Vec<&Node> = match n {
        Arr(items) => items.iter().collect(),
        Tab(entries) => entries.iter().map(|(_, v)| v).collect(),
        _ => Vec::new(),
    };
    for (i, k) in kids.into_iter().enumerate() {
        path.push(i);
        collect(k, path, out);
        path.pop();
    }
}

fn at<'a>(n: &'a mut Node, path: &[usize]) -> &'a mut Node {
    match path.split_first() {
        None => n,
        Some((i, rest)) => at(
            children_mut(n).into_iter().nth(*i).expect("a path of the current tree"),
            rest,
        ),
    }
}

/// Paths of nodes of one of `kinds` (any node when empty), never the root.
fn paths_of(root: &Node, kinds: &[&str]) -> Vec<Path> {
    let mut all = Vec::new();
    collect(root, &mut Vec::new(), &mut all);
    all.into_iter()
        .filter(|(p, k)| !p.is_empty() && (kinds.is_empty() || kinds.contains(k)))
        .map(|(p, _)| p)
        .collect()
}

#[derive(Debug, Clone)]
enum Mutation {
    /// Replace a numeric leaf by a (usually nasty) number.
    Number(usize, f64),
    /// Replace an integer leaf.
    Integer(usize, i64),
    /// Replace a string leaf (enum values, ids, kind names, model paths).
    Text(usize, String),
    /// Replace any node by an arbitrary small value.
    Replace(usize, Node),
    /// Remove a table entry or array element.
    Delete(usize),
    /// Add a key (known or unknown) to a table.
    Insert(usize, String, Node),
    /// Duplicate an array element (duplicate kinds, duplicate ids, overlapping objects).
    Duplicate(usize),
}

fn apply(root: &mut Node, m: &Mutation) {
    let pick = |root: &Node, kinds: &[&str], sel: usize| {
        let ps = paths_of(root, kinds);
        (!ps.is_empty()).then(|| ps[sel % ps.len()].clone())
    };
    match m {
        Mutation::Number(sel, v) => {
            if let Some(p) = pick(root, &["num", "int"], *sel) {
                *at(root, &p) = Num(*v);
            }
        }
        Mutation::Integer(sel, v) => {
            if let Some(p) = pick(root, &["int", "num"], *sel) {
                *at(root, &p) = Int(*v);
            }
        }
        Mutation::Text(sel, s) => {
            if let Some(p) = pick(root, &["str"], *sel) {
                *at(root, &p) = Str(s.clone());
            }
        }
        Mutation::Replace(sel, v) => {
            if let Some(p) = pick(root, &[], *sel) {
                *at(root, &p) = v.clone();
            }
        }
        Mutation::Delete(sel) => {
            if let Some(p) = pick(root, &[], *sel) {
                let (last, parent) = p.split_last().unwrap();
                match at(root, parent) {
                    Arr(items) if !items.is_empty() => {
                        let i = last % items.len();
                        items.remove(i);
                    }
                    Tab(entries) if !entries.is_empty() => {
                        let i = last % entries.len();
                        entries.remove(i);
                    }
                    _ => {}
                }
            }
        }
        Mutation::Insert(sel, key, v) => {
            let mut tabs = paths_of(root, &["tab"]);
            tabs.push(Vec::new());
            let p = tabs[sel % tabs.len()].clone();
            if let Tab(entries) = at(root, &p) {
                if let Some(e) = entries.iter_mut().find(|(k, _)| k == key) {
                    e.1 = v.clone();
                } else {
                    entries.push((key.clone(), v.clone()));
                }
            }
        }
        Mutation::Duplicate(sel) => {
            if let Some(p) = pick(root, &["arr"], *sel) {
                if let Arr(items) = at(root, &p) {
                    if let Some(first) = items.first().cloned() {
                        items.push(first);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Strategies.

fn nasty_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => prop::sample::select(vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            1e308,
            -1e308,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            1e-9,
            -1.0,
            1e6,
            0.015,
        ]),
        2 => -1.0..1.0f64,
        1 => -1e3..1e3f64,
        1 => any::<f64>(),
    ]
}

fn nasty_i64() -> impl Strategy<Value = i64> {
    prop_oneof![
        prop::sample::select(vec![0i64, -1, 1, 2, i64::MAX, i64::MIN, 1 << 53]),
        any::<i64>(),
    ]
}

fn nasty_string() -> impl Strategy<Value = String> {
    prop_oneof![
        3 => prop::sample::select(vec![
            "", " ", "m", "cm", "mm", "km", "M", "any", "upright", "Upright", "x", "y", "z", "+x", "-z", "w", "left",
            "right", "both", "a", "b", "o1", "o2", "nan", "inf", "0.1", "broken.urdf", "no_arms.urdf",
            "../../models/nextage_open.urdf", "models/nextage_open.urdf", "missing.urdf", ".", "..",
        ])
        .prop_map(String::from),
        // No '/', so a random string never names a device file.
        1 => "[a-zA-Z0-9_ .+\\-]{0,12}",
        1 => any::<String>().prop_map(|s| s.replace('/', "")),
    ]
}

const KEYS: &[&str] = &[
    "units",
    "yaw",
    "floor_z",
    "min_offset",
    "push_height",
    "model",
    "tcp_offset",
    "arms",
    "home",
    "table_z",
    "transfer_clearance",
    "seed",
    "bl_orders",
    "time_limit",
    "max_nodes",
    "min_push_margin",
    "max_push_rotation_deg",
    "max_push_drift",
    "no_direct",
    "no_multi_push",
    "mu_floor",
    "mu_obj",
    "mu_finger",
    "up",
    "orientations",
    "robot",
    "planner",
    "kinds",
    "objects",
    "format_version",
    "size",
    "mass",
    "id",
    "kind",
    "x",
    "y",
    "width",
    "colour",
    "",
];

fn leaf() -> impl Strategy<Value = Node> {
    prop_oneof![
        nasty_f64().prop_map(Num),
        nasty_i64().prop_map(Int),
        nasty_string().prop_map(Str),
        any::<bool>().prop_map(Bool),
    ]
}

fn small_node() -> impl Strategy<Value = Node> {
    leaf().prop_recursive(2, 12, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Arr),
            prop::collection::vec(("[a-z_]{0,8}", inner), 0..4).prop_map(Tab),
        ]
    })
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let sel = any::<usize>();
    prop_oneof![
        4 => (sel, nasty_f64()).prop_map(|(s, v)| Mutation::Number(s, v)),
        1 => (sel, nasty_i64()).prop_map(|(s, v)| Mutation::Integer(s, v)),
        2 => (sel, nasty_string()).prop_map(|(s, v)| Mutation::Text(s, v)),
        1 => (sel, small_node()).prop_map(|(s, v)| Mutation::Replace(s, v)),
        2 => sel.prop_map(Mutation::Delete),
        2 => (sel, prop::sample::select(KEYS).prop_map(String::from), small_node())
            .prop_map(|(s, k, v)| Mutation::Insert(s, k, v)),
        1 => sel.prop_map(Mutation::Duplicate),
    ]
}

// ---------------------------------------------------------------------------------------------
// The property every input must satisfy.

fn base_dir() -> PathBuf {
    // Lets the model strings "broken.urdf" / "no_arms.urdf" / "../../models/…" resolve.
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("instances/invalid")
}

fn check(text: &str, json: bool) -> Result<(), TestCaseError> {
    match Instance::parse(text, json, "<fuzz>", Some(&base_dir())) {
        Ok(inst) => {
            // Accepted: the invariants the later stages rely on hold.
            prop_assert!(inst.n() > 0);
            let c = &inst.container;
            for v in [c.width, c.depth, c.wall_height, c.wall_thickness] {
                prop_assert!(v.is_finite() && v > 0.0);
            }
            prop_assert!(c.center.iter().chain([&c.yaw, &c.floor_z]).all(|v| v.is_finite()));
            let g = &inst.gripper;
            prop_assert!(g.min_offset >= g.finger_thickness + g.release_clearance - 1e-12);
            for o in &inst.objects {
                prop_assert!(o.size.iter().all(|s| s.is_finite() && *s > 0.0), "{:?}", o.size);
                prop_assert!(o.mass.is_finite() && o.mass > 0.0);
                prop_assert!([o.mu_floor, o.mu_obj, o.mu_finger]
                    .iter()
                    .all(|m| m.is_finite() && *m >= 0.0));
                prop_assert!([o.table.x, o.table.y, o.table.yaw].iter().all(|v| v.is_finite()));
                prop_assert!(!o.orientations.is_empty());
                for q in &o.orientations {
                    let (fp, h) = q.dims(o.size);
                    prop_assert!(fp[0] <= c.width + 1e-9 && fp[1] <= c.depth + 1e-9 && h <= c.wall_height + 1e-9);
                }
            }
            let ids: std::collections::HashSet<&str> = inst.objects.iter().map(|o| o.id.as_str()).collect();
            prop_assert_eq!(ids.len(), inst.n());
            prop_assert!(inst.settings.time_limit.is_finite() && inst.settings.time_limit > 0.0);
            prop_assert!(inst.settings.bl_orders >= 1 && inst.settings.max_nodes >= 1);
            Ok(())
        }
        Err(Error::Input { file, field, reason }) => {
            prop_assert_eq!(file, "<fuzz>");
            prop_assert!(!field.trim().is_empty(), "empty field, reason {:?}", reason);
            prop_assert!(!reason.trim().is_empty(), "empty reason for field {:?}", field);
            Ok(())
        }
        Err(other) => Err(TestCaseError::fail(format!("not an input error: {other:?}"))),
    }
}

/// `PROPTEST_CASES` from the environment, else `default`.
fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn valid_text(json: bool) -> String {
    let name = if json { "row_of_three.json" } else { "two_boxes.toml" };
    std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("instances/examples")
            .join(name),
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(256), ..ProptestConfig::default() })]

    #[test]
    fn template_is_valid(json in any::<bool>()) {
        let text = document(&template(), json);
        prop_assert!(Instance::parse(&text, json, "<fuzz>", Some(&base_dir())).is_ok(), "{}", text);
    }

    #[test]
    fn mutated_structured_instances_never_panic(
        muts in prop::collection::vec(mutation(), 1..6),
        json in any::<bool>(),
    ) {
        let mut root = template();
        for m in &muts {
            apply(&mut root, m);
        }
        check(&document(&root, json), json)?;
    }

    #[test]
    fn random_structures_never_panic(root in small_node(), json in any::<bool>()) {
        check(&document(&root, json), json)?;
    }

    #[test]
    fn random_text_never_panics(text in any::<String>(), json in any::<bool>()) {
        check(&text, json)?;
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512), json in any::<bool>()) {
        check(&String::from_utf8_lossy(&bytes), json)?;
    }

    #[test]
    fn edited_instance_files_never_panic(
        json in any::<bool>(),
        edits in prop::collection::vec((0usize..4, any::<usize>(), any::<usize>(), "[ -~\n]{0,8}"), 1..4),
    ) {
        let mut chars: Vec<char> = valid_text(json).chars().collect();
        for (op, a, b, s) in &edits {
            let n = chars.len().max(1);
            let (i, j) = (a % n, b % n);
            let (lo, hi) = (i.min(j).min(chars.len()), i.max(j).min(chars.len()));
            match op {
                0 => chars.truncate(hi),
                1 => { chars.drain(lo..(lo + 16).min(hi)); }
                2 => { chars.splice(lo..lo, s.chars()); }
                _ => { chars.splice(lo..(lo + 4).min(chars.len()), s.chars()); }
            }
        }
        let text: String = chars.into_iter().collect();
        check(&text, json)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Random valid instances plan or are infeasible, and their plans verify.

/// Table slots of the default cell: two columns × two rows per arm zone, 9 cm apart, so boxes of
/// up to 7 cm never overlap; boxes are at most 6 cm tall, below the hands at home (≈ 6.8 cm).
const SLOTS: [(f64, f64); 8] = [
    (0.22, 0.26),
    (0.31, 0.26),
    (0.22, 0.35),
    (0.31, 0.35),
    (0.22, -0.26),
    (0.31, -0.26),
    (0.22, -0.35),
    (0.31, -0.35),
];

#[derive(Debug, Clone)]
struct BoxSpec {
    size: [f64; 3],
    mass: f64,
    mu_floor: f64,
    yaw90: bool,
    upright: bool,
}

fn box_spec() -> impl Strategy<Value = BoxSpec> {
    (
        0.03..0.07f64,
        0.03..0.07f64,
        0.03..0.06f64,
        0.02..0.2f64,
        0.2..0.6f64,
        any::<bool>(),
        prop::bool::weighted(0.25),
    )
        .prop_map(|(a, b, c, mass, mu_floor, yaw90, upright)| BoxSpec {
            size: [a, b, c],
            mass,
            mu_floor,
            yaw90,
            upright,
        })
}

fn valid_instance_text(boxes: &[BoxSpec], slots: &[usize], seed: u64) -> String {
    let mut s = format!(
        "name = \"fuzz-valid\"\n\
         [container]\nwidth = 0.30\ndepth = 0.20\nwall_height = 0.10\nwall_thickness = 0.01\ncenter = [0.30, 0.0]\n\
         [friction]\nmu_floor = 0.35\nmu_obj = 0.4\nmu_finger = 0.6\n\
         [gripper]\nfinger_thickness = 0.01\nfinger_width = 0.02\nfinger_length = 0.06\nmax_opening = 0.09\n\
         grasp_depth = 0.015\nrelease_clearance = 0.005\n\
         [planner]\nseed = {seed}\n"
    );
    for (i, b) in boxes.iter().enumerate() {
        s += &format!(
            "[[kinds]]\nname = \"k{i}\"\nsize = [{:?}, {:?}, {:?}]\nmass = {:?}\nmu_floor = {:?}\n",
            b.size[0], b.size[1], b.size[2], b.mass, b.mu_floor
        );
    }
    for (i, (b, slot)) in boxes.iter().zip(slots).enumerate() {
        let (x, y) = SLOTS[*slot];
        let yaw = if b.yaw90 { std::f64::consts::FRAC_PI_2 } else { 0.0 };
        let ori = if b.upright { "upright" } else { "any" };
        s += &format!(
            "[[objects]]\nid = \"b{i}\"\nkind = \"k{i}\"\nx = {x:?}\ny = {y:?}\nyaw = {yaw:?}\norientations = \"{ori}\"\n"
        );
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(32), ..ProptestConfig::default() })]

    #[test]
    fn random_valid_instances_plan_or_are_infeasible(
        boxes in prop::collection::vec(box_spec(), 2..=4),
        slots in Just((0..SLOTS.len()).collect::<Vec<usize>>()).prop_shuffle(),
        seed in 0u64..1000,
    ) {
        let text = valid_instance_text(&boxes, &slots[..boxes.len()], seed);
        let inst = match Instance::parse(&text, false, "<fuzz-valid>", None) {
            Ok(i) => i,
            Err(e) => return Err(TestCaseError::fail(format!("valid instance rejected: {e}\n{text}"))),
        };
        let mut opts = PlanOptions::from_instance(&inst);
        // Bottom-Left placement keeps 32 cases fast; the MILP is exercised by the examples test.
        opts.placement = PlacementSolver::Bl;
        opts.bl_orders = 4;
        opts.max_nodes = 20_000;
        opts.time_limit = 10.0;
        // Random boxes in any orientation: a packing study, which the robot need not run.
        opts.packing_only = true;
        match optimize(&inst, &opts) {
            Ok(out) => {
                prop_assert_eq!(out.plan.placements.len(), inst.n());
                let report = pushpack::verify::verify(&inst, &out.plan);
                prop_assert!(report.is_valid(), "{}\n{}", report, text);
            }
            Err(Error::Infeasible { reason }) => prop_assert!(!reason.is_empty()),
            Err(e) => return Err(TestCaseError::fail(format!("unexpected error {e:?}\n{text}"))),
        }
    }
}

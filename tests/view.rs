//! The 3-D view (`view.html`): a self-contained page whose frames put every object where the
//! plan puts it, and which a real browser plays.

mod common;

use pushpack::motion::collision::{object_in_container, object_on_table};
use pushpack::plan::{optimize, PlanOptions};
use pushpack::render::view_html;
use serde_json::Value;

/// The embedded data of a page.
fn data(page: &str) -> Value {
    let start = page.find("const DATA = ").expect("data") + "const DATA = ".len();
    let end = start + page[start..].find(";\nconst canvas").expect("end of data");
    serde_json::from_str(&page[start..end]).expect("the data is JSON")
}

/// Position (mm) of drawn box `b`.
fn pos(b: &Value) -> [f64; 3] {
    [4, 5, 6].map(|k| b[k].as_f64().unwrap())
}

#[test]
fn the_view_is_self_contained_and_its_objects_follow_the_plan() {
    for file in ["paper/exp1_4objects.toml", "paper/exp2_8objects.toml"] {
        let inst = common::load(file);
        let out = optimize(&inst, &PlanOptions::from_instance(&inst)).unwrap();
        assert!(pushpack::verify::verify(&inst, &out.plan).is_executable());
        let page = view_html(&inst, &out.plan).unwrap();
        for fetch in ["http://", "https://", "src=", "<link"] {
            assert!(!page.contains(fetch), "{file}: the page fetches nothing ({fetch})");
        }
        let d = data(&page);
        let frames = d["frames"].as_array().unwrap();
        let end = out.plan.trajectories.iter().map(|t| t.t_end).fold(0.0, f64::max);
        assert_eq!(
            frames.len(),
            (end / 0.25).ceil() as usize + 1,
            "{file}: a frame every 0.25 s"
        );
        assert!((frames.last().unwrap()[0].as_f64().unwrap() - end).abs() < 0.01);
        // Objects are the last n boxes of a frame: on the table first, at their targets last.
        let n = inst.n();
        let first = frames[0][1].as_array().unwrap();
        let last = frames.last().unwrap()[1].as_array().unwrap();
        for i in 0..n {
            let table = object_on_table(&inst, i).pose.translation.vector * 1000.0;
            let p = pos(&first[first.len() - n + i]);
            assert!(
                (0..3).all(|k| (p[k] - table[k]).abs() < 0.1),
                "{file}: object {i} starts on the table"
            );
            let t = &out.plan.placement(&inst).unwrap().targets[i];
            let target = object_in_container(&inst, i, &t.rect, t.height).pose.translation.vector * 1000.0;
            let p = pos(&last[last.len() - n + i]);
            assert!(
                (0..3).all(|k| (p[k] - target[k]).abs() < 1.0),
                "{file}: object {i} ends at its target: {p:?} vs {target:?}"
            );
        }
        // Something moves between frames: the arms.
        assert_ne!(frames[0][1], frames[frames.len() / 2][1]);
    }
}

/// The page plays in a real browser: headless Chromium runs its script, which draws the first,
/// middle and last frames and says so in `#status`. Browser tier (`.ci/browser` installs
/// Chromium and runs it).
#[test]
#[ignore = "browser tier: needs Chromium (`.ci/browser`)"]
fn the_view_plays_in_a_headless_browser() {
    let browser = std::env::var("PUSHPACK_CHROMIUM").unwrap_or_else(|_| "chromium".into());
    let inst = common::load("paper/exp2_8objects.toml");
    let out = optimize(&inst, &PlanOptions::from_instance(&inst)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("view.html");
    std::fs::write(&file, view_html(&inst, &out.plan).unwrap()).unwrap();
    let run = std::process::Command::new(&browser)
        .args([
            "--headless=new",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=5000",
            "--dump-dom",
        ])
        .arg(format!("file://{}", file.display()))
        .output()
        .unwrap_or_else(|e| panic!("cannot run {browser} (install Chromium or set PUSHPACK_CHROMIUM): {e}"));
    let dom = String::from_utf8_lossy(&run.stdout);
    let frames = data(&std::fs::read_to_string(&file).unwrap())["frames"]
        .as_array()
        .unwrap()
        .len();
    let status = dom
        .split("<div id=\"status\">")
        .nth(1)
        .and_then(|s| s.split('<').next())
        .unwrap_or_else(|| panic!("no status in the page the browser ran: {dom}"));
    assert!(status.starts_with(&format!("ok: {frames} frames")), "{status}");
}

//! `pushpack report` on rows made by hand: each planner's figures over what it solved, pairs
//! compared over what both solved, no blank table when a planner solves nothing or batches of
//! different planners are merged, whole-number ticks on the object axis, and status words
//! instead of internal names.

use pushpack::bench::row::{ResultRow, RunStatus};
use pushpack::bench::run::base_row;
use pushpack::bench::spec::PlannerSpec;
use pushpack::report::{summary_markdown, Merged};
use pushpack::Status;

/// A run of `planner` on `s/<name>` with `objects` objects: solved in `time` seconds with
/// `actions` actions and an area of `actions` (so ratios are easy to compute), or stopped by
/// the time limit after 10 s when `time` is `None`.
fn row(name: &str, planner: &str, objects: usize, time: Option<f64>, actions: usize) -> ResultRow {
    let inst = pushpack::Instance::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/instances/examples/two_boxes.toml"
    ))
    .expect("bundled example");
    let spec = PlannerSpec::parse(planner, "planner").expect("a planner spec");
    let mut r = base_row(&format!("s/{name}.toml"), &inst, &spec, 10.0);
    r.objects = objects;
    match time {
        Some(t) => {
            r.status = RunStatus::Planner(Status::Optimal);
            r.verify = Some("valid".into());
            r.seq_len = Some(actions);
            r.occupied_area = Some(actions as f64);
            r.wall_time_s = t;
        }
        None => {
            r.status = RunStatus::Planner(Status::TimeLimit);
            r.wall_time_s = 10.0;
        }
    }
    r
}

fn summary(rows: Vec<ResultRow>) -> String {
    summary_markdown(&Merged {
        rows,
        files: vec![],
        duplicates: 0,
    })
}

/// The table row of the markdown `md` under the heading `section` that starts with `start`.
fn table_row<'a>(md: &'a str, section: &str, start: &str) -> &'a str {
    let body = md
        .split(section)
        .nth(1)
        .unwrap_or_else(|| panic!("no {section}:\n{md}"));
    let body = body.split("\n## ").next().unwrap();
    body.lines()
        .find(|l| l.starts_with(start))
        .unwrap_or_else(|| panic!("no row {start:?} under {section}:\n{md}"))
}

fn cells(row: &str) -> Vec<&str> {
    row.trim_matches('|').split('|').map(str::trim).collect()
}

/// A planner that solves nothing once emptied every time, ratio and interval of the planners
/// that solved everything; now only its own cells are empty, and the failures table names its
/// status as result files do.
#[test]
fn a_planner_that_solves_nothing_leaves_the_others_figures_standing() {
    let mut rows = Vec::new();
    for (k, n) in ["a", "b", "c", "d"].iter().enumerate() {
        rows.push(row(n, "bl+paper", 4, Some(1.0 + k as f64), 8));
        rows.push(row(n, "bl+astar", 4, Some(0.5), 6));
        rows.push(row(n, "milp+astar", 4, None, 0));
    }
    let md = summary(rows);
    let all = cells(table_row(&md, "## All sets", "| bl+paper "));
    // planner, runs, solved, proven, infeasible, failed, time limit, node limit, median time…
    assert_eq!(all[2], "100 %", "{md}");
    assert_eq!(all[8], "2.50", "median of 1, 2, 3, 4 s: {md}");
    assert_eq!(all[12], "1.333", "area 8 against the best 6: {md}");
    let none = cells(table_row(&md, "## All sets", "| milp+astar "));
    assert_eq!((none[2], none[8]), ("0 %", "–"), "{md}");
    let ci = cells(table_row(&md, "## Confidence intervals", "| bl+astar "));
    assert_eq!(ci[1], "4");
    assert!(ci[2].starts_with("0.50"), "{md}");
    let pair = cells(table_row(&md, "## Pairwise comparisons", "| bl+astar | bl+paper "));
    assert_eq!(pair[2], "4", "{md}");
    assert_eq!(pair[6], "0.750", "6 actions against 8: {md}");
    let pair = cells(table_row(&md, "## Pairwise comparisons", "| bl+astar | milp+astar "));
    assert_eq!((pair[2], pair[3]), ("0", "–"), "{md}");
    assert!(
        md.contains("over **the instances both solved**"),
        "pairs are labelled: {md}"
    );
    let failures = cells(table_row(
        &md,
        "## Runs without a verified plan",
        "| s/a.toml | milp+astar ",
    ));
    assert_eq!(failures[2], "time_limit", "{md}");
    assert!(!md.contains("Planner("), "no internal names: {md}");
}

/// Two batches with different planners, merged: no instance was run by both, so there is no
/// profile over all planners (said, not drawn empty), while every planner keeps its figures
/// and the pair that shares instances is compared.
#[test]
fn merged_batches_with_different_planners_keep_every_table_filled() {
    let mut rows = Vec::new();
    for n in ["a", "b", "c"] {
        rows.push(row(n, "bl+paper", 4, Some(2.0), 8));
        rows.push(row(n, "bl+astar", 4, Some(1.0), 6));
    }
    for n in ["d", "e"] {
        rows.push(row(n, "milp+astar", 6, Some(3.0), 7));
    }
    let md = summary(rows.clone());
    for p in ["bl+paper", "bl+astar", "milp+astar"] {
        let c = cells(table_row(&md, "## All sets", &format!("| {p} ")));
        assert_ne!(c[8], "–", "{p} has a median time: {md}");
        assert_ne!(c[12], "–", "{p} has an area ratio: {md}");
    }
    let pair = cells(table_row(&md, "## Pairwise comparisons", "| bl+astar | bl+paper "));
    assert_eq!((pair[2], pair[3], pair[4]), ("3", "0.50", "3 of 3"), "{md}");
    assert!(md.contains("No instance was run by every planner"), "{md}");
    assert!(!md.contains("τ = 1"), "no profile table of zeros: {md}");

    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results.jsonl");
    let text: String = rows.iter().map(|r| r.to_json_line() + "\n").collect();
    std::fs::write(&results, text).unwrap();
    let out = dir.path().join("report");
    pushpack::report::write_report(&[results], &out).unwrap();
    assert!(out.join("summary.md").exists() && out.join("time_vs_objects.svg").exists());
    assert!(!out.join("performance_profile.svg").exists(), "no empty profile plot");
}

/// The labels of the x axis of a plotters SVG: the numeric `<text>` elements that share one
/// `y` (the axis line), the largest such group; y-axis labels each sit at their own `y`.
fn x_axis_labels(svg: &str) -> Vec<String> {
    let mut by_y: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for piece in svg.split("<text").skip(1) {
        let Some((attrs, rest)) = piece.split_once('>') else {
            continue;
        };
        let label = rest.split("</text>").next().unwrap().trim().to_string();
        if label.parse::<f64>().is_err() {
            continue;
        }
        let Some(y) = attrs.split(" y=\"").nth(1).and_then(|s| s.split('"').next()) else {
            continue;
        };
        by_y.entry(y.to_string()).or_default().push(label);
    }
    by_y.into_values().max_by_key(Vec::len).unwrap_or_default()
}

/// Object counts 6 to 8 once gave the axis "5 6 6 6 7 8 8 8 9": labels at fractional
/// positions printed without decimals. The ticks are now whole and distinct.
#[test]
fn the_time_vs_objects_axis_has_whole_distinct_ticks() {
    let rows = vec![
        row("a", "bl+paper", 6, Some(0.2), 8),
        row("b", "bl+paper", 7, Some(0.5), 9),
        row("c", "bl+paper", 8, Some(1.5), 10),
        row("a", "bl+astar", 6, Some(0.1), 8),
        row("c", "bl+astar", 8, Some(0.9), 10),
    ];
    let dir = tempfile::tempdir().unwrap();
    pushpack::report::plots::write_plots(&rows, dir.path()).unwrap();
    for file in ["time_vs_objects.svg", "cactus.svg"] {
        let svg = std::fs::read_to_string(dir.path().join(file)).unwrap();
        let labels = x_axis_labels(&svg);
        assert!(labels.len() >= 3, "{file}: {labels:?}");
        let mut seen = std::collections::BTreeSet::new();
        for l in &labels {
            assert!(l.parse::<u32>().is_ok(), "{file}: a whole number, got {l}");
            assert!(seen.insert(l.clone()), "{file}: {l} twice in {labels:?}");
        }
    }
    let svg = std::fs::read_to_string(dir.path().join("time_vs_objects.svg")).unwrap();
    assert_eq!(x_axis_labels(&svg), ["5", "6", "7", "8", "9"]);
}

//! Benchmark reports: merge result rows (shards, reruns), summarise them per set and planner in
//! markdown (`summary.md`, `per_instance.md`), and draw plots (`report::plots`) as SVG, PNG
//! and PDF.

mod convert;
pub mod plots;
pub mod tables;

use crate::bench::row::{read_jsonl, result_files, ResultRow, RunStatus};
use crate::error::{Error, Result};
use crate::status::Status;
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Merged rows and what merging did.
#[derive(Debug, Clone)]
pub struct Merged {
    /// One row per (instance, planner), sorted by that key.
    pub rows: Vec<ResultRow>,
    /// Files read.
    pub files: Vec<PathBuf>,
    /// Rows dropped because a later file (or line) had the same (instance, planner).
    pub duplicates: usize,
}

/// Read every result file among `paths` (files or directories) and keep one row per
/// (instance, planner): the last one read, files in the order given (directories sorted).
pub fn load_rows(paths: &[PathBuf]) -> Result<Merged> {
    let files = result_files(paths)?;
    let mut by_key: BTreeMap<(String, String), ResultRow> = BTreeMap::new();
    let mut duplicates = 0;
    for f in &files {
        for r in read_jsonl(f)?.0 {
            if by_key.insert(r.key(), r).is_some() {
                duplicates += 1;
            }
        }
    }
    Ok(Merged {
        rows: by_key.into_values().collect(),
        files,
        duplicates,
    })
}

/// Median of a sample (mean of the middle two for even sizes); `None` when empty.
pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let m = s.len() / 2;
    Some(if s.len() % 2 == 1 {
        s[m]
    } else {
        0.5 * (s[m - 1] + s[m])
    })
}

/// Mean of a sample; `None` when empty.
pub fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// Per instance, the best (smallest) occupied area and number of actions of any solved row.
pub fn best_per_instance(rows: &[ResultRow]) -> HashMap<String, (f64, f64)> {
    let mut best: HashMap<String, (f64, f64)> = HashMap::new();
    for r in rows.iter().filter(|r| r.solved()) {
        let (Some(a), Some(l)) = (r.occupied_area, r.seq_len) else {
            continue;
        };
        let e = best.entry(r.instance.clone()).or_insert((f64::INFINITY, f64::INFINITY));
        e.0 = e.0.min(a);
        e.1 = e.1.min(l as f64);
    }
    best
}

/// Statistics of one group of rows (a set and planner, or a planner over every set).
#[derive(Debug, Clone, PartialEq)]
pub struct GroupStats {
    /// Runs.
    pub runs: usize,
    /// Runs with a verified plan.
    pub solved: usize,
    /// Solved runs with both stages proven optimal.
    pub proven: usize,
    /// Runs recorded as `failed`.
    pub failed: usize,
    /// Runs recorded as `timeout`.
    pub timeout: usize,
    /// Runs recorded as `node_limit`.
    pub node_limit: usize,
    /// Runs proven to have no plan (answers, not failures).
    pub infeasible: usize,
    /// Median wall time (s). This and every figure below are over the group's solved runs:
    /// a planner that solves nothing leaves only its own cells empty, and no other planner's
    /// result changes the figures of this one (pairwise comparisons: [`tables::pairwise`]).
    pub median_time: Option<f64>,
    /// Largest wall time (s).
    pub max_time: Option<f64>,
    /// Median placement stage time (s).
    pub median_placement_s: Option<f64>,
    /// Median sequence stage time (s).
    pub median_sequence_s: Option<f64>,
    /// Median joint-trajectory time: the run's plan time less its two search stages (s).
    pub median_motion_s: Option<f64>,
    /// Median verifier time (s).
    pub median_verify_s: Option<f64>,
    /// Mean placement gap.
    pub mean_gap: Option<f64>,
    /// Mean occupied area relative to the best planner that solved the same instance.
    pub area_vs_best: Option<f64>,
    /// Mean number of actions relative to the best planner that solved the same instance.
    pub len_vs_best: Option<f64>,
}

/// The instances that every planner of `planners` solved (a verified plan). Used for groups
/// that are compared as a whole (the ablation means); a pair of planners is compared over the
/// instances both solved ([`tables::pairwise`]).
pub fn commonly_solved(rows: &[ResultRow], planners: &[String]) -> HashSet<String> {
    let mut by_instance: HashMap<&str, HashSet<&str>> = HashMap::new();
    for r in rows.iter().filter(|r| r.solved()) {
        by_instance.entry(&r.instance).or_default().insert(&r.planner);
    }
    by_instance
        .into_iter()
        .filter(|(_, ps)| planners.iter().all(|p| ps.contains(p.as_str())))
        .map(|(i, _)| i.to_string())
        .collect()
}

/// Statistics of `rows` against the per-instance `best`. Counts are over every row; times,
/// gaps and ratios over the solved rows. (They were once over the instances every planner
/// solved, and one planner that solved nothing emptied every other planner's cells.)
pub fn group_stats(rows: &[&ResultRow], best: &HashMap<String, (f64, f64)>) -> GroupStats {
    let solved: Vec<&&ResultRow> = rows.iter().filter(|r| r.solved()).collect();
    let compared = &solved;
    let times: Vec<f64> = compared.iter().map(|r| r.wall_time_s).collect();
    let gaps: Vec<f64> = compared.iter().filter_map(|r| r.placement_gap).collect();
    let stage =
        |f: &dyn Fn(&ResultRow) -> Option<f64>| median(&compared.iter().filter_map(|r| f(r)).collect::<Vec<_>>());
    let mut area_r = Vec::new();
    let mut len_r = Vec::new();
    for r in compared {
        if let (Some(&(ba, bl)), Some(a), Some(l)) = (best.get(&r.instance), r.occupied_area, r.seq_len) {
            area_r.push(a / ba);
            len_r.push(l as f64 / bl);
        }
    }
    GroupStats {
        runs: rows.len(),
        solved: solved.len(),
        proven: rows.iter().filter(|r| r.proven()).count(),
        failed: rows.iter().filter(|r| r.status.is_failure()).count(),
        timeout: rows
            .iter()
            .filter(|r| matches!(r.status, RunStatus::Planner(Status::TimeLimit) | RunStatus::Killed))
            .count(),
        node_limit: rows
            .iter()
            .filter(|r| r.status == RunStatus::Planner(Status::NodeLimit))
            .count(),
        infeasible: rows
            .iter()
            .filter(|r| r.status == RunStatus::Planner(Status::Infeasible))
            .count(),
        median_time: median(&times),
        median_placement_s: stage(&|r| r.placement_time_s),
        median_sequence_s: stage(&|r| r.sequence_time_s),
        median_motion_s: stage(&|r| {
            Some(r.plan_time_s? - r.placement_time_s.unwrap_or(0.0) - r.sequence_time_s.unwrap_or(0.0))
        }),
        median_verify_s: stage(&|r| r.verify_time_s),
        max_time: times.iter().copied().reduce(f64::max),
        mean_gap: mean(&gaps),
        area_vs_best: mean(&area_r),
        len_vs_best: mean(&len_r),
    }
}

fn opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or("–".into(), f)
}

pub(crate) fn pct(n: usize, d: usize) -> String {
    if d == 0 {
        "–".into()
    } else {
        format!("{:.0} %", 100.0 * n as f64 / d as f64)
    }
}

const TABLE_HEAD: &str = "| runs | solved | proven optimal | infeasible | failed | time limit | node limit | median time (s) | max time (s) | placement / sequence / motion / verify (s) | mean placement gap | area / best | actions / best |\n";
const TABLE_RULE: &str = "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";

fn stats_cells(s: &GroupStats) -> String {
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        s.runs,
        pct(s.solved, s.runs),
        pct(s.proven, s.runs),
        s.infeasible,
        s.failed,
        s.timeout,
        s.node_limit,
        opt(s.median_time, |t| format!("{t:.2}")),
        opt(s.max_time, |t| format!("{t:.2}")),
        [
            s.median_placement_s,
            s.median_sequence_s,
            s.median_motion_s,
            s.median_verify_s
        ]
        .map(|v| opt(v, |t| format!("{t:.2}")))
        .join(" / "),
        opt(s.mean_gap, |g| format!("{:.1} %", 100.0 * g)),
        opt(s.area_vs_best, |x| format!("{x:.3}")),
        opt(s.len_vs_best, |x| format!("{x:.3}")),
    )
}

/// Planners in the order of first appearance after sorting by name, base planners first.
pub fn planners(rows: &[ResultRow]) -> Vec<String> {
    let set: BTreeSet<&str> = rows.iter().map(|r| r.planner.as_str()).collect();
    set.into_iter().map(String::from).collect()
}

/// Sets sorted by the smallest object count they hold, then by name.
pub fn sets(rows: &[ResultRow]) -> Vec<String> {
    let mut m: BTreeMap<String, usize> = BTreeMap::new();
    for r in rows {
        let e = m.entry(r.set.clone()).or_insert(usize::MAX);
        *e = (*e).min(r.objects);
    }
    let mut v: Vec<(String, usize)> = m.into_iter().collect();
    v.sort_by(|a, b| a.1.cmp(&b.1).then(a.0.cmp(&b.0)));
    v.into_iter().map(|(s, _)| s).collect()
}

/// Ablation variants present for each base planner (the paper's Table II), base first.
pub fn ablation_groups(rows: &[ResultRow]) -> Vec<(String, Vec<String>)> {
    let names = planners(rows);
    let mut out = Vec::new();
    for base in names.iter().filter(|p| !p.contains("+no-")) {
        let variants: Vec<String> = [
            base.clone(),
            format!("{base}+no-direct"),
            format!("{base}+no-multi-push"),
            format!("{base}+no-direct+no-multi-push"),
        ]
        .into_iter()
        .filter(|v| names.contains(v))
        .collect();
        if variants.len() > 1 {
            out.push((base.clone(), variants));
        }
    }
    out
}

/// Per planner, how the plans of runs with the `simulate` option fared in the physics replay
/// (empty when no row was simulated).
fn simulation_table(rows: &[ResultRow], names: &[String]) -> String {
    let mut s = String::new();
    if rows.iter().all(|r| r.sim_ok.is_none()) {
        return s;
    }
    let _ = writeln!(s, "\n## Physics replay\n");
    let _ = writeln!(
        s,
        "Plans of runs with the `simulate` option, replayed in rapier3d (`pushpack simulate`, docs/simulate.md): \
*within tolerance*: every action and every box within the instance's push tolerances; the worst box of each plan: \
its final distance from its target and its rotation.\n"
    );
    s += "| planner | simulated | within tolerance | median worst error (mm) | max worst error (mm) | median worst rotation (°) |\n";
    s += "|---|---:|---:|---:|---:|---:|\n";
    for p in names {
        let g: Vec<&ResultRow> = rows.iter().filter(|r| &r.planner == p && r.sim_ok.is_some()).collect();
        if g.is_empty() {
            continue;
        }
        let ok = g.iter().filter(|r| r.sim_ok == Some(true)).count();
        let pos: Vec<f64> = g.iter().filter_map(|r| r.sim_position_error_mm).collect();
        let rot: Vec<f64> = g.iter().filter_map(|r| r.sim_rotation_deg).collect();
        let _ = writeln!(
            s,
            "| {p} | {} | {} | {} | {} | {} |",
            g.len(),
            pct(ok, g.len()),
            opt(median(&pos), |x| format!("{x:.2}")),
            opt(pos.iter().copied().reduce(f64::max), |x| format!("{x:.2}")),
            opt(median(&rot), |x| format!("{x:.2}")),
        );
    }
    s
}

/// The markdown summary of merged rows.
pub fn summary_markdown(m: &Merged) -> String {
    let rows = &m.rows;
    let best = best_per_instance(rows);
    let mut s = String::new();
    let _ = writeln!(s, "# Benchmark summary\n");
    let commits: BTreeSet<String> = rows
        .iter()
        .map(|r| format!("{} ({})", r.tool_version, r.git_commit))
        .collect();
    let limits: BTreeSet<String> = rows.iter().map(|r| format!("{} s", r.time_limit_s)).collect();
    let _ = writeln!(
        s,
        "{} rows from {} file(s), {} duplicate row(s) dropped; pushpack {}; time limit per run {}.\n",
        rows.len(),
        m.files.len(),
        m.duplicates,
        commits.into_iter().collect::<Vec<_>>().join(", "),
        limits.into_iter().collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(
        s,
        "*solved*: a plan the verifier accepts; *proven optimal*: the run's status is `optimal` (placement \
proven, and A* proved the sequence for it; Bottom-Left and the paper's sequencer are heuristics, never proven); \
*infeasible*: proven to have no plan (an answer, not a failure). Times, gaps and ratios of a row are over \
**the runs that row's planner solved**, so each planner's figures stand on their own; planners that solved \
different instances are compared pair by pair in *Pairwise comparisons*, over the instances both solved. \
Times are wall-clock seconds (one process per run), split into the placement and sequence stages, the joint \
trajectories (motion) and the verifier; *area / best* and *actions / best*: mean ratio to the best planner \
that solved the same instance.\n"
    );
    let names = planners(rows);
    let _ = writeln!(s, "## All sets\n");
    s += "| planner ";
    s += TABLE_HEAD;
    s += "|---";
    s += TABLE_RULE;
    for p in &names {
        let g: Vec<&ResultRow> = rows.iter().filter(|r| &r.planner == p).collect();
        let _ = writeln!(s, "| {p} {}", stats_cells(&group_stats(&g, &best)));
    }
    let _ = writeln!(s, "\n## Per set\n");
    s += "| set | objects | planner ";
    s += TABLE_HEAD;
    s += "|---|---:|---";
    s += TABLE_RULE;
    for set in sets(rows) {
        let objs: BTreeSet<usize> = rows.iter().filter(|r| r.set == set).map(|r| r.objects).collect();
        let objs = objs.iter().map(usize::to_string).collect::<Vec<_>>().join(", ");
        for p in &names {
            let g: Vec<&ResultRow> = rows.iter().filter(|r| r.set == set && &r.planner == p).collect();
            if !g.is_empty() {
                let _ = writeln!(s, "| {set} | {objs} | {p} {}", stats_cells(&group_stats(&g, &best)));
            }
        }
    }
    s += &simulation_table(rows, &names);
    s += &tables::pairwise_markdown(rows, &names);
    s += &tables::confidence_markdown(rows, &names);
    let prof = (names.len() > 1 && names.len() <= 63).then(|| performance_profile(rows, &names));
    if prof.as_ref().is_some_and(|p| p.instances == 0) {
        let _ = writeln!(s, "\n## Performance profile (wall time)\n");
        let _ = writeln!(
            s,
            "No instance was run by every planner (batches with different planners merged?), so there is no \
profile over all planners; see *Pairwise comparisons*.\n"
        );
    }
    if let Some(prof) = prof.filter(|p| p.instances > 0) {
        let taus = [1.0, 1.5, 2.0, 4.0, 10.0, 100.0];
        let _ = writeln!(s, "\n## Performance profile (wall time)\n");
        let _ = writeln!(
            s,
            "Share of the {} instances every planner ran that each planner solved within τ times the \
fastest solved time on that instance (Dolan and Moré 2002); an unsolved run never counts, so the last column is \
the solved share. `performance_profile.svg` draws it.\n",
            prof.instances
        );
        s += "| planner |";
        for t in taus {
            let _ = write!(s, " τ = {t} |");
        }
        s += " solved |\n|---|";
        s += &"---:|".repeat(taus.len() + 1);
        s.push('\n');
        for (k, p) in names.iter().enumerate() {
            let _ = write!(s, "| {p} |");
            for t in taus {
                let _ = write!(s, " {:.0} % |", 100.0 * prof.share_within(k, t));
            }
            let _ = writeln!(s, " {:.0} % |", 100.0 * prof.share_within(k, f64::INFINITY));
        }
    }
    let groups = ablation_groups(rows);
    if !groups.is_empty() {
        let _ = writeln!(s, "\n## Ablations (the paper's Table II): mean number of actions\n");
        let _ = writeln!(
            s,
            "Over the instances every variant of the group solved, so the means compare like with like.\n"
        );
        for (base, variants) in &groups {
            let means: Vec<_> = ablation_means(rows, variants).into_iter().filter(|m| m.1 > 0).collect();
            if means.is_empty() {
                let _ = writeln!(
                    s,
                    "No instance was solved by every variant of {}: no means to compare.\n",
                    variants.join(", ")
                );
                continue;
            }
            let _ = write!(s, "| set | instances |");
            for v in variants {
                let _ = write!(s, " {v} |");
            }
            let _ = write!(s, "\n|---|---:|");
            s += &"---:|".repeat(variants.len());
            s.push('\n');
            for (set, n, means) in means {
                let _ = write!(s, "| {set} | {n} |");
                for m in means {
                    let _ = write!(s, " {} |", opt(m, |x| format!("{x:.2}")));
                }
                s.push('\n');
            }
            let _ = writeln!(s, "\n(base planner {base})\n");
        }
    }
    let failures: Vec<&ResultRow> = rows
        .iter()
        // A proven-infeasible run answered its question: it is not a failure.
        .filter(|r| !r.solved() && r.status != RunStatus::Planner(Status::Infeasible))
        .collect();
    if !failures.is_empty() {
        let _ = writeln!(s, "\n## Runs without a verified plan\n");
        let _ = writeln!(
            s,
            "| instance | planner | status | verifier | error |\n|---|---|---|---|---|"
        );
        for r in failures {
            let err = r.error.as_deref().unwrap_or("").replace('|', "\\|");
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} |",
                r.instance,
                r.planner,
                r.status.as_str(),
                r.verify.as_deref().unwrap_or("–"),
                err
            );
        }
    }
    s
}

/// A Dolan–Moré performance profile of wall time: the instances every planner of `names` ran,
/// and per planner the ratio of its time to the fastest solved time on each instance it solved,
/// sorted. `ρ_p(τ)`, the share of instances planner `p` solved within `τ` times the fastest, is
/// the number of its ratios at most `τ` over the instance count; unsolved runs never count, so
/// `ρ_p(∞)` is its solved share. Unlike mean ratios over the commonly solved instances, a
/// profile also charges a planner for the instances it did not solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Instances every planner ran.
    pub instances: usize,
    /// Per planner (in the order given): its sorted time ratios on the instances it solved.
    pub ratios: Vec<Vec<f64>>,
}

impl Profile {
    /// `ρ_p(τ)` of planner index `k`.
    pub fn share_within(&self, k: usize, tau: f64) -> f64 {
        if self.instances == 0 {
            return 0.0;
        }
        self.ratios[k].partition_point(|&r| r <= tau * (1.0 + 1e-12)) as f64 / self.instances as f64
    }
}

/// The wall-time [`Profile`] of `names` (at most 63 planners) over `rows`.
pub fn performance_profile(rows: &[ResultRow], names: &[String]) -> Profile {
    // Per instance: which planners ran it (a bit each), and each one's time when it solved it.
    let mut runs: BTreeMap<&str, (u64, Vec<Option<f64>>)> = BTreeMap::new();
    for r in rows {
        if let Some(k) = names.iter().position(|p| *p == r.planner) {
            let e = runs.entry(&r.instance).or_insert_with(|| (0, vec![None; names.len()]));
            e.0 |= 1 << k;
            e.1[k] = r.solved().then_some(r.wall_time_s.max(1e-9));
        }
    }
    let all = (1u64 << names.len()) - 1;
    let mut ratios = vec![Vec::new(); names.len()];
    let mut instances = 0;
    for (ran, times) in runs.values() {
        if *ran != all {
            continue;
        }
        instances += 1;
        let best = times.iter().flatten().copied().fold(f64::INFINITY, f64::min);
        for (k, t) in times.iter().enumerate() {
            if let Some(t) = t {
                ratios[k].push(t / best);
            }
        }
    }
    for r in &mut ratios {
        r.sort_by(f64::total_cmp);
    }
    Profile { instances, ratios }
}

/// Per set: number of instances every variant solved, and each variant's mean actions on them.
pub fn ablation_means(rows: &[ResultRow], variants: &[String]) -> Vec<(String, usize, Vec<Option<f64>>)> {
    let mut out = Vec::new();
    for set in sets(rows) {
        let mut per_inst: BTreeMap<&str, Vec<Option<usize>>> = BTreeMap::new();
        for r in rows.iter().filter(|r| r.set == set) {
            if let Some(k) = variants.iter().position(|v| *v == r.planner) {
                let e = per_inst.entry(&r.instance).or_insert(vec![None; variants.len()]);
                e[k] = if r.solved() { r.seq_len } else { None };
            }
        }
        let common: Vec<Vec<usize>> = per_inst
            .into_values()
            .filter_map(|v| v.into_iter().collect::<Option<Vec<usize>>>())
            .collect();
        let means = (0..variants.len())
            .map(|k| mean(&common.iter().map(|v| v[k] as f64).collect::<Vec<_>>()))
            .collect();
        out.push((set, common.len(), means));
    }
    out
}

/// Merge `results`, write `summary.md`, `merged.jsonl` and the plots into `out`; returns the files.
pub fn write_report(results: &[PathBuf], out: &Path) -> Result<Vec<PathBuf>> {
    let m = load_rows(results)?;
    if m.rows.is_empty() {
        return Err(Error::input(
            results
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
            "<rows>",
            "no result rows to report",
        ));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    let write = |name: &str, text: String| -> Result<PathBuf> {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| Error::Io {
            path: p.clone(),
            source: e,
        })?;
        Ok(p)
    };
    let mut files = vec![write("summary.md", summary_markdown(&m))?];
    files.push(write(
        "per_instance.md",
        tables::per_instance_markdown(&m.rows, &planners(&m.rows)),
    )?);
    let merged: String = m.rows.iter().map(|r| r.to_json_line() + "\n").collect();
    files.push(write("merged.jsonl", merged)?);
    let svgs = plots::write_plots(&m.rows, out)?;
    for svg in &svgs {
        files.extend(convert::png_and_pdf(svg)?);
    }
    files.extend(svgs);
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{run::base_row, spec::PlannerSpec};

    fn row(inst: &str, planner: &str, len: Option<usize>) -> ResultRow {
        let i = crate::instance::Instance::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/instances/examples/two_boxes.toml"
        ))
        .expect("bundled example");
        let mut r = base_row(inst, &i, &PlannerSpec::parse(planner, "p").expect("spec"), 5.0);
        if let Some(l) = len {
            r.status = RunStatus::Planner(Status::Optimal);
            r.verify = Some("valid".into());
            r.seq_len = Some(l);
            r.occupied_area = Some(l as f64);
        }
        r
    }

    /// Hand-computed profile: on a, milp+astar 1 s and bl+paper 2 s; on b, milp+astar unsolved
    /// and bl+paper 3 s; on c, both unsolved; d is run by milp+astar only and stays out.
    #[test]
    fn performance_profile_counts_unsolved_runs_against_the_planner() {
        let timed = |inst: &str, planner: &str, t: Option<f64>| {
            let mut r = row(inst, planner, t.map(|_| 5));
            r.wall_time_s = t.unwrap_or(9.0);
            r
        };
        let rows = vec![
            timed("s/a", "milp+astar", Some(1.0)),
            timed("s/a", "bl+paper", Some(2.0)),
            timed("s/b", "milp+astar", None),
            timed("s/b", "bl+paper", Some(3.0)),
            timed("s/c", "milp+astar", None),
            timed("s/c", "bl+paper", None),
            timed("s/d", "milp+astar", Some(1.0)),
        ];
        let names = vec!["milp+astar".to_string(), "bl+paper".to_string()];
        let p = performance_profile(&rows, &names);
        assert_eq!(p.instances, 3);
        assert_eq!(p.ratios, vec![vec![1.0], vec![1.0, 2.0]]);
        assert_eq!(p.share_within(0, 1.0), 1.0 / 3.0);
        assert_eq!(p.share_within(0, f64::INFINITY), 1.0 / 3.0);
        assert_eq!(p.share_within(1, 1.0), 1.0 / 3.0);
        assert_eq!(p.share_within(1, 1.9), 1.0 / 3.0);
        assert_eq!(p.share_within(1, 2.0), 2.0 / 3.0);
        let md = summary_markdown(&Merged {
            rows,
            files: vec![],
            duplicates: 0,
        });
        assert!(
            md.contains("| bl+paper | 33 % | 33 % | 67 % | 67 % | 67 % | 67 % | 67 % |"),
            "{md}"
        );
    }

    #[test]
    fn medians_and_ratios_use_solved_runs_and_ablation_means_common_instances() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0]), Some(2.5));
        assert_eq!(median(&[]), None);
        let rows = vec![
            row("s/a", "bl+paper", Some(4)),
            row("s/a", "bl+paper+no-direct", Some(6)),
            row("s/b", "bl+paper", Some(8)),
            row("s/b", "bl+paper+no-direct", None), // unsolved: b drops out of the ablation means
        ];
        assert_eq!(best_per_instance(&rows)["s/a"], (4.0, 4.0));
        let groups = ablation_groups(&rows);
        assert_eq!(groups.len(), 1);
        let m = ablation_means(&rows, &groups[0].1);
        assert_eq!(m, vec![("s".to_string(), 1, vec![Some(4.0), Some(6.0)])]);
        let refs: Vec<&ResultRow> = rows.iter().filter(|r| r.planner == "bl+paper+no-direct").collect();
        let names = planners(&rows);
        let common = commonly_solved(&rows, &names);
        assert_eq!(common, HashSet::from(["s/a".to_string()]));
        let g = group_stats(&refs, &best_per_instance(&rows));
        assert_eq!((g.runs, g.solved, g.failed), (2, 1, 1));
        assert_eq!(g.len_vs_best, Some(1.5));
        // bl+paper's figures are over what it solved, b included, whatever the variant did.
        let refs: Vec<&ResultRow> = rows.iter().filter(|r| r.planner == "bl+paper").collect();
        let g = group_stats(&refs, &best_per_instance(&rows));
        assert_eq!(g.solved, 2);
        assert_eq!(g.len_vs_best, Some(1.0));
    }

    #[test]
    fn the_physics_table_counts_simulated_runs_only() {
        let sim = |inst: &str, ok: Option<bool>, mm: f64| {
            let mut r = row(inst, "bl+astar+simulate", Some(5));
            r.sim_ok = ok;
            r.sim_position_error_mm = ok.map(|_| mm);
            r.sim_rotation_deg = ok.map(|_| 0.5);
            r
        };
        let rows = vec![
            sim("s/a", Some(true), 0.2),
            sim("s/b", Some(false), 3.0),
            sim("s/c", Some(true), 0.4),
            sim("s/d", None, 0.0),
        ];
        let names = planners(&rows);
        let t = simulation_table(&rows, &names);
        assert!(
            t.contains("| bl+astar+simulate | 3 | 67 % | 0.40 | 3.00 | 0.50 |"),
            "{t}"
        );
        let plain = vec![row("s/a", "bl+astar", Some(5))];
        assert_eq!(simulation_table(&plain, &planners(&plain)), "");
    }
}

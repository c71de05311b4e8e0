//! Report tables beyond the summary: one row per instance with every planner's result, and
//! bootstrap confidence intervals on the summary's medians and mean ratios.

use super::{best_per_instance, mean, median, pct};
use crate::bench::row::ResultRow;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// Resamples of each bootstrap interval.
pub const BOOTSTRAP_RESAMPLES: usize = 2000;
/// Seed of the bootstrap: the same rows give the same intervals.
pub const BOOTSTRAP_SEED: u64 = 0x0b00_75ee;

/// Percentile bootstrap interval (95 %) of `stat` over `v`: `stat` of [`BOOTSTRAP_RESAMPLES`]
/// resamples with replacement, cut at the 2.5th and 97.5th percentiles. `None` for fewer than
/// two values (no spread to resample).
pub fn bootstrap_ci(v: &[f64], stat: fn(&[f64]) -> Option<f64>) -> Option<(f64, f64)> {
    if v.len() < 2 {
        return None;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(BOOTSTRAP_SEED);
    let mut sample = vec![0.0; v.len()];
    let mut stats: Vec<f64> = (0..BOOTSTRAP_RESAMPLES)
        .filter_map(|_| {
            for s in sample.iter_mut() {
                *s = v[rng.random_range(0..v.len())];
            }
            stat(&sample)
        })
        .collect();
    stats.sort_by(f64::total_cmp);
    let at = |q: f64| stats[((q * (stats.len() - 1) as f64).round() as usize).min(stats.len() - 1)];
    Some((at(0.025), at(0.975)))
}

fn interval(v: &[f64], stat: fn(&[f64]) -> Option<f64>, digits: usize) -> String {
    match (stat(v), bootstrap_ci(v, stat)) {
        (Some(x), Some((lo, hi))) => format!("{x:.digits$} [{lo:.digits$}, {hi:.digits$}]"),
        (Some(x), None) => format!("{x:.digits$}"),
        _ => "–".into(),
    }
}

/// Per planner, over the instances it solved: median wall time, mean area and mean number of
/// actions relative to the best planner on the instance, each with its 95 % interval.
pub fn confidence_markdown(rows: &[ResultRow], names: &[String]) -> String {
    let best = best_per_instance(rows);
    let mut s = String::new();
    let _ = writeln!(s, "\n## Confidence intervals\n");
    let _ = writeln!(
        s,
        "Per planner over the instances it solved: the estimate and its 95 % percentile bootstrap interval \
({BOOTSTRAP_RESAMPLES} resamples of the instances, seed {BOOTSTRAP_SEED:#x}, so the same rows give the same intervals).\n"
    );
    s += "| planner | instances | median wall time (s) | mean area / best | mean actions / best |\n";
    s += "|---|---:|---:|---:|---:|\n";
    for p in names {
        let (mut t, mut a, mut l) = (Vec::new(), Vec::new(), Vec::new());
        for r in rows.iter().filter(|r| &r.planner == p && r.solved()) {
            t.push(r.wall_time_s);
            if let (Some(&(ba, bl)), Some(x), Some(n)) = (best.get(&r.instance), r.occupied_area, r.seq_len) {
                a.push(x / ba);
                l.push(n as f64 / bl);
            }
        }
        let _ = writeln!(
            s,
            "| {p} | {} | {} | {} | {} |",
            t.len(),
            interval(&t, median, 2),
            interval(&a, mean, 3),
            interval(&l, mean, 3)
        );
    }
    s
}

/// Two planners compared over the instances both solved.
#[derive(Debug, Clone, PartialEq)]
pub struct Pair {
    /// The first planner.
    pub a: String,
    /// The second planner.
    pub b: String,
    /// Instances both solved: every figure below is over these.
    pub both: usize,
    /// Of those, the instances on which `a` took less wall time than `b`.
    pub a_faster: usize,
    /// Median over those instances of `a`'s wall time over `b`'s.
    pub time_ratio: Option<f64>,
    /// Mean of `a`'s occupied area over `b`'s.
    pub area_ratio: Option<f64>,
    /// Mean of `a`'s number of actions over `b`'s.
    pub len_ratio: Option<f64>,
}

/// `a` against `b` over the instances both solved.
pub fn pairwise(rows: &[ResultRow], a: &str, b: &str) -> Pair {
    let solved = |p: &str| -> BTreeMap<&str, &ResultRow> {
        rows.iter()
            .filter(|r| r.planner == p && r.solved())
            .map(|r| (r.instance.as_str(), r))
            .collect()
    };
    let (sa, sb) = (solved(a), solved(b));
    let (mut t, mut area, mut len, mut faster) = (Vec::new(), Vec::new(), Vec::new(), 0);
    for (i, ra) in &sa {
        let Some(rb) = sb.get(i) else { continue };
        t.push(ra.wall_time_s.max(1e-9) / rb.wall_time_s.max(1e-9));
        faster += usize::from(ra.wall_time_s < rb.wall_time_s);
        if let (Some(x), Some(y)) = (ra.occupied_area, rb.occupied_area) {
            area.push(x / y);
        }
        if let (Some(x), Some(y)) = (ra.seq_len, rb.seq_len) {
            len.push(x as f64 / y as f64);
        }
    }
    Pair {
        a: a.to_string(),
        b: b.to_string(),
        both: t.len(),
        a_faster: faster,
        time_ratio: median(&t),
        area_ratio: mean(&area),
        len_ratio: mean(&len),
    }
}

/// Every pair of planners, each over the instances both solved (empty for one planner).
pub fn pairwise_markdown(rows: &[ResultRow], names: &[String]) -> String {
    let mut s = String::new();
    if names.len() < 2 {
        return s;
    }
    let _ = writeln!(s, "\n## Pairwise comparisons\n");
    let _ = writeln!(
        s,
        "Each row compares planner A with planner B over **the instances both solved** (*both*), and only those: \
the median of A's wall time over B's, how often A was faster, and the mean ratios of occupied area and of actions \
(below 1: A better).\n"
    );
    s += "| A | B | both solved | median time A / B | A faster | mean area A / B | mean actions A / B |\n";
    s += "|---|---|---:|---:|---:|---:|---:|\n";
    let f = |v: Option<f64>, d: usize| v.map_or("–".to_string(), |x| format!("{x:.d$}"));
    for (i, a) in names.iter().enumerate() {
        for b in &names[i + 1..] {
            let p = pairwise(rows, a, b);
            let _ = writeln!(
                s,
                "| {a} | {b} | {} | {} | {} | {} | {} |",
                p.both,
                f(p.time_ratio, 2),
                if p.both == 0 {
                    "–".to_string()
                } else {
                    format!("{} of {}", p.a_faster, p.both)
                },
                f(p.area_ratio, 3),
                f(p.len_ratio, 3)
            );
        }
    }
    s
}

fn cell(r: Option<&&ResultRow>) -> String {
    let Some(r) = r else {
        return "not run".into();
    };
    if !r.solved() {
        return format!("{} ({:.1} s)", r.status.as_str(), r.wall_time_s);
    }
    let area = r.occupied_area.map_or("–".into(), |a| format!("{:.1}", a * 1e4));
    let len = r.seq_len.map_or("–".into(), |n| n.to_string());
    let sim = match r.sim_ok {
        Some(true) => " · sim ok",
        Some(false) => " · sim out of tolerance",
        None => "",
    };
    format!(
        "{} · {area} cm² · {len} actions · {:.2} s{sim}",
        r.status.as_str(),
        r.wall_time_s
    )
}

/// One row per instance and one column per planner: status, occupied area, actions and wall
/// time of each run (unsolved runs: their status and time).
pub fn per_instance_markdown(rows: &[ResultRow], names: &[String]) -> String {
    let mut by_instance: BTreeMap<(&str, &str), BTreeMap<&str, &ResultRow>> = BTreeMap::new();
    for r in rows {
        by_instance
            .entry((r.set.as_str(), r.name.as_str()))
            .or_default()
            .insert(r.planner.as_str(), r);
    }
    let mut s = String::new();
    let _ = writeln!(s, "# Per-instance results\n");
    let _ = writeln!(
        s,
        "Each cell: the run's status, occupied area, number of actions and wall time; a run without a verified \
plan shows its status. `sim` is the physics replay (planner option `simulate`).\n"
    );
    s += "| set | instance | objects |";
    for p in names {
        let _ = write!(s, " {p} |");
    }
    s += "\n|---|---|---:|";
    s += &"---|".repeat(names.len());
    s += "\n";
    for ((set, name), by_planner) in &by_instance {
        let objects = by_planner.values().next().map_or(0, |r| r.objects);
        let _ = write!(s, "| {set} | {name} | {objects} |");
        for p in names {
            let _ = write!(s, " {} |", cell(by_planner.get(p.as_str())));
        }
        s += "\n";
    }
    let solved: Vec<String> = names
        .iter()
        .map(|p| {
            let g: Vec<&ResultRow> = rows.iter().filter(|r| &r.planner == p).collect();
            format!(
                "{p}: {} of {} solved ({})",
                g.iter().filter(|r| r.solved()).count(),
                g.len(),
                pct(g.iter().filter(|r| r.solved()).count(), g.len())
            )
        })
        .collect();
    let _ = writeln!(s, "\n{}", solved.join("; "));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bootstrap_intervals_hold_the_estimate_and_are_reproducible() {
        let v: Vec<f64> = (1..=40).map(|i| i as f64).collect();
        let (lo, hi) = bootstrap_ci(&v, mean).unwrap();
        // Mean 20.5, standard error 11.5/√40 ≈ 1.82: a 95 % interval of about ±3.6.
        assert!(lo < 20.5 && 20.5 < hi, "[{lo}, {hi}]");
        assert!((hi - lo - 2.0 * 1.96 * 1.82).abs() < 1.5, "[{lo}, {hi}]");
        assert_eq!(bootstrap_ci(&v, mean), Some((lo, hi)));
        assert_eq!(bootstrap_ci(&[3.0], mean), None);
        let same = bootstrap_ci(&[2.0, 2.0, 2.0], median).unwrap();
        assert_eq!(same, (2.0, 2.0));
    }
}

//! The two sequencers (A* and the paper's Algorithms 1 + 2) on seeded random instances and on
//! the paper's eight-object instance.
//!
//! Not a criterion bench: a run takes seconds to minutes. The placement is fixed and cheap:
//! Bottom-Left with the instance's seed and order count (256), as `pushpack plan --placement bl`
//! places it, for the random instances, so only the sequence stage is timed;
//! the paper instance uses its MILP placement, as `pushpack plan` does by default. Per size it
//! reports, for each sequencer, the time to a proven optimum (A*) or to a complete search of its
//! own candidate space (paper), median and max; nodes expanded (median); the share finished
//! within the limit; runs without a plan, split into proven to have none (A*'s bound) and
//! stopped (with A*'s proven minimum number of actions); and for A* runs stopped by the limit
//! with a plan, the mean gap per cost component (incumbent − proven lower bound: actions, swept
//! area in cm², travel in m). Run:
//!
//! ```sh
//! cargo bench --bench sequence_random -- [--sizes 6,8,10,12,16,20] [--count 10] [--seeds 0,3] [--time-limit 60] \
//!     [--sequencers astar,paper] [--no-exp2] [--exp2-repeats 3] [--exp2-time-limit 60]
//! ```
//!
//! Per-instance lines go to stderr, the summary tables to stdout.

use pushpack::control::TimeLimit;
use pushpack::error::Error;
use pushpack::instance::generate::{random_instance, to_toml, GenerateParams};
use pushpack::instance::Instance;
use pushpack::placement::{bl, Placement};
use pushpack::plan::{solve_placement, PlacementSolver};
use pushpack::sequence::astar::{self, AstarSettings, Cost};
use pushpack::sequence::{paper, SearchStatus, SequenceOptions, SequenceResult};

mod common;
use common::{arg, median, seeds};

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

fn fmt(x: f64, prec: usize) -> String {
    if x.is_nan() {
        "–".into()
    } else {
        format!("{x:.prec$}")
    }
}

fn run(which: &str, inst: &Instance, placement: &Placement, limit: f64) -> pushpack::error::Result<SequenceResult> {
    let opts = SequenceOptions {
        no_direct: false,
        no_multi_push: false,
        max_nodes: u64::MAX,
        vetoes: Vec::new(),
    };
    let stop = TimeLimit::new(limit);
    match which {
        "astar" => astar::solve(inst, placement, &opts, &AstarSettings::default(), &stop),
        _ => paper::solve(inst, placement, &opts, &stop),
    }
}

/// A table cell listing seeds: `–` when none, else the count and the seeds.
fn list(v: &[String]) -> String {
    if v.is_empty() {
        "–".to_string()
    } else {
        format!("{}: {}", v.len(), v.join(", "))
    }
}

/// Gap per component of a stopped A* run: (actions, area cm², travel m).
fn gap(r: &SequenceResult) -> [f64; 3] {
    let b: Cost = r.bound.expect("A* reports a bound");
    [
        r.metrics.seq_len as f64 - b.len as f64,
        (r.metrics.swept_area - b.area) * 1e4,
        r.metrics.travel - b.travel,
    ]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let sizes: Vec<usize> = arg(&args, "--sizes", "6,8,10,12,16,20".to_string())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    let count: u64 = arg(&args, "--count", 10);
    let seeds = seeds(&args, count);
    let count = seeds.len();
    let limit: f64 = arg(&args, "--time-limit", 60.0);
    let sequencers: Vec<String> = arg(&args, "--sequencers", "astar,paper".to_string())
        .split(',')
        .map(str::to_string)
        .collect();
    let exp2_repeats: usize = arg(&args, "--exp2-repeats", 3);
    // exp2 gets its own limit: the point there is the time to a proof, not a cut-off.
    let exp2_limit: f64 = arg(&args, "--exp2-time-limit", 60.0);

    if !args.iter().any(|a| a == "--no-exp2") {
        let inst = Instance::load(format!(
            "{}/instances/paper/exp2_8objects.toml",
            env!("CARGO_MANIFEST_DIR")
        ))
        .expect("bundled instance");
        // The placement `pushpack plan` uses by default (MILP, warm-started by Bottom-Left).
        let placement = solve_placement(
            &inst,
            PlacementSolver::Milp,
            inst.settings.seed,
            inst.settings.bl_orders,
            60.0,
        )
        .expect("MILP")
        .placement;
        println!(
            "exp2_8objects (MILP placement, {:.1} cm²):",
            placement.occupied_area() * 1e4
        );
        println!();
        println!(
            "| sequencer | actions | swept area (cm²) | travel (m) | status | nodes | median time (s) | times (s) |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        for which in &sequencers {
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..exp2_repeats {
                let r = run(which, &inst, &placement, exp2_limit).expect("exp2 has a plan");
                times.push(r.time_s);
                last = Some(r);
            }
            let r = last.expect("at least one repeat");
            let all: Vec<String> = times.iter().map(|t| format!("{t:.3}")).collect();
            println!(
                "| {which} | {} | {:.1} | {:.3} | {:?} | {} | {:.3} | {} |",
                r.metrics.seq_len,
                r.metrics.swept_area * 1e4,
                r.metrics.travel,
                r.status,
                r.nodes,
                median(&times),
                all.join(", ")
            );
        }
        println!();
    }

    println!("Random instances (BL placement, {count} seeds per size, {limit} s limit per run):");
    println!();
    println!("| objects | sequencer | instances | finished | share finished | median time (s) | max time (s) | median nodes | stopped with a plan: mean gap (actions, cm², m) | proven no plan (seeds) | stopped without a plan (seeds, proven min. actions) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        for which in &sequencers {
            let mut times = Vec::new();
            let mut nodes = Vec::new();
            let mut gaps: Vec<[f64; 3]> = Vec::new();
            let mut finished = 0;
            let mut instances = 0;
            let mut infeasible: Vec<String> = Vec::new();
            let mut stopped: Vec<String> = Vec::new();
            for &seed in &seeds {
                let kinds = 2 + (seed as usize % 3);
                let text = to_toml(&random_instance(&GenerateParams::new(n, kinds.min(n), seed)).expect("valid"));
                let inst = Instance::parse(&text, false, "<bench>", None).expect("generated instances validate");
                let placement = match bl::solve(
                    &inst,
                    inst.settings.seed,
                    inst.settings.bl_orders,
                    &TimeLimit::new(60.0),
                ) {
                    Ok(p) => p.placement,
                    Err(e) => {
                        eprintln!("n={n:2} seed={seed}: BL failed: {e}");
                        continue;
                    }
                };
                instances += 1;
                match run(which, &inst, &placement, limit) {
                    Ok(r) => {
                        nodes.push(r.nodes as f64);
                        let g = if which == "astar" && r.status != SearchStatus::Complete {
                            Some(gap(&r))
                        } else {
                            None
                        };
                        eprintln!(
                            "n={n:2} seed={seed} {which}: {:?} len {} area {:.2} cm² travel {:.3} m, {} nodes, {:.3} s{}",
                            r.status,
                            r.metrics.seq_len,
                            r.metrics.swept_area * 1e4,
                            r.metrics.travel,
                            r.nodes,
                            r.time_s,
                            g.map(|g| format!(", gap ({}, {:.2}, {:.3})", g[0], g[1], g[2]))
                                .unwrap_or_default()
                        );
                        if r.status == SearchStatus::Complete {
                            finished += 1;
                            times.push(r.time_s);
                        } else if let Some(g) = g {
                            gaps.push(g);
                        }
                    }
                    Err(e) => {
                        eprintln!("n={n:2} seed={seed} {which}: no plan: {e}");
                        match e {
                            Error::Infeasible { .. } => infeasible.push(format!("{seed}")),
                            Error::Stopped {
                                min_actions: Some(m), ..
                            } => stopped.push(format!("{seed} (≥ {m})")),
                            _ => stopped.push(format!("{seed}")),
                        }
                    }
                }
            }
            let max = times.iter().cloned().fold(f64::NAN, f64::max);
            let g = |k: usize| mean(&gaps.iter().map(|g| g[k]).collect::<Vec<_>>());
            println!(
                "| {n} | {which} | {instances} | {finished} | {:.0} % | {} | {} | {} | {} | {} | {} |",
                100.0 * finished as f64 / instances.max(1) as f64,
                fmt(median(&times), 3),
                fmt(max, 3),
                fmt(median(&nodes), 0),
                if gaps.is_empty() {
                    "–".to_string()
                } else {
                    format!("{} runs: ({:.2}, {:.2}, {:.3})", gaps.len(), g(0), g(1), g(2))
                },
                list(&infeasible),
                list(&stopped)
            );
        }
    }
}

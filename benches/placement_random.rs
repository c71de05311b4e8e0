//! Exact placement (MILP) against Bottom-Left on random instances: generated ones, or the
//! committed sets.
//!
//! Not a criterion bench: each run takes seconds to minutes, so it reports per set the share
//! proven (the area alone, and both stages: area then contact length), the median and largest
//! time of each stage, the mean gap at the limit and the area gain over Bottom-Left. Run:
//!
//! ```sh
//! # generated instances, `--count` seeds per size
//! cargo bench --bench placement_random -- [--sizes 4,6,8,10,12,16] [--count 10] [--seeds 0,3] [--time-limit 60]
//! # the committed sets, the first `--count` files of each (sorted by name)
//! cargo bench --bench placement_random -- --sets instances/random/n12,instances/random/n16 --count 10 [--threads 1]
//! # contact-stage budget rules side by side on the same files: rest | area | seconds
//! cargo bench --bench placement_random -- --sets instances/random/n16 --budgets rest,area
//! ```

use pushpack::control::TimeLimit;
use pushpack::instance::generate::{random_instance, to_toml, GenerateParams};
use pushpack::instance::Instance;
use pushpack::placement::milp::ContactBudget;
use pushpack::placement::{bl, milp, PlacementStatus};

mod common;
use common::{arg, median, seeds};

/// One instance to place: a label, the instance, its seed.
type Case = (String, Instance, u64);

fn generated(n: usize, seeds: &[u64]) -> Vec<Case> {
    seeds
        .iter()
        .map(|&seed| {
            let kinds = 2 + (seed as usize % 3);
            let text =
                to_toml(&random_instance(&GenerateParams::new(n, kinds.min(n), seed)).expect("valid parameters"));
            let inst = Instance::parse(&text, false, "<bench>", None).expect("generated instances validate");
            (format!("n{n} seed {seed}"), inst, seed)
        })
        .collect()
}

fn committed(dir: &str, count: usize) -> Vec<Case> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .take(count)
        .map(|f| {
            let inst = Instance::load(&f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            let seed = inst.settings.seed;
            (f.file_stem().unwrap().to_string_lossy().into_owned(), inst, seed)
        })
        .collect()
}

fn budget(s: &str) -> ContactBudget {
    match s {
        "rest" => ContactBudget::Rest,
        "area" => ContactBudget::AreaTime,
        v => ContactBudget::Seconds(v.parse().expect("--budgets: rest, area or seconds")),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let sizes: Vec<usize> = arg(&args, "--sizes", "4,6,8,10,12,16".to_string())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    let count: u64 = arg(&args, "--count", 10);
    let limit: f64 = arg(&args, "--time-limit", 60.0);
    let threads: usize = arg(&args, "--threads", 1);
    let budgets: Vec<String> = arg(&args, "--budgets", "rest".to_string())
        .split(',')
        .map(str::to_string)
        .collect();
    let sets: Vec<(String, Vec<Case>)> = match args.iter().position(|a| a == "--sets") {
        Some(i) => args[i + 1]
            .split(',')
            .map(|d| (d.to_string(), committed(d, count as usize)))
            .collect(),
        None => {
            let seeds = seeds(&args, count);
            sizes.iter().map(|&n| (format!("n{n}"), generated(n, &seeds))).collect()
        }
    };
    println!("| set | contact budget | instances | area proven | both proven | area stage s, median (max) | contact stage s, median (max) | mean gap at limit | mean area gain over BL |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, cases) in &sets {
        for b in &budgets {
            let (mut area_ok, mut both_ok) = (0, 0);
            let (mut area_s, mut contact_s, mut gaps, mut gains) = (vec![], vec![], vec![], vec![]);
            for (label, inst, seed) in cases {
                let blr = bl::solve(inst, *seed, 256, &TimeLimit::new(limit)).expect("BL places these instances");
                let settings = milp::MilpSettings {
                    time_limit: limit,
                    contact_stage: true,
                    seed: *seed,
                    contact_budget: budget(b),
                    threads,
                    ..Default::default()
                };
                let (r, rep) = milp::solve_report(inst, &blr, &settings, &TimeLimit::new(limit))
                    .expect("the exact placement runs");
                assert!(r.placement.violations(inst).is_empty(), "{label}: invalid placement");
                let (a, bla) = (r.placement.occupied_area(), blr.placement.occupied_area());
                gains.push((bla - a) / bla);
                gaps.push(r.gap());
                area_ok += rep.area_optimal as usize;
                both_ok += (r.status == PlacementStatus::Optimal) as usize;
                area_s.push(rep.area_stage_s);
                contact_s.push(rep.contact_stage_s);
                eprintln!(
                    "{label} [{b}]: {:?} area {a:.6} (BL {bla:.6}) gap {:.4}; area stage {:.2} s (proven {}), contact stage {:.2} s (proven {}; enumeration {:.2} s, {} proofs; MILP {:.2} s, {} proofs)",
                    r.status,
                    r.gap(),
                    rep.area_stage_s,
                    rep.area_optimal,
                    rep.contact_stage_s,
                    rep.contact_optimal,
                    rep.contact_enumeration_s,
                    rep.contact_proofs_by_enumeration,
                    rep.contact_milp_s,
                    rep.contact_proofs_by_milp
                );
            }
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
            let max = |v: &[f64]| v.iter().cloned().fold(f64::NAN, f64::max);
            println!(
                "| {name} | {b} | {} | {area_ok} | {both_ok} | {:.2} ({:.2}) | {:.2} ({:.2}) | {:.2} % | {:.1} % |",
                cases.len(),
                median(&area_s),
                max(&area_s),
                median(&contact_s),
                max(&contact_s),
                100.0 * mean(&gaps),
                100.0 * mean(&gains)
            );
        }
    }
}

//! Exact placement (MILP) against Bottom-Left on seeded random instances.
//!
//! Not a criterion bench: each run takes seconds to minutes, so it reports per size the time to
//! a proven optimum (median, max), the share proven within the limit, the mean gap at the limit
//! and the area gain over Bottom-Left. Run:
//!
//! ```sh
//! cargo bench --bench placement_random -- [--sizes 4,6,8,10,12,16] [--count 10] [--seeds 0,3] [--time-limit 60]
//! ```

use pushpack::control::TimeLimit;
use pushpack::instance::generate::{random_instance, to_toml, GenerateParams};
use pushpack::instance::Instance;
use pushpack::placement::{bl, milp, PlacementStatus};

mod common;
use common::{arg, median, seeds};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let sizes: Vec<usize> = arg(&args, "--sizes", "4,6,8,10,12,16".to_string())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    let count: u64 = arg(&args, "--count", 10);
    let limit: f64 = arg(&args, "--time-limit", 60.0);
    let seeds = seeds(&args, count);
    let count = seeds.len() as u64;
    println!("| objects | instances | proven | share proven | median time to proof (s) | max time to proof (s) | mean gap at limit | mean area gain over BL |");
    println!("|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        let mut times = Vec::new();
        let mut gaps = Vec::new();
        let mut gains = Vec::new();
        for &seed in &seeds {
            let kinds = 2 + (seed as usize % 3);
            let text =
                to_toml(&random_instance(&GenerateParams::new(n, kinds.min(n), seed)).expect("valid parameters"));
            let inst = Instance::parse(&text, false, "<bench>", None).expect("generated instances validate");
            let start = std::time::Instant::now();
            let blr = bl::solve(&inst, seed, 256, &TimeLimit::new(limit)).expect("BL places generated instances");
            let settings = milp::MilpSettings {
                time_limit: limit,
                contact_stage: true,
                seed,
                ..Default::default()
            };
            let r = milp::solve(&inst, &blr, &settings, &TimeLimit::new(limit)).expect("MILP runs");
            let t = start.elapsed().as_secs_f64();
            assert!(
                r.placement.violations(&inst).is_empty(),
                "n={n} seed={seed}: invalid placement"
            );
            let (a, b) = (r.placement.occupied_area(), blr.placement.occupied_area());
            gains.push((b - a) / b);
            if r.status == PlacementStatus::Optimal {
                times.push(t);
            } else {
                gaps.push(r.gap());
            }
            eprintln!(
                "n={n:2} seed={seed}: {:?} area {a:.6} bl {b:.6} gap {:.4} {t:.2}s {} MILPs",
                r.status,
                r.gap(),
                r.subproblems
            );
        }
        let proven = times.len();
        let max = times.iter().cloned().fold(f64::NAN, f64::max);
        let mean = |v: &[f64]| {
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().sum::<f64>() / v.len() as f64
            }
        };
        println!(
            "| {n} | {count} | {proven} | {:.0} % | {:.2} | {:.2} | {} | {:.1} % |",
            100.0 * proven as f64 / count as f64,
            median(&times),
            max,
            if gaps.is_empty() {
                "–".to_string()
            } else {
                format!("{:.1} %", 100.0 * mean(&gaps))
            },
            100.0 * mean(&gains)
        );
    }
}

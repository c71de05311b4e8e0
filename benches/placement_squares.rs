//! Exact placement on the consecutive squares 1×1 … N×N (OEIS A038666), upright, in a container
//! that never binds (sides = 1 + 2 + … + N) and in the tight container (exactly the optimal box).
//!
//! Not a criterion bench: it reports per N the optimum found, whether the area and the contact
//! stage are proven, and the seconds of each stage (median over `--repeat` runs; the machine is
//! noisy). Run:
//!
//! ```sh
//! cargo bench --bench placement_squares -- [--from 1] [--to 22] [--time-limit 60] [--repeat 3] [--tight] [--threads 1]
//! # the area stage's two masters side by side (combinatorial x-phase, HiGHS MILP)
//! cargo bench --bench placement_squares -- --to 12 --masters search,highs
//! # the packing search alone on each enclosing box W × D (W ≥ D) of area below the optimum
//! # and at it, that the bounds do not refute (integer sizes): outcome, nodes, seconds
//! cargo bench --bench placement_squares -- --boxes 18 --time-limit 300
//! # one of those boxes only
//! cargo bench --bench placement_squares -- --boxes 21 --only 71x47
//! # the contact stage's enumeration alone on each box of the optimal area that packs (loose
//! # container): nodes, seconds, finished or not, the best contact length found (units)
//! cargo bench --bench placement_squares -- --contact 17 --time-limit 60
//! ```

use pushpack::control::TimeLimit;
use pushpack::instance::generate::consecutive_squares_toml;
use pushpack::instance::Instance;
use pushpack::placement::milp::AreaMaster;
use pushpack::placement::{milp, PlacementResult, PlacementStatus};

#[allow(dead_code)] // shared helpers: this bench uses two of them
mod common;
use common::{arg, median};

/// OEIS A038666, n = 1 … 22 (minimum area of a rectangle holding squares 1 … n).
const A038666: [u32; 22] = [
    1, 6, 15, 35, 60, 99, 154, 210, 300, 405, 513, 667, 836, 1035, 1265, 1512, 1794, 2139, 2491, 2890, 3344, 3822,
];

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let from: u32 = arg(&args, "--from", 1);
    let to: u32 = arg(&args, "--to", 22);
    let limit: f64 = arg(&args, "--time-limit", 60.0);
    let repeat: usize = arg(&args, "--repeat", 3);
    let tight = args.iter().any(|a| a == "--tight");
    let threads: usize = arg(&args, "--threads", 1);
    let boxes: u32 = arg(&args, "--boxes", 0);
    if boxes > 0 {
        let only: String = arg(&args, "--only", String::new());
        return decide_boxes(boxes, limit, &only, threads);
    }
    let contact: u32 = arg(&args, "--contact", 0);
    if contact > 0 {
        return contact_boxes(contact, limit, threads);
    }
    let masters: Vec<AreaMaster> = arg(&args, "--masters", "search".to_string())
        .split(',')
        .map(|m| match m {
            "search" => AreaMaster::Search,
            "highs" => AreaMaster::Highs,
            _ => panic!("--masters: search or highs"),
        })
        .collect();
    // "area proven at": when the bound met the incumbent (the trace's first such point); the
    // area stage goes on deciding the boxes tied with it, which the contact stage needs closed.
    println!("| N | master | A038666 | area found | area proven | contact proven | area proven at (s, median) | area stage (s, median) | contact stage (s, median) | CPU s, both stages (median) | boxes (searched) | nodes |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for n in from..=to.min(22) {
        let want = A038666[n as usize - 1];
        // The tight container: the optimal box, found by the unconstrained run.
        let mut text = consecutive_squares_toml(n, None);
        if tight {
            let inst = Instance::parse(&text, false, "<bench>", None).expect("valid");
            let r = run(&inst, limit, AreaMaster::Search, threads).0;
            let (w, d) = r.placement.extent();
            text = consecutive_squares_toml(n, Some(((w / 0.002).round() as u32, (d / 0.002).round() as u32)));
        }
        let inst = Instance::parse(&text, false, "<bench>", None).expect("valid");
        for &master in &masters {
            let mut proven_s = Vec::new();
            let mut area_s = Vec::new();
            let mut contact_s = Vec::new();
            let mut cpu = Vec::new();
            let mut last = None;
            // Runs with each stage proven: with `--repeat`, the status of every run counts.
            let (mut area_yes, mut both_yes) = (0, 0);
            for _ in 0..repeat {
                let c0 = cpu_s();
                let (r, rep) = run(&inst, limit, master, threads);
                cpu.push(cpu_s() - c0);
                assert!(r.placement.violations(&inst).is_empty(), "N={n}: invalid placement");
                let met = rep
                    .trace
                    .iter()
                    .find(|b| b.incumbent.is_some_and(|i| i <= b.lower_bound + 1e-9));
                proven_s.push(met.map_or(f64::NAN, |b| b.t_s));
                area_s.push(rep.area_stage_s);
                contact_s.push(rep.contact_stage_s);
                area_yes += rep.area_optimal as usize;
                both_yes += (r.status == PlacementStatus::Optimal) as usize;
                last = Some((r, rep));
            }
            let (r, rep) = last.expect("repeat ≥ 1");
            let units = (r.placement.occupied_area() / 4e-6).round() as u32;
            println!(
                "| {n} | {master:?} | {want} | {units}{} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {} ({}) | {} |",
                if units == want { "" } else { " (differs)" },
                runs(area_yes, repeat),
                runs(both_yes, repeat),
                median(&proven_s),
                median(&area_s),
                median(&contact_s),
                median(&cpu),
                rep.boxes,
                rep.boxes_searched,
                r.nodes
            );
        }
    }
}

/// "yes" / "no" for one run; "k / n yes" over several.
fn runs(yes: usize, of: usize) -> String {
    match (of, yes) {
        (1, 1) => "yes".into(),
        (1, _) => "no".into(),
        _ => format!("{yes} / {of} yes"),
    }
}

fn run(inst: &Instance, limit: f64, area_master: AreaMaster, threads: usize) -> (PlacementResult, milp::MilpReport) {
    let none = PlacementResult::empty("none", 0.0);
    let s = milp::MilpSettings {
        time_limit: limit,
        contact_stage: true,
        seed: 1,
        area_master,
        threads,
        ..Default::default()
    };
    milp::solve_report(inst, &none, &s, &TimeLimit::new(limit)).expect("squares always fit the loose container")
}

/// The squares 1 × 1 … N × N as packing-search items, largest first.
fn square_items(n: u32) -> Vec<pushpack::placement::opp::Item> {
    (1..=n)
        .rev()
        .map(|s| pushpack::placement::opp::Item {
            opts: vec![[s as f64, s as f64]],
            class: s as usize,
        })
        .collect()
}

/// `--boxes N`: every box `W × D`, `W ≥ D ≥ N`, with `sum ≤ W·D ≤ A038666(N)`, decided by the
/// packing search alone (the area stage decides these, in area order, until one packs).
fn decide_boxes(n: u32, limit: f64, only: &str, threads: usize) {
    use pushpack::placement::opp::{decide_metered, refuted_by_bounds};
    use std::time::Instant;
    let items = square_items(n);
    let sum: u32 = (1..=n).map(|s| s * s).sum();
    let best = A038666[n as usize - 1];
    let mut list: Vec<(u32, u32)> = Vec::new();
    for w in n..=best / n {
        for d in n..=w {
            if w * d >= sum && w * d <= best {
                list.push((w, d));
            }
        }
    }
    list.sort_by_key(|&(w, d)| (w * d, w));
    if !only.is_empty() {
        list.retain(|&(w, d)| format!("{w}x{d}") == only);
    }
    println!("| W | D | area | outcome | nodes | s | CPU s |");
    println!("|---|---|---|---|---|---|---|");
    for (w, d) in list {
        let (wf, df) = (w as f64, d as f64);
        if refuted_by_bounds(&items, wf, df) {
            continue;
        }
        let t0 = Instant::now();
        let c0 = cpu_s();
        let stop = || t0.elapsed().as_secs_f64() > limit;
        let (r, nodes) = decide_metered(&items, wf, df, &stop, None, threads);
        let kind = match r {
            pushpack::placement::opp::Outcome::Packed(_) => "packed",
            pushpack::placement::opp::Outcome::Infeasible => "infeasible",
            pushpack::placement::opp::Outcome::Stopped => "stopped",
        };
        println!(
            "| {w} | {d} | {} | {kind} | {} | {:.3} | {:.3} |",
            w * d,
            nodes,
            t0.elapsed().as_secs_f64(),
            cpu_s() - c0
        );
    }
}

/// `--contact N`: [`pushpack::placement::area::max_contact`] alone on every box `W × D` of the
/// optimal area that packs (both orientations: the pipeline skips a transpose only when the walls
/// allow), starting from no contact to beat.
fn contact_boxes(n: u32, limit: f64, threads: usize) {
    use pushpack::placement::area::max_contact;
    use pushpack::placement::opp::{decide, Outcome};
    use std::time::Instant;
    let inst = Instance::parse(&consecutive_squares_toml(n, None), false, "<bench>", None).expect("valid");
    let fps = milp::footprints(&inst);
    let items = square_items(n);
    let best = A038666[n as usize - 1];
    println!("| W | D | finished | contact (units) | nodes | s | CPU s |");
    println!("|---|---|---|---|---|---|---|");
    for w in n..=best / n {
        let d = best / w;
        if d < n || w * d != best || d > w {
            continue;
        }
        let never = || false;
        if !matches!(decide(&items, w as f64, d as f64, &never).0, Outcome::Packed(_)) {
            continue;
        }
        let t0 = Instant::now();
        let c0 = cpu_s();
        let stop = || t0.elapsed().as_secs_f64() > limit;
        let e = (w as f64 * 0.002, d as f64 * 0.002);
        let (p, done, nodes, _) = max_contact(&inst, &fps, e, 0.0, &stop, None, threads);
        let c = p.map(|p| p.contact_length(&inst) / 0.002).unwrap_or(0.0);
        println!(
            "| {w} | {d} | {} | {c:.0} | {nodes} | {:.3} | {:.3} |",
            if done { "yes" } else { "no" },
            t0.elapsed().as_secs_f64(),
            cpu_s() - c0
        );
    }
}

/// CPU seconds (user and system) this process has used: on a machine shared with other work,
/// steadier than the wall clock (the solver runs on one thread).
fn cpu_s() -> f64 {
    #[cfg(unix)]
    {
        // SAFETY: getrusage only writes the struct it is given.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } == 0 {
            let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
            return tv(u.ru_utime) + tv(u.ru_stime);
        }
    }
    f64::NAN
}

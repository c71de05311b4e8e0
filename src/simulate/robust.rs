//! A plan replayed under the errors a real cell makes: release poses off by about half a
//! millimetre and half a degree, friction off by a fifth, and the sweep's engine settings.
//! The share of replays that stay within tolerance is the plan's robustness.

use serde::Serialize;

use super::sweep::variants;
use super::{simulate, Perturbation, Replayable, SimOptions, SimReport};
use crate::error::Result;
use crate::instance::Instance;

/// One perturbed replay.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobustRun {
    /// Seed of its draws.
    pub seed: u64,
    /// The engine setting of the sweep it used.
    pub setting: String,
    /// The replay.
    pub report: SimReport,
}

/// `n` replays of `plan`: run `k` draws its errors from seed `seed + k` and uses the sweep's
/// setting `k mod 6` ([`variants`]), so that every setting sees errors.
pub fn robust(
    inst: &Instance,
    plan: &impl Replayable,
    base: &SimOptions,
    n: usize,
    seed: u64,
) -> Result<Vec<RobustRun>> {
    let settings = variants(base);
    (0..n)
        .map(|k| {
            let (setting, mut o) = settings[k % settings.len()].clone();
            let s = seed.wrapping_add(k as u64);
            o.perturb = Some(Perturbation::with_seed(s));
            Ok(RobustRun {
                seed: s,
                setting,
                report: simulate(inst, plan, &o)?,
            })
        })
        .collect()
}

/// Share of `runs` within tolerance (1 for no runs).
pub fn share_ok(runs: &[RobustRun]) -> f64 {
    if runs.is_empty() {
        return 1.0;
    }
    runs.iter().filter(|r| r.report.ok).count() as f64 / runs.len() as f64
}

/// A table of the runs: per replay the seed, the setting, the verdict and the first action out
/// of tolerance; then the share.
pub fn robust_table(runs: &[RobustRun]) -> String {
    let mut s = String::from(
        "| seed | setting | verdict | worst box (mm, °) | first action out of tolerance |\n|---|---|---|---|---|\n",
    );
    for r in runs {
        s += &format!("| {} | {} | {} |\n", r.seed, r.setting, r.report.row_cells());
    }
    s += &format!(
        "\n{} of {} perturbed replays within tolerance ({:.0} %)\n",
        runs.iter().filter(|r| r.report.ok).count(),
        runs.len(),
        share_ok(runs) * 100.0
    );
    s
}

//! One plan replayed under several settings: a replay is one sample of a contact-rich process,
//! and a push that succeeds under one step size and fails under the next is fragile
//! (docs/simulate.md, "A fragile push").

use serde::Serialize;

use super::{simulate, Replayable, SimOptions, SimReport};
use crate::error::Result;
use crate::instance::Instance;

/// The settings a sweep varies around `base`: the base itself, half the step, a half and a
/// quarter of the push speed, and contacts two thirds and four thirds as stiff. Each is a
/// setting a quasi-static push should not depend on, so a verdict that changes across them is
/// fragile. Faster pushes are not in the list: above the default the boxes' momentum starts to
/// matter (two_boxes at 40 mm/s rebounds 10 mm), which the push rules do not model.
pub fn variants(base: &SimOptions) -> Vec<(String, SimOptions)> {
    let with = |label: String, f: &dyn Fn(&mut SimOptions)| {
        let mut o = base.clone();
        f(&mut o);
        (label, o)
    };
    vec![
        with("defaults".into(), &|_| {}),
        with(format!("dt {:.4} s", base.dt / 2.0), &|o| o.dt /= 2.0),
        with(format!("push {:.0} mm/s", base.push_speed * 500.0), &|o| {
            o.push_speed /= 2.0
        }),
        with(format!("push {:.0} mm/s", base.push_speed * 250.0), &|o| {
            o.push_speed /= 4.0
        }),
        with(format!("contacts {:.0} Hz", base.contact_hz * 2.0 / 3.0), &|o| {
            o.contact_hz *= 2.0 / 3.0
        }),
        with(format!("contacts {:.0} Hz", base.contact_hz * 4.0 / 3.0), &|o| {
            o.contact_hz *= 4.0 / 3.0
        }),
    ]
}

/// One replay of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepRun {
    /// What was changed from the base settings.
    pub setting: String,
    /// The replay.
    pub report: SimReport,
}

/// Replay `plan` under every one of [`variants`]`(base)`.
pub fn sweep(inst: &Instance, plan: &impl Replayable, base: &SimOptions) -> Result<Vec<SweepRun>> {
    variants(base)
        .into_iter()
        .map(|(setting, o)| {
            Ok(SweepRun {
                setting,
                report: simulate(inst, plan, &o)?,
            })
        })
        .collect()
}

/// A table of a sweep: per setting the verdict, the worst box and the first action out of
/// tolerance.
pub fn sweep_table(runs: &[SweepRun]) -> String {
    let mut s =
        String::from("| setting | verdict | worst box (mm, °) | first action out of tolerance |\n|---|---|---|---|\n");
    for r in runs {
        s += &format!("| {} | {} |\n", r.setting, r.report.row_cells());
    }
    s
}

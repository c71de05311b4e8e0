//! The physics replay as a verifier check: every action and box out of tolerance becomes a
//! violation of class `physics`.

use super::{PhysicsCheck, Report, Violation, ViolationClass};
use crate::instance::Instance;
use crate::plan::Plan;
use crate::simulate::{simulate, SimOptions};

/// Replay `plan` with the instance's settings and record what it finds in `report`. A replay
/// that cannot run (the plan does not match the instance) is a `physics` violation too: the
/// plan is then not shown to be executable.
pub(super) fn check(inst: &Instance, plan: &Plan, report: &mut Report) {
    let issue = |step: Option<usize>, message: String| Violation {
        step,
        class: ViolationClass::Physics,
        message,
    };
    match simulate(inst, plan, &SimOptions::from_instance(inst)) {
        Err(e) => report
            .physics_issues
            .push(issue(None, format!("the replay could not run: {e}"))),
        Ok(sim) => {
            let t = sim.tolerances;
            let (tol_deg, tol_mm) = (t.max_rotation.to_degrees(), t.max_drift * 1e3);
            for a in sim.actions.iter().filter(|a| !a.ok) {
                let mut what = Vec::new();
                for (k, id) in a.objects.iter().enumerate() {
                    if a.rotation_deg[k] > tol_deg {
                        what.push(format!("{id} turns {:.2}°", a.rotation_deg[k]));
                    }
                    if a.drift_mm[k] > tol_mm {
                        what.push(format!("{id} drifts {:.2} mm", a.drift_mm[k]));
                    }
                }
                if a.disturbed_mm > tol_mm {
                    what.push(format!("another box moves {:.2} mm", a.disturbed_mm));
                }
                report.physics_issues.push(issue(
                    Some(a.step),
                    format!(
                        "{} {}: {} (tolerances {tol_deg:.2}°, {tol_mm:.2} mm)",
                        a.kind,
                        a.objects.join(","),
                        what.join(", ")
                    ),
                ));
            }
            for b in sim.boxes.iter().filter(|b| !b.ok) {
                report.physics_issues.push(issue(
                    None,
                    if b.placed {
                        format!(
                            "{} ends {:.2} mm from its target, turned {:.2}°",
                            b.object, b.position_error_mm, b.rotation_deg
                        )
                    } else {
                        format!("{} never reaches the container", b.object)
                    },
                ));
            }
            let (worst_mm, worst_deg) = sim.worst();
            report.physics = PhysicsCheck::Replayed {
                ok: sim.ok,
                worst_mm,
                worst_deg,
                wall_s: sim.wall_s,
            };
        }
    }
}

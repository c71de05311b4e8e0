//! What a physics replay found: per action and per box, the motion against the tolerances.

use std::fmt;

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};

use crate::instance::Instance;

/// What a box may do during one push and where it may end: the instance's push tolerances
/// (`[planner] max_push_rotation_deg`, `max_push_drift`), the same ones the planner's travel
/// rule uses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    /// Largest rotation of a box (rad): during an action, and from its target at the end.
    pub max_rotation: f64,
    /// Largest sideways drift of a pushed box, displacement of a box the action should not
    /// move, and distance of a box from its target at the end (m).
    pub max_drift: f64,
}

impl Tolerances {
    /// The instance's push tolerances.
    pub fn from_instance(inst: &Instance) -> Tolerances {
        Tolerances {
            max_rotation: inst.settings.max_push_rotation,
            max_drift: inst.settings.max_push_drift,
        }
    }
}

/// One action as the replay saw it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ActionSim {
    /// 1-based step number, as in `plan.json`.
    pub step: usize,
    /// `place` or `push`.
    pub kind: String,
    /// The objects the action moves (a push: front to back).
    pub objects: Vec<String>,
    /// Largest rotation of each moved object during the action (degrees).
    pub rotation_deg: Vec<f64>,
    /// Each moved object's drift (mm): sideways across a push; for a place, how far the box
    /// moved on the floor after it was released.
    pub drift_mm: Vec<f64>,
    /// Largest displacement of any other box in the container during the action (mm).
    pub disturbed_mm: f64,
    /// Every figure within the tolerances.
    pub ok: bool,
}

impl ActionSim {
    pub(super) fn new(
        step: usize,
        kind: &str,
        objects: &[String],
        rotation: Vec<f64>,
        drift: Vec<f64>,
        disturbed: f64,
        tol: &Tolerances,
    ) -> ActionSim {
        let ok = rotation.iter().all(|&r| r <= tol.max_rotation)
            && drift.iter().all(|&d| d <= tol.max_drift)
            && disturbed <= tol.max_drift;
        ActionSim {
            step,
            kind: kind.into(),
            objects: objects.to_vec(),
            rotation_deg: rotation.iter().map(|r| r.to_degrees()).collect(),
            drift_mm: drift.iter().map(|d| d * 1e3).collect(),
            disturbed_mm: disturbed * 1e3,
            ok,
        }
    }
}

/// One box at the end of the replay, against its target.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoxSim {
    /// Object id.
    pub object: String,
    /// Whether the box was ever put in the container.
    pub placed: bool,
    /// Horizontal distance of its centre from the target's (mm).
    pub position_error_mm: f64,
    /// That offset along C's x and y (mm, signed: where the box is minus where it should be).
    pub offset_mm: [f64; 2],
    /// Height of its centre above the target's (mm): far from 0 when it fell over.
    pub height_error_mm: f64,
    /// Rotation about the vertical from the target's orientation (degrees, signed).
    pub yaw_error_deg: f64,
    /// Whole rotation from the target's orientation (degrees): yaw and tilt.
    pub rotation_deg: f64,
    /// Within the tolerances.
    pub ok: bool,
}

impl BoxSim {
    pub(super) fn new(object: String, pose: &Isometry3<f64>, target: &Isometry3<f64>, tol: &Tolerances) -> BoxSim {
        let d = pose.translation.vector - target.translation.vector;
        let rel = target.rotation.inverse() * pose.rotation;
        let rotation = rel.angle();
        let (_, _, yaw) = rel.euler_angles();
        let horizontal = d.xy().norm();
        BoxSim {
            object,
            placed: true,
            position_error_mm: horizontal * 1e3,
            offset_mm: [d.x * 1e3, d.y * 1e3],
            height_error_mm: d.z * 1e3,
            yaw_error_deg: yaw.to_degrees(),
            rotation_deg: rotation.to_degrees(),
            ok: horizontal.hypot(d.z) <= tol.max_drift && rotation <= tol.max_rotation,
        }
    }

    pub(super) fn missing(object: String) -> BoxSim {
        BoxSim {
            object,
            placed: false,
            position_error_mm: f64::NAN,
            offset_mm: [f64::NAN; 2],
            height_error_mm: f64::NAN,
            yaw_error_deg: f64::NAN,
            rotation_deg: f64::NAN,
            ok: false,
        }
    }
}

/// The replay of a whole plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimReport {
    /// Every action and every box within the tolerances.
    pub ok: bool,
    /// The tolerances judged against.
    pub tolerances: Tolerances,
    /// Per action, in plan order.
    pub actions: Vec<ActionSim>,
    /// Per object, in instance order, at the end.
    pub boxes: Vec<BoxSim>,
    /// Physics steps taken.
    pub steps: u64,
    /// Simulated time (s).
    pub simulated_s: f64,
    /// Wall-clock time of the replay (s).
    pub wall_s: f64,
}

impl SimReport {
    pub(super) fn new(
        tolerances: Tolerances,
        actions: Vec<ActionSim>,
        boxes: Vec<BoxSim>,
        steps: u64,
        simulated_s: f64,
        wall_s: f64,
    ) -> SimReport {
        let ok = actions.iter().all(|a| a.ok) && boxes.iter().all(|b| b.ok);
        SimReport {
            ok,
            tolerances,
            actions,
            boxes,
            steps,
            simulated_s,
            wall_s,
        }
    }

    /// The cells a table row of one replay ends with: the verdict, the worst box (mm, °) and
    /// the first action out of tolerance (`–` when none is).
    pub fn row_cells(&self) -> String {
        let (pos, rot) = self.worst();
        let first = self.actions.iter().find(|a| !a.ok).map_or("–".to_string(), |a| {
            format!("step {} {} {}", a.step, a.kind, a.objects.join(","))
        });
        let verdict = if self.ok {
            "within tolerance"
        } else {
            "OUT OF TOLERANCE"
        };
        format!("{verdict} | {pos:.3}, {rot:.3} | {first}")
    }

    /// The worst box: largest final distance from its target (mm) and largest rotation (°).
    pub fn worst(&self) -> (f64, f64) {
        self.boxes.iter().fold((0.0, 0.0), |(p, r), b| {
            (
                f64::max(p, b.position_error_mm.hypot(b.height_error_mm)),
                f64::max(r, b.rotation_deg),
            )
        })
    }
}

fn list(v: &[f64], digits: usize) -> String {
    v.iter().map(|x| format!("{x:.digits$}")).collect::<Vec<_>>().join(", ")
}

impl fmt::Display for SimReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (pos, rot) = self.worst();
        writeln!(
            f,
            "simulation: {} ({} steps, {:.1} s simulated in {:.2} s); tolerances {:.2}° and {:.2} mm",
            if self.ok {
                "every box within tolerance"
            } else {
                "OUT OF TOLERANCE"
            },
            self.steps,
            self.simulated_s,
            self.wall_s,
            self.tolerances.max_rotation.to_degrees(),
            self.tolerances.max_drift * 1e3
        )?;
        writeln!(f, "worst box: {pos:.3} mm from its target, turned {rot:.3}°")?;
        for a in &self.actions {
            writeln!(
                f,
                "  step {:>2} {:<5} {:<20} turned [{}]°, drift [{}] mm, others moved {:.3} mm{}",
                a.step,
                a.kind,
                a.objects.join(","),
                list(&a.rotation_deg, 3),
                list(&a.drift_mm, 3),
                a.disturbed_mm,
                if a.ok { "" } else { "  ← out of tolerance" }
            )?;
        }
        for b in &self.boxes {
            if b.placed {
                writeln!(
                    f,
                    "  box {:<10} {:.3} mm from target (x {:+.3}, y {:+.3}), height {:+.3} mm, yaw {:+.3}°, rotation {:.3}°{}",
                    b.object,
                    b.position_error_mm,
                    b.offset_mm[0],
                    b.offset_mm[1],
                    b.height_error_mm,
                    b.yaw_error_deg,
                    b.rotation_deg,
                    if b.ok { "" } else { "  ← out of tolerance" }
                )?;
            } else {
                writeln!(f, "  box {:<10} never placed  ← out of tolerance", b.object)?;
            }
        }
        Ok(())
    }
}

//! Push mechanics: is pushing a line of boxes quasi-statically stable, and by how much?
//!
//! A line of `k` boxes (front to back) is pushed along `u` by the back of the closed fingers.
//! The push *sticks* (no box slides against another or against the finger, none rotates or
//! tips) iff there are contact forces that keep every moving box in equilibrium with its floor
//! friction `μ_floor m g` acting against `u` at its centre of friction. Each contact
//! (finger–box, box–box) is a segment in 2-D and a patch in 3-D; its force lies in the friction
//! cone (linear in 2-D, second-order in 3-D) at the segment's end points (patch corners).
//!
//! * [`model`] — the push model ([`PushModel`]): bodies, contacts, phases; built from the
//!   planner's [`LineGeometry`], from an instance ([`line_model`]) or from a scenario file.
//! * [`convex`] — the production check: equilibrium as a convex program solved with clarabel
//!   (an LP in 2-D, an SOCP in 3-D), maximising the stability **margin**; solver structure is
//!   reused between calls and 2-D results are cached by geometry.
//! * [`robust`] — the same check over intervals of friction and a region of centres of friction.
//! * [`scenario`] — the `push-check` scenario format, [`load_scenario`] and [`check_scenario`].
//! * [`side`] — the faces beside the line: neighbours a pushed box would drag, slots that
//!   wedge it.
//! * [`analytic`] — the paper's closed-form condition and the closed forms of
//!   `docs/push_stability.md`; an independent test oracle only.
//!
//! **Margin** (metres, positive = stable, larger = safer): the largest `t` such that every
//! contact's line of action (centre of pressure) lies at least `t` inside its contact segment,
//! and in 3-D every floor centre of pressure at least `t` inside its footprint, with every
//! friction cone shrunk by the fixed fraction [`CONE_SHRINK`]. Shrinks are measured at each
//! contact's reference load (the load it carries in the statically determinate 2-D line, `m g`
//! for a floor), which makes the 2-D margin exactly the paper's margin wherever the paper's
//! condition applies. A push is stable iff its margin exceeds [`MARGIN_TOL`].

pub mod analytic;
pub mod convex;
pub mod model;
pub mod robust;
pub mod scenario;
pub mod side;
pub mod travel;

pub use convex::{CheckOptions, ContactForce, Dim, FloorForce, PhaseResult, PhaseStatus};
pub use model::{Body, Contact, ContactKind, PushModel};
pub use scenario::{check_scenario, load_scenario, parse_scenario, Failure, FailureKind, Mode, PushReport, Scenario};

use crate::geometry::PushDir;
use crate::instance::Instance;
use crate::placement::Placement;
use serde::Serialize;
use travel::TravelCheck;

/// Fraction by which every friction coefficient is shrunk ("strictly inside the cone"):
/// contacts use `μ (1 − CONE_SHRINK)`. Floor friction is a load, not a cone, and is not shrunk.
pub const CONE_SHRINK: f64 = 0.05;

/// A push is stable iff its margin exceeds this (m); 1 µm, the geometric tolerance.
pub const MARGIN_TOL: f64 = crate::geometry::EPS;

/// Default largest rotation (rad) a box may make over a phase of known, finite travel whose
/// line of action leaves its contact: the instance default
/// [`crate::instance::DEFAULT_MAX_PUSH_ROTATION`] (1°), defined there because instances sit below
/// the push model.
pub const MAX_ROTATION: f64 = crate::instance::DEFAULT_MAX_PUSH_ROTATION;

/// Default largest lateral drift (m) of a box's centre over such a phase:
/// [`crate::instance::DEFAULT_MAX_PUSH_DRIFT`] (1 mm).
pub const MAX_DRIFT: f64 = crate::instance::DEFAULT_MAX_PUSH_DRIFT;

/// Lateral intervals and friction weights of a line, front to back (the planner's 2-D view:
/// boxes axis-aligned, pushed perpendicular to their faces).
#[derive(Debug, Clone, PartialEq)]
pub struct LineGeometry {
    /// Lateral interval `[lo, hi]` of each box's footprint.
    pub lateral: Vec<[f64; 2]>,
    /// Friction weight `μ_floor · m` of each box.
    pub weight: Vec<f64>,
    /// Lateral interval of the pusher face.
    pub pusher: [f64; 2],
}

/// Stability margin (m) of a line over the phases that occur, every phase judged as if it
/// lasted forever (the rule for gaps known only as flags), from the clarabel 2-D check
/// ([`convex::line_margin_2d`], cached by geometry). `gaps[m]` says whether box `m + 1` starts
/// separated from box `m` (so boxes `m + 1..` move alone first). `−∞` when no contact forces
/// exist at all (cannot happen for a [`LineGeometry`], whose contact normals are along `u`).
/// The planner and the verifier know the gaps and use [`geometry_verdict`].
pub fn geometry_margin(line: &LineGeometry, gaps: &[bool]) -> f64 {
    convex::line_margin_2d(line, gaps)
}

/// What judging a planner line's phases by their travel needs beyond its [`LineGeometry`]
/// (`docs/push_stability.md` §5.4).
#[derive(Debug, Clone, PartialEq)]
pub struct LineTravel {
    /// `gaps[m]`: how far box `m + 1` starts behind box `m` (m; 0 = touching). A gap above
    /// [`crate::geometry::EPS`] makes boxes `m + 1..` a phase of their own that lasts exactly
    /// this distance.
    pub gaps: Vec<f64>,
    /// Extent of each box along the push (m), front to back: the finger's lever arm about the
    /// back box's centre and the box's friction radius depend on it.
    pub depth: Vec<f64>,
    /// Finger–box friction at the back box (sticking or sliding at the pivot).
    pub mu_finger: f64,
    /// Largest rotation (rad) of a box over a phase judged by its travel.
    pub max_rotation: f64,
    /// Largest lateral drift (m) of its centre over such a phase.
    pub max_drift: f64,
    /// The margin (m) a push needs. A phase that falls short of it (its line of action nearer
    /// the finger's edge than this, or beyond it) is judged by its travel when the rule applies.
    pub min_margin: f64,
}

/// The planner's and the verifier's verdict on a push: accepted iff `margin > min_margin`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LineVerdict {
    /// Smallest margin (m) of the phases not passed by their travel (all of them when the back
    /// box's phase fails its travel); `−∞` when some phase has no equilibrium at all.
    pub margin: f64,
    /// The back box's phase alone, when it is judged by its travel: how far the box turns and
    /// drifts while it closes its gap, against the tolerances.
    pub travel: Option<TravelCheck>,
}

impl LineVerdict {
    /// Whether the push is accepted with the required margin `min_margin` (the one the verdict
    /// was computed with). A phase that fails its travel keeps its own margin, which is at most
    /// `min_margin`, so the margin alone decides.
    pub fn accepted(&self, min_margin: f64) -> bool {
        self.margin > min_margin
    }
}

/// The verdict on a line of known travel ([`convex::line_verdict_2d`], cached by every input):
/// a phase in which the back box closes a finite gap alone, short of `min_margin` because its
/// line of action nears or leaves the finger, is judged by how far the box turns and drifts over
/// the gap; every other phase by its margin. Equal to `push-check` on the same line.
pub fn geometry_verdict(line: &LineGeometry, travel: &LineTravel) -> LineVerdict {
    convex::line_verdict_2d(line, travel)
}

/// Build the line geometry of objects (front to back) at their targets, pushed along `dir`
/// by a pusher centred at lateral coordinate `pusher_at`.
pub fn line_geometry(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    pusher_at: f64,
) -> LineGeometry {
    let lat = dir.axis().other();
    let half = inst.gripper.finger_width / 2.0;
    LineGeometry {
        lateral: objects
            .iter()
            .map(|&i| [placement.targets[i].rect.lo(lat), placement.targets[i].rect.hi(lat)])
            .collect(),
        weight: objects
            .iter()
            .map(|&i| inst.objects[i].mu_floor * inst.objects[i].mass)
            .collect(),
        pusher: [pusher_at - half, pusher_at + half],
    }
}

/// The travel data of pushing `objects` (front to back) along `dir` with the given gaps (m;
/// `gaps[m]` between objects `m` and `m + 1`, from their release offsets), with the instance's
/// tolerances (`planner.min_push_margin`, `max_push_rotation_deg`, `max_push_drift`).
pub fn line_travel(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    gaps: &[f64],
) -> LineTravel {
    let axis = dir.axis();
    let back = *objects.last().expect("a line has at least one object");
    LineTravel {
        gaps: gaps.to_vec(),
        depth: objects
            .iter()
            .map(|&i| placement.targets[i].rect.extent(axis))
            .collect(),
        mu_finger: inst.objects[back].mu_finger,
        max_rotation: inst.settings.max_push_rotation,
        max_drift: inst.settings.max_push_drift,
        min_margin: inst.settings.min_push_margin,
    }
}

/// The planner's and the verifier's production check (2-D, clarabel) of pushing `objects`
/// (front to back) along `dir` by the finger centred at `pusher_at`, with the gaps (m) the
/// releases left between consecutive objects: [`geometry_verdict`] with the instance's
/// tolerances.
pub fn line_verdict(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    pusher_at: f64,
    gaps: &[f64],
) -> LineVerdict {
    geometry_verdict(
        &line_geometry(inst, placement, objects, dir, pusher_at),
        &line_travel(inst, placement, objects, dir, gaps),
    )
}

/// Stability margin (m) of pushing `objects` (front to back) along `dir`, every phase judged as
/// if it lasted forever ([`geometry_margin`]); positive = stable. The planner and the verifier
/// use [`line_verdict`], which knows how long each phase lasts.
pub fn line_margin(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    pusher_at: f64,
    gaps: &[bool],
) -> f64 {
    geometry_margin(&line_geometry(inst, placement, objects, dir, pusher_at), gaps)
}

/// Stability margin (m) of the same push in any [`Mode`] (2-D, 3-D with toppling, robust), from
/// the full model [`line_model`] (heights, masses, per-object friction, the fingertip at the
/// gripper's push height). Robust modes use `±robust_fraction` relative intervals around every
/// friction coefficient and a centre-of-friction region of `±robust_fraction` of each half extent.
#[allow(clippy::too_many_arguments)]
pub fn line_margin_mode(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    pusher_at: f64,
    gaps: &[bool],
    mode: Mode,
    robust_fraction: f64,
) -> f64 {
    let model = line_model(inst, placement, objects, dir, pusher_at, gaps);
    let opts = CheckOptions::default();
    let margin = match mode {
        Mode::D2 => convex::check(&model, Dim::D2, &opts).margin,
        Mode::D3 => convex::check(&model, Dim::D3, &opts).margin,
        Mode::Robust | Mode::Robust3d => {
            let dim = if mode == Mode::Robust { Dim::D2 } else { Dim::D3 };
            let set = robust::UncertaintySet::relative(&model, robust_fraction);
            robust::check(&model, &set, dim, &opts).result.margin
        }
    };
    margin.unwrap_or(f64::NEG_INFINITY)
}

/// The full push model of `objects` (front to back) at their targets, pushed along `dir` by the
/// finger centred at lateral coordinate `pusher_at`, fingertip at the gripper's push height.
/// Box–box contacts use the smaller of the two objects' `mu_obj`; the finger contact the back
/// object's `mu_finger`.
pub fn line_model(
    inst: &Instance,
    placement: &Placement,
    objects: &[usize],
    dir: PushDir,
    pusher_at: f64,
    gaps: &[bool],
) -> PushModel {
    let axis = dir.axis();
    let lat = axis.other();
    let u = dir.unit();
    let mut lat_unit = [0.0; 2];
    lat_unit[lat.index()] = 1.0;
    let bodies: Vec<Body> = objects
        .iter()
        .map(|&i| {
            let t = &placement.targets[i];
            let o = &inst.objects[i];
            Body::aligned(
                &o.id,
                t.rect.center(),
                [t.rect.width() / 2.0, t.rect.depth() / 2.0],
                t.height,
                o.mass,
                o.mu_floor,
            )
        })
        .collect();
    let mut contacts = Vec::with_capacity(objects.len());
    for (m, &i) in objects.iter().enumerate() {
        let r = placement.targets[i].rect;
        // The face of box m that the push presses on: its back face (against u).
        let face = if u[axis.index()] < 0.0 { r.hi(axis) } else { r.lo(axis) };
        let (lo, hi, z, mu, kind) = if m + 1 < objects.len() {
            let b = placement.targets[objects[m + 1]].rect;
            let mu = inst.objects[i].mu_obj.min(inst.objects[objects[m + 1]].mu_obj);
            let h = placement.targets[i]
                .height
                .min(placement.targets[objects[m + 1]].height);
            (
                r.lo(lat).max(b.lo(lat)),
                r.hi(lat).min(b.hi(lat)),
                [0.0, h],
                mu,
                ContactKind::Object,
            )
        } else {
            let half = inst.gripper.finger_width / 2.0;
            let h = placement.targets[i].height;
            let z0 = inst.gripper.push_height.min(h);
            (
                r.lo(lat).max(pusher_at - half),
                r.hi(lat).min(pusher_at + half),
                [z0, h],
                inst.objects[i].mu_finger,
                ContactKind::Pusher,
            )
        };
        let mut p0 = [0.0; 2];
        p0[axis.index()] = face;
        p0[lat.index()] = lo;
        contacts.push(Contact {
            front: m,
            kind,
            p0,
            dir: lat_unit,
            len: hi - lo,
            normal: u,
            z,
            mu,
        });
    }
    PushModel::new(u, bodies, contacts, gaps)
}

/// Pusher lateral position that centres it on the friction centroid of the whole line.
pub fn centred_pusher(inst: &Instance, placement: &Placement, objects: &[usize], dir: PushDir) -> f64 {
    let lat = dir.axis().other();
    let (mut w, mut m) = (0.0, 0.0);
    for &i in objects {
        let r = placement.targets[i].rect;
        let wi = inst.objects[i].mu_floor * inst.objects[i].mass;
        w += wi;
        m += wi * (r.lo(lat) + r.hi(lat)) / 2.0;
    }
    if w > 0.0 {
        m / w
    } else {
        let r = placement.targets[objects[0]].rect;
        (r.lo(lat) + r.hi(lat)) / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn single(pusher_at: f64) -> LineGeometry {
        LineGeometry {
            lateral: vec![[0.0, 0.06]],
            weight: vec![1.0],
            pusher: [pusher_at - 0.01, pusher_at + 0.01],
        }
    }

    #[test]
    fn clarabel_matches_the_paper_on_the_unit_cases() {
        for at in [0.03, 0.035, 0.04, 0.045, 0.0, 0.07] {
            let (c, a) = (
                geometry_margin(&single(at), &[]),
                analytic::geometry_margin(&single(at), &[]),
            );
            assert!((c - a).abs() < 1e-8, "pusher at {at}: clarabel {c} vs paper {a}");
        }
        let line = LineGeometry {
            lateral: vec![[0.0, 0.04], [0.0, 0.10]],
            weight: vec![1.0, 1.0],
            pusher: [0.03, 0.05],
        };
        for gaps in [[false], [true]] {
            let (c, a) = (geometry_margin(&line, &gaps), analytic::geometry_margin(&line, &gaps));
            assert!((c - a).abs() < 1e-8, "gaps {gaps:?}: clarabel {c} vs paper {a}");
        }
    }
}

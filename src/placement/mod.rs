//! Stage 1: where each object goes in the container, and in which orientation.
//!
//! A [`Placement`] assigns every object an [`Orientation`] and a footprint [`Rect`] in C. The
//! objective is lexicographic: minimum [`Placement::occupied_area`], then maximum
//! [`Placement::contact_length`]. Solvers: [`bl`] (the paper's extended Bottom-Left).

pub mod area;
pub mod bl;
pub mod milp;
pub mod opp;
mod progress;

use crate::geometry::{Axis2, Orientation, Rect, EPS};
use crate::instance::Instance;
use serde::{Deserialize, Serialize};

/// One object's target in the container.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Target {
    /// Orientation in C.
    pub orientation: Orientation,
    /// Footprint in C.
    pub rect: Rect,
    /// Height above the floor.
    pub height: f64,
}

/// Targets of all objects, indexed like [`Instance::objects`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Placement {
    /// One target per object.
    pub targets: Vec<Target>,
}

/// Whether a placement solver proved its result optimal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlacementStatus {
    /// Proven optimal: the lower bound meets the objective.
    Optimal,
    /// Feasible, optimality not proven (heuristic, or stopped early).
    Feasible,
}

/// A placement with the solver's account of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacementResult {
    /// The placement.
    pub placement: Placement,
    /// Optimal or merely feasible.
    pub status: PlacementStatus,
    /// Proven lower bound on the occupied area (m²); the sum of footprint areas for heuristics.
    pub lower_bound: f64,
    /// Solver name (`bl`, `milp`).
    pub solver: String,
    /// Wall-clock seconds.
    pub time_s: f64,
    /// Work done: orders tried (BL) or branch-and-bound nodes (MILP).
    pub nodes: u64,
    /// MILPs solved (0 for heuristics).
    #[serde(default)]
    pub subproblems: u64,
}

impl PlacementResult {
    /// No placement at all, from `solver` after `time_s` seconds: what the exact solver starts
    /// from when it has no warm start (feasibility never depends on one).
    pub fn empty(solver: &str, time_s: f64) -> Self {
        PlacementResult {
            placement: Placement { targets: Vec::new() },
            status: PlacementStatus::Feasible,
            lower_bound: 0.0,
            solver: solver.into(),
            time_s,
            nodes: 0,
            subproblems: 0,
        }
    }

    /// Relative gap `(area − bound) / area`.
    pub fn gap(&self) -> f64 {
        let a = self.placement.occupied_area();
        if a <= 0.0 {
            0.0
        } else {
            ((a - self.lower_bound) / a).max(0.0)
        }
    }
}

impl Placement {
    /// Area of the rectangle spanned by C's origin and the largest x and y extents.
    pub fn occupied_area(&self) -> f64 {
        let (mx, my) = self.extent();
        mx * my
    }

    /// Largest x and y extents of all footprints.
    pub fn extent(&self) -> (f64, f64) {
        self.targets
            .iter()
            .fold((0.0f64, 0.0f64), |(mx, my), t| (mx.max(t.rect.x1), my.max(t.rect.y1)))
    }

    /// Sum of shared boundary lengths object–object and object–wall.
    pub fn contact_length(&self, inst: &Instance) -> f64 {
        let (w, d) = (inst.container.width, inst.container.depth);
        let mut len = 0.0;
        for (i, a) in self.targets.iter().enumerate() {
            len += a.rect.wall_contact_length(w, d);
            for b in &self.targets[i + 1..] {
                len += a.rect.contact_length(&b.rect);
            }
        }
        len
    }

    /// Every violated placement condition, as text (empty when valid). Conditions: one target
    /// per object, allowed orientation with matching dims, inside the floor, heights fit,
    /// pairwise non-overlapping, BL-stable.
    pub fn violations(&self, inst: &Instance) -> Vec<String> {
        let mut out = Vec::new();
        if self.targets.len() != inst.n() {
            out.push(format!(
                "placement has {} targets for {} objects",
                self.targets.len(),
                inst.n()
            ));
            return out;
        }
        let floor = inst.container.floor();
        for (i, t) in self.targets.iter().enumerate() {
            let o = &inst.objects[i];
            if !o
                .orientations
                .iter()
                .any(|q| q.dims(o.size) == t.orientation.dims(o.size))
            {
                out.push(format!(
                    "{}: orientation {} is not allowed",
                    o.id,
                    t.orientation.label()
                ));
            }
            let (fp, h) = t.orientation.dims(o.size);
            if (t.rect.width() - fp[0]).abs() > EPS
                || (t.rect.depth() - fp[1]).abs() > EPS
                || (t.height - h).abs() > EPS
            {
                out.push(format!(
                    "{}: footprint/height do not match orientation {}",
                    o.id,
                    t.orientation.label()
                ));
            }
            if !t.rect.inside(&floor) {
                out.push(format!("{}: footprint {:?} leaves the container floor", o.id, t.rect));
            }
            if t.height > inst.container.wall_height + EPS {
                out.push(format!("{}: height {:.4} exceeds the wall height", o.id, t.height));
            }
            for (j, u) in self.targets.iter().enumerate().skip(i + 1) {
                if t.rect.overlaps(&u.rect) {
                    out.push(format!("{} overlaps {}", o.id, inst.objects[j].id));
                }
            }
            for axis in [Axis2::X, Axis2::Y] {
                if !supported_on(&self.targets, i, axis) {
                    out.push(format!(
                        "{}: not BL-stable (nothing on its -{} side)",
                        o.id,
                        if axis == Axis2::X { "x" } else { "y" }
                    ));
                }
            }
        }
        out
    }
}

/// Named invariant: target `i` touches the wall or another target on its −`axis` side with a
/// contact of positive length.
pub fn supported_on(targets: &[Target], i: usize, axis: Axis2) -> bool {
    let r = &targets[i].rect;
    if r.lo(axis).abs() <= EPS {
        return true;
    }
    targets
        .iter()
        .enumerate()
        .any(|(j, t)| j != i && (t.rect.hi(axis) - r.lo(axis)).abs() <= EPS && t.rect.overlap_on(r, axis.other()) > EPS)
}

/// Named invariant: every target is BL-stable (supported on its −x and −y sides).
pub fn is_bl_stable(targets: &[Target]) -> bool {
    (0..targets.len()).all(|i| supported_on(targets, i, Axis2::X) && supported_on(targets, i, Axis2::Y))
}

/// Sum of the smallest footprint area of every object: a trivial lower bound on occupied area.
pub fn area_lower_bound(inst: &Instance) -> f64 {
    inst.objects
        .iter()
        .map(|o| {
            o.orientations
                .iter()
                .map(|q| q.dims(o.size).0[0] * q.dims(o.size).0[1])
                .fold(f64::INFINITY, f64::min)
        })
        .sum()
}

//! The push model: a line of boxes (front to back) on the floor, the pusher, the contact
//! segments (2-D) / patches (3-D) between them, masses, friction, and the phases of the push.
//!
//! Conventions: the plane is the floor (x, y), z is up. `u` is the unit push direction. Body
//! `m` is pushed from behind through contact `m`, whose *back* side is body `m + 1`, or the
//! pusher for the last body. A contact is a segment `p0 + s·dir`, `s ∈ [0, len]`, with unit
//! normal `normal` (the direction of the force on the front body, into it) and vertical extent
//! `z = [z0, z1]`. Phase `s` moves bodies `s..k` (boxes in front of `s` still wait behind
//! their gaps); phases occur from the back: [`PushModel::phase_starts`] is in that order.

use serde::Serialize;

/// A point or vector in the floor plane.
pub type V2 = [f64; 2];

/// Cross product (z component) of two plane vectors.
pub fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Dot product of two plane vectors.
pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// One box of the line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Body {
    /// Name used in reports.
    pub name: String,
    /// Footprint centroid in the plane (m).
    pub centre: V2,
    /// Unit body axes in the plane (the footprint's edge directions).
    pub axes: [V2; 2],
    /// Half extents of the footprint along `axes` (m).
    pub half: V2,
    /// Height (m).
    pub height: f64,
    /// Mass (kg).
    pub mass: f64,
    /// Box–floor friction coefficient.
    pub mu_floor: f64,
    /// Centre of friction in the plane (the centroid for uniform pressure).
    pub cof: V2,
}

impl Body {
    /// An axis-aligned box with its centre of friction at the centroid.
    pub fn aligned(name: &str, centre: V2, half: V2, height: f64, mass: f64, mu_floor: f64) -> Body {
        Body::with_yaw(name, centre, 0.0, half, height, mass, mu_floor)
    }

    /// A box turned by `yaw` (rad) about the vertical.
    pub fn with_yaw(name: &str, centre: V2, yaw: f64, half: V2, height: f64, mass: f64, mu_floor: f64) -> Body {
        let (s, c) = yaw.sin_cos();
        Body {
            name: name.to_string(),
            centre,
            axes: [[c, s], [-s, c]],
            half,
            height,
            mass,
            mu_floor,
            cof: centre,
        }
    }

    /// Footprint corners, counter-clockwise.
    pub fn corners(&self) -> [V2; 4] {
        let [a, b] = self.axes;
        let [ha, hb] = self.half;
        let p = |sa: f64, sb: f64| {
            [
                self.centre[0] + sa * ha * a[0] + sb * hb * b[0],
                self.centre[1] + sa * ha * a[1] + sb * hb * b[1],
            ]
        };
        [p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)]
    }

    /// Floor friction load `μ_floor m g` (N) under uniform pressure.
    pub fn load(&self, g: f64) -> f64 {
        self.mu_floor * self.mass * g
    }
}

/// What pushes a body from behind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactKind {
    /// The back of the closed fingers.
    Pusher,
    /// The next box of the line.
    Object,
}

/// The contact through which body `front` is pushed from behind.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Contact {
    /// Index of the body in front (the one this contact pushes).
    pub front: usize,
    /// Pusher or box behind (`front + 1`).
    pub kind: ContactKind,
    /// First end of the contact segment (plane, m).
    pub p0: V2,
    /// Unit direction along the segment.
    pub dir: V2,
    /// Segment length (m); `0` for a point contact. The planner's path may pass a negative
    /// length for faces that do not overlap (the check then reports a negative margin).
    pub len: f64,
    /// Unit normal, the direction of the force on the front body.
    pub normal: V2,
    /// Vertical extent `[z0, z1]` of the patch above the floor (m; 3-D only).
    pub z: [f64; 2],
    /// Friction coefficient of the contact (before the cone shrink).
    pub mu: f64,
}

impl Contact {
    /// Second end of the segment.
    pub fn p1(&self) -> V2 {
        [self.p0[0] + self.len * self.dir[0], self.p0[1] + self.len * self.dir[1]]
    }
}

/// A line of bodies, its contacts and its phases.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PushModel {
    /// Unit push direction in the plane.
    pub u: V2,
    /// Gravitational acceleration (m/s²).
    pub gravity: f64,
    /// Bodies, front (nearest the destination) to back (touched by the pusher).
    pub bodies: Vec<Body>,
    /// `contacts[m]` pushes `bodies[m]` from behind; the last one is the pusher's.
    pub contacts: Vec<Contact>,
    /// Front body of each moving group, in the order the phases occur (back group first).
    pub phase_starts: Vec<usize>,
    /// How far each phase moves its group (m), parallel to `phase_starts`: the gap it closes,
    /// `∞` for the last phase (the whole line, to the end of the push) and whenever the gap is
    /// not known (the planner's lines). Finite travel lets a phase be judged by how far its box
    /// turns and drifts over it (`docs/push_stability.md` §5.4).
    pub phase_travel: Vec<f64>,
}

impl PushModel {
    /// A model with phases from `gaps` (`gaps[m]`: box `m + 1` starts separated from box `m`),
    /// standard gravity.
    pub fn new(u: V2, bodies: Vec<Body>, contacts: Vec<Contact>, gaps: &[bool]) -> PushModel {
        let mut phase_starts = super::analytic::phase_starts(gaps);
        phase_starts.retain(|&s| s < bodies.len());
        phase_starts.reverse();
        let phase_travel = vec![f64::INFINITY; phase_starts.len()];
        PushModel {
            u,
            gravity: crate::instance::GRAVITY,
            bodies,
            contacts,
            phase_starts,
            phase_travel,
        }
    }

    /// Number of bodies.
    pub fn k(&self) -> usize {
        self.bodies.len()
    }

    /// Report name of contact `m`, e.g. `pusher → b2` or `b2 → b1`.
    pub fn contact_name(&self, m: usize) -> String {
        let c = &self.contacts[m];
        let back = match c.kind {
            ContactKind::Pusher => "pusher".to_string(),
            ContactKind::Object => self.bodies[m + 1].name.clone(),
        };
        format!("{back} → {}", self.bodies[c.front].name)
    }

    /// A unit vector to the left of the push direction (`ẑ × u`).
    pub fn left(&self) -> V2 {
        [-self.u[1], self.u[0]]
    }
}

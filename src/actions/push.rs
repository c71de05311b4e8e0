//! Push mechanics, the paper's analytic condition (Section III-C.2).
//!
//! Quasi-static pushing of a line of boxes in pure translation along `u`, uniform pressure, so
//! each box's support friction `μ_i m_i g` acts at its footprint centroid against `u`. The chain
//! is statically determinate: the force a contact transmits to the boxes in front of it equals
//! their total friction and is normal to the contact (along `u`), so it lies strictly inside
//! every friction cone with μ > 0. Moment balance puts its line of action through the
//! friction-weighted lateral centroid of the boxes it drives. The push sticks (no slip, no
//! rotation) iff that centroid lies strictly inside every contact segment. The *margin* is the
//! smallest distance from such a centroid to an end of its segment, over all contacts and all
//! phases (a gap between released boxes makes the back ones move alone first).

use crate::geometry::PushDir;
use crate::instance::Instance;
use crate::placement::Placement;

/// One contact of a pushed line: the lateral interval where force can pass, and the lateral
/// point its line of action must go through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactCheck {
    /// Lower end of the contact segment (lateral coordinate in C).
    pub seg_lo: f64,
    /// Upper end of the contact segment.
    pub seg_hi: f64,
    /// Lateral coordinate of the line of action.
    pub line_of_action: f64,
}

impl ContactCheck {
    /// Signed distance of the line of action from the nearer segment end (negative = outside).
    pub fn margin(&self) -> f64 {
        (self.line_of_action - self.seg_lo).min(self.seg_hi - self.line_of_action)
    }
}

/// Lateral intervals and friction weights of a line, front to back.
#[derive(Debug, Clone, PartialEq)]
pub struct LineGeometry {
    /// Lateral interval `[lo, hi]` of each box's footprint.
    pub lateral: Vec<[f64; 2]>,
    /// Friction weight `μ_floor · m` of each box.
    pub weight: Vec<f64>,
    /// Lateral interval of the pusher face.
    pub pusher: [f64; 2],
}

/// Contacts of one phase in which boxes `first..` of the line move (front index `first`).
pub fn phase_contacts(line: &LineGeometry, first: usize) -> Vec<ContactCheck> {
    let k = line.lateral.len();
    let mut out = Vec::new();
    let mut wsum = 0.0;
    let mut msum = 0.0;
    for m in first..k {
        let c = (line.lateral[m][0] + line.lateral[m][1]) / 2.0;
        wsum += line.weight[m];
        msum += line.weight[m] * c;
        let centroid = if wsum > 0.0 { msum / wsum } else { c };
        let behind = if m + 1 < k { line.lateral[m + 1] } else { line.pusher };
        let seg = [line.lateral[m][0].max(behind[0]), line.lateral[m][1].min(behind[1])];
        out.push(ContactCheck {
            seg_lo: seg[0],
            seg_hi: seg[1],
            line_of_action: centroid,
        });
    }
    out
}

/// Margin of a line over the phases that occur. `gaps[m]` says whether box `m + 1` starts
/// separated from box `m` (so boxes `m + 1..` move alone first).
pub fn geometry_margin(line: &LineGeometry, gaps: &[bool]) -> f64 {
    let mut starts = vec![0usize];
    for (m, g) in gaps.iter().enumerate() {
        if *g {
            starts.push(m + 1);
        }
    }
    starts
        .into_iter()
        .flat_map(|s| phase_contacts(line, s))
        .map(|c| c.margin())
        .fold(f64::INFINITY, f64::min)
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

/// Stability margin (m) of pushing `objects` (front to back) along `dir`; positive = stable.
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
    fn centred_single_push_is_stable() {
        let m = geometry_margin(&single(0.03), &[]);
        assert!((m - 0.01).abs() < 1e-12, "margin = half the finger width, got {m}");
    }

    #[test]
    fn offset_beyond_segment_is_unstable() {
        // Pusher centred at 0.045: its face covers [0.035, 0.055], the centroid 0.03 is outside.
        assert!(geometry_margin(&single(0.045), &[]) < 0.0);
        // Exactly at the edge: zero margin, not stable.
        assert!(geometry_margin(&single(0.04), &[]).abs() < 1e-12);
    }

    #[test]
    fn two_box_line_with_lateral_offset() {
        // Front box [0, 0.06], back box [0.04, 0.10]: contact segment [0.04, 0.06], front centroid 0.03.
        let line = LineGeometry {
            lateral: vec![[0.0, 0.06], [0.04, 0.10]],
            weight: vec![1.0, 1.0],
            pusher: [0.04, 0.06],
        };
        assert!(geometry_margin(&line, &[false]) < 0.0, "the front box would rotate");
        let aligned = LineGeometry {
            lateral: vec![[0.0, 0.06], [0.0, 0.06]],
            weight: vec![1.0, 1.0],
            pusher: [0.02, 0.04],
        };
        assert!((geometry_margin(&aligned, &[true]) - 0.01).abs() < 1e-12);
    }

    #[test]
    fn heavier_back_box_shifts_the_pusher_centroid() {
        // Back box alone first (gap): its own centroid must be inside the pusher face.
        let line = LineGeometry {
            lateral: vec![[0.0, 0.04], [0.0, 0.10]],
            weight: vec![1.0, 1.0],
            pusher: [0.03, 0.05],
        };
        // Full line centroid = (0.02 + 0.05)/2 = 0.035 → inside [0.03, 0.05]; back alone 0.05 → on the edge.
        assert!(geometry_margin(&line, &[false]) > 0.0);
        assert!(geometry_margin(&line, &[true]) <= 0.0);
    }
}

//! The paper's analytic push condition (Section III-C.2) and the closed forms derived in
//! `docs/push_stability.md` — an **independent test oracle**, not a production path.
//!
//! Quasi-static pushing of a line of boxes in pure translation along `u`, every contact normal
//! parallel to `u`, uniform pressure, so each box's support friction `μ_i m_i g` acts at its
//! footprint centroid against `u`. The chain is statically determinate: the force a contact
//! transmits to the boxes in front of it equals their total friction and is normal to the
//! contact (along `u`), so it lies strictly inside every friction cone with μ > 0. Moment
//! balance puts its line of action through the friction-weighted lateral centroid of the boxes
//! it drives. The push sticks (no slip, no rotation) iff that centroid lies strictly inside every
//! contact segment. The *margin* is the smallest distance from such a centroid to an end of its
//! segment, over all contacts and all phases (a gap between released boxes makes the back ones
//! move alone first).

use super::LineGeometry;

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

/// Phase start indices (front box of each moving group) implied by `gaps`: `0`, and `m + 1`
/// for every `gaps[m]`.
pub fn phase_starts(gaps: &[bool]) -> Vec<usize> {
    let mut starts = vec![0usize];
    for (m, g) in gaps.iter().enumerate() {
        if *g {
            starts.push(m + 1);
        }
    }
    starts
}

/// The paper's margin of a line over the phases that occur. `gaps[m]` says whether box `m + 1`
/// starts separated from box `m` (so boxes `m + 1..` move alone first).
pub fn geometry_margin(line: &LineGeometry, gaps: &[bool]) -> f64 {
    phase_starts(gaps)
        .into_iter()
        .flat_map(|s| phase_contacts(line, s))
        .map(|c| c.margin())
        .fold(f64::INFINITY, f64::min)
}

/// Closed form (single box, pusher off-centre): margin of a box whose face is `face` wide along
/// the lateral axis, pushed perpendicular to that face by a flat finger `finger` wide whose
/// centre is `offset` away from the box's centroid line: `min(face/2, finger/2 − |offset|)`.
/// Zero at `|offset| = finger/2`, independent of every friction coefficient.
pub fn single_box_margin(face: f64, finger: f64, offset: f64) -> f64 {
    (face / 2.0).min(finger / 2.0 - offset.abs())
}

/// Closed form (two boxes, lateral offset): two boxes `depth` deep along the contact normal whose
/// centroids are offset by `offset` across it, pushed along the line through both centroids (so
/// that the line of action passes through both). Every contact force is parallel to that line,
/// at angle `atan(offset/depth)` to the contact normals; it stays inside a friction cone iff
/// `μ > offset / depth`. With the check's cone shrink `ε` the threshold is `offset/(depth(1−ε))`.
pub fn two_box_friction_threshold(depth: f64, offset: f64) -> f64 {
    offset.abs() / depth
}

/// Closed form (toppling, 3-D model): highest fingertip height at which a box `depth` deep along
/// the push, on a floor with friction `mu_floor`, pushed by a finger with (effective) friction
/// `mu_finger` whose contact patch reaches from the fingertip up the back face, still does not tip
/// over its front edge: `depth·(1 + μ_finger μ_floor) / (2 μ_floor)` while `μ_finger μ_floor < 1`
/// (`depth / μ_floor` beyond: the finger's friction can then press the box down without bound).
/// Without finger friction this is the familiar `depth / (2 μ_floor)`.
pub fn topple_height(depth: f64, mu_floor: f64, mu_finger: f64) -> f64 {
    let k = (mu_finger * mu_floor).min(1.0);
    depth * (1.0 + k) / (2.0 * mu_floor)
}

/// Toppling margin of that single box (m): the largest distance of the floor's centre of
/// pressure from the front edge over the finger forces the cone allows (the finger's friction
/// pressing the box down as hard as it can), for a fingertip at `height`:
/// `depth·(1 + μ_finger μ_floor)/2 − height·μ_floor`; negative = tips. Only the tipping
/// constraint: the check's margin is the minimum of this and the other margins.
pub fn topple_margin(depth: f64, mu_floor: f64, mu_finger: f64, height: f64) -> f64 {
    let k = (mu_finger * mu_floor).min(1.0);
    depth * (1.0 + k) / 2.0 - height * mu_floor
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
        assert!((single_box_margin(0.06, 0.02, 0.0) - m).abs() < 1e-12);
    }

    #[test]
    fn offset_beyond_segment_is_unstable() {
        assert!(geometry_margin(&single(0.045), &[]) < 0.0);
        assert!(geometry_margin(&single(0.04), &[]).abs() < 1e-12);
        assert!((single_box_margin(0.06, 0.02, 0.015) - geometry_margin(&single(0.045), &[])).abs() < 1e-12);
    }

    #[test]
    fn two_box_line_with_lateral_offset() {
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
        let line = LineGeometry {
            lateral: vec![[0.0, 0.04], [0.0, 0.10]],
            weight: vec![1.0, 1.0],
            pusher: [0.03, 0.05],
        };
        assert!(geometry_margin(&line, &[false]) > 0.0);
        assert!(geometry_margin(&line, &[true]) <= 0.0);
    }

    #[test]
    fn topple_closed_forms_agree() {
        let z = topple_height(0.03, 0.5, 0.3);
        assert!(topple_margin(0.03, 0.5, 0.3, z).abs() < 1e-12);
        assert!(topple_margin(0.03, 0.5, 0.3, z - 1e-3) > 0.0);
        assert!(topple_margin(0.03, 0.5, 0.3, z + 1e-3) < 0.0);
        assert!((topple_height(0.03, 0.5, 0.0) - 0.03).abs() < 1e-15);
    }
}

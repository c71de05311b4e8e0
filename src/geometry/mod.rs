//! Geometry of the container frame C: axes, orientations, rectangles, contacts and 3-D boxes.
//!
//! Everything here is a value type with exact f64 arithmetic and one tolerance, [`EPS`]:
//! two rectangles *overlap* when their interiors intersect by more than `EPS` in both axes and
//! *touch* when a shared boundary has positive length. 3-D intersection questions go through
//! parry3d in [`parry_bridge`], the one place where parry's types meet ours.

mod arm;
pub mod parry_bridge;

pub use arm::Arm;

use serde::{Deserialize, Serialize};

/// Geometric tolerance in metres (1 µm).
pub const EPS: f64 = 1e-6;

/// A horizontal axis of the container frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis2 {
    /// C's x axis (container width).
    X,
    /// C's y axis (container depth).
    Y,
}

impl Axis2 {
    /// The other horizontal axis.
    pub fn other(self) -> Axis2 {
        match self {
            Axis2::X => Axis2::Y,
            Axis2::Y => Axis2::X,
        }
    }
    /// 0 for x, 1 for y.
    pub fn index(self) -> usize {
        match self {
            Axis2::X => 0,
            Axis2::Y => 1,
        }
    }
}

/// A push direction: toward the left wall (−x, row pushing) or the front wall (−y, column pushing).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum PushDir {
    /// Row pushing, along −x of C.
    #[serde(rename = "-x")]
    MinusX,
    /// Column pushing, along −y of C.
    #[serde(rename = "-y")]
    MinusY,
}

impl PushDir {
    /// Both directions, in a fixed order.
    pub const ALL: [PushDir; 2] = [PushDir::MinusX, PushDir::MinusY];
    /// The axis the push moves along.
    pub fn axis(self) -> Axis2 {
        match self {
            PushDir::MinusX => Axis2::X,
            PushDir::MinusY => Axis2::Y,
        }
    }
    /// Unit vector in C.
    pub fn unit(self) -> [f64; 2] {
        match self {
            PushDir::MinusX => [-1.0, 0.0],
            PushDir::MinusY => [0.0, -1.0],
        }
    }
}

/// A body axis of a box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BodyAxis {
    /// Body x (size\[0\]).
    X,
    /// Body y (size\[1\]).
    Y,
    /// Body z (size\[2\]).
    Z,
}

impl BodyAxis {
    /// All three, in order.
    pub const ALL: [BodyAxis; 3] = [BodyAxis::X, BodyAxis::Y, BodyAxis::Z];
    /// Index into a size triple.
    pub fn index(self) -> usize {
        match self {
            BodyAxis::X => 0,
            BodyAxis::Y => 1,
            BodyAxis::Z => 2,
        }
    }
    /// `x`, `y` or `z`.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// One of the six axis-aligned orientations of a box in C: which body axis is vertical, and
/// whether the remaining pair is turned by 90° about the vertical.
///
/// With `up` = a and the other two body axes b < c (in x, y, z order), yaw 0 puts b along C's x
/// and c along C's y; yaw 90 swaps them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Orientation {
    /// Body axis pointing up.
    pub up: BodyAxis,
    /// Turned by 90° about the vertical.
    pub yaw90: bool,
}

impl Orientation {
    /// All six orientations in a fixed order.
    pub fn all() -> [Orientation; 6] {
        let mut out = [Orientation {
            up: BodyAxis::Z,
            yaw90: false,
        }; 6];
        for (i, up) in BodyAxis::ALL.iter().enumerate() {
            out[2 * i] = Orientation { up: *up, yaw90: false };
            out[2 * i + 1] = Orientation { up: *up, yaw90: true };
        }
        out
    }

    /// Footprint extents (along C's x, along C's y) and height for a box of the given size.
    pub fn dims(self, size: [f64; 3]) -> ([f64; 2], f64) {
        let a = self.up.index();
        let (b, c) = match a {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let fp = if self.yaw90 {
            [size[c], size[b]]
        } else {
            [size[b], size[c]]
        };
        (fp, size[a])
    }

    /// Short label such as `z0` or `x90`.
    pub fn label(self) -> String {
        let up = match self.up {
            BodyAxis::X => "x",
            BodyAxis::Y => "y",
            BodyAxis::Z => "z",
        };
        format!("{up}{}", if self.yaw90 { 90 } else { 0 })
    }
}

/// Closed axis-aligned rectangle `[x0, x1] × [y0, y1]` in C.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rect {
    /// Minimum x.
    pub x0: f64,
    /// Minimum y.
    pub y0: f64,
    /// Maximum x.
    pub x1: f64,
    /// Maximum y.
    pub y1: f64,
}

impl Rect {
    /// From the minimum corner and the extents.
    pub fn new(x: f64, y: f64, w: f64, d: f64) -> Rect {
        Rect {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + d,
        }
    }
    /// Extent along x.
    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }
    /// Extent along y.
    pub fn depth(&self) -> f64 {
        self.y1 - self.y0
    }
    /// Area.
    pub fn area(&self) -> f64 {
        self.width() * self.depth()
    }
    /// Euclidean distance from point `p` to the rectangle (0 inside).
    pub fn distance_to(&self, p: [f64; 2]) -> f64 {
        let dx = (self.x0 - p[0]).max(p[0] - self.x1).max(0.0);
        let dy = (self.y0 - p[1]).max(p[1] - self.y1).max(0.0);
        // Not `hypot`: its overflow care costs more than the search's many calls can afford.
        (dx * dx + dy * dy).sqrt()
    }
    /// Centre point.
    pub fn center(&self) -> [f64; 2] {
        [(self.x0 + self.x1) / 2.0, (self.y0 + self.y1) / 2.0]
    }
    /// Minimum along an axis.
    pub fn lo(&self, a: Axis2) -> f64 {
        match a {
            Axis2::X => self.x0,
            Axis2::Y => self.y0,
        }
    }
    /// Maximum along an axis.
    pub fn hi(&self, a: Axis2) -> f64 {
        match a {
            Axis2::X => self.x1,
            Axis2::Y => self.y1,
        }
    }
    /// Extent along an axis.
    pub fn extent(&self, a: Axis2) -> f64 {
        self.hi(a) - self.lo(a)
    }
    /// Translated copy.
    pub fn translated(&self, dx: f64, dy: f64) -> Rect {
        Rect {
            x0: self.x0 + dx,
            y0: self.y0 + dy,
            x1: self.x1 + dx,
            y1: self.y1 + dy,
        }
    }
    /// Copy moved by `dist` along a push direction (negative `dist` moves against it).
    pub fn moved(&self, dir: PushDir, dist: f64) -> Rect {
        let u = dir.unit();
        self.translated(u[0] * dist, u[1] * dist)
    }
    /// Smallest rectangle containing both.
    pub fn union(&self, o: &Rect) -> Rect {
        Rect {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }
    /// Interiors intersect by more than [`EPS`] in both axes.
    pub fn overlaps(&self, o: &Rect) -> bool {
        self.x0 < o.x1 - EPS && o.x0 < self.x1 - EPS && self.y0 < o.y1 - EPS && o.y0 < self.y1 - EPS
    }
    /// Contained in `outer` up to [`EPS`].
    pub fn inside(&self, outer: &Rect) -> bool {
        self.x0 >= outer.x0 - EPS && self.y0 >= outer.y0 - EPS && self.x1 <= outer.x1 + EPS && self.y1 <= outer.y1 + EPS
    }
    /// Overlap of the projections on an axis (negative when disjoint).
    pub fn overlap_on(&self, o: &Rect, a: Axis2) -> f64 {
        self.hi(a).min(o.hi(a)) - self.lo(a).max(o.lo(a))
    }
    /// Length of the shared boundary of two non-overlapping rectangles (0 when apart).
    pub fn contact_length(&self, o: &Rect) -> f64 {
        let mut len = 0.0;
        if (self.x1 - o.x0).abs() <= EPS || (o.x1 - self.x0).abs() <= EPS {
            len += self.overlap_on(o, Axis2::Y).max(0.0);
        }
        if (self.y1 - o.y0).abs() <= EPS || (o.y1 - self.y0).abs() <= EPS {
            len += self.overlap_on(o, Axis2::X).max(0.0);
        }
        len
    }
    /// Length of this rectangle's boundary lying on the walls of a container floor `[0,w]×[0,d]`.
    pub fn wall_contact_length(&self, w: f64, d: f64) -> f64 {
        let mut len = 0.0;
        if self.x0.abs() <= EPS {
            len += self.depth();
        }
        if (self.x1 - w).abs() <= EPS {
            len += self.depth();
        }
        if self.y0.abs() <= EPS {
            len += self.width();
        }
        if (self.y1 - d).abs() <= EPS {
            len += self.width();
        }
        len
    }
}

/// Closed axis-aligned box in C (z up from the container floor).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Box3 {
    /// Minimum corner.
    pub min: [f64; 3],
    /// Maximum corner.
    pub max: [f64; 3],
}

impl Box3 {
    /// A footprint extruded from `z0` to `z1`.
    pub fn extrude(r: &Rect, z0: f64, z1: f64) -> Box3 {
        Box3 {
            min: [r.x0, r.y0, z0],
            max: [r.x1, r.y1, z1],
        }
    }
    /// Interiors intersect by more than [`EPS`].
    pub fn intersects(&self, o: &Box3) -> bool {
        parry_bridge::boxes_intersect(self, o)
    }
}

/// Rectangle footprint of a box of `size` turned by `yaw` about its centre `(cx, cy)`, as its
/// four corners counter-clockwise (used for table poses, which need not be axis aligned).
pub fn oriented_corners(cx: f64, cy: f64, yaw: f64, w: f64, d: f64) -> [[f64; 2]; 4] {
    let (s, c) = yaw.sin_cos();
    let hw = w / 2.0;
    let hd = d / 2.0;
    let local = [[-hw, -hd], [hw, -hd], [hw, hd], [-hw, hd]];
    local.map(|[u, v]| [cx + c * u - s * v, cy + s * u + c * v])
}

/// Whether two convex quadrilaterals (corner lists) overlap by more than [`EPS`] (separating axes).
pub fn convex_overlap(a: &[[f64; 2]; 4], b: &[[f64; 2]; 4]) -> bool {
    for poly in [a, b] {
        for i in 0..4 {
            let p = poly[i];
            let q = poly[(i + 1) % 4];
            let n = [q[1] - p[1], p[0] - q[0]];
            let len = (n[0] * n[0] + n[1] * n[1]).sqrt();
            if len == 0.0 {
                continue;
            }
            let proj = |pts: &[[f64; 2]; 4]| {
                let mut lo = f64::INFINITY;
                let mut hi = f64::NEG_INFINITY;
                for r in pts {
                    let v = (r[0] * n[0] + r[1] * n[1]) / len;
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
                (lo, hi)
            };
            let (alo, ahi) = proj(a);
            let (blo, bhi) = proj(b);
            if ahi <= blo + EPS || bhi <= alo + EPS {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_rects_do_not_overlap_but_have_contact() {
        let a = Rect::new(0.0, 0.0, 0.1, 0.05);
        let b = Rect::new(0.1, 0.02, 0.1, 0.05);
        assert!(!a.overlaps(&b));
        assert!((a.contact_length(&b) - 0.03).abs() < 1e-12);
        let c = Rect::new(0.1 - 2.0 * EPS, 0.0, 0.1, 0.05);
        assert!(c.overlaps(&a), "2 µm of interpenetration is an overlap");
        let d = Rect::new(0.1 - 0.5 * EPS, 0.0, 0.1, 0.05);
        assert!(!d.overlaps(&a), "0.5 µm is within tolerance");
    }

    #[test]
    fn corner_touch_has_zero_contact() {
        let a = Rect::new(0.0, 0.0, 0.1, 0.1);
        let b = Rect::new(0.1, 0.1, 0.1, 0.1);
        assert_eq!(a.contact_length(&b), 0.0);
        assert!(!a.overlaps(&b));
    }

    #[test]
    fn wall_contact() {
        let a = Rect::new(0.0, 0.0, 0.1, 0.05);
        assert!((a.wall_contact_length(0.3, 0.2) - 0.15).abs() < 1e-12);
        let full = Rect::new(0.0, 0.0, 0.3, 0.2);
        assert!((full.wall_contact_length(0.3, 0.2) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn orientation_dims() {
        let s = [0.1, 0.2, 0.3];
        let o = Orientation {
            up: BodyAxis::Z,
            yaw90: false,
        };
        assert_eq!(o.dims(s), ([0.1, 0.2], 0.3));
        let o = Orientation {
            up: BodyAxis::X,
            yaw90: true,
        };
        assert_eq!(o.dims(s), ([0.3, 0.2], 0.1));
        assert_eq!(Orientation::all().len(), 6);
    }

    #[test]
    fn rotated_overlap() {
        let a = oriented_corners(0.0, 0.0, 0.0, 0.1, 0.1);
        let b = oriented_corners(0.1, 0.0, 0.0, 0.1, 0.1);
        assert!(!convex_overlap(&a, &b), "touching squares");
        let c = oriented_corners(0.1, 0.0, std::f64::consts::FRAC_PI_4, 0.1, 0.1);
        assert!(convex_overlap(&a, &c), "a diamond reaches into the square");
        let d = oriented_corners(0.2, 0.0, std::f64::consts::FRAC_PI_4, 0.1, 0.1);
        assert!(!convex_overlap(&a, &d));
    }

    #[test]
    fn boxes_via_parry() {
        let a = Box3 {
            min: [0.0, 0.0, 0.0],
            max: [0.1, 0.1, 0.1],
        };
        let b = Box3 {
            min: [0.1, 0.0, 0.0],
            max: [0.2, 0.1, 0.1],
        };
        assert!(!a.intersects(&b), "face contact is not an intersection");
        let c = Box3 {
            min: [0.05, 0.05, 0.09],
            max: [0.2, 0.2, 0.3],
        };
        assert!(a.intersects(&c));
        let d = Box3 {
            min: [0.05, 0.05, 0.1],
            max: [0.2, 0.2, 0.3],
        };
        assert!(!a.intersects(&d), "resting on top is not an intersection");
    }
}

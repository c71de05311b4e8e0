//! The one place where parry3d (glam types) meets our nalgebra/array maths.
//!
//! parry3d ≥ 0.26 speaks glam; everything else in pushpack speaks nalgebra or plain arrays.
//! Conversions live here and nowhere else.

use super::{Box3, EPS};
use nalgebra::{Isometry3, Vector3};
use parry3d::math::{Pose, Rotation, Vector};
use parry3d::query::details::intersection_test_cuboid_cuboid;
use parry3d::shape::Cuboid;

/// nalgebra vector → parry vector.
pub fn to_parry_vec(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// nalgebra isometry → parry pose.
pub fn to_parry_pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    let rot = Rotation::from_xyzw(q.i, q.j, q.k, q.w);
    Pose::from_parts(to_parry_vec(&iso.translation.vector), rot)
}

/// Cuboid of a box shrunk by [`EPS`] on every side, with its centre pose, so that touching
/// faces never count as an intersection.
fn shrunk_cuboid(b: &Box3) -> Option<(Cuboid, Pose)> {
    let mut half = [0.0; 3];
    let mut centre = [0.0; 3];
    for i in 0..3 {
        half[i] = (b.max[i] - b.min[i]) / 2.0 - EPS;
        centre[i] = (b.max[i] + b.min[i]) / 2.0;
        if half[i] <= 0.0 {
            return None;
        }
    }
    let cub = Cuboid::new(Vector::new(half[0], half[1], half[2]));
    Some((cub, Pose::translation(centre[0], centre[1], centre[2])))
}

/// Whether two axis-aligned boxes intersect by more than [`EPS`] in every axis.
///
/// A broad phase on the shrunk bounds answers "apart" without parry (most queries of the
/// planner); parry's separating-axis test decides the rest.
pub fn boxes_intersect(a: &Box3, b: &Box3) -> bool {
    for i in 0..3 {
        if a.max[i] - EPS <= b.min[i] + EPS || b.max[i] - EPS <= a.min[i] + EPS {
            return false;
        }
    }
    let (Some((ca, pa)), Some((cb, pb))) = (shrunk_cuboid(a), shrunk_cuboid(b)) else {
        return false;
    };
    let pos12 = pa.inv_mul(&pb);
    intersection_test_cuboid_cuboid(&pos12, &ca, &cb)
}

/// A convex solid in its own frame, described with nalgebra values (the robot's collision
/// primitives, obstacles, the carried box). Converted to parry shapes only here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Solid {
    /// Box centred at the origin with these half extents.
    Cuboid {
        /// Half extents along x, y, z.
        half: Vector3<f64>,
    },
    /// Cylinder centred at the origin, axis along z (URDF convention).
    Cylinder {
        /// Radius.
        radius: f64,
        /// Half of the length along z.
        half_length: f64,
    },
    /// Capsule between two points.
    Capsule {
        /// First end of the segment.
        a: Vector3<f64>,
        /// Second end of the segment.
        b: Vector3<f64>,
        /// Radius.
        radius: f64,
    },
    /// Ball centred at the origin.
    Ball {
        /// Radius.
        radius: f64,
    },
}

impl Solid {
    /// The same solid shrunk by `d` on every side (never below a tiny positive size).
    pub fn shrunk(&self, d: f64) -> Solid {
        let tiny = 1e-9;
        match *self {
            Solid::Cuboid { half } => Solid::Cuboid {
                half: half.map(|h| (h - d).max(tiny)),
            },
            Solid::Cylinder { radius, half_length } => Solid::Cylinder {
                radius: (radius - d).max(tiny),
                half_length: (half_length - d).max(tiny),
            },
            Solid::Capsule { a, b, radius } => Solid::Capsule {
                a,
                b,
                radius: (radius - d).max(tiny),
            },
            Solid::Ball { radius } => Solid::Ball {
                radius: (radius - d).max(tiny),
            },
        }
    }

    /// Radius of a ball about the frame origin that contains the solid.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Solid::Cuboid { half } => half.norm(),
            Solid::Cylinder { radius, half_length } => (radius * radius + half_length * half_length).sqrt(),
            Solid::Capsule { a, b, radius } => a.norm().max(b.norm()) + radius,
            Solid::Ball { radius } => radius,
        }
    }
}

/// A parry shape and the pose correction it needs (parry cylinders stand along y, URDF's along z).
fn parry_shape(s: &Solid) -> (Box<dyn parry3d::shape::Shape>, Option<Pose>) {
    use parry3d::shape::{Ball, Capsule, Cylinder};
    match *s {
        Solid::Cuboid { half } => (Box::new(Cuboid::new(to_parry_vec(&half))), None),
        Solid::Cylinder { radius, half_length } => {
            let turn = Pose::from_parts(
                Vector::ZERO,
                Rotation::from_axis_angle(Vector::X, std::f64::consts::FRAC_PI_2),
            );
            (Box::new(Cylinder::new(half_length, radius)), Some(turn))
        }
        Solid::Capsule { a, b, radius } => (Box::new(Capsule::new(to_parry_vec(&a), to_parry_vec(&b), radius)), None),
        Solid::Ball { radius } => (Box::new(Ball::new(radius)), None),
    }
}

fn posed(s: &Solid, iso: &Isometry3<f64>) -> (Box<dyn parry3d::shape::Shape>, Pose) {
    let (shape, fix) = parry_shape(s);
    let p = to_parry_pose(iso);
    (shape, fix.map(|f| p * f).unwrap_or(p))
}

/// Whether two posed solids overlap (touching counts as overlapping; shrink first to allow contact).
pub fn solids_intersect(a: &Solid, pa: &Isometry3<f64>, b: &Solid, pb: &Isometry3<f64>) -> bool {
    let (sa, qa) = posed(a, pa);
    let (sb, qb) = posed(b, pb);
    parry3d::query::intersection_test(&qa, sa.as_ref(), &qb, sb.as_ref()).is_ok_and(|r| r.intersecting)
}

/// Distance between two posed solids (0 when they touch or overlap).
pub fn solids_distance(a: &Solid, pa: &Isometry3<f64>, b: &Solid, pb: &Isometry3<f64>) -> f64 {
    let (sa, qa) = posed(a, pa);
    let (sb, qb) = posed(b, pb);
    parry3d::query::distance(&qa, sa.as_ref(), &qb, sb.as_ref())
        .map(|d| d.distance)
        .unwrap_or(0.0)
}

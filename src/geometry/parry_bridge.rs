//! The one place where parry3d (glam types) meets our nalgebra/array maths.
//!
//! parry3d ≥ 0.26 speaks glam; everything else in pushpack speaks nalgebra or plain arrays.
//! Conversions live here and nowhere else.

use super::{Box3, EPS};
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use parry3d::math::{Pose, Rotation, Vector};
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

/// parry (and rapier) pose → nalgebra isometry.
pub fn from_parry_pose(p: &Pose) -> Isometry3<f64> {
    let (t, q) = (p.translation, p.rotation);
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, t.z),
        UnitQuaternion::from_quaternion(Quaternion::new(q.w, q.x, q.y, q.z)),
    )
}

/// Whether two axis-aligned boxes intersect by more than [`EPS`] in every axis.
///
/// Both are shrunk by [`EPS`] on every side (so touching faces never count) and must keep a
/// positive extent. For axis-aligned boxes the interval test is exact; it used to go on to
/// parry's separating-axis test, which could only agree and cost 6 % of an A* run (the layout
/// checks ask this millions of times). The test module checks the two agree.
pub fn boxes_intersect(a: &Box3, b: &Box3) -> bool {
    (0..3).all(|i| {
        a.max[i] - a.min[i] > 2.0 * EPS
            && b.max[i] - b.min[i] > 2.0 * EPS
            && a.max[i] - EPS > b.min[i] + EPS
            && b.max[i] - EPS > a.min[i] + EPS
    })
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

    /// How far the solid, posed at `pose`, reaches along the unit direction `d` (the support
    /// function: the largest `d · p` over its points).
    pub fn support_extent(&self, pose: &Isometry3<f64>, d: &Vector3<f64>) -> f64 {
        let l = pose.rotation.inverse() * d;
        let c = d.dot(&pose.translation.vector);
        match *self {
            Solid::Cuboid { half } => c + l.abs().dot(&half),
            Solid::Cylinder { radius, half_length } => c + radius * l.xy().norm() + half_length * l.z.abs(),
            Solid::Capsule { a, b, radius } => c + l.dot(&a).max(l.dot(&b)) + radius,
            Solid::Ball { radius } => c + radius,
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

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d::query::details::intersection_test_cuboid_cuboid;
    use proptest::prelude::*;

    /// The former implementation: parry's separating-axis test on the shrunk cuboids.
    fn by_parry(a: &Box3, b: &Box3) -> bool {
        let shrunk = |b: &Box3| -> Option<(Cuboid, Pose)> {
            let h: Vec<f64> = (0..3).map(|i| (b.max[i] - b.min[i]) / 2.0 - EPS).collect();
            if h.iter().any(|&x| x <= 0.0) {
                return None;
            }
            let c: Vec<f64> = (0..3).map(|i| (b.max[i] + b.min[i]) / 2.0).collect();
            Some((
                Cuboid::new(Vector::new(h[0], h[1], h[2])),
                Pose::translation(c[0], c[1], c[2]),
            ))
        };
        match (shrunk(a), shrunk(b)) {
            (Some((ca, pa)), Some((cb, pb))) => intersection_test_cuboid_cuboid(&pa.inv_mul(&pb), &ca, &cb),
            _ => false,
        }
    }

    /// A box on a 1 mm grid, its faces moved by up to ±1.5 [`EPS`], so that touching faces and
    /// overlaps inside the tolerance band come up often.
    fn grid_box() -> impl Strategy<Value = Box3> {
        (
            prop::array::uniform3(0i32..6),
            prop::array::uniform3(0i32..5),
            prop::array::uniform6(-5i32..=5),
        )
            .prop_map(|(lo, ext, j)| {
                // Steps of 0.3 EPS never sum to the 2 EPS threshold itself, where the two
                // implementations may round a tie differently.
                let min = [0, 1, 2].map(|i| f64::from(lo[i]) * 1e-3 + f64::from(j[i]) * 0.3 * EPS);
                let max = [0, 1, 2].map(|i| f64::from(lo[i] + ext[i]) * 1e-3 + f64::from(j[i + 3]) * 0.3 * EPS);
                Box3 { min, max }
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]
        #[test]
        fn interval_test_agrees_with_parry(a in grid_box(), b in grid_box()) {
            prop_assert_eq!(boxes_intersect(&a, &b), by_parry(&a, &b), "{:?} {:?}", a, b);
        }
    }

    #[test]
    fn touching_faces_do_not_intersect() {
        let a = Box3 {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let b = Box3 {
            min: [1.0, 0.0, 0.0],
            max: [2.0, 1.0, 1.0],
        };
        assert!(!boxes_intersect(&a, &b));
        let c = Box3 {
            min: [0.5, 0.5, 0.5],
            max: [2.0, 1.0, 1.0],
        };
        assert!(boxes_intersect(&a, &c));
    }
}

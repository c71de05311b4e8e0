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
pub fn boxes_intersect(a: &Box3, b: &Box3) -> bool {
    let (Some((ca, pa)), Some((cb, pb))) = (shrunk_cuboid(a), shrunk_cuboid(b)) else {
        return false;
    };
    let pos12 = pa.inv_mul(&pb);
    intersection_test_cuboid_cuboid(&pos12, &ca, &cb)
}

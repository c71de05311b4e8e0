//! One push on an open floor, outside any plan: the replay's physics on the cases whose answer
//! is known in closed form (`docs/push_stability.md`), so the simulator can be checked against
//! them (`tests/simulate.rs`).

use nalgebra::{Isometry3, Vector3};

use super::world::World;
use super::SimOptions;
use crate::geometry::Box3;

/// An axis-aligned box resting on the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorBox {
    /// Footprint centre (m).
    pub centre: [f64; 2],
    /// Extents along x, y and the height (m).
    pub size: [f64; 3],
    /// Mass (kg).
    pub mass: f64,
    /// Coulomb coefficients `[floor, object, finger]`.
    pub mu: [f64; 3],
    /// Turn about the vertical (rad) from the axes of C: a release error.
    pub yaw: f64,
}

/// A finger plate moving in a straight line at the options' push speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pusher {
    /// Half extents along x, y and z (m).
    pub half: [f64; 3],
    /// Horizontal position of its centre at the start and at the end (m).
    pub path: [[f64; 2]; 2],
    /// Height of its lowest point above the floor (m).
    pub tip_height: f64,
}

/// What one box did during the push.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Pose at the end (C frame: centre, orientation).
    pub end: Isometry3<f64>,
    /// Largest rotation from the start orientation during the push (rad).
    pub max_rotation: f64,
    /// Largest tilt of the box's vertical axis during the push (rad).
    pub max_tilt: f64,
}

/// Push `boxes` with `pusher` and report each box's motion. Boxes start at rest, exactly on
/// the floor.
pub fn push_line(boxes: &[FloorBox], pusher: &Pusher, opts: &SimOptions) -> Vec<Motion> {
    push_among(boxes, &[], pusher, opts)
}

/// [`push_line`] with fixed `walls` on the floor: a box can be held against one, or slide
/// along it.
pub fn push_among(boxes: &[FloorBox], walls: &[Box3], pusher: &Pusher, opts: &SimOptions) -> Vec<Motion> {
    let mut w = World::new(walls, boxes.iter().map(|b| b.mu).collect(), opts);
    for (i, b) in boxes.iter().enumerate() {
        let half = Vector3::from(b.size) / 2.0;
        let k = w.add_object(i, half, b.mass, Vector3::new(b.centre[0], b.centre[1], half.z));
        if b.yaw != 0.0 {
            w.turn(k, b.yaw);
        }
        w.release(k);
    }
    let z = pusher.tip_height + pusher.half[2];
    let [a, e] = pusher.path;
    let (a, e) = (Vector3::new(a[0], a[1], z), Vector3::new(e[0], e[1], z));
    let finger = w.kinematic_box(Vector3::from(pusher.half), a, None);
    let start: Vec<Isometry3<f64>> = (0..boxes.len()).map(|i| w.object_pose(i).expect("added")).collect();
    let mut rot = vec![0.0f64; boxes.len()];
    let mut tilt = vec![0.0f64; boxes.len()];
    let n = ((e - a).norm() / (opts.push_speed * opts.dt)).ceil().max(1.0) as usize;
    for s in 1..=n {
        w.drive(finger, a + (e - a) * (s as f64 / n as f64));
        w.step();
        for (i, p0) in start.iter().enumerate() {
            let p = w.object_pose(i).expect("added");
            rot[i] = rot[i].max(p.rotation.angle_to(&p0.rotation));
            let up = p.rotation * Vector3::z();
            tilt[i] = tilt[i].max(up.z.clamp(-1.0, 1.0).acos());
        }
    }
    (0..boxes.len())
        .map(|i| Motion {
            end: w.object_pose(i).expect("added"),
            max_rotation: rot[i],
            max_tilt: tilt[i],
        })
        .collect()
}

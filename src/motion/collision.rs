//! The work cell as collision obstacles and the robot as collision primitives at a configuration.
//!
//! Obstacles: the four container walls, the container floor (when it stands above the table),
//! the table top, every object at its current place (table pose, release pose or target), and
//! the idle arm. Robot parts: the primitives of the model's arm links and of links fixed to the
//! wrist (the hand housing), the two finger plates built from the instance's `[gripper]` (or one plate of
//! `finger_thickness` when closed — the spec's pusher), and the carried object. A part that
//! penetrates an obstacle by more than [`CONTACT_TOLERANCE`] collides; touching does not (objects
//! are packed with zero gaps and fingers close on objects). All queries go through
//! [`crate::geometry::parry_bridge`] (parry3d).

use crate::geometry::parry_bridge::{solids_distance, solids_intersect, Solid};
use crate::geometry::Arm;
use crate::geometry::{Box3, Rect};
use crate::instance::Instance;
use crate::robot::{tcp_from_wrist, RobotModel};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Penetration below this (m) counts as touching, not as a collision. Objects are packed with
/// zero gaps, so a held object slides down along its neighbours and fingers open against walls;
/// planned straight lines are followed within `motion::LINE_TOLERANCE` = 0.05 mm, below this.
pub const CONTACT_TOLERANCE: f64 = 1e-4;

/// What an obstacle is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObstacleKind {
    /// Container wall k (0: x = 0, 1: x = width, 2: y = 0, 3: y = depth).
    Wall(usize),
    /// Container floor plate.
    Floor,
    /// Table top.
    Table,
    /// Object i.
    Object(usize),
    /// A part of the other arm.
    OtherArm,
}

/// A posed solid in the world.
#[derive(Debug, Clone)]
pub struct Obstacle {
    /// Name for messages.
    pub name: String,
    /// Kind.
    pub kind: ObstacleKind,
    /// Solid in its own frame.
    pub solid: Solid,
    /// Pose in the world.
    pub pose: Isometry3<f64>,
    radius: f64,
    /// World axis-aligned bounding box (min, max).
    aabb: (Vector3<f64>, Vector3<f64>),
}

impl Obstacle {
    /// A posed solid.
    pub fn new(name: impl Into<String>, kind: ObstacleKind, solid: Solid, pose: Isometry3<f64>) -> Obstacle {
        let radius = solid.bounding_radius();
        let c = pose.translation.vector;
        let ext = match solid {
            Solid::Cuboid { half } => pose.rotation.to_rotation_matrix().matrix().abs() * half,
            _ => Vector3::repeat(radius),
        };
        Obstacle {
            name: name.into(),
            kind,
            radius,
            solid,
            pose,
            aabb: (c - ext, c + ext),
        }
    }

    /// Whether a ball of radius `r` about `c` can touch the obstacle's bounding box.
    fn near(&self, c: &Vector3<f64>, r: f64) -> bool {
        (0..3).all(|k| c[k] + r >= self.aabb.0[k] && c[k] - r <= self.aabb.1[k])
    }
}

/// A box given in C (container frame) as a world obstacle.
pub fn container_box(inst: &Instance, b: &Box3, name: impl Into<String>, kind: ObstacleKind) -> Obstacle {
    let c = &inst.container;
    let centre = [
        (b.min[0] + b.max[0]) / 2.0,
        (b.min[1] + b.max[1]) / 2.0,
        (b.min[2] + b.max[2]) / 2.0,
    ];
    let half = Vector3::new(
        (b.max[0] - b.min[0]) / 2.0,
        (b.max[1] - b.min[1]) / 2.0,
        (b.max[2] - b.min[2]) / 2.0,
    );
    let p = c.to_world(centre);
    let pose = Isometry3::from_parts(
        Translation3::from(p),
        UnitQuaternion::from_euler_angles(0.0, 0.0, c.yaw),
    );
    Obstacle::new(name, kind, Solid::Cuboid { half }, pose)
}

/// The static obstacles: walls, container floor plate (if raised above the table), table top.
pub fn static_obstacles(inst: &Instance) -> Vec<Obstacle> {
    let c = &inst.container;
    let mut out: Vec<Obstacle> = c
        .walls()
        .iter()
        .enumerate()
        .map(|(k, b)| container_box(inst, b, format!("container wall {k}"), ObstacleKind::Wall(k)))
        .collect();
    let t = c.wall_thickness;
    if c.floor_z > inst.robot.table_z + 1e-9 {
        let b = Box3 {
            min: [-t, -t, inst.robot.table_z - c.floor_z],
            max: [c.width + t, c.depth + t, 0.0],
        };
        out.push(container_box(inst, &b, "container floor", ObstacleKind::Floor));
    }
    // The table: 0.8 m deep from x = 0.10 (in front of the base cabinet), 1.8 m wide, 5 cm slab.
    let tz = inst.robot.table_z;
    out.push(Obstacle::new(
        "table",
        ObstacleKind::Table,
        Solid::Cuboid {
            half: Vector3::new(0.40, 0.90, 0.025),
        },
        Isometry3::translation(0.50, 0.0, tz - 0.025),
    ));
    out
}

/// Object `i` with footprint `rect` (C) and height `h`, standing on the container floor.
pub fn object_in_container(inst: &Instance, i: usize, rect: &Rect, h: f64) -> Obstacle {
    container_box(
        inst,
        &Box3::extrude(rect, 0.0, h),
        format!("object {}", inst.objects[i].id),
        ObstacleKind::Object(i),
    )
}

/// Object `i` at its start pose on the table.
pub fn object_on_table(inst: &Instance, i: usize) -> Obstacle {
    let o = &inst.objects[i];
    let (fp, h) = crate::geometry::Orientation {
        up: o.table.up,
        yaw90: false,
    }
    .dims(o.size);
    Obstacle::new(
        format!("object {}", o.id),
        ObstacleKind::Object(i),
        Solid::Cuboid {
            half: Vector3::new(fp[0] / 2.0, fp[1] / 2.0, h / 2.0),
        },
        Isometry3::from_parts(
            Translation3::new(o.table.x, o.table.y, inst.robot.table_z + h / 2.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, o.table.yaw),
        ),
    )
}

/// An object held between the fingers: a box in the TCP frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Held {
    /// Object index.
    pub object: usize,
    /// Extent along the closing axis (TCP y).
    pub closing: f64,
    /// Extent along TCP x.
    pub other: f64,
    /// Height.
    pub height: f64,
}

/// The gripper at some moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hand {
    /// Finger opening (gap between the inner faces, m); 0 = closed into one pusher plate.
    pub opening: f64,
    /// The carried object, if any.
    pub held: Option<Held>,
}

/// Kind of robot part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartKind {
    /// A link primitive of the model.
    Link,
    /// A finger plate.
    Finger,
    /// The carried object.
    Held,
}

/// A robot part posed in the world.
#[derive(Debug, Clone)]
pub struct Part {
    /// Name for messages.
    pub name: String,
    /// Kind.
    pub kind: PartKind,
    /// Solid (already shrunk by [`CONTACT_TOLERANCE`]).
    pub solid: Solid,
    /// World pose.
    pub pose: Isometry3<f64>,
    radius: f64,
}

/// Every part of `arm` at `q` with the hand in state `hand`.
pub fn robot_parts(model: &RobotModel, inst: &Instance, arm: Arm, q: &[f64; 6], hand: &Hand) -> Vec<Part> {
    let frames = model.link_frames(arm, q);
    let mut parts: Vec<Part> = model.shapes[arm.index()]
        .iter()
        .map(|s| {
            let solid = s.solid.shrunk(CONTACT_TOLERANCE);
            Part {
                name: s.name.clone(),
                kind: PartKind::Link,
                radius: solid.bounding_radius(),
                solid,
                pose: frames[s.link] * s.origin,
            }
        })
        .collect();
    // The wrist frame is the last link frame: no second pass down the chain.
    debug_assert_eq!(frames[5], model.wrist_pose(arm, q));
    let tcp = tcp_from_wrist(&frames[5], &inst.robot.tcp_offset);
    let g = &inst.gripper;
    // The plates run from the TCP up to the hand (validation keeps that at least
    // `finger_length`), so nothing can pass between the fingertips and the housing.
    let reach = g
        .finger_length
        .max(Vector3::from(inst.robot.tcp_offset).norm() - model.hand_bottom(arm));
    let mut plate = |name: &str, y: f64| {
        let solid = Solid::Cuboid {
            half: Vector3::new(g.finger_width / 2.0, g.finger_thickness / 2.0, reach / 2.0),
        }
        .shrunk(CONTACT_TOLERANCE);
        parts.push(Part {
            name: format!("{}_{name}", arm.prefix()),
            kind: PartKind::Finger,
            radius: solid.bounding_radius(),
            solid,
            pose: tcp * Isometry3::translation(0.0, y, -reach / 2.0),
        });
    };
    if hand.opening <= 1e-12 {
        plate("closed_fingers", 0.0);
    } else {
        let y = hand.opening / 2.0 + g.finger_thickness / 2.0;
        plate("finger_left", y);
        plate("finger_right", -y);
    }
    if let Some(h) = hand.held {
        let solid = Solid::Cuboid {
            half: Vector3::new(h.other / 2.0, h.closing / 2.0, h.height / 2.0),
        }
        .shrunk(CONTACT_TOLERANCE);
        parts.push(Part {
            name: format!("held object {}", inst.objects[h.object].id),
            kind: PartKind::Held,
            radius: solid.bounding_radius(),
            solid,
            pose: tcp * Isometry3::translation(0.0, 0.0, h.height / 2.0 - g.grasp_depth),
        });
    }
    parts
}

/// The same parts grown by `d` on every side: a joint-space move is checked at samples, and a
/// margin keeps what happens between them (and between the verifier's other samples) clear.
pub fn grown(parts: &[Part], d: f64) -> Vec<Part> {
    parts
        .iter()
        .map(|p| {
            let solid = p.solid.shrunk(-d);
            Part {
                radius: solid.bounding_radius(),
                solid,
                ..p.clone()
            }
        })
        .collect()
}

/// The parts of an idle arm as obstacles.
pub fn arm_as_obstacles(parts: Vec<Part>, arm: Arm) -> Vec<Obstacle> {
    parts
        .into_iter()
        .map(|p| {
            Obstacle::new(
                format!("{} arm: {}", arm.name(), p.name),
                ObstacleKind::OtherArm,
                p.solid,
                p.pose,
            )
        })
        .collect()
}

/// The first (part, obstacle) pair that collides, skipping pairs for which `skip` is true.
pub fn first_collision<'p, 'o>(
    parts: &'p [Part],
    obstacles: &'o [Obstacle],
    skip: impl Fn(&Part, &Obstacle) -> bool,
) -> Option<(&'p Part, &'o Obstacle)> {
    for p in parts {
        let pc = p.pose.translation.vector;
        for o in obstacles {
            if (pc - o.pose.translation.vector).norm() > p.radius + o.radius || !o.near(&pc, p.radius) {
                continue;
            }
            if skip(p, o) {
                continue;
            }
            if solids_intersect(&p.solid, &p.pose, &o.solid, &o.pose) {
                return Some((p, o));
            }
        }
    }
    None
}

/// Smallest distance between any part and any obstacle (for reports; negative down to
/// −[`CONTACT_TOLERANCE`] for accepted contacts), skipping as above.
pub fn clearance(parts: &[Part], obstacles: &[Obstacle], skip: impl Fn(&Part, &Obstacle) -> bool) -> f64 {
    let mut best = f64::INFINITY;
    for p in parts {
        let pc = p.pose.translation.vector;
        for o in obstacles {
            // Bounding spheres give a lower bound: skip pairs that cannot beat the best.
            if (pc - o.pose.translation.vector).norm() - p.radius - o.radius >= best || skip(p, o) {
                continue;
            }
            best = best.min(solids_distance(&p.solid, &p.pose, &o.solid, &o.pose));
        }
    }
    best - CONTACT_TOLERANCE
}

//! The rapier3d scene of a replay: floor, walls, boxes and fingers in the container frame C,
//! with each contact pair's friction coefficient taken from the instance.

use crate::geometry::parry_bridge::{from_parry_pose, to_parry_pose, to_parry_vec};
use crate::geometry::Box3;
use crate::instance::Instance;
use nalgebra::{Isometry3, Vector3};
use rapier3d::prelude::{
    ActiveHooks, ColliderBuilder, ContactModificationContext, FrictionModel, PhysicsHooks, PhysicsWorld,
    RigidBodyBuilder, RigidBodyHandle, RigidBodyType,
};

use super::SimOptions;

/// What a collider is; stored in its `user_data` so the friction hook can look a pair up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    Floor,
    Wall,
    Finger,
    Object(usize),
}

impl Role {
    fn encode(self) -> u128 {
        match self {
            Role::Floor => 0,
            Role::Wall => 1,
            Role::Finger => 2,
            Role::Object(i) => 3 + i as u128,
        }
    }
    fn decode(d: u128) -> Role {
        match d {
            0 => Role::Floor,
            1 => Role::Wall,
            2 => Role::Finger,
            i => Role::Object((i - 3) as usize),
        }
    }
}

/// Per-pair Coulomb coefficients, as the planner's push model pairs them: an object on the
/// floor `mu_floor`, two objects the smaller `mu_obj`, an object and a finger `mu_finger`, an
/// object and a wall its `mu_obj`. The physics uses the nominal values, not the planner's
/// shrunk cones: it is the reference the planner's margins are judged against.
struct Friction {
    /// The object in the fingers, if any: it touches only the floor (see [`World::carry`]).
    held: Option<usize>,
    mu_floor: Vec<f64>,
    mu_obj: Vec<f64>,
    mu_finger: Vec<f64>,
}

impl Friction {
    fn pair(&self, a: Role, b: Role) -> Option<f64> {
        use Role::*;
        match (a, b) {
            (Object(i), Object(j)) => Some(self.mu_obj[i].min(self.mu_obj[j])),
            (Object(i), Floor) | (Floor, Object(i)) => Some(self.mu_floor[i]),
            (Object(i), Wall) | (Wall, Object(i)) => Some(self.mu_obj[i]),
            (Object(i), Finger) | (Finger, Object(i)) => Some(self.mu_finger[i]),
            _ => None,
        }
    }
}

impl PhysicsHooks for Friction {
    fn modify_solver_contacts(&self, ctx: &mut ContactModificationContext) {
        let a = Role::decode(ctx.colliders[ctx.collider1].user_data);
        let b = Role::decode(ctx.colliders[ctx.collider2].user_data);
        let held = |r: Role| self.held.is_some_and(|h| r == Role::Object(h));
        let (Some(mu), Some(m)) = (self.pair(a, b), ctx.rigid_mut()) else {
            return;
        };
        if matches!((a, b), (Role::Object(_), Role::Object(_))) && (held(a) || held(b)) {
            m.solver_contacts.clear();
        } else {
            *m.friction = mu;
        }
    }
}

/// A box-shaped kinematic body driven along a path (a finger, or a carried object).
#[derive(Debug, Clone, Copy)]
pub struct Kinematic {
    handle: RigidBodyHandle,
}

/// The scene and its clock.
pub struct World {
    world: PhysicsWorld,
    friction: Friction,
    objects: Vec<Option<RigidBodyHandle>>,
    /// Steps taken.
    pub steps: u64,
}

impl World {
    /// Floor and walls of the instance's container (C frame, z up from the floor), no objects.
    pub fn for_instance(inst: &Instance, opts: &SimOptions) -> World {
        use rand::{RngExt, SeedableRng};
        // Friction errors, when perturbed: every coefficient of every object scaled alone.
        let mut rng = opts
            .perturb
            .map(|p| (p.friction, rand_chacha::ChaCha8Rng::seed_from_u64(p.seed)));
        let coefficients = inst
            .objects
            .iter()
            .map(|o| {
                [o.mu_floor, o.mu_obj, o.mu_finger].map(|mu| match rng.as_mut() {
                    Some((f, r)) => mu * (1.0 + *f * r.random_range(-1.0..=1.0)),
                    None => mu,
                })
            })
            .collect();
        World::new(&inst.container.walls(), coefficients, opts)
    }

    /// A floor at z = 0 with `walls`; `mu[i]` = object `i`'s `[mu_floor, mu_obj, mu_finger]`.
    pub fn new(walls: &[Box3], mu: Vec<[f64; 3]>, opts: &SimOptions) -> World {
        let mut world = PhysicsWorld::new();
        world.gravity = to_parry_vec(&Vector3::new(0.0, 0.0, -crate::instance::GRAVITY));
        let ip = &mut world.integration_parameters;
        ip.dt = opts.dt;
        // Boxes of a few centimetres judged to a millimetre: rapier's slops (5 mm penetration,
        // 2 cm prediction at length_unit 1) scaled to 50 µm and 0.2 mm.
        ip.length_unit = 0.01;
        ip.num_solver_iterations = opts.solver_iterations;
        // One friction constraint per contact point: the pressure distribution under a pushed
        // box decides whether it turns, which the simplified (per-manifold) model blurs.
        ip.friction_model = FrictionModel::Coulomb;
        ip.contact_recycling = false;
        ip.contact_softness.natural_frequency = opts.contact_hz;
        ip.static_contact_softness.natural_frequency = 2.0 * opts.contact_hz;
        world.insert(
            RigidBodyBuilder::fixed().translation(to_parry_vec(&Vector3::new(0.0, 0.0, -0.05))),
            ColliderBuilder::cuboid(10.0, 10.0, 0.05).user_data(Role::Floor.encode()),
        );
        for w in walls {
            let centre = Vector3::from_fn(|i, _| (w.min[i] + w.max[i]) / 2.0);
            let half = Vector3::from_fn(|i, _| (w.max[i] - w.min[i]) / 2.0);
            world.insert(
                RigidBodyBuilder::fixed().translation(to_parry_vec(&centre)),
                ColliderBuilder::cuboid(half.x, half.y, half.z).user_data(Role::Wall.encode()),
            );
        }
        let friction = Friction {
            held: None,
            mu_floor: mu.iter().map(|m| m[0]).collect(),
            mu_obj: mu.iter().map(|m| m[1]).collect(),
            mu_finger: mu.iter().map(|m| m[2]).collect(),
        };
        World {
            world,
            objects: vec![None; mu.len()],
            friction,
            steps: 0,
        }
    }

    /// A kinematic box of half extents `half` centred at `centre`.
    pub fn kinematic_box(&mut self, half: Vector3<f64>, centre: Vector3<f64>, role_object: Option<usize>) -> Kinematic {
        let role = role_object.map_or(Role::Finger, Role::Object);
        let (handle, _) = self.world.insert(
            RigidBodyBuilder::kinematic_position_based().translation(to_parry_vec(&centre)),
            ColliderBuilder::cuboid(half.x, half.y, half.z)
                .user_data(role.encode())
                .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS),
        );
        Kinematic { handle }
    }

    /// Object `i` as a box of half extents `half` and mass `mass`, carried (kinematic) until
    /// [`World::release`].
    ///
    /// While carried it touches no other object. The planner lets a released box touch its
    /// neighbour exactly (zero clearance); a real box then slides down past it with no normal
    /// force between them, but a rigid-body solver keeps a speculative contact there whose
    /// friction, driven by an infinitely heavy kinematic body, drags the neighbour into the
    /// (soft) floor and turned them (exp2's Bottom-Left plan: a box tipped over without this
    /// rule). Overlaps are the verifier's to find, not the replay's.
    pub fn add_object(&mut self, i: usize, half: Vector3<f64>, mass: f64, centre: Vector3<f64>) -> Kinematic {
        let (handle, _) = self.world.insert(
            RigidBodyBuilder::kinematic_position_based()
                .translation(to_parry_vec(&centre))
                .can_sleep(false),
            ColliderBuilder::cuboid(half.x, half.y, half.z)
                .mass(mass)
                .restitution(0.0)
                .user_data(Role::Object(i).encode())
                .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS),
        );
        self.objects[i] = Some(handle);
        self.friction.held = Some(i);
        Kinematic { handle }
    }

    /// Turn a carried object about the vertical through its centre by `yaw` (rad): a release
    /// error, for the side-contact cases of `tests/simulate_side.rs`.
    pub fn turn(&mut self, k: Kinematic, yaw: f64) {
        self.displace(k, 0.0, 0.0, yaw);
    }

    /// Move a carried object by `(dx, dy)` on the floor and turn it by `yaw` about the vertical
    /// through its centre: a release error.
    pub fn displace(&mut self, k: Kinematic, dx: f64, dy: f64, yaw: f64) {
        let b = &mut self.world.bodies[k.handle];
        let p = from_parry_pose(b.position());
        let moved = Isometry3::from_parts(
            (p.translation.vector + Vector3::new(dx, dy, 0.0)).into(),
            nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw) * p.rotation,
        );
        b.set_position(to_parry_pose(&moved), true);
    }

    /// Let go of a carried object: from now on gravity and contacts move it.
    pub fn release(&mut self, k: Kinematic) {
        self.friction.held = None;
        let b = &mut self.world.bodies[k.handle];
        b.set_body_type(RigidBodyType::Dynamic, true);
        b.set_linvel(to_parry_vec(&Vector3::zeros()), true);
        b.set_angvel(to_parry_vec(&Vector3::zeros()), true);
    }

    /// Remove a finger.
    pub fn remove(&mut self, k: Kinematic) {
        let w = &mut self.world;
        w.bodies.remove(
            k.handle,
            &mut w.islands,
            &mut w.colliders,
            &mut w.impulse_joints,
            &mut w.multibody_joints,
            &mut w.soft_bodies,
            true,
        );
    }

    /// Where kinematic body `k` is asked to be at the end of the next step.
    pub fn drive(&mut self, k: Kinematic, centre: Vector3<f64>) {
        self.world.bodies[k.handle].set_next_kinematic_translation(to_parry_vec(&centre));
    }

    /// One time step.
    pub fn step(&mut self) {
        self.world.step_with_events(&self.friction, &());
        self.steps += 1;
    }

    /// Pose of object `i` in C, once it is in the container.
    pub fn object_pose(&self, i: usize) -> Option<Isometry3<f64>> {
        self.objects[i].map(|h| from_parry_pose(self.world.bodies[h].position()))
    }
}

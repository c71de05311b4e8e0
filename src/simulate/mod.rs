//! Physics replay of a plan: rapier3d executes every place and push with rigid fingers moving
//! along the planned TCP path, and each box's motion is judged against the push tolerances.
//!
//! The planner and the verifier judge a plan push by push with quasi-static rules
//! (`docs/push_stability.md`). The replay is the independent check of the whole execution:
//! boxes are rigid bodies with their masses and the instance's Coulomb coefficients, the
//! container is a fixed floor and four walls, and the gripper is kinematic — two finger plates
//! that carry a box down to its release pose and open by the release clearance, or the closed
//! pair that pushes a line along the planned path at a slow, quasi-static speed. Nothing in it
//! reads the planner's margins.
//!
//! What is not simulated, and why (`docs/simulate.md`): the transfer from the table (the box is
//! held rigidly until it is above the container), the arm links (the joint plan and the
//! verifier check them), and the robot's timing (a quasi-static path at `push_speed` is what
//! the push rules model). Motions start and end just above everything in the container: higher
//! up nothing can be touched.
//!
//! The replay is deterministic: a fixed step, no random input, one thread.

pub mod line;
pub mod report;
pub mod robust;
pub mod sweep;
mod world;

use std::time::Instant;

use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};

use crate::actions::Action;
use crate::error::{Error, Result};
use crate::geometry::{Axis2, Rect};
use crate::instance::Instance;
use crate::motion::keypoints::action_keypoints;
use crate::placement::Placement;

pub use report::{ActionSim, BoxSim, SimReport, Tolerances};
use world::{Kinematic, World};

/// How the replay runs. Defaults: [`SimOptions::from_instance`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Time step (s). Default 1/240 s: a push at 20 mm/s moves 83 µm per step.
    pub dt: f64,
    /// Velocity iterations of rapier's solver per step. Default 8 (rapier's own default is 4,
    /// tuned for games; resting boxes creep less with 8).
    pub solver_iterations: usize,
    /// Natural frequency of the contacts between moving bodies (Hz); contacts with the fixed
    /// floor and walls are twice as stiff. Default 150 Hz. rapier's contacts are springs:
    /// at its game default of 30 Hz a 30 g box in a pushed line gives way 0.3 mm per contact
    /// (load / (m ω²)), and floor friction keeps the boxes overlapped after the push.
    pub contact_hz: f64,
    /// Speed of the gripper's approach, descent, opening and retreat (m/s). Default 0.1.
    pub move_speed: f64,
    /// Speed of the pusher along a push (m/s). Default 0.02: slow enough that inertia is
    /// negligible (the push rules are quasi-static).
    pub push_speed: f64,
    /// Time the scene settles after each action before it is measured (s). Default 0.1.
    pub settle_s: f64,
    /// What a box may do: from the instance's push tolerances.
    pub tolerances: Tolerances,
    /// Errors a real cell makes, drawn from a seed (default none: the nominal replay).
    pub perturb: Option<Perturbation>,
}

/// Random errors of one replay ([`robust`]): every release off its planned pose by up to
/// `release_offset` along each floor axis and `release_yaw` about the vertical, every friction
/// coefficient scaled by up to `1 ± friction`. Uniform, drawn from `seed`: the same seed gives
/// the same replay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perturbation {
    /// Seed of the draws.
    pub seed: u64,
    /// Largest release error along x and along y (m). Default 0.5 mm.
    pub release_offset: f64,
    /// Largest release error about the vertical (rad). Default 0.5°.
    pub release_yaw: f64,
    /// Largest relative friction error. Default 0.2.
    pub friction: f64,
}

impl Perturbation {
    /// The default errors (0.5 mm, 0.5°, ±20 % friction) with `seed`.
    pub fn with_seed(seed: u64) -> Perturbation {
        Perturbation {
            seed,
            release_offset: 5e-4,
            release_yaw: 0.5f64.to_radians(),
            friction: 0.2,
        }
    }
}

impl SimOptions {
    /// Defaults with the instance's tolerances.
    pub fn from_instance(inst: &Instance) -> SimOptions {
        SimOptions {
            dt: 1.0 / 240.0,
            solver_iterations: 8,
            contact_hz: 150.0,
            move_speed: 0.1,
            push_speed: 0.02,
            settle_s: 0.1,
            tolerances: Tolerances::from_instance(inst),
            perturb: None,
        }
    }

    fn validate(&self) -> Result<()> {
        let positive = [
            ("dt", self.dt),
            ("contact_hz", self.contact_hz),
            ("move_speed", self.move_speed),
            ("push_speed", self.push_speed),
            ("tolerances.max_rotation", self.tolerances.max_rotation),
            ("tolerances.max_drift", self.tolerances.max_drift),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::input(
                    "<simulate options>",
                    field,
                    format!("must be finite and > 0, got {v}"),
                ));
            }
        }
        if !(self.settle_s.is_finite() && self.settle_s >= 0.0) {
            return Err(Error::input(
                "<simulate options>",
                "settle_s",
                format!("must be finite and ≥ 0, got {}", self.settle_s),
            ));
        }
        if let Some(p) = self.perturb {
            let ranges = [
                ("perturb.release_offset", p.release_offset),
                ("perturb.release_yaw", p.release_yaw),
                ("perturb.friction", p.friction),
            ];
            for (field, v) in ranges {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(Error::input(
                        "<simulate options>",
                        field,
                        format!("must be finite and ≥ 0, got {v}"),
                    ));
                }
            }
            if p.friction >= 1.0 {
                return Err(Error::input(
                    "<simulate options>",
                    "perturb.friction",
                    format!("must be below 1 (a coefficient stays positive), got {}", p.friction),
                ));
            }
        }
        if self.solver_iterations == 0 {
            return Err(Error::input("<simulate options>", "solver_iterations", "must be ≥ 1"));
        }
        Ok(())
    }
}

/// What a replay needs: the targets and the actions, read against the instance. `plan.json`'s
/// [`crate::plan::Plan`] is one (implemented where it is defined, above this stage); a
/// [`Sequence`] is the planner's own, before any plan file exists.
pub trait Replayable {
    /// The targets.
    fn replay_placement(&self, inst: &Instance) -> Result<Placement>;
    /// The actions, in order.
    fn replay_actions(&self, inst: &Instance) -> Result<Vec<Action>>;
}

/// A placement and an order of actions, as the sequencers produce them.
#[derive(Debug, Clone, Copy)]
pub struct Sequence<'a> {
    /// The targets.
    pub placement: &'a Placement,
    /// The actions, in order.
    pub actions: &'a [Action],
}

impl Replayable for Sequence<'_> {
    fn replay_placement(&self, _inst: &Instance) -> Result<Placement> {
        Ok(self.placement.clone())
    }
    fn replay_actions(&self, _inst: &Instance) -> Result<Vec<Action>> {
        Ok(self.actions.to_vec())
    }
}

/// Replay `plan` for `inst` in the physics engine and judge every action and box.
///
/// Errors: a plan that does not match the instance (its placement or actions cannot be read),
/// or options out of range. A plan that fails in simulation is not an error: the report says
/// which action and box, and by how much.
pub fn simulate(inst: &Instance, plan: &impl Replayable, opts: &SimOptions) -> Result<SimReport> {
    replay(inst, plan, opts, false)
}

/// Replay until the first action out of tolerance, and report the actions up to it (the boxes
/// as they are then): what a planner needs to know which action to avoid.
pub fn first_failure(inst: &Instance, plan: &impl Replayable, opts: &SimOptions) -> Result<SimReport> {
    replay(inst, plan, opts, true)
}

fn replay(inst: &Instance, plan: &impl Replayable, opts: &SimOptions, stop_at_failure: bool) -> Result<SimReport> {
    opts.validate()?;
    let placement = plan.replay_placement(inst)?;
    let actions = plan.replay_actions(inst)?;
    let started = Instant::now();
    let mut r = Replay {
        inst,
        placement: &placement,
        opts,
        world: World::for_instance(inst, opts),
        in_container: Vec::new(),
        rng: opts
            .perturb
            .map(|p| rand_chacha::ChaCha8Rng::seed_from_u64(p.seed ^ 0x5eed_0fe7_7025)),
    };
    let mut action_reports = Vec::with_capacity(actions.len());
    for (k, a) in actions.iter().enumerate() {
        let report = r.action(k + 1, a);
        let failed = !report.ok;
        action_reports.push(report);
        if failed && stop_at_failure {
            break;
        }
    }
    let boxes = (0..inst.objects.len()).map(|i| r.final_box(i)).collect();
    Ok(SimReport::new(
        opts.tolerances,
        action_reports,
        boxes,
        r.world.steps,
        r.world.steps as f64 * opts.dt,
        started.elapsed().as_secs_f64(),
    ))
}

/// What the boxes did while one action ran.
struct Watch {
    start: Vec<(usize, Isometry3<f64>)>,
    /// Drift measured along this axis only (sideways across a push), else in full.
    lateral: Option<Axis2>,
    /// Largest rotation (rad) and drift (m) of each watched box so far.
    rotation: Vec<f64>,
    drift: Vec<f64>,
}

struct Replay<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    opts: &'a SimOptions,
    world: World,
    in_container: Vec<usize>,
    /// Draws of the release errors, when perturbed.
    rng: Option<rand_chacha::ChaCha8Rng>,
}

impl Replay<'_> {
    fn action(&mut self, step: usize, a: &Action) -> ActionSim {
        let kp = action_keypoints(self.inst, self.placement, a);
        let c = |label: &str| -> Vector3<f64> {
            let p = &kp
                .iter()
                .find(|p| p.label == label)
                .expect("keypoint labels are fixed")
                .position;
            Vector3::from(self.inst.container.from_world(&Vector3::from(*p)))
        };
        match a {
            Action::Place { object, grasp_axis, .. } => {
                let release = c("release");
                self.place(step, *object, *grasp_axis, release)
            }
            Action::Push { objects, push_dir, .. } => {
                let (start, end) = (c("push-start"), c("push-end"));
                let lateral = push_dir.axis().other();
                self.push(step, objects, start, end, lateral)
            }
        }
    }

    /// Height (from the floor) above which a fingertip touches nothing in the container.
    fn free_height(&self) -> f64 {
        let tallest = self
            .in_container
            .iter()
            .map(|&i| self.placement.targets[i].height)
            .fold(0.0, f64::max);
        self.inst.container.wall_height.max(tallest) + 0.01
    }

    /// Half extents of a finger plate, its thickness along `along`.
    fn finger_half(&self, along: Axis2) -> Vector3<f64> {
        let g = &self.inst.gripper;
        let mut half = Vector3::new(g.finger_width / 2.0, g.finger_width / 2.0, g.finger_length / 2.0);
        half[along.index()] = g.finger_thickness / 2.0;
        half
    }

    fn place(&mut self, step: usize, object: usize, axis: Axis2, release: Vector3<f64>) -> ActionSim {
        let g = self.inst.gripper;
        let t = self.placement.targets[object];
        let (w, d, h) = (t.rect.width(), t.rect.depth(), t.height);
        let half = Vector3::new(w / 2.0, d / 2.0, h / 2.0);
        // A release error moves the whole gripper, box and fingers together: the TCP lands off
        // its planned point and the hand is turned about the vertical through it.
        let (release, turn) = self.release_error(object, half, release);
        let rot = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), turn);
        // TCP → box centre and finger centres: the fingertips are at the TCP, the plates reach
        // up from it, each against one face of the box along the grasp axis.
        let to_box = Vector3::new(0.0, 0.0, h / 2.0 - (h - g.grasp_depth));
        let mut side = Vector3::zeros();
        side[axis.index()] = half[axis.index()] + g.finger_thickness / 2.0;
        let side = rot * side;
        let up = Vector3::new(0.0, 0.0, g.finger_length / 2.0);
        let above = Vector3::new(release.x, release.y, release.z.max(self.free_height()));

        let mut watch = self.watch(&self.in_container, None);
        let held = self
            .world
            .add_object(object, half, self.inst.objects[object].mass, above + to_box);
        let fhalf = self.finger_half(axis);
        let fingers = [
            self.world.kinematic_box(fhalf, above + up + side, None),
            self.world.kinematic_box(fhalf, above + up - side, None),
        ];
        if turn != 0.0 {
            for k in [held, fingers[0], fingers[1]] {
                self.world.turn(k, turn);
            }
        }
        self.move_rigid(
            &[(held, to_box), (fingers[0], up + side), (fingers[1], up - side)],
            above,
            release,
            self.opts.move_speed,
            &mut watch,
        );
        self.world.release(held);
        self.in_container.push(object);
        let released_at = self.world.object_pose(object).expect("just added");
        // Open: each plate moves out by the release clearance.
        let mut out = Vector3::zeros();
        out[axis.index()] = g.release_clearance;
        let open = side + rot * out;
        let n = steps_for(g.release_clearance, self.opts.move_speed, self.opts.dt);
        for s in 1..=n {
            let f = s as f64 / n as f64;
            let off = side + (open - side) * f;
            self.world.drive(fingers[0], release + up + off);
            self.world.drive(fingers[1], release + up - off);
            self.world.step();
            self.observe(&mut watch);
        }
        let top = Vector3::new(release.x, release.y, self.free_height().max(release.z));
        self.move_rigid(
            &[(fingers[0], up + open), (fingers[1], up - open)],
            release,
            top,
            self.opts.move_speed,
            &mut watch,
        );
        for f in fingers {
            self.world.remove(f);
        }
        self.settle(&mut watch);
        let now = self.world.object_pose(object).expect("in the container");
        let moved = (now.translation.vector - released_at.translation.vector).xy().norm();
        let turned = now.rotation.angle_to(&released_at.rotation);
        ActionSim::new(
            step,
            "place",
            &self.ids(&[object]),
            vec![turned],
            vec![moved],
            self.disturbed(&watch, &[object]),
            &self.opts.tolerances,
        )
    }

    /// The release error of one place, when the replay is perturbed: the TCP's floor offset and
    /// the hand's turn (rad). A box cannot come down inside a neighbour or a wall: their faces
    /// guide it, so the offset is corrected out of each overlap (of the bounding rectangles)
    /// along the axis of the smaller one. A release error then only opens a gap, or closes one
    /// to contact.
    fn release_error(&mut self, object: usize, half: Vector3<f64>, release: Vector3<f64>) -> (Vector3<f64>, f64) {
        let (Some(p), Some(rng)) = (self.opts.perturb, self.rng.as_mut()) else {
            return (release, 0.0);
        };
        let mut draw = |m: f64| rng.random_range(-1.0..=1.0) * m;
        let (dx, dy, turn) = (draw(p.release_offset), draw(p.release_offset), draw(p.release_yaw));
        // Between faces on both sides a turned box does not fit: they align it as it comes
        // down, so it lands unturned.
        let mut turn = turn;
        let mut c = [release.x + dx, release.y + dy];
        for _ in 0..2 {
            c = [release.x + dx, release.y + dy];
            if self.guide(object, &mut c, turn, &half) {
                break;
            }
            turn = 0.0;
        }
        (Vector3::new(c[0], c[1], release.z), turn)
    }

    /// Move the footprint centred at `c` (turned `turn`, half extents `half`) out of the walls
    /// and the boxes in the container, each overlap along the axis of its smaller extent; false
    /// when it still overlaps something after a few rounds (it does not fit turned).
    fn guide(&self, object: usize, c: &mut [f64; 2], turn: f64, half: &Vector3<f64>) -> bool {
        let bounds = |c: [f64; 2], yaw: f64, h: &Vector3<f64>| {
            let (s, co) = yaw.sin_cos();
            let e = [h.x * co.abs() + h.y * s.abs(), h.x * s.abs() + h.y * co.abs()];
            Rect {
                x0: c[0] - e[0],
                x1: c[0] + e[0],
                y0: c[1] - e[1],
                y1: c[1] + e[1],
            }
        };
        let floor = self.inst.container.floor();
        for _ in 0..4 {
            let me = bounds(*c, turn, half);
            let mut shift = [
                (floor.x0 - me.x0).max(0.0) - (me.x1 - floor.x1).max(0.0),
                (floor.y0 - me.y0).max(0.0) - (me.y1 - floor.y1).max(0.0),
            ];
            for &j in self.in_container.iter().filter(|&&j| j != object) {
                let t = self.placement.targets[j];
                let hj = Vector3::new(t.rect.width() / 2.0, t.rect.depth() / 2.0, t.height / 2.0);
                let pj = self.world.object_pose(j).expect("in the container");
                let tj = pj.translation.vector;
                let other = bounds([tj.x, tj.y], pj.rotation.euler_angles().2, &hj);
                let (ox, oy) = (me.overlap_on(&other, Axis2::X), me.overlap_on(&other, Axis2::Y));
                if ox <= 1e-7 || oy <= 1e-7 {
                    continue;
                }
                let (mc, oc) = (me.center(), other.center());
                if ox < oy {
                    shift[0] += ox.copysign(mc[0] - oc[0]);
                } else {
                    shift[1] += oy.copysign(mc[1] - oc[1]);
                }
            }
            if shift.iter().all(|v| v.abs() <= 1e-7) {
                return true;
            }
            *c = [c[0] + shift[0], c[1] + shift[1]];
        }
        false
    }

    fn push(
        &mut self,
        step: usize,
        line: &[usize],
        start: Vector3<f64>,
        end: Vector3<f64>,
        lateral: Axis2,
    ) -> ActionSim {
        let axis = if lateral == Axis2::X { Axis2::Y } else { Axis2::X };
        let fhalf = self.finger_half(axis);
        let up = Vector3::new(0.0, 0.0, self.inst.gripper.finger_length / 2.0);
        let above = Vector3::new(start.x, start.y, self.free_height().max(start.z));
        let mut watch = self.watch(&self.in_container, None);
        let pusher = self.world.kinematic_box(fhalf, above + up, None);
        self.move_rigid(&[(pusher, up)], above, start, self.opts.move_speed, &mut watch);
        // Lateral drift and rotation are measured over the push itself.
        let mut pushing = self.watch(line, Some(lateral));
        let n = steps_for((end - start).norm(), self.opts.push_speed, self.opts.dt);
        for s in 1..=n {
            let p = start + (end - start) * (s as f64 / n as f64);
            self.world.drive(pusher, p + up);
            self.world.step();
            self.observe(&mut watch);
            self.observe(&mut pushing);
        }
        let top = Vector3::new(end.x, end.y, self.free_height().max(end.z));
        self.move_rigid(&[(pusher, up)], end, top, self.opts.move_speed, &mut watch);
        self.world.remove(pusher);
        self.settle(&mut watch);
        self.observe(&mut pushing);
        ActionSim::new(
            step,
            "push",
            &self.ids(line),
            pushing.rotation.clone(),
            pushing.drift.clone(),
            self.disturbed(&watch, line),
            &self.opts.tolerances,
        )
    }

    /// Move rigidly attached kinematic bodies (each at an offset from the TCP) in a straight
    /// line from `a` to `b` at `speed`.
    fn move_rigid(
        &mut self,
        bodies: &[(Kinematic, Vector3<f64>)],
        a: Vector3<f64>,
        b: Vector3<f64>,
        speed: f64,
        watch: &mut Watch,
    ) {
        let n = steps_for((b - a).norm(), speed, self.opts.dt);
        for s in 1..=n {
            let p = a + (b - a) * (s as f64 / n as f64);
            for (k, off) in bodies {
                self.world.drive(*k, p + off);
            }
            self.world.step();
            self.observe(watch);
        }
    }

    fn settle(&mut self, watch: &mut Watch) {
        for _ in 0..(self.opts.settle_s / self.opts.dt).ceil() as usize {
            self.world.step();
            self.observe(watch);
        }
    }

    /// Start watching boxes `ids`: their drift along `lateral`, or in full without one.
    fn watch(&self, ids: &[usize], lateral: Option<Axis2>) -> Watch {
        let start: Vec<_> = ids
            .iter()
            .map(|&i| (i, self.world.object_pose(i).expect("in the container")))
            .collect();
        Watch {
            rotation: vec![0.0; start.len()],
            drift: vec![0.0; start.len()],
            lateral,
            start,
        }
    }

    /// Largest rotation and drift of every watched box since the watch began.
    fn observe(&self, w: &mut Watch) {
        for (k, (i, p0)) in w.start.iter().enumerate() {
            let p = self.world.object_pose(*i).expect("watched");
            let d = p.translation.vector - p0.translation.vector;
            w.rotation[k] = w.rotation[k].max(p.rotation.angle_to(&p0.rotation));
            w.drift[k] = w.drift[k].max(w.lateral.map_or(d.norm(), |l| d[l.index()].abs()));
        }
    }

    /// Largest displacement (m) of a box the action should not have moved.
    fn disturbed(&self, w: &Watch, moved: &[usize]) -> f64 {
        w.start
            .iter()
            .zip(&w.drift)
            .filter(|((i, _), _)| !moved.contains(i))
            .map(|(_, &d)| d)
            .fold(0.0, f64::max)
    }

    fn ids(&self, objects: &[usize]) -> Vec<String> {
        objects.iter().map(|&i| self.inst.objects[i].id.clone()).collect()
    }

    fn final_box(&self, i: usize) -> BoxSim {
        let t = self.placement.targets[i];
        let id = self.inst.objects[i].id.clone();
        match self.world.object_pose(i) {
            None => BoxSim::missing(id),
            Some(p) => BoxSim::new(id, &p, &target_pose(&t.rect, t.height), &self.opts.tolerances),
        }
    }
}

/// The pose a box should end at: its footprint's centre, resting on the floor, axes along C's.
fn target_pose(r: &Rect, height: f64) -> Isometry3<f64> {
    let c = r.center();
    Isometry3::from_parts(
        Vector3::new(c[0], c[1], height / 2.0).into(),
        UnitQuaternion::identity(),
    )
}

fn steps_for(distance: f64, speed: f64, dt: f64) -> usize {
    ((distance / (speed * dt)).ceil() as usize).max(1)
}

//! Joint plans of actions: key poses with orientation and finger opening, inverse kinematics
//! along them, straight Cartesian lines and joint-space moves, collision checks along the motion,
//! arm selection and the reachability predicate of the action planner.
//!
//! Per action (SPEC §8): place = pre-grasp → grasp → lift → pre-place → release → retreat;
//! push = above-push → push-start → push-end → push-retreat. The positions are exactly those of
//! [`super::keypoints::action_keypoints`] (so travel and verifier agree). Every vertical move and
//! the push itself are straight lines in Cartesian space, sampled adaptively until the TCP stays
//! within [`LINE_TOLERANCE`] of the line between consecutive samples (the spec's bound, checked by
//! the verifier, is [`LINE_LIMIT`]); the transfer (lift → pre-place) and the approach from the
//! arm's previous configuration are joint-space moves, replaced by a Cartesian line when the joint
//! move collides. The gripper is symmetric about its closing axis, so every grasp or push can be
//! done with the hand turned by π: each action is planned in every such variant and the feasible
//! one with the least joint motion (and the larger joint margin) wins.

use super::collision::{
    arm_as_obstacles, clearance, first_collision, object_in_container, object_on_table, robot_parts, static_obstacles,
    Hand, Held, Obstacle, ObstacleKind, Part, PartKind,
};
use super::keypoints::action_keypoints;
use super::trajectory::{
    time_segment, ActionTrajectory, KeyPose, RobotInfo, TrajPoint, TrajectoryOptions, GRIPPER_DWELL,
};
use crate::actions::{Action, PlaceMode};
use crate::geometry::Arm;
use crate::geometry::{Axis2, BodyAxis, PushDir, Rect};
use crate::instance::Instance;
use crate::placement::Placement;
use crate::robot::ik::{max_abs_diff, top_down_pose, IkSolver};
use crate::robot::RobotError;
use nalgebra::{Isometry3, Vector3};
use std::cell::RefCell;
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};

/// Joint-space legs of a move: each a polyline of configurations of one arm.
type Legs = Vec<Vec<[f64; 6]>>;
/// Planning tolerance of straight lines: largest TCP distance from the line between two samples (m).
pub const LINE_TOLERANCE: f64 = 5e-5;
/// The spec's bound on the deviation of a straight-line push (m), checked by the verifier.
pub const LINE_LIMIT: f64 = 1e-3;
/// Line tolerance of the reachability predicate (m): it needs to know that a line can be
/// followed and roughly where the arm is, not the joint plan's fine waypoints.
pub const PREDICATE_LINE_TOLERANCE: f64 = 1e-3;
/// Planning tolerance of straight lines: largest turn of the tool from its interpolated
/// orientation between two samples (rad).
pub const ROT_TOLERANCE: f64 = 5e-4;
/// Largest joint step between two waypoints of a straight line (rad).
pub const MAX_LINE_STEP: f64 = 0.05;
/// Joint step between collision samples of a joint-space move (rad).
pub const COLLISION_STEP: f64 = 0.01;

/// How a segment is moved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Move {
    /// Joint-space interpolation (a Cartesian line if that collides).
    Joint,
    /// Straight Cartesian line.
    Line,
}

/// Where an object is when an action starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjAt {
    /// At its start pose on the table.
    Table,
    /// On the container floor with this footprint (C), at its target height.
    Floor(Rect),
}

/// A key pose to reach, with the gripper state after it.
#[derive(Debug, Clone)]
struct Spec {
    label: String,
    target: Isometry3<f64>,
    opening: f64,
    held: Option<Held>,
    mv: Move,
}

/// The yaw, closing extent, other extent and height of a top-down grasp of `object` on the table
/// along the body axis that is the closing axis at its target; and whether the object changes its
/// up axis between table and target (a top-down pick cannot do that).
fn table_grasp(inst: &Instance, placement: &Placement, object: usize, grasp_axis: Axis2) -> (f64, f64, f64, f64, bool) {
    let o = &inst.objects[object];
    let t = &placement.targets[object];
    let others = |a: BodyAxis| match a {
        BodyAxis::X => (BodyAxis::Y, BodyAxis::Z),
        BodyAxis::Y => (BodyAxis::X, BodyAxis::Z),
        BodyAxis::Z => (BodyAxis::X, BodyAxis::Y),
    };
    let (b, c) = others(t.orientation.up);
    let g = match (grasp_axis, t.orientation.yaw90) {
        (Axis2::X, false) | (Axis2::Y, true) => b,
        _ => c,
    };
    let (bt, ct) = others(o.table.up);
    let s = o.size;
    let h = s[o.table.up.index()];
    if g == bt {
        (
            o.table.yaw,
            s[bt.index()],
            s[ct.index()],
            h,
            t.orientation.up != o.table.up,
        )
    } else if g == ct {
        (
            o.table.yaw + FRAC_PI_2,
            s[ct.index()],
            s[bt.index()],
            h,
            t.orientation.up != o.table.up,
        )
    } else if s[bt.index()] <= s[ct.index()] {
        (o.table.yaw, s[bt.index()], s[ct.index()], h, true)
    } else {
        (o.table.yaw + FRAC_PI_2, s[ct.index()], s[bt.index()], h, true)
    }
}

/// Release footprint of a place.
fn release_rect(placement: &Placement, object: usize, mode: &PlaceMode) -> Rect {
    let t = placement.targets[object].rect;
    match mode {
        PlaceMode::Direct => t,
        PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
    }
}

fn axis_yaw(inst: &Instance, a: Axis2) -> f64 {
    inst.container.yaw
        + match a {
            Axis2::X => 0.0,
            Axis2::Y => FRAC_PI_2,
        }
}

/// Key pose specs of `action` with the hand turned by π where `flip` says so.
fn specs(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    flip: [bool; 2],
    notes: &mut Vec<String>,
) -> Vec<Spec> {
    let kps = action_keypoints(inst, placement, action);
    let g = &inst.gripper;
    let pose = |k: usize, yaw: f64| top_down_pose(&Vector3::from(kps[k].position), yaw);
    let turn = |f: bool| if f { PI } else { 0.0 };
    match action {
        Action::Place {
            object,
            mode,
            grasp_axis,
            ..
        } => {
            let (yaw_t, closing_t, other_t, h_t, reoriented) = table_grasp(inst, placement, *object, *grasp_axis);
            if reoriented {
                notes.push(format!(
                    "object {} changes its up axis between the table and its target: a top-down pick cannot turn \
                     it over; the joint plan assumes the cell's regrasp (robot.regrasp{}) has it in its target \
                     orientation when it is lowered into the container (the regrasp itself is not planned)",
                    inst.objects[*object].id,
                    if inst.robot.regrasp {
                        " = true"
                    } else {
                        " is false: not executable"
                    }
                ));
            }
            let rel = release_rect(placement, *object, mode);
            let closing_r = rel.extent(*grasp_axis);
            let other_r = rel.extent(grasp_axis.other());
            let h_r = placement.targets[*object].height;
            let yaw_r = axis_yaw(inst, *grasp_axis) + turn(flip[1]);
            let yaw_t = yaw_t + turn(flip[0]);
            let open = |w: f64| (w + 2.0 * g.release_clearance).min(g.max_opening.max(w));
            let held_t = Held {
                object: *object,
                closing: closing_t,
                other: other_t,
                height: h_t,
            };
            let held_r = Held {
                object: *object,
                closing: closing_r,
                other: other_r,
                height: h_r,
            };
            let mk = |k: usize, yaw: f64, opening: f64, held: Option<Held>, mv: Move| Spec {
                label: kps[k].label.clone(),
                target: pose(k, yaw),
                opening,
                held,
                mv,
            };
            vec![
                mk(0, yaw_t, open(closing_t), None, Move::Joint),
                mk(1, yaw_t, closing_t, Some(held_t), Move::Line),
                mk(2, yaw_t, closing_t, Some(held_t), Move::Line),
                mk(3, yaw_r, closing_r, Some(held_r), Move::Joint),
                mk(4, yaw_r, open(closing_r), None, Move::Line),
                mk(5, yaw_r, open(closing_r), None, Move::Line),
            ]
        }
        Action::Push { push_dir, .. } => {
            let yaw = axis_yaw(inst, push_dir.axis()) + turn(flip[0]);
            let mv = [Move::Joint, Move::Line, Move::Line, Move::Line];
            (0..kps.len())
                .map(|k| Spec {
                    label: kps[k].label.clone(),
                    target: pose(k, yaw),
                    opening: 0.0,
                    held: None,
                    mv: mv[k.min(3)],
                })
                .collect()
        }
    }
}

/// World point → container frame C (x, y).
fn to_container(inst: &Instance, p: &Vector3<f64>) -> [f64; 2] {
    let c = &inst.container;
    let (s, co) = c.yaw.sin_cos();
    let (u, v) = (p.x - c.center[0], p.y - c.center[1]);
    [co * u + s * v + c.width / 2.0, -s * u + co * v + c.depth / 2.0]
}

/// Footprints of a pushed line when the pusher's front face is at `face` along the push axis:
/// objects (front to back, released footprints `rel`) move only when pushed.
fn pushed_rects(rel: &[Rect], dir: PushDir, face: f64) -> Vec<Rect> {
    let axis = dir.axis();
    let mut drive = face;
    let mut out = vec![rel[0]; rel.len()];
    for k in (0..rel.len()).rev() {
        let hi = rel[k].hi(axis).min(drive);
        let r = rel[k].moved(dir, rel[k].hi(axis) - hi);
        drive = r.lo(axis);
        out[k] = r;
    }
    out
}

/// The context of planning one action.
struct Ctx<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    statics: Vec<Obstacle>,
    /// Objects before the action.
    at: Vec<ObjAt>,
    /// The idle arm as obstacles.
    other: Vec<Obstacle>,
    /// Which collisions to check.
    scope: Scope,
    /// Joint moves go to any IK branch at the target, not the nearest (the predicate).
    fast_ik: bool,
    /// Memo of IK results shared between the predicate's queries (see [`IkMemo`]).
    memo: Option<&'a RefCell<IkMemo>>,
}

/// IK results of the reachability predicate by their exact inputs. Actions of one object share
/// their table half (pre-grasp, grasp, lift: the same poses for every release mode), and an
/// unreachable pose costs a search over every IK seed, so repeating it per mode dominated the
/// predicate's time.
#[derive(Debug, Default)]
pub struct IkMemo {
    map: HashMap<Vec<u64>, Result<Vec<[f64; 6]>, RobotError>>,
}

impl IkMemo {
    fn get(
        cell: Option<&RefCell<IkMemo>>,
        key: impl FnOnce() -> Vec<u64>,
        f: impl FnOnce() -> Result<Vec<[f64; 6]>, RobotError>,
    ) -> Result<Vec<[f64; 6]>, RobotError> {
        let Some(cell) = cell else {
            return f();
        };
        let k = key();
        if let Some(v) = cell.borrow().map.get(&k) {
            return v.clone();
        }
        let v = f();
        cell.borrow_mut().map.insert(k, v.clone());
        v
    }
}

/// Exact bits of a pose, a configuration and a few more numbers, as a memo key.
fn key_bits(tag: u64, arm: Arm, poses: &[&Isometry3<f64>], q: Option<&[f64; 6]>, extra: &[f64]) -> Vec<u64> {
    let mut k = vec![tag, arm.index() as u64];
    for p in poses {
        k.extend(p.translation.vector.iter().map(|x| x.to_bits()));
        k.extend(p.rotation.coords.iter().map(|x| x.to_bits()));
    }
    if let Some(q) = q {
        k.extend(q.iter().map(|x| x.to_bits()));
    }
    k.extend(extra.iter().map(|x| x.to_bits()));
    k
}

/// Which collisions a [`Ctx`] checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scope {
    /// None: kinematics only (ranking hand variants).
    Kinematic,
    /// The reachability predicate: the straight lines of the action (descents, lifts, releases,
    /// retreats, the push) against the fixed cell (walls, floor plate, table). Joint-space moves
    /// depend on where the arm comes from and the objects on the state, so they are left to the
    /// joint plan (objects on the table are handled as pick blockers).
    StaticLines,
    /// Everything: the joint plan.
    Full,
}

impl Ctx<'_> {
    fn object_obstacle(&self, i: usize, at: ObjAt) -> Obstacle {
        match at {
            ObjAt::Table => object_on_table(self.inst, i),
            ObjAt::Floor(r) => object_in_container(self.inst, i, &r, self.placement.targets[i].height),
        }
    }

    /// Obstacles during segment `seg` of `action` (before the TCP-dependent push motion).
    fn obstacles(&self, action: &Action, seg: usize, tcp: Option<&Vector3<f64>>) -> Vec<Obstacle> {
        let mut out = self.statics.clone();
        if self.scope == Scope::StaticLines {
            out.extend(self.other.iter().cloned());
            // A push's back object is where the action says (its target moved back by the push
            // distance) whatever the state: the pusher descends behind it and drives it, and a
            // palm hanging below its top hits it.
            if let Action::Push {
                objects,
                push_dir,
                distance,
                ..
            } = action
            {
                let back = *objects.last().expect("a push moves an object");
                let rel = [self.placement.targets[back].rect.moved(*push_dir, -distance)];
                let now = match (seg, tcp) {
                    (0 | 1, _) => rel[0],
                    (2, Some(p)) => {
                        let c = to_container(self.inst, p);
                        let face = c[push_dir.axis().index()] - self.inst.gripper.finger_thickness / 2.0;
                        pushed_rects(&rel, *push_dir, face)[0]
                    }
                    _ => self.placement.targets[back].rect,
                };
                out.push(self.object_obstacle(back, ObjAt::Floor(now)));
            }
            return out;
        }
        out.extend(self.other.iter().cloned());
        let n = self.inst.n();
        match action {
            Action::Place { object, mode, .. } => {
                for i in 0..n {
                    if i == *object {
                        match seg {
                            0 | 1 => out.push(self.object_obstacle(i, self.at[i])),
                            5.. => {
                                out.push(self.object_obstacle(i, ObjAt::Floor(release_rect(self.placement, i, mode))))
                            }
                            _ => {}
                        }
                    } else {
                        out.push(self.object_obstacle(i, self.at[i]));
                    }
                }
            }
            Action::Push { objects, push_dir, .. } => {
                let rel: Vec<Rect> = objects
                    .iter()
                    .map(|&i| match self.at[i] {
                        ObjAt::Floor(r) => r,
                        ObjAt::Table => self.placement.targets[i].rect,
                    })
                    .collect();
                let now: Vec<Rect> = match (seg, tcp) {
                    (0 | 1, _) => rel.clone(),
                    (2, Some(p)) => {
                        let c = to_container(self.inst, p);
                        let face = c[push_dir.axis().index()] - self.inst.gripper.finger_thickness / 2.0;
                        pushed_rects(&rel, *push_dir, face)
                    }
                    _ => objects.iter().map(|&i| self.placement.targets[i].rect).collect(),
                };
                for i in 0..n {
                    match objects.iter().position(|&j| j == i) {
                        Some(k) => out.push(self.object_obstacle(i, ObjAt::Floor(now[k]))),
                        None => out.push(self.object_obstacle(i, self.at[i])),
                    }
                }
            }
        }
        out
    }

    /// Pairs that are allowed to touch beyond the tolerance: the pusher on the pushed line.
    fn skip(action: &Action, seg: usize) -> impl Fn(&Part, &Obstacle) -> bool + '_ {
        move |p: &Part, o: &Obstacle| match (action, o.kind) {
            (Action::Push { objects, .. }, ObstacleKind::Object(i)) => {
                p.kind == PartKind::Finger && seg >= 2 && objects.contains(&i)
            }
            _ => false,
        }
    }
}

/// The motion of one action variant.
#[derive(Debug, Clone)]
struct Motion {
    /// Legs (each from rest to rest) per segment; segment k ends at key pose k.
    segments: Vec<Legs>,
    key_q: Vec<[f64; 6]>,
    specs: Vec<Spec>,
    cost: f64,
    clearance: f64,
}

fn lerp(a: &[f64; 6], b: &[f64; 6], u: f64) -> [f64; 6] {
    std::array::from_fn(|k| a[k] + u * (b[k] - a[k]))
}

fn interp_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    a.lerp_slerp(b, s)
}

/// Distance from `p` to the segment a–b.
pub fn line_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let u = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * u)).norm()
}

/// Follow the straight line a → b from configuration `q0` (at a).
fn follow_line(
    solver: &IkSolver,
    q0: &[f64; 6],
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    what: &str,
) -> Result<Vec<[f64; 6]>, RobotError> {
    follow_line_tol(solver, q0, a, b, what, LINE_TOLERANCE)
}

/// [`follow_line`] with another position tolerance (the predicate only needs to know that the
/// line can be followed, not the fine waypoints the joint plan emits).
fn follow_line_tol(
    solver: &IkSolver,
    q0: &[f64; 6],
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    what: &str,
    tol: f64,
) -> Result<Vec<[f64; 6]>, RobotError> {
    let len = (b.translation.vector - a.translation.vector).norm();
    let ang = a.rotation.angle_to(&b.rotation);
    let n = (len / 0.01).max(ang / 0.05).ceil().max(1.0) as usize;
    let mut out = vec![*q0];
    let mut worst = (0.0f64, 0.0f64);
    for i in 1..=n {
        let s0 = (i - 1) as f64 / n as f64;
        let s1 = i as f64 / n as f64;
        refine(solver, a, b, s0, s1, &mut out, 0, what, &mut worst, tol)?;
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn refine(
    solver: &IkSolver,
    a: &Isometry3<f64>,
    b: &Isometry3<f64>,
    s0: f64,
    s1: f64,
    out: &mut Vec<[f64; 6]>,
    depth: usize,
    what: &str,
    worst: &mut (f64, f64),
    tol: f64,
) -> Result<(), RobotError> {
    let q0 = *out.last().expect("starts with q0");
    let target = interp_pose(a, b, s1);
    let q1 = solver
        .track(&target, &q0)
        .or_else(|_| solver.solve_near(&target, &q0))?;
    let jump = max_abs_diff(&q0, &q1);
    let (pa, pb) = (a.translation.vector, b.translation.vector);
    // Position off the line, and orientation off the interpolated one: a held box reaches
    // ~0.05 m from the TCP, so a turn of ROT_TOLERANCE moves its corners by < 0.03 mm.
    let (mut dev, mut rot) = (0.0f64, 0.0f64);
    for u in [0.25, 0.5, 0.75] {
        let f = solver.fk(&lerp(&q0, &q1, u));
        dev = dev.max(line_distance(&f.translation.vector, &pa, &pb));
        let want = interp_pose(a, b, s0 + u * (s1 - s0));
        rot = rot.max(f.rotation.angle_to(&want.rotation));
    }
    if jump > MAX_LINE_STEP || dev > tol || rot > ROT_TOLERANCE * tol / LINE_TOLERANCE {
        worst.0 = worst.0.max(dev);
        worst.1 = worst.1.max(jump);
        if depth >= 14 {
            return Err(RobotError::Path {
                what: what.to_string(),
                deviation: worst.0,
                limit: tol,
                jump: worst.1,
            });
        }
        let sm = 0.5 * (s0 + s1);
        refine(solver, a, b, s0, sm, out, depth + 1, what, worst, tol)?;
        refine(solver, a, b, sm, s1, out, depth + 1, what, worst, tol)?;
    } else {
        out.push(q1);
    }
    Ok(())
}

/// Collision check of configurations `qs` of `arm` with hand `hand` during segment `seg`.
#[allow(clippy::too_many_arguments)]
fn check_samples(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    seg: usize,
    hand: &Hand,
    qs: &[[f64; 6]],
    what: &str,
    min_clear: &mut f64,
) -> Result<(), RobotError> {
    if ctx.scope == Scope::Kinematic {
        return Ok(());
    }
    let model = &ctx.inst.robot.model;
    let arm = solver.arm();
    let moving = matches!(action, Action::Push { .. }) && seg == 2;
    let fixed_obs = if moving {
        Vec::new()
    } else {
        ctx.obstacles(action, seg, None)
    };
    // The predicate discards the clearance (its answer is yes/no and the joint cost), and the
    // distance queries cost more than the boolean test they would follow.
    let report_clearance = ctx.scope == Scope::Full;
    for (k, q) in qs.iter().enumerate() {
        let parts = robot_parts(model, ctx.inst, arm, q, hand);
        let tcp = solver.fk(q).translation.vector;
        let moved_obs;
        let obs = if moving {
            moved_obs = ctx.obstacles(action, seg, Some(&tcp));
            &moved_obs
        } else {
            &fixed_obs
        };
        let skip = Ctx::skip(action, seg);
        if let Some((p, o)) = first_collision(&parts, obs, &skip) {
            return Err(RobotError::Collision {
                what: what.to_string(),
                part: p.name.clone(),
                obstacle: o.name.clone(),
                tcp: [tcp.x, tcp.y, tcp.z],
            });
        }
        // Clearance report on a subset of samples (it is slower than the boolean test).
        if report_clearance && (k % 8 == 0 || k + 1 == qs.len()) {
            *min_clear = min_clear.min(clearance(&parts, obs, &skip));
        }
    }
    Ok(())
}

/// Dense samples of a waypoint path for collision checks: every waypoint and intermediate
/// configurations no more than [`COLLISION_STEP`] apart.
fn densify(path: &[[f64; 6]]) -> Vec<[f64; 6]> {
    let mut out = vec![path[0]];
    for w in path.windows(2) {
        let n = (max_abs_diff(&w[0], &w[1]) / COLLISION_STEP).ceil().max(1.0) as usize;
        for i in 1..=n {
            out.push(lerp(&w[0], &w[1], i as f64 / n as f64));
        }
    }
    out
}

/// A move to `target` in joint space; where that collides, a straight line; where that collides
/// too and the start is below transfer height, straight up to transfer height first and then a
/// joint move (or a line). Returns the legs.
#[allow(clippy::too_many_arguments)]
fn joint_move(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    seg: usize,
    hand: &Hand,
    q: &[f64; 6],
    target: &Isometry3<f64>,
    what: &str,
    min_clear: &mut f64,
) -> Result<Legs, RobotError> {
    let check = |p: &[[f64; 6]], mc: &mut f64| check_samples(ctx, solver, action, seg, hand, &densify(p), what, mc);
    let from = solver.fk(q);
    // The predicate only needs some branch at the target (the joint move is not checked); the
    // nearest one costs a search over every IK seed when the move is long.
    let qt = if ctx.fast_ik {
        IkMemo::get(
            ctx.memo,
            || key_bits(1, solver.arm(), &[target], None, &[]),
            || solver.solve_any(target).map(|q| vec![q]),
        )?[0]
    } else {
        solver.solve_near(target, q)?
    };
    let joint = vec![*q, qt];
    if ctx.scope != Scope::Full {
        return Ok(vec![joint]);
    }
    let joint_err = match check(&joint, min_clear) {
        Ok(()) => return Ok(vec![joint]),
        Err(e) => e,
    };
    if let Ok(line) = follow_line(solver, q, &from, target, what) {
        if check(&line, min_clear).is_ok() {
            return Ok(vec![line]);
        }
    }
    let zt = super::keypoints::transfer_z(ctx.inst);
    if from.translation.vector.z < zt - 1e-6 {
        let mut up = from;
        up.translation.vector.z = zt;
        let Ok(rise) = follow_line(solver, q, &from, &up, what) else {
            return Err(joint_err);
        };
        if check(&rise, min_clear).is_err() {
            return Err(joint_err);
        }
        let q1 = *rise.last().expect("non-empty");
        let qt = solver.solve_near(target, &q1)?;
        let joint = vec![q1, qt];
        if check(&joint, min_clear).is_ok() {
            return Ok(vec![rise, joint]);
        }
        if let Ok(line) = follow_line(solver, &q1, &up, target, what) {
            if check(&line, min_clear).is_ok() {
                return Ok(vec![rise, line]);
            }
        }
    }
    Err(joint_err)
}

/// Plan one variant of an action for `arm` from `start` with the hand in `start_hand`.
fn plan_variant(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    specs: Vec<Spec>,
    start: &[f64; 6],
    start_hand: Hand,
) -> Result<Motion, RobotError> {
    let mut q = *start;
    let mut segments = Vec::new();
    let mut key_q = Vec::new();
    let mut min_clear = f64::INFINITY;
    let mut cost = 0.0;
    let name = action_label(ctx.inst, action);
    for (k, sp) in specs.iter().enumerate() {
        let hand = if k == 0 {
            start_hand
        } else {
            Hand {
                opening: specs[k - 1].opening,
                held: specs[k - 1].held,
            }
        };
        let what = format!("{name}, move to {}", sp.label);
        let from = solver.fk(&q);
        let legs: Legs = match sp.mv {
            Move::Line => {
                let tol = if ctx.fast_ik {
                    PREDICATE_LINE_TOLERANCE
                } else {
                    LINE_TOLERANCE
                };
                let p = IkMemo::get(
                    ctx.memo,
                    || key_bits(2, solver.arm(), &[&from, &sp.target], Some(&q), &[tol]),
                    || follow_line_tol(solver, &q, &from, &sp.target, &what, tol),
                )?;
                check_samples(ctx, solver, action, k, &hand, &densify(&p), &what, &mut min_clear)?;
                vec![p]
            }
            Move::Joint => joint_move(ctx, solver, action, k, &hand, &q, &sp.target, &what, &mut min_clear)?,
        };
        for path in &legs {
            for w in path.windows(2) {
                cost += (0..6).map(|j| (w[1][j] - w[0][j]).abs()).sum::<f64>();
            }
        }
        q = *legs.last().and_then(|l| l.last()).expect("non-empty");
        key_q.push(q);
        segments.push(legs);
    }
    let margin = key_q
        .iter()
        .map(|q| ctx.inst.robot.model.joint_margin(solver.arm(), q))
        .fold(f64::INFINITY, f64::min);
    Ok(Motion {
        segments,
        key_q,
        specs,
        cost: cost - 0.5 * margin.min(0.5),
        clearance: min_clear,
    })
}

/// Hand turned by π (at the table, in the container) in each variant of an action.
fn hand_variants(action: &Action) -> &'static [[bool; 2]] {
    match action {
        Action::Place { .. } => &[[false, false], [false, true], [true, false], [true, true]],
        Action::Push { .. } => &[[false, false], [true, false]],
    }
}

/// The hand variants of `action` (turned by 0 or π at the table and in the container) that are
/// kinematically feasible from `start`, ranked by joint motion (least first), and the first error
/// when some were not.
fn rank_variants(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    start: &[f64; 6],
    start_hand: Hand,
    notes: &mut Vec<String>,
) -> (Vec<(f64, [bool; 2])>, Option<RobotError>) {
    let flips = hand_variants(action);
    let mut ranked: Vec<(f64, [bool; 2])> = Vec::new();
    let mut first_err: Option<RobotError> = None;
    let free = Ctx {
        inst: ctx.inst,
        placement: ctx.placement,
        statics: Vec::new(),
        at: ctx.at.clone(),
        other: Vec::new(),
        scope: Scope::Kinematic,
        fast_ik: ctx.fast_ik,
        memo: ctx.memo,
    };
    for f in flips {
        let mut n = Vec::new();
        let sp = specs(ctx.inst, ctx.placement, action, *f, &mut n);
        if notes.is_empty() {
            notes.extend(n);
        }
        match plan_variant(&free, solver, action, sp, start, start_hand) {
            Ok(m) => ranked.push((m.cost, *f)),
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    (ranked, first_err)
}

/// Plan the best variant: the cheap kinematic pass ranks the variants by joint motion, the full
/// pass then takes the first (least motion) variant that is collision-free.
fn plan_action(
    ctx: &Ctx,
    solver: &IkSolver,
    action: &Action,
    start: &[f64; 6],
    start_hand: Hand,
    notes: &mut Vec<String>,
) -> Result<Motion, RobotError> {
    let (ranked, first_err) = rank_variants(ctx, solver, action, start, start_hand, notes);
    let mut errs: Vec<String> = Vec::new();
    for (_, f) in &ranked {
        let sp = specs(ctx.inst, ctx.placement, action, *f, &mut Vec::new());
        match plan_variant(ctx, solver, action, sp, start, start_hand) {
            Ok(m) => return Ok(m),
            Err(e) => {
                let e = e.to_string();
                if !errs.contains(&e) {
                    errs.push(e);
                }
            }
        }
    }
    match (errs.len(), first_err) {
        (0, e) => Err(e.expect("at least one variant")),
        // Every hand variant failed: say why each did, not just the first.
        (1, _) => Err(RobotError::Other(errs.remove(0))),
        _ => Err(RobotError::Other(format!(
            "every hand variant failed: {}",
            errs.join("; ")
        ))),
    }
}

/// Short label of an action (`place 1a`, `push 2a+4a`).
pub fn action_label(inst: &Instance, action: &Action) -> String {
    let ids: Vec<&str> = action.objects().iter().map(|&i| inst.objects[i].id.as_str()).collect();
    match action {
        Action::Place { .. } => format!("place {}", ids.join("+")),
        Action::Push { .. } => format!("push {}", ids.join("+")),
    }
}

/// The action with another executing arm.
pub fn with_arm(action: &Action, arm: Arm) -> Action {
    let mut a = action.clone();
    match &mut a {
        Action::Place { arm: x, .. } | Action::Push { arm: x, .. } => *x = arm,
    }
    a
}

/// What the action planner needs to know about one action for its own arm (see
/// [`action_reach`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Reach {
    /// Joint path length from home of the cheapest feasible hand variant (rad), minus half its
    /// smallest joint margin at the key poses (capped at 0.5 rad).
    pub cost: f64,
    /// For every feasible hand variant, the other objects that block it while they are still on
    /// the table (the open fingers, the hand or the held object would hit them during the grasp or
    /// the lift). Empty for pushes.
    pub table_blockers: Vec<Vec<usize>>,
}

impl Reach {
    /// Whether some hand variant is free, given which objects are still on the table.
    pub fn free_when(&self, on_table: impl Fn(usize) -> bool) -> bool {
        self.table_blockers.is_empty() || self.table_blockers.iter().any(|b| !b.iter().any(|&j| on_table(j)))
    }
}

/// Objects still on the table (other than the picked one) that collide with the grasp and lift
/// lines of a place motion.
fn blockers_of(ctx: &Ctx, solver: &IkSolver, action: &Action, m: &Motion) -> Vec<usize> {
    let Action::Place { object, .. } = action else {
        return Vec::new();
    };
    let inst = ctx.inst;
    let here = &inst.objects[*object].table;
    let near: Vec<(usize, Obstacle)> = (0..inst.n())
        .filter(|&j| j != *object)
        .filter(|&j| {
            let c = &inst.objects[j].table;
            (c.x - here.x).hypot(c.y - here.y) < 0.25
        })
        .map(|j| (j, object_on_table(inst, j)))
        .collect();
    let mut out = Vec::new();
    for seg in 1..=2 {
        let hand = Hand {
            opening: m.specs[seg - 1].opening,
            held: m.specs[seg - 1].held,
        };
        for leg in &m.segments[seg] {
            for q in densify(leg) {
                let parts = robot_parts(&inst.robot.model, inst, solver.arm(), &q, &hand);
                for (j, o) in &near {
                    if !out.contains(j) && first_collision(&parts, std::slice::from_ref(o), |_, _| false).is_some() {
                        out.push(*j);
                    }
                }
            }
        }
    }
    out.sort_unstable();
    out
}

/// The action planner's predicate for `action` with its own arm, from the arm's home pose: every
/// key pose reachable within the joint limits and every straight line followable, in some hand
/// orientation, and the straight lines of that variant free of the fixed cell (walls, floor
/// plate, table). Objects in the container are the finger and pusher slabs' job
/// ([`crate::actions::Layout::check`]); objects on the table are returned as blockers.
/// `None` when no hand variant passes.
pub fn action_reach(inst: &Instance, placement: &Placement, action: &Action) -> Option<Reach> {
    action_reach_memo(inst, placement, action, &RefCell::new(IkMemo::default()), false)
}

/// [`action_reach`] sharing IK results with earlier queries of the same instance (the memo must
/// not be shared across instances with different robots). With `first_free`, stops at the first
/// hand variant without table blockers: feasibility is then settled, but `cost` is that
/// variant's, not the least.
pub fn action_reach_memo(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    memo: &RefCell<IkMemo>,
    first_free: bool,
) -> Option<Reach> {
    let arm = action.arm();
    if !inst.robot.arms.contains(&arm) {
        return None;
    }
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: vec![ObjAt::Table; inst.n()],
        // The joint plan parks an idle arm at home when it is in the way, so the other arm at
        // home is part of the fixed cell.
        other: idle_arm(inst, arm.other(), &inst.robot.home[arm.other().index()], 0.0),
        scope: Scope::StaticLines,
        fast_ik: true,
        memo: Some(memo),
    };
    let solver = IkSolver::new(&inst.robot.model, arm, &inst.robot.tcp_offset);
    let home = inst.robot.home[arm.index()];
    let hand = Hand {
        opening: 0.0,
        held: None,
    };
    let mut cost = f64::INFINITY;
    let mut table_blockers = Vec::new();
    for f in hand_variants(action) {
        let sp = specs(inst, placement, action, *f, &mut Vec::new());
        if let Ok(m) = plan_variant(&ctx, &solver, action, sp, &home, hand) {
            cost = cost.min(m.cost);
            let b = blockers_of(&ctx, &solver, action, &m);
            let free = b.is_empty();
            if !table_blockers.contains(&b) {
                table_blockers.push(b);
            }
            if free && first_free {
                break;
            }
        }
    }
    cost.is_finite().then_some(Reach { cost, table_blockers })
}

/// Whether the action's arm can execute `action` when no other object is in the way (see
/// [`action_reach`]); table blockers are ignored here.
pub fn action_reachable(inst: &Instance, placement: &Placement, action: &Action) -> bool {
    action_reach(inst, placement, action).is_some()
}

/// The allowed arms that can execute `action` (each tried in place of the action's own arm).
pub fn arms_reaching(inst: &Instance, placement: &Placement, action: &Action) -> Vec<Arm> {
    inst.robot
        .arms
        .iter()
        .copied()
        .filter(|a| action_reachable(inst, placement, &with_arm(action, *a)))
        .collect()
}

/// The arm that executes `action` best: among the allowed arms that pass [`action_reach`], the
/// one with the least joint motion from its home pose (joint path length in rad, minus half the
/// smallest joint margin at the key poses, capped at 0.5 rad). `None` when no arm reaches.
pub fn select_arm(inst: &Instance, placement: &Placement, action: &Action) -> Option<Arm> {
    inst.robot
        .arms
        .iter()
        .filter_map(|a| action_reach(inst, placement, &with_arm(action, *a)).map(|r| (*a, r.cost)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(a, _)| a)
}

/// What an action does to the objects.
fn apply(at: &mut [ObjAt], placement: &Placement, action: &Action) {
    match action {
        Action::Place { object, mode, .. } => at[*object] = ObjAt::Floor(release_rect(placement, *object, mode)),
        Action::Push { objects, .. } => {
            for &i in objects {
                at[i] = ObjAt::Floor(placement.targets[i].rect);
            }
        }
    }
}

/// The `robot` section for an instance.
pub fn robot_info(inst: &Instance, opts: &TrajectoryOptions) -> RobotInfo {
    let m = &inst.robot.model;
    RobotInfo {
        model: inst.robot.model_path.clone(),
        tcp_offset: inst.robot.tcp_offset,
        base_frame: "WAIST".into(),
        tcp_frame: "TCP at tcp_offset in *ARM_JOINT5_Link; rotation columns: x = thick side of the hand \
                    (JOINT5_Link z), y = finger closing axis (JOINT5_Link y), z = approach (JOINT5_Link -x)"
            .into(),
        joint_names_left: m.joint_names(Arm::Left),
        joint_names_right: m.joint_names(Arm::Right),
        timing: *opts,
        velocity_limits: m.arms[0].iter().map(|j| j.velocity * opts.velocity_scale).collect(),
    }
}

fn vmax(inst: &Instance, arm: Arm) -> [f64; 6] {
    std::array::from_fn(|k| inst.robot.model.arms[arm.index()][k].velocity)
}

/// A move of an arm back to its home pose (to park it out of the other arm's way, or at the end):
/// up to transfer height above the home TCP, then down to home; each leg a joint move, or a
/// straight line where the joint move collides. Returns the legs (each timed from rest to rest)
/// and the smallest clearance.
#[allow(clippy::too_many_arguments)]
fn home_move(
    inst: &Instance,
    placement: &Placement,
    at: &[ObjAt],
    arm: Arm,
    from: &[f64; 6],
    hand: Hand,
    other: Vec<Obstacle>,
) -> Result<(Legs, f64), RobotError> {
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: at.to_vec(),
        other,
        scope: Scope::Full,
        fast_ik: false,
        memo: None,
    };
    let solver = IkSolver::new(&inst.robot.model, arm, &inst.robot.tcp_offset);
    // Obstacles of an idle move = every object where it is (an empty push sees them so).
    let idle = Action::Push {
        objects: vec![],
        push_dir: PushDir::MinusX,
        distance: 0.0,
        pusher_at: 0.0,
        arm,
    };
    let home = inst.robot.home[arm.index()];
    let home_pose = solver.fk(&home);
    let mut above = home_pose;
    above.translation.vector.z = above.translation.vector.z.max(super::keypoints::transfer_z(inst));
    let via = solver.solve_near(&above, &home)?;
    let what = format!("{} arm back home", arm.name());
    let mut clear = f64::INFINITY;
    let mut legs = Vec::new();
    let mut q = *from;
    for (target_q, target_pose) in [(via, above), (home, home_pose)] {
        let joint = vec![q, target_q];
        let leg = match check_samples(&ctx, &solver, &idle, 0, &hand, &densify(&joint), &what, &mut clear) {
            Ok(()) => joint,
            Err(e) => {
                let mut line = follow_line(&solver, &q, &solver.fk(&q), &target_pose, &what).map_err(|_| e.clone())?;
                if max_abs_diff(line.last().expect("non-empty"), &target_q) > 1e-6 {
                    return Err(e);
                }
                *line.last_mut().expect("non-empty") = target_q;
                check_samples(&ctx, &solver, &idle, 0, &hand, &densify(&line), &what, &mut clear).map_err(|_| e)?;
                line
            }
        };
        q = target_q;
        legs.push(leg);
    }
    Ok((legs, clear))
}

/// Time several rest-to-rest legs one after the other.
fn time_legs(legs: &[Vec<[f64; 6]>], v: &[f64; 6], opts: &TrajectoryOptions, t0: f64) -> (Vec<TrajPoint>, f64) {
    let mut points = Vec::new();
    let mut t = t0;
    for leg in legs {
        let (pts, t1) = time_segment(leg, v, opts, t);
        append(&mut points, pts);
        t = t1;
    }
    (points, t)
}

/// Key pose records of a motion, timed.
fn key_pose_records(inst: &Instance, arm: Arm, m: &Motion, times: &[f64]) -> Vec<KeyPose> {
    m.specs
        .iter()
        .zip(&m.key_q)
        .zip(times)
        .map(|((sp, q), t)| {
            let pose = inst.robot.model.tcp_pose(arm, q, &inst.robot.tcp_offset);
            let r = pose.rotation.to_rotation_matrix();
            let r = r.matrix();
            let p = pose.translation.vector;
            KeyPose {
                label: sp.label.clone(),
                position: [p.x, p.y, p.z],
                rotation: std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)])),
                joints: q.to_vec(),
                t: *t,
                opening: sp.opening,
            }
        })
        .collect()
}

fn append(points: &mut Vec<TrajPoint>, mut seg: Vec<TrajPoint>) {
    if !points.is_empty() && !seg.is_empty() {
        seg.remove(0);
    }
    points.extend(seg);
}

fn hold(points: &mut Vec<TrajPoint>, dt: f64) -> f64 {
    let last = points.last().expect("non-empty").clone();
    let t = last.t + dt;
    points.push(TrajPoint { t, ..last });
    t
}

/// Joint trajectories of a whole plan: the `robot` section and one record per action, plus park
/// moves of an idle arm that is in the way and the final moves back home. Never fails: an action
/// without a feasible motion gets a record with `error` set (and the verifier reports it).
pub fn plan_trajectories(
    inst: &Instance,
    placement: &Placement,
    actions: &[Action],
    opts: &TrajectoryOptions,
) -> (RobotInfo, Vec<ActionTrajectory>) {
    let model = &inst.robot.model;
    let mut q_cur = inst.robot.home;
    let mut hand_cur = [Hand {
        opening: 0.0,
        held: None,
    }; 2];
    let mut at = vec![ObjAt::Table; inst.n()];
    let mut t = 0.0;
    let mut out = Vec::new();
    let statics = static_obstacles(inst);
    let solvers = [Arm::Left, Arm::Right].map(|a| IkSolver::new(model, a, &inst.robot.tcp_offset));
    let idle_obstacles =
        |arm: Arm, q: &[f64; 6], hand: &Hand| arm_as_obstacles(robot_parts(model, inst, arm, q, hand), arm);
    let simple_record = |label: String, arm: Arm, pts: Vec<TrajPoint>, t0: f64, t1: f64, clear: f64| ActionTrajectory {
        action: None,
        label,
        arm,
        joint_names: model.joint_names(arm),
        t_start: t0,
        t_end: t1,
        points: pts,
        key_poses: Vec::new(),
        clearance: clear.is_finite().then_some(clear),
        notes: Vec::new(),
        error: None,
    };
    for (k, action) in actions.iter().enumerate() {
        let arm = action.arm();
        let other = arm.other();
        let label = action_label(inst, action);
        let mut notes = Vec::new();
        let record_err = |e: String, notes: Vec<String>, t: f64| ActionTrajectory {
            action: Some(k),
            label: label.clone(),
            arm,
            joint_names: model.joint_names(arm),
            t_start: t,
            t_end: t,
            points: Vec::new(),
            key_poses: Vec::new(),
            clearance: None,
            notes,
            error: Some(e),
        };
        if !inst.robot.arms.contains(&arm) {
            out.push(record_err(
                format!("the {} arm is not allowed by the instance", arm.name()),
                notes,
                t,
            ));
            apply(&mut at, placement, action);
            continue;
        }
        let mut ctx = Ctx {
            inst,
            placement,
            statics: statics.clone(),
            at: at.clone(),
            other: idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]),
            scope: Scope::Full,
            fast_ik: false,
            memo: None,
        };
        let solver = &solvers[arm.index()];
        // An idle arm whose hand hangs over the container is in the way of every action there:
        // park it at once (saves a failing first attempt); otherwise only when the action fails.
        let over_container = q_cur[other.index()] != inst.robot.home[other.index()] && {
            let p = model.tcp_position(other, &q_cur[other.index()], &inst.robot.tcp_offset);
            let c = to_container(inst, &p);
            let m = 0.05 + inst.container.wall_thickness;
            c[0] > -m && c[0] < inst.container.width + m && c[1] > -m && c[1] < inst.container.depth + m
        };
        let mut result = if over_container {
            Err(RobotError::Other("idle arm over the container".into()))
        } else {
            plan_action(
                &ctx,
                solver,
                action,
                &q_cur[arm.index()],
                hand_cur[arm.index()],
                &mut notes,
            )
        };
        // The idle arm in the way: park it at home first.
        if result.is_err() && q_cur[other.index()] != inst.robot.home[other.index()] {
            let park = home_move(
                inst,
                placement,
                &at,
                other,
                &q_cur[other.index()],
                hand_cur[other.index()],
                idle_obstacles(arm, &q_cur[arm.index()], &hand_cur[arm.index()]),
            );
            if let Ok((legs, clear)) = park {
                let (pts, t1) = time_legs(&legs, &vmax(inst, other), opts, t);
                out.push(simple_record(
                    format!("park {}", other.name()),
                    other,
                    pts,
                    t,
                    t1,
                    clear,
                ));
                t = t1;
                q_cur[other.index()] = inst.robot.home[other.index()];
                ctx.other = idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]);
                notes.clear();
                result = plan_action(
                    &ctx,
                    solver,
                    action,
                    &q_cur[arm.index()],
                    hand_cur[arm.index()],
                    &mut notes,
                );
            }
        }
        match result {
            Ok(m) => {
                let t0 = t;
                let mut points: Vec<TrajPoint> = Vec::new();
                let mut times = Vec::new();
                let v = vmax(inst, arm);
                for (s, legs) in m.segments.iter().enumerate() {
                    let (pts, t1) = time_legs(legs, &v, opts, t);
                    append(&mut points, pts);
                    t = t1;
                    // The gripper closes at the grasp and opens at the release.
                    if matches!(action, Action::Place { .. }) && (s == 1 || s == 4) {
                        times.push(t);
                        t = hold(&mut points, GRIPPER_DWELL);
                    } else {
                        times.push(t);
                    }
                }
                let key_poses = key_pose_records(inst, arm, &m, &times);
                q_cur[arm.index()] = *m.key_q.last().expect("key poses");
                hand_cur[arm.index()] = Hand {
                    opening: m.specs.last().map(|s| s.opening).unwrap_or(0.0),
                    held: None,
                };
                out.push(ActionTrajectory {
                    action: Some(k),
                    label: label.clone(),
                    arm,
                    joint_names: model.joint_names(arm),
                    t_start: t0,
                    t_end: t,
                    points,
                    key_poses,
                    clearance: m.clearance.is_finite().then_some(m.clearance),
                    notes,
                    error: None,
                });
            }
            Err(e) => out.push(record_err(e.to_string(), notes, t)),
        }
        apply(&mut at, placement, action);
    }
    // Back home.
    for arm in [Arm::Left, Arm::Right] {
        let home = inst.robot.home[arm.index()];
        if q_cur[arm.index()] == home {
            continue;
        }
        let other = arm.other();
        let res = home_move(
            inst,
            placement,
            &at,
            arm,
            &q_cur[arm.index()],
            hand_cur[arm.index()],
            idle_obstacles(other, &q_cur[other.index()], &hand_cur[other.index()]),
        );
        match res {
            Ok((legs, clear)) => {
                let (pts, t1) = time_legs(&legs, &vmax(inst, arm), opts, t);
                out.push(simple_record(format!("home {}", arm.name()), arm, pts, t, t1, clear));
                t = t1;
                q_cur[arm.index()] = home;
            }
            Err(e) => {
                let mut r = simple_record(format!("home {}", arm.name()), arm, Vec::new(), t, t, f64::INFINITY);
                r.error = Some(e.to_string());
                out.push(r);
            }
        }
    }
    (robot_info(inst, opts), out)
}

/// The hand during segment `seg` of `action` (segment k ends at key pose k), given the openings
/// recorded at the key poses and the opening before the action.
pub(crate) fn segment_hand(
    inst: &Instance,
    placement: &Placement,
    action: &Action,
    seg: usize,
    openings: &[f64],
    before: f64,
) -> Hand {
    if seg == 0 {
        return Hand {
            opening: before,
            held: None,
        };
    }
    let opening = openings.get(seg - 1).copied().unwrap_or(before);
    let held = match action {
        Action::Place {
            object,
            mode,
            grasp_axis,
            ..
        } => match seg {
            2 | 3 => {
                let (_, closing, other, height, _) = table_grasp(inst, placement, *object, *grasp_axis);
                Some(Held {
                    object: *object,
                    closing,
                    other,
                    height,
                })
            }
            4 => {
                let rel = release_rect(placement, *object, mode);
                Some(Held {
                    object: *object,
                    closing: rel.extent(*grasp_axis),
                    other: rel.extent(grasp_axis.other()),
                    height: placement.targets[*object].height,
                })
            }
            _ => None,
        },
        Action::Push { .. } => None,
    };
    Hand { opening, held }
}

/// The first collision of `arm` at `q` with hand `hand` during segment `seg` of `action` (or of
/// an idle move when `action` is `None`), objects placed as in `at`, the other arm's parts in
/// `other`: (robot part, obstacle).
#[allow(clippy::too_many_arguments)]
pub(crate) fn collision_at(
    inst: &Instance,
    placement: &Placement,
    at: &[ObjAt],
    action: Option<&Action>,
    seg: usize,
    hand: &Hand,
    arm: Arm,
    q: &[f64; 6],
    other: &[Obstacle],
) -> Option<(String, String)> {
    let ctx = Ctx {
        inst,
        placement,
        statics: static_obstacles(inst),
        at: at.to_vec(),
        other: other.to_vec(),
        scope: Scope::Full,
        fast_ik: false,
        memo: None,
    };
    let idle = Action::Push {
        objects: vec![],
        push_dir: PushDir::MinusX,
        distance: 0.0,
        pusher_at: 0.0,
        arm,
    };
    let (action, seg) = match action {
        Some(a) => (a, seg),
        None => (&idle, 0),
    };
    let parts = robot_parts(&inst.robot.model, inst, arm, q, hand);
    let tcp = inst.robot.model.tcp_position(arm, q, &inst.robot.tcp_offset);
    let obs = ctx.obstacles(action, seg, Some(&tcp));
    first_collision(&parts, &obs, Ctx::skip(action, seg)).map(|(p, o)| (p.name.clone(), o.name.clone()))
}

/// Apply an action's effect on object positions (for replays).
pub(crate) fn apply_action(at: &mut [ObjAt], placement: &Placement, action: &Action) {
    apply(at, placement, action)
}

/// The idle arm's parts as obstacles.
pub(crate) fn idle_arm(inst: &Instance, arm: Arm, q: &[f64; 6], opening: f64) -> Vec<Obstacle> {
    arm_as_obstacles(
        robot_parts(&inst.robot.model, inst, arm, q, &Hand { opening, held: None }),
        arm,
    )
}

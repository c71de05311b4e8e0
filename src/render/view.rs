//! `view.html`: the plan played in 3-D in any browser, without ROS or a server.
//!
//! The page is self-contained (no scripts or styles fetched from anywhere): the frames are
//! computed here and embedded as JSON, and a small canvas renderer draws them. Every
//! `FRAME_DT` seconds of plan time a frame holds every solid as an oriented box: both arms'
//! collision primitives at their interpolated joint angles (the model's link primitives drawn as
//! their bounding boxes, the hand housing, the finger plates at their opening), and every object
//! where it is at that moment — on the table, carried by the fingers, at its release pose,
//! driven by the pusher, at its target. The container walls and the table are drawn once.

use super::kind_colour;
use crate::actions::Action;
use crate::error::Result;
use crate::geometry::parry_bridge::Solid;
use crate::geometry::Arm;
use crate::instance::Instance;
use crate::motion::collision::{object_in_container, object_on_table, robot_parts, static_obstacles, ObstacleKind};
use crate::motion::collision::{Hand, PartKind};
use crate::motion::joint_plan::segment_hand;
use crate::motion::ActionTrajectory;
use crate::placement::Placement;
use crate::plan::Plan;
use nalgebra::{Isometry3, Translation3, Vector3};
use std::fmt::Write;

/// Index of a place's `release` key pose (pre-grasp, grasp, lift, pre-place, release, retreat).
const RELEASE: usize = 4;

/// Plan time between two frames (s): smooth enough to follow a push (20 mm/s → 5 mm a frame).
const FRAME_DT: f64 = 0.25;

/// Colours of the robot and the cell, after the objects' kind colours (indices 0..10).
const LINK: usize = 10;
const FINGER: usize = 11;
const WALL: usize = 12;
const TABLE: usize = 13;
const CELL_COLOURS: [&str; 4] = ["#9aa3ad", "#262626", "#8c6d4f", "#e8e2d6"];

/// A box to draw: colour index, half extents and pose.
struct Drawn {
    colour: usize,
    half: Vector3<f64>,
    pose: Isometry3<f64>,
}

impl Drawn {
    fn from_solid(colour: usize, solid: &Solid, pose: Isometry3<f64>) -> Drawn {
        let half = match *solid {
            Solid::Cuboid { half } => half,
            Solid::Cylinder { radius, half_length } => Vector3::new(radius, radius, half_length),
            Solid::Ball { radius } => Vector3::repeat(radius),
            Solid::Capsule { a, b, radius } => {
                // Centred between its ends, along z of a frame turned onto a → b.
                let mid = (a + b) / 2.0;
                let axis = b - a;
                let rot = nalgebra::UnitQuaternion::rotation_between(&Vector3::z(), &axis)
                    .unwrap_or_else(nalgebra::UnitQuaternion::identity);
                return Drawn {
                    colour,
                    half: Vector3::new(radius, radius, axis.norm() / 2.0 + radius),
                    pose: pose * Isometry3::from_parts(Translation3::from(mid), rot),
                };
            }
        };
        Drawn { colour, half, pose }
    }

    /// `[colour, hx, hy, hz, x, y, z, qw, qx, qy, qz]`, lengths in mm.
    fn write(&self, out: &mut String) {
        let p = self.pose.translation.vector * 1000.0;
        let h = self.half * 1000.0;
        let q = self.pose.rotation.quaternion();
        let _ = write!(
            out,
            "[{},{:.1},{:.1},{:.1},{:.1},{:.1},{:.1},{:.4},{:.4},{:.4},{:.4}]",
            self.colour, h.x, h.y, h.z, p.x, p.y, p.z, q.w, q.i, q.j, q.k
        );
    }
}

/// Joint angles of a trajectory at time `t`, linear between its points.
fn joints_at(tr: &ActionTrajectory, t: f64) -> [f64; 6] {
    let pts = &tr.points;
    let k = pts.partition_point(|p| p.t <= t).clamp(1, pts.len().max(1));
    let (a, b) = (&pts[k - 1], &pts[k.min(pts.len() - 1)]);
    let u = if b.t > a.t {
        ((t - a.t) / (b.t - a.t)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    std::array::from_fn(|j| a.positions[j] + u * (b.positions[j] - a.positions[j]))
}

/// Where every object is while the plan runs.
struct Objects {
    /// Current pose and half extents per object.
    now: Vec<(Isometry3<f64>, Vector3<f64>)>,
    /// Poses at the start of the push being played (per object of its line), once it started.
    push_start: Option<(usize, Vec<Isometry3<f64>>)>,
}

impl Objects {
    fn new(inst: &Instance) -> Objects {
        let now = (0..inst.n())
            .map(|i| {
                let o = object_on_table(inst, i);
                let Solid::Cuboid { half } = o.solid else {
                    unreachable!("objects are boxes")
                };
                (o.pose, half)
            })
            .collect();
        Objects { now, push_start: None }
    }

    /// Move the objects of push `a` (index `k`) for the pusher's TCP at `tcp`: each object starts
    /// when the pusher has closed the gaps behind it, then moves with it up to its target.
    fn push(
        &mut self,
        inst: &Instance,
        placement: &Placement,
        k: usize,
        a: &Action,
        tr: &ActionTrajectory,
        tcp: Vector3<f64>,
    ) {
        let Action::Push { objects, .. } = a else { return };
        let (Some(s), Some(e)) = (
            tr.key_poses.iter().find(|p| p.label == "push-start"),
            tr.key_poses.iter().find(|p| p.label == "push-end"),
        ) else {
            return;
        };
        let (s, e) = (Vector3::from(s.position), Vector3::from(e.position));
        let total = (e - s).norm();
        if total <= 0.0 {
            return;
        }
        let u = (e - s) / total;
        if self.push_start.as_ref().map(|(j, _)| *j) != Some(k) {
            self.push_start = Some((k, objects.iter().map(|&i| self.now[i].0).collect()));
        }
        let travelled = (tcp - s).dot(&u).clamp(0.0, total);
        let starts = &self.push_start.as_ref().expect("set above").1;
        for (n, &i) in objects.iter().enumerate() {
            let t = &placement.targets[i];
            let target = object_in_container(inst, i, &t.rect, t.height).pose;
            let need = (target.translation.vector - starts[n].translation.vector)
                .dot(&u)
                .max(0.0);
            let moved = (travelled - (total - need)).clamp(0.0, need);
            let mut p = starts[n];
            p.translation.vector += u * moved;
            self.now[i].0 = p;
        }
    }
}

/// The page for `plan` (which must carry trajectories).
pub fn view_html(inst: &Instance, plan: &Plan) -> Result<String> {
    let placement = plan.placement(inst)?;
    let actions = plan.actions(inst)?;
    let model = &inst.robot.model;
    let mut trs: [Vec<&ActionTrajectory>; 2] = [Vec::new(), Vec::new()];
    for tr in plan.trajectories.iter().filter(|t| !t.points.is_empty()) {
        trs[tr.arm.index()].push(tr);
    }
    let end = plan.trajectories.iter().map(|t| t.t_end).fold(0.0, f64::max);

    let mut statics = String::new();
    for (n, o) in static_obstacles(inst).iter().enumerate() {
        let colour = if o.kind == ObstacleKind::Table { TABLE } else { WALL };
        if n > 0 {
            statics.push(',');
        }
        Drawn::from_solid(colour, &o.solid, o.pose).write(&mut statics);
    }

    let mut objects = Objects::new(inst);
    let mut opening = [inst.gripper.max_opening; 2];
    // Places whose object was set at its release pose already (once per place is enough).
    let mut released = vec![false; actions.len()];
    let mut frames = String::new();
    let n_frames = (end / FRAME_DT).ceil() as usize + 1;
    for f in 0..n_frames {
        let t = (f as f64 * FRAME_DT).min(end);
        let mut drawn: Vec<Drawn> = Vec::new();
        for arm in [Arm::Left, Arm::Right] {
            let list = &trs[arm.index()];
            // The arm's trajectory now, else the last one it finished, else its home.
            let cur = list.iter().rev().find(|tr| tr.t_start <= t + 1e-9);
            let (q, hand, active) = match cur {
                None => (
                    inst.robot.home[arm.index()],
                    Hand {
                        opening: opening[arm.index()],
                        held: None,
                    },
                    None,
                ),
                Some(tr) => {
                    let q = joints_at(tr, t);
                    // The opening the arm last set: parks and returns home keep it (they have no
                    // key poses of their own).
                    let before = list
                        .iter()
                        .rev()
                        .filter(|p| !p.key_poses.is_empty())
                        .find(|p| p.t_end <= tr.t_start + 1e-9)
                        .and_then(|p| p.key_poses.last())
                        .map(|k| k.opening)
                        .unwrap_or(inst.gripper.max_opening);
                    let openings: Vec<f64> = tr.key_poses.iter().map(|k| k.opening).collect();
                    let seg = tr
                        .key_poses
                        .iter()
                        .position(|k| k.t >= t - 1e-9)
                        .unwrap_or(tr.key_poses.len());
                    let hand = match tr.action.and_then(|a| actions.get(a)) {
                        Some(a) if t <= tr.t_end => segment_hand(inst, &placement, a, seg, &openings, before),
                        _ => Hand {
                            opening: openings.last().copied().unwrap_or(before),
                            held: None,
                        },
                    };
                    opening[arm.index()] = hand.opening;
                    if let Some((k, a @ Action::Place { .. })) = tr.action.and_then(|k| Some((k, actions.get(k)?))) {
                        // Past the release, the object stands exactly where it was let go (a
                        // frame may fall a little before the release pose).
                        if seg > RELEASE && tr.key_poses.len() > RELEASE && !released[k] {
                            released[k] = true;
                            let at = &tr.key_poses[RELEASE].joints;
                            if let Ok(qr) = <[f64; 6]>::try_from(at.as_slice()) {
                                let h = segment_hand(inst, &placement, a, RELEASE, &openings, before);
                                for p in robot_parts(model, inst, arm, &qr, &h) {
                                    if let (PartKind::Held, Some(held), Solid::Cuboid { half }) =
                                        (p.kind, h.held, p.solid)
                                    {
                                        objects.now[held.object] = (p.pose, half);
                                    }
                                }
                            }
                        }
                    }
                    (q, hand, (t <= tr.t_end).then_some(tr))
                }
            };
            for p in robot_parts(model, inst, arm, &q, &hand) {
                match p.kind {
                    PartKind::Held => {
                        if let Some(h) = hand.held {
                            let Solid::Cuboid { half } = p.solid else { continue };
                            objects.now[h.object] = (p.pose, half);
                        }
                    }
                    PartKind::Finger => drawn.push(Drawn::from_solid(FINGER, &p.solid, p.pose)),
                    PartKind::Link => drawn.push(Drawn::from_solid(LINK, &p.solid, p.pose)),
                }
            }
            if let Some(tr) = active {
                if let Some(k) = tr.action {
                    if let Some(a @ Action::Push { .. }) = actions.get(k) {
                        let tcp = model.tcp_pose(arm, &q, &inst.robot.tcp_offset).translation.vector;
                        objects.push(inst, &placement, k, a, tr, tcp);
                    }
                }
            }
        }
        for (i, (pose, half)) in objects.now.iter().enumerate() {
            drawn.push(Drawn {
                colour: inst.objects[i].kind % 10,
                half: *half,
                pose: *pose,
            });
        }
        frames.push_str(if f == 0 { "[" } else { ",\n[" });
        let _ = write!(frames, "{t:.2},[");
        for (n, d) in drawn.iter().enumerate() {
            if n > 0 {
                frames.push(',');
            }
            d.write(&mut frames);
        }
        frames.push_str("]]");
    }

    Ok(page(inst, plan, end, &statics, &frames))
}

/// The page around the frames: the colours of the object kinds and the cell, the trajectory
/// labels for the caption, the data as JSON inside the script.
fn page(inst: &Instance, plan: &Plan, end: f64, statics: &str, frames: &str) -> String {
    let mut colours: Vec<String> = (0..10)
        .map(|k| {
            let i = inst.objects.iter().position(|o| o.kind % 10 == k).unwrap_or(0);
            format!("\"{}\"", if inst.n() > 0 { kind_colour(inst, i) } else { "#999999" })
        })
        .collect();
    colours.extend(CELL_COLOURS.iter().map(|c| format!("\"{c}\"")));
    let labels: Vec<String> = plan
        .trajectories
        .iter()
        .map(|t| format!("[{:.2},{:.2},{}]", t.t_start, t.t_end, json_string(&t.label)))
        .collect();
    let data = format!(
        "{{\"name\":{},\"end\":{end:.2},\"colours\":[{}],\"statics\":[{statics}],\"labels\":[{}],\"frames\":[{frames}]}}",
        json_string(&inst.name),
        colours.join(","),
        labels.join(","),
    );
    // `<` escaped inside the script, so that no id (`</script>`) can end it; the title first,
    // so that no name in the data is taken for the title's slot.
    let data = data.replace('<', "\\u003c");
    PAGE.replace("{{TITLE}}", &html_escape(&inst.name))
        .replace("/*DATA*/null", &data)
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The page: a canvas, a play button, a time slider and a speed choice; drag to turn the view,
/// wheel to zoom. `#status` says what was drawn (the browser test reads it).
const PAGE: &str = include_str!("view.html");

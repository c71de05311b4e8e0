//! Stage 2: packing actions (place direct / place indirect / push a line) and their feasibility
//! in a given floor state, including push mechanics.
//!
//! [`Layout`] is the mutable floor state (which object is where); [`Layout::check`] decides
//! whether an action can run now and [`Layout::apply`] runs it. Feasibility covers the finger
//! slabs (3-D, parry3d), swept space, the container, and push stability ([`push`]).

pub mod push;
pub mod veto;

use crate::geometry::Arm;
use crate::geometry::{Axis2, Box3, PushDir, Rect, EPS};
use crate::instance::{Gripper, Instance};
use crate::placement::Placement;
use serde::{Deserialize, Serialize};

/// How an object is released.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "mode", rename_all = "lowercase")]
pub enum PlaceMode {
    /// Released at its target.
    Direct,
    /// Released at `target − offset · push_dir`, to be pushed later.
    Indirect {
        /// Direction of the later push.
        push_dir: PushDir,
        /// Distance from the target against `push_dir` (m).
        offset: f64,
    },
}

/// One robot action.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Action {
    /// Pick an object from the table and release it in the container.
    Place {
        /// Object index.
        object: usize,
        /// Direct or indirect.
        #[serde(flatten)]
        mode: PlaceMode,
        /// Horizontal axis of C along which the fingers close.
        grasp_axis: Axis2,
        /// Arm that executes it.
        arm: Arm,
    },
    /// Push a line of released objects to their targets with the back of the closed fingers.
    Push {
        /// Object indices, front (nearest the destination) to back (touched by the pusher).
        objects: Vec<usize>,
        /// Push direction.
        push_dir: PushDir,
        /// Pusher travel after first contact = the back object's offset (m).
        distance: f64,
        /// Lateral coordinate in C of the pusher's centre line (y for −x pushes, x for −y).
        pusher_at: f64,
        /// Arm that executes it.
        arm: Arm,
    },
}

impl Action {
    /// Objects the action moves.
    pub fn objects(&self) -> Vec<usize> {
        match self {
            Action::Place { object, .. } => vec![*object],
            Action::Push { objects, .. } => objects.clone(),
        }
    }
    /// Executing arm.
    pub fn arm(&self) -> Arm {
        match self {
            Action::Place { arm, .. } | Action::Push { arm, .. } => *arm,
        }
    }
}

/// Where an object is at some moment of a plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ObjState {
    /// Still on the table.
    Table,
    /// Released in the container at this footprint, waiting for a push.
    Released {
        /// Footprint.
        rect: Rect,
        /// Direction of the pending push.
        push_dir: PushDir,
        /// Offset from the target.
        offset: f64,
    },
    /// At its target.
    Done,
}

/// Why an action cannot run now.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Infeasible {
    /// Violated condition class (`overlap`, `wall`, `finger_slab`, `swept_space`, `side_contact`,
    /// `push_stability`, `precedence`, `gripper_opening`).
    pub class: String,
    /// Human-readable detail.
    pub detail: String,
}

fn infeasible(class: &str, detail: String) -> Infeasible {
    Infeasible {
        class: class.into(),
        detail,
    }
}

/// The mutable floor state during planning: a cheap, clonable snapshot (save/restore = clone).
#[derive(Debug, Clone)]
pub struct Layout<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    /// State of each object.
    pub state: Vec<ObjState>,
    /// Count every box at its target as held against a push ([`push::side::side_failure`]'s
    /// `assume_held`): set by the sequencers' bounds, which must stay monotone.
    pub assume_held: bool,
    /// Actions a physics replay rejected in a neighbourhood ([`veto`]); ignored while
    /// `assume_held` is set, so that bounds stay relaxations.
    pub vetoes: Option<std::sync::Arc<[veto::Veto]>>,
}

/// Height of the space above the container that fingers and pushers sweep through (m); any
/// object or wall lower than this blocks a slab that overlaps it horizontally.
pub const SLAB_TOP: f64 = 10.0;

/// Something a finger or pusher slab can hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Obstacle {
    Wall(usize),
    Object(usize),
}

/// Finger slabs of a grasp of footprint `r` (height `h`) along `axis`: thickness plus release
/// clearance beside each face, finger width centred on the face, from `h − grasp_depth` up.
pub fn finger_slabs(g: &Gripper, r: &Rect, h: f64, axis: Axis2) -> [Box3; 2] {
    let t = g.finger_thickness + g.release_clearance;
    let c = r.center();
    let z0 = (h - g.grasp_depth).max(0.0);
    let half = g.finger_width / 2.0;
    match axis {
        Axis2::X => [
            Box3::extrude(
                &Rect {
                    x0: r.x0 - t,
                    x1: r.x0,
                    y0: c[1] - half,
                    y1: c[1] + half,
                },
                z0,
                SLAB_TOP,
            ),
            Box3::extrude(
                &Rect {
                    x0: r.x1,
                    x1: r.x1 + t,
                    y0: c[1] - half,
                    y1: c[1] + half,
                },
                z0,
                SLAB_TOP,
            ),
        ],
        Axis2::Y => [
            Box3::extrude(
                &Rect {
                    y0: r.y0 - t,
                    y1: r.y0,
                    x0: c[0] - half,
                    x1: c[0] + half,
                },
                z0,
                SLAB_TOP,
            ),
            Box3::extrude(
                &Rect {
                    y0: r.y1,
                    y1: r.y1 + t,
                    x0: c[0] - half,
                    x1: c[0] + half,
                },
                z0,
                SLAB_TOP,
            ),
        ],
    }
}

/// Pusher slab (closed fingers) behind footprint `back` for a push along `dir`, centred at
/// lateral coordinate `at`, `finger_thickness + extra` deep, from the push height up.
pub fn pusher_slab(g: &Gripper, back: &Rect, dir: PushDir, at: f64, extra: f64) -> Box3 {
    let t = g.finger_thickness + extra;
    let half = g.finger_width / 2.0;
    let r = match dir {
        PushDir::MinusX => Rect {
            x0: back.x1,
            x1: back.x1 + t,
            y0: at - half,
            y1: at + half,
        },
        PushDir::MinusY => Rect {
            y0: back.y1,
            y1: back.y1 + t,
            x0: at - half,
            x1: at + half,
        },
    };
    Box3::extrude(&r, g.push_height, SLAB_TOP)
}

impl<'a> Layout<'a> {
    /// Every object on the table.
    pub fn new(inst: &'a Instance, placement: &'a Placement) -> Layout<'a> {
        Layout {
            inst,
            placement,
            state: vec![ObjState::Table; inst.n()],
            assume_held: false,
            vetoes: None,
        }
    }

    /// Current footprint of an object in the container, if it is there.
    pub fn rect_of(&self, i: usize) -> Option<Rect> {
        match self.state[i] {
            ObjState::Table => None,
            ObjState::Released { rect, .. } => Some(rect),
            ObjState::Done => Some(self.placement.targets[i].rect),
        }
    }

    /// Boxes (in C) of everything in the container except the listed objects.
    fn obstacles<'s>(&'s self, except: &'s [usize]) -> impl Iterator<Item = (Obstacle, Box3)> + 's {
        let walls = self
            .inst
            .container
            .walls()
            .into_iter()
            .enumerate()
            .map(|(k, b)| (Obstacle::Wall(k), b));
        let objects = (0..self.inst.n())
            .filter(move |i| !except.contains(i))
            .filter_map(move |i| {
                self.rect_of(i).map(|r| {
                    (
                        Obstacle::Object(i),
                        Box3::extrude(&r, 0.0, self.placement.targets[i].height),
                    )
                })
            });
        walls.chain(objects)
    }

    /// Finger slabs of a grasp of footprint `r` (height `h`) along `axis`: thickness plus release
    /// clearance beside each face, finger width centred, from `h − grasp_depth` up.
    pub fn finger_slabs(&self, r: &Rect, h: f64, axis: Axis2) -> [Box3; 2] {
        finger_slabs(&self.inst.gripper, r, h, axis)
    }

    /// Pusher slab behind a footprint `back` for a push along `dir`, at lateral coordinate `at`,
    /// `extra` metres deep beyond the finger thickness (the release clearance when lowering).
    pub fn pusher_slab(&self, back: &Rect, dir: PushDir, at: f64, extra: f64) -> Box3 {
        pusher_slab(&self.inst.gripper, back, dir, at, extra)
    }

    fn first_hit(&self, slab: &Box3, except: &[usize]) -> Option<String> {
        self.obstacles(except)
            .find(|(_, b)| b.intersects(slab))
            .map(|(o, _)| match o {
                Obstacle::Wall(k) => format!("wall {k}"),
                Obstacle::Object(i) => self.inst.objects[i].id.clone(),
            })
    }

    /// Footprint at which a place action releases its object.
    pub fn release_rect(&self, object: usize, mode: &PlaceMode) -> Rect {
        let t = self.placement.targets[object].rect;
        match mode {
            PlaceMode::Direct => t,
            PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
        }
    }

    /// Whether `action` can run in the current state; the push-stability margin when it is a push.
    pub fn check(&self, action: &Action) -> Result<Option<f64>, Infeasible> {
        if let Some(v) = self.vetoes.as_ref().filter(|_| !self.assume_held) {
            if let Some(v) = v.iter().find(|v| v.rejects(self, action)) {
                return Err(infeasible("physics", v.reason.clone()));
            }
        }
        match action {
            Action::Place {
                object,
                mode,
                grasp_axis,
                ..
            } => self.check_place(*object, mode, *grasp_axis),
            Action::Push {
                objects,
                push_dir,
                distance,
                pusher_at,
                ..
            } => {
                self.check_line(objects, *push_dir, *distance)?;
                self.check_push_space(objects, *push_dir, *pusher_at)?;
                self.check_side_contacts(objects, *push_dir)?;
                self.check_push_stability(objects, *push_dir, *pusher_at).map(Some)
            }
        }
    }

    /// A place: the object is on the table, and its release fits the gripper, the floor, the
    /// objects already in the container and the finger slabs.
    fn check_place(&self, i: usize, mode: &PlaceMode, grasp_axis: Axis2) -> Result<Option<f64>, Infeasible> {
        let inst = self.inst;
        let floor = inst.container.floor();
        if self.state[i] != ObjState::Table {
            return Err(infeasible(
                "precedence",
                format!("{} is not on the table", inst.objects[i].id),
            ));
        }
        if let PlaceMode::Indirect { offset, .. } = mode {
            if *offset < inst.gripper.min_offset - EPS {
                return Err(infeasible(
                    "finger_slab",
                    format!(
                        "offset {:.4} m is below the minimum {:.4} m",
                        offset, inst.gripper.min_offset
                    ),
                ));
            }
        }
        let r = self.release_rect(i, mode);
        let h = self.placement.targets[i].height;
        if r.extent(grasp_axis) + 2.0 * inst.gripper.release_clearance > inst.gripper.max_opening + EPS {
            return Err(infeasible(
                "gripper_opening",
                format!("{} is too wide along the grasp axis", inst.objects[i].id),
            ));
        }
        if !r.inside(&floor) {
            return Err(infeasible(
                "wall",
                format!("release footprint of {} leaves the floor", inst.objects[i].id),
            ));
        }
        for j in 0..inst.n() {
            if let Some(rj) = self.rect_of(j) {
                if rj.overlaps(&r) {
                    return Err(infeasible(
                        "overlap",
                        format!("release of {} overlaps {}", inst.objects[i].id, inst.objects[j].id),
                    ));
                }
            }
        }
        for slab in self.finger_slabs(&r, h, grasp_axis) {
            if let Some(hit) = self.first_hit(&slab, &[i]) {
                return Err(infeasible(
                    "finger_slab",
                    format!("finger slab of {} hits {hit}", inst.objects[i].id),
                ));
            }
        }
        Ok(None)
    }

    /// A push's objects form a line ready for it: released against `push_dir` with offsets that
    /// do not decrease toward the back, `distance` the back object's offset, targets touching.
    fn check_line(&self, objects: &[usize], push_dir: PushDir, distance: f64) -> Result<(), Infeasible> {
        let inst = self.inst;
        if objects.is_empty() {
            return Err(infeasible("precedence", "push of no objects".into()));
        }
        let mut max_off: f64 = 0.0;
        for (k, &i) in objects.iter().enumerate() {
            match self.state[i] {
                ObjState::Released {
                    push_dir: d, offset, ..
                } if d == push_dir => {
                    max_off = max_off.max(offset);
                    if k + 1 < objects.len() {
                        let next = objects[k + 1];
                        if let ObjState::Released { offset: o2, .. } = self.state[next] {
                            if o2 + EPS < offset {
                                return Err(infeasible(
                                    "precedence",
                                    "line offsets must not decrease toward the back".into(),
                                ));
                            }
                        }
                    }
                }
                _ => {
                    return Err(infeasible(
                        "precedence",
                        format!("{} is not released for a {:?} push", inst.objects[i].id, push_dir),
                    ))
                }
            }
        }
        let back = *objects.last().expect("non-empty");
        if let ObjState::Released { offset, .. } = self.state[back] {
            if (offset - max_off).abs() > EPS || (distance - offset).abs() > EPS {
                return Err(infeasible(
                    "precedence",
                    "push distance must equal the back object's offset".into(),
                ));
            }
        }
        // Targets of consecutive objects must touch along the push axis.
        let axis = push_dir.axis();
        for w in objects.windows(2) {
            let (a, b) = (self.placement.targets[w[0]].rect, self.placement.targets[w[1]].rect);
            if (a.hi(axis) - b.lo(axis)).abs() > EPS || a.overlap_on(&b, axis.other()) <= EPS {
                return Err(infeasible(
                    "precedence",
                    format!(
                        "{} and {} do not form a line",
                        inst.objects[w[0]].id, inst.objects[w[1]].id
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The pusher lowers behind the back object without a hit, and neither the objects nor the
    /// pusher sweep through anything on their way.
    fn check_push_space(&self, objects: &[usize], push_dir: PushDir, pusher_at: f64) -> Result<(), Infeasible> {
        let inst = self.inst;
        let floor = inst.container.floor();
        let back = *objects.last().expect("non-empty");
        let back_rel = self.rect_of(back).expect("released");
        let lower = self.pusher_slab(&back_rel, push_dir, pusher_at, inst.gripper.release_clearance);
        if let Some(hit) = self.first_hit(&lower, objects) {
            return Err(infeasible(
                "finger_slab",
                format!("pusher behind {} hits {hit}", inst.objects[back].id),
            ));
        }
        for &i in objects {
            let from = self.rect_of(i).expect("released");
            let to = self.placement.targets[i].rect;
            let swept = from.union(&to);
            if !swept.inside(&floor) {
                return Err(infeasible(
                    "wall",
                    format!("push sweeps {} outside the floor", inst.objects[i].id),
                ));
            }
            for j in 0..inst.n() {
                if objects.contains(&j) {
                    continue;
                }
                if let Some(rj) = self.rect_of(j) {
                    if rj.overlaps(&swept) {
                        return Err(infeasible(
                            "swept_space",
                            format!("push of {} sweeps through {}", inst.objects[i].id, inst.objects[j].id),
                        ));
                    }
                }
            }
        }
        let back_t = self.placement.targets[back].rect;
        let end = self.pusher_slab(&back_t, push_dir, pusher_at, 0.0);
        let sweep = Box3 {
            min: [lower.min[0].min(end.min[0]), lower.min[1].min(end.min[1]), lower.min[2]],
            max: [lower.max[0].max(end.max[0]), lower.max[1].max(end.max[1]), lower.max[2]],
        };
        if let Some(hit) = self.first_hit(&sweep, objects) {
            return Err(infeasible(
                "swept_space",
                format!("pusher sweep behind {} hits {hit}", inst.objects[back].id),
            ));
        }
        Ok(())
    }

    /// No pushed box slides along a neighbour that nothing holds against the push, nor between
    /// faces on both of its sides ([`push::side`]), unless the instance turns side contacts off.
    fn check_side_contacts(&self, objects: &[usize], push_dir: PushDir) -> Result<(), Infeasible> {
        let inst = self.inst;
        if !inst.settings.side_contacts {
            return Ok(());
        }
        let moving: Vec<(usize, Rect)> = objects
            .iter()
            .map(|&i| {
                let from = self.rect_of(i).expect("released");
                (i, from.union(&self.placement.targets[i].rect))
            })
            .collect();
        let standing: Vec<push::side::Standing> = (0..inst.n())
            .filter(|i| !objects.contains(i))
            .filter_map(|i| {
                self.rect_of(i).map(|rect| push::side::Standing {
                    object: i,
                    rect,
                    at_target: self.state[i] == ObjState::Done,
                })
            })
            .collect();
        let floor = inst.container.floor();
        match push::side::side_failure(
            &floor,
            &moving,
            &standing,
            push_dir,
            &push::side::SideRule {
                clearance: inst.settings.side_clearance,
                assume_held: self.assume_held,
                forbid_slots: inst.settings.forbid_slots,
            },
        ) {
            None => Ok(()),
            Some(push::side::SideFailure::Drags { moving, neighbour }) => Err(infeasible(
                "side_contact",
                format!(
                    "{} slides along {}, which nothing holds against the push",
                    inst.objects[moving].id, inst.objects[neighbour].id
                ),
            )),
            Some(push::side::SideFailure::Wedged { moving }) => Err(infeasible(
                "side_contact",
                format!("{} slides between faces on both of its sides", inst.objects[moving].id),
            )),
        }
    }

    /// The push model accepts the push (docs/push_stability.md); its margin.
    fn check_push_stability(&self, objects: &[usize], push_dir: PushDir, pusher_at: f64) -> Result<f64, Infeasible> {
        let inst = self.inst;
        let back = *objects.last().expect("non-empty");
        let verdict = self.push_verdict(objects, push_dir, pusher_at);
        if !verdict.accepted(inst.settings.min_push_margin) {
            let detail = match &verdict.travel {
                Some(t) if !t.passes => format!(
                    "{} turns {:.3}° and drifts {:.4} mm while it closes its {:.4} mm gap alone ({:.0} % of the limits)",
                    inst.objects[back].id,
                    t.rotation.to_degrees(),
                    t.drift * 1e3,
                    t.travel * 1e3,
                    t.usage * 100.0
                ),
                _ => format!(
                    "push margin {:.4} m is below the minimum {:.4} m",
                    verdict.margin, inst.settings.min_push_margin
                ),
            };
            return Err(infeasible("push_stability", detail));
        }
        Ok(verdict.margin)
    }

    /// For each consecutive pair (front, back) of a line, the gap (m) that separates them now:
    /// the difference of their release offsets (their targets touch). A gap is a separate push
    /// phase that lasts exactly that distance.
    pub fn phase_gaps(&self, objects: &[usize]) -> Vec<f64> {
        objects
            .windows(2)
            .map(|w| match (self.state[w[0]], self.state[w[1]]) {
                (ObjState::Released { offset: a, .. }, ObjState::Released { offset: b, .. }) => (b - a).max(0.0),
                // Not both released: the push is infeasible anyway; an unlimited gap keeps the
                // phase judged by its margin alone.
                _ => f64::INFINITY,
            })
            .collect()
    }

    /// The stability verdict on pushing `objects` (released, front to back) along `dir` from
    /// their current releases, with the instance's tolerances ([`push::line_verdict`]).
    pub fn push_verdict(&self, objects: &[usize], dir: PushDir, pusher_at: f64) -> push::LineVerdict {
        push::line_verdict(
            self.inst,
            self.placement,
            objects,
            dir,
            pusher_at,
            &self.phase_gaps(objects),
        )
    }

    /// Run an action (assumes [`Layout::check`] passed).
    pub fn apply(&mut self, action: &Action) {
        match action {
            Action::Place { object, mode, .. } => {
                self.state[*object] = match mode {
                    PlaceMode::Direct => ObjState::Done,
                    PlaceMode::Indirect { push_dir, offset } => ObjState::Released {
                        rect: self.release_rect(*object, mode),
                        push_dir: *push_dir,
                        offset: *offset,
                    },
                }
            }
            Action::Push { objects, .. } => {
                for &i in objects {
                    self.state[i] = ObjState::Done;
                }
            }
        }
    }

    /// Named invariant: no two objects in the container overlap.
    pub fn no_overlaps(&self) -> bool {
        let rects: Vec<Rect> = (0..self.inst.n()).filter_map(|i| self.rect_of(i)).collect();
        rects
            .iter()
            .enumerate()
            .all(|(k, a)| rects[k + 1..].iter().all(|b| !a.overlaps(b)))
    }
}

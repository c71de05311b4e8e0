//! Best-first (A*) search over partial plans, choosing the packing actions and their order
//! together, with admissible bounds on every cost component.
//!
//! A state is where every object is (table / released with a push direction and offset / at its
//! target) and where each arm's TCP is. Edges are the feasible actions of SPEC §5 in that state:
//! place direct, place indirect with a direction and an offset `m·d` (`m = 1..=max_offset_steps`),
//! push any line of released objects whose targets touch along the push direction. The cost is
//! the lexicographic triple (actions, swept area, travel): actions and travel add up along a
//! path, swept area is a running maximum. The heuristic bounds each component from below
//! (docs/algorithms.md), which bounds the triple lexicographically, so the first goal popped is
//! optimal. States reached again keep a Pareto set of (actions, area, travel) labels; a
//! dominated label is dropped. A greedy dive gives an incumbent first, so nodes whose bound is
//! not below it are never opened. With a node or time limit the best plan found is returned with
//! the smallest open bound (status `node_limit`/`time_limit`).
//!
//! The explored state graph is a petgraph `DiGraph` (nodes = search nodes, edges = actions); the
//! plan is the path from the root to the goal node.

use super::{metrics, SearchStatus, SequenceOptions, SequenceResult};
use crate::actions::{push, Action, Layout, ObjState, PlaceMode};
use crate::control::Terminator;
use crate::error::{Error, Result};
use crate::geometry::{Axis2, PushDir, EPS};
use crate::instance::Instance;
use crate::placement::Placement;
use crate::robot::keypoints::{action_keypoints, path_length, pick_arm, transfer_z};
use crate::robot::Arm;
use nalgebra::Vector3;
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::EdgeRef;
use petgraph::Direction;
use serde::{Deserialize, Serialize};
use std::cell::{Cell, RefCell};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::rc::Rc;
use std::time::Instant;

/// A* settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AstarSettings {
    /// Largest indirect offset as a multiple of the minimum offset `d` (default 3).
    pub max_offset_steps: usize,
    /// Node budget of the greedy dive that provides the first incumbent (default 20,000).
    pub dive_nodes: u64,
}

impl Default for AstarSettings {
    fn default() -> Self {
        AstarSettings {
            max_offset_steps: 3,
            dive_nodes: 20_000,
        }
    }
}

/// Lexicographic cost (actions, swept area, travel).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Cost {
    /// Number of actions.
    pub len: usize,
    /// Swept area (m²).
    pub area: f64,
    /// Travel (m).
    pub travel: f64,
}

impl Cost {
    /// Lexicographic comparison with tolerances (1e-12 m² on area, 1e-9 m on travel).
    pub fn cmp_lex(&self, o: &Cost) -> Ordering {
        self.len
            .cmp(&o.len)
            .then(fuzzy_cmp(self.area, o.area, 1e-12))
            .then(fuzzy_cmp(self.travel, o.travel, 1e-9))
    }
}

/// A path label at a state: what the future cost depends on besides the state itself.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Label {
    len: usize,
    ext: [f64; 2],
    travel: f64,
}

impl Label {
    fn of(n: &Node) -> Label {
        Label {
            len: n.g.len,
            ext: n.ext,
            travel: n.g.travel,
        }
    }
    /// Every completion from the same state costs no more with this label.
    fn dominates(&self, o: &Label) -> bool {
        self.len <= o.len
            && self.ext[0] <= o.ext[0] + 1e-12
            && self.ext[1] <= o.ext[1] + 1e-12
            && self.travel <= o.travel + 1e-9
    }
}

fn fuzzy_cmp(a: f64, b: f64, tol: f64) -> Ordering {
    if a < b - tol {
        Ordering::Less
    } else if a > b + tol {
        Ordering::Greater
    } else {
        Ordering::Equal
    }
}

/// A search node.
#[derive(Debug, Clone)]
struct Node {
    state: Vec<ObjState>,
    pos: [Vector3<f64>; 2],
    used: [bool; 2],
    /// Swept extents so far (max x1, max y1).
    ext: [f64; 2],
    g: Cost,
    f: Cost,
    goal: bool,
}

struct Open {
    f: Cost,
    seq: u64,
    node: NodeIndex,
}

impl PartialEq for Open {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        // BinaryHeap is a max-heap: reverse for smallest f first; FIFO among equals.
        o.f.cmp_lex(&self.f).then(o.seq.cmp(&self.seq))
    }
}

/// Per-object data the heuristic needs, computed once.
struct ObjectInfo {
    /// TCP above the table pose (transfer height).
    pre_grasp: Vector3<f64>,
    /// Vertical travel of the pick (down and up).
    pick_vertical: f64,
    /// Vertical travel of the release (down and up).
    release_vertical: f64,
    /// World TCP position above the target centre.
    above_target: Vector3<f64>,
    /// No direct placement can ever work (both grasp axes blocked by walls or the opening).
    never_direct: bool,
    /// Extents (x1, y1) of the nearest indirect release in each direction that fits the floor.
    release_ext: Vec<[f64; 2]>,
}

struct Search<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    opts: SequenceOptions,
    settings: AstarSettings,
    info: Vec<ObjectInfo>,
    home: [Vector3<f64>; 2],
    /// Container floor at transfer height, as a world-frame rectangle test (min distance).
    container_corners: [Vector3<f64>; 4],
    push_vertical: f64,
    /// Reachability of actions by the robot (inverse kinematics), memoised.
    reach: crate::robot::reach_cache::ReachCache<'a>,
    /// Feasible actions per object state.
    succ_cache: RefCell<HashMap<Vec<i64>, Rc<Vec<(Action, Option<f64>)>>>>,
    /// Remaining-actions memo per object state: (value, exact). Not exact = a lower bound.
    len_memo: RefCell<HashMap<Vec<i64>, (usize, bool)>>,
    /// The proven minimum number of actions, once known.
    lstar: Cell<Option<usize>>,
    /// Time limit watched by phase 1, and whether it struck.
    stop: Option<&'a dyn Terminator>,
    stopped: Cell<bool>,
    calls: Cell<u64>,
}

fn obj_key(state: &[ObjState]) -> Vec<i64> {
    state
        .iter()
        .map(|s| match s {
            ObjState::Table => 0,
            ObjState::Done => 1,
            ObjState::Released { push_dir, offset, .. } => 2 + (*push_dir as i64) + 2 * ((offset * 1e6).round() as i64),
        })
        .collect()
}

fn key(n: &Node) -> Vec<i64> {
    let mut k = obj_key(&n.state);
    for (p, u) in n.pos.iter().zip(n.used) {
        for c in p.iter() {
            k.push((c * 1e6).round() as i64);
        }
        k.push(u as i64);
    }
    k
}

impl<'a> Search<'a> {
    fn new(inst: &'a Instance, placement: &'a Placement, opts: SequenceOptions, settings: AstarSettings) -> Self {
        let zt = transfer_z(inst);
        let g = &inst.gripper;
        let layout = Layout::new(inst, placement);
        let floor = inst.container.floor();
        let walls = inst.container.walls();
        let info = (0..inst.n())
            .map(|i| {
                let o = &inst.objects[i];
                let (_, h_table) = o.table_footprint();
                let grasp_z = inst.robot.table_z + h_table - g.grasp_depth;
                let t = placement.targets[i];
                let c = t.rect.center();
                let release = inst.container.to_world([c[0], c[1], t.height - g.grasp_depth]);
                let never_direct = [Axis2::X, Axis2::Y].iter().all(|&ax| {
                    t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS
                        || layout
                            .finger_slabs(&t.rect, t.height, ax)
                            .iter()
                            .any(|s| walls.iter().any(|w| w.intersects(s)))
                });
                let release_ext = PushDir::ALL
                    .iter()
                    .map(|d| t.rect.moved(*d, -g.min_offset))
                    .filter(|r| r.inside(&floor))
                    .map(|r| [r.x1, r.y1])
                    .collect();
                ObjectInfo {
                    pre_grasp: Vector3::new(o.table.x, o.table.y, zt),
                    pick_vertical: 2.0 * (zt - grasp_z),
                    release_vertical: 2.0 * (zt - release.z),
                    above_target: Vector3::new(release.x, release.y, zt),
                    never_direct: never_direct || opts.no_direct,
                    release_ext,
                }
            })
            .collect();
        let w = inst.container.width;
        let d = inst.container.depth;
        let container_corners = [[0.0, 0.0], [w, 0.0], [w, d], [0.0, d]].map(|[x, y]| {
            let p = inst.container.to_world([x, y, 0.0]);
            Vector3::new(p.x, p.y, zt)
        });
        Search {
            inst,
            placement,
            opts,
            settings,
            info,
            home: [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)],
            container_corners,
            push_vertical: 2.0 * (zt - (inst.container.floor_z + g.push_height)),
            reach: crate::robot::reach_cache::ReachCache::new(inst, placement),
            succ_cache: RefCell::new(HashMap::new()),
            len_memo: RefCell::new(HashMap::new()),
            lstar: Cell::new(None),
            stop: None,
            stopped: Cell::new(false),
            calls: Cell::new(0),
        }
    }

    /// Distance from `p` to the container floor rectangle lifted to transfer height.
    fn dist_to_container(&self, p: &Vector3<f64>) -> f64 {
        let c = &self.container_corners;
        // Work in the container's own axes: project onto its edges.
        let ex = c[1] - c[0];
        let ey = c[3] - c[0];
        let v = p - c[0];
        let u = (v.dot(&ex) / ex.norm_squared()).clamp(0.0, 1.0);
        let w = (v.dot(&ey) / ey.norm_squared()).clamp(0.0, 1.0);
        (c[0] + ex * u + ey * w - p).norm()
    }

    /// Direct placing of table object `i` is impossible for good: on both grasp axes a finger
    /// slab hits a wall or one of the `done` objects (or the object is too wide to grasp).
    fn direct_blocked(&self, i: usize, done: &[usize]) -> bool {
        let g = &self.inst.gripper;
        let t = self.placement.targets[i];
        let walls = self.inst.container.walls();
        [Axis2::X, Axis2::Y].iter().all(|&ax| {
            if t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS {
                return true;
            }
            crate::actions::finger_slabs(g, &t.rect, t.height, ax).iter().any(|s| {
                walls.iter().any(|w| w.intersects(s))
                    || done.iter().any(|&j| {
                        let tj = self.placement.targets[j];
                        crate::geometry::Box3::extrude(&tj.rect, 0.0, tj.height).intersects(s)
                    })
            })
        })
    }

    fn layout(&self, state: &[ObjState]) -> Layout<'a> {
        let mut l = Layout::new(self.inst, self.placement);
        l.state = state.to_vec();
        l
    }

    /// Admissible lower bounds on the remaining (actions, area, travel) from a node.
    /// Remaining actions from an object state: exact when it is at most `budget`, else a lower
    /// bound above `budget` (depth-first with a memo; Bellman over object states, since
    /// feasibility does not depend on where the arms are).
    fn togo(&self, state: &[ObjState], budget: usize) -> usize {
        if state.iter().all(|s| *s == ObjState::Done) {
            return 0;
        }
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() % 256 == 0 && self.stop.map(|t| t.should_stop()).unwrap_or(false) {
            self.stopped.set(true);
        }
        if self.stopped.get() {
            return budget + 1; // not stored as exact: phase 1 is abandoned
        }
        let k = obj_key(state);
        let known = self.len_memo.borrow().get(&k).copied();
        let mut lb = match known {
            Some((v, true)) => return v,
            Some((v, false)) => v,
            None => 0,
        };
        if known.is_none() {
            let table = state.iter().filter(|s| **s == ObjState::Table).count();
            lb = table + self.push_lower_bound(state).0;
        }
        if lb > budget {
            self.len_memo.borrow_mut().insert(k, (lb, false));
            return lb;
        }
        let mut best = usize::MAX;
        for (a, _) in self.successors(state).iter() {
            let mut l = self.layout(state);
            l.apply(a);
            let v = self.togo(&l.state, budget - 1);
            best = best.min(v.saturating_add(1));
            if best <= lb {
                break; // meets the lower bound: nothing can be shorter
            }
        }
        if self.stopped.get() {
            return budget + 1;
        }
        let entry = if best <= budget {
            (best, true)
        } else {
            (lb.max(budget + 1), false)
        };
        self.len_memo.borrow_mut().insert(k, entry);
        entry.0
    }

    /// Lower bound on the pushes still needed, and the objects that need one.
    fn push_lower_bound(&self, state: &[ObjState]) -> (usize, Vec<usize>) {
        let inst = self.inst;
        let done: Vec<usize> = (0..inst.n()).filter(|&i| state[i] == ObjState::Done).collect();
        let needs_push: Vec<usize> = (0..inst.n())
            .filter(|&i| match state[i] {
                ObjState::Released { .. } => true,
                ObjState::Table => self.info[i].never_direct || self.direct_blocked(i, &done),
                ObjState::Done => false,
            })
            .collect();
        let open: Vec<usize> = (0..inst.n()).filter(|&i| state[i] != ObjState::Done).collect();
        let comps: Vec<Vec<usize>> = PushDir::ALL
            .iter()
            .map(|&d| component_map(self.placement, &open, d))
            .collect();
        let allows = |i: usize, k: usize| match state[i] {
            ObjState::Released { push_dir, .. } => push_dir == PushDir::ALL[k],
            _ => true,
        };
        let share = |a: usize, b: usize| (0..2).any(|k| allows(a, k) && allows(b, k) && comps[k][a] == comps[k][b]);
        let mut independent: Vec<usize> = Vec::new();
        for &i in &needs_push {
            if independent.iter().all(|&j| !share(i, j)) {
                independent.push(i);
            }
        }
        (independent.len(), needs_push)
    }

    fn h(&self, n: &Node) -> Cost {
        let inst = self.inst;
        let table: Vec<usize> = (0..inst.n()).filter(|&i| n.state[i] == ObjState::Table).collect();
        // Pushes still needed: exact (given the proven minimum) once that is known, else a bound
        // from objects that need a push and cannot share one.
        let (mut pushes, needs_push) = self.push_lower_bound(&n.state);
        if let Some(l) = self.lstar.get() {
            let budget = l.saturating_sub(n.g.len);
            let t = self.togo(&n.state, budget);
            pushes = pushes.max(t.saturating_sub(table.len()));
        }
        let any_released = n.state.iter().any(|s| matches!(s, ObjState::Released { .. }));
        // Area: every object on the table that needs a push must be released somewhere; each
        // one alone forces at least its cheapest direction (offsets beyond d only grow it).
        let grown = |e: &[f64; 2]| n.ext[0].max(e[0]) * n.ext[1].max(e[1]);
        let mut area = n.ext[0] * n.ext[1];
        for &i in &needs_push {
            if n.state[i] == ObjState::Table {
                let forced = self.info[i].release_ext.iter().map(grown).fold(f64::INFINITY, f64::min);
                if forced.is_finite() {
                    area = area.max(forced);
                }
            }
        }
        // Travel: each remaining place's own vertical and transfer moves, its approach from the
        // nearest possible predecessor, each push's vertical moves and distance, and going home.
        let d = inst.gripper.min_offset;
        let max_off = d * self.settings.max_offset_steps as f64;
        let mut travel = 0.0;
        for &i in &table {
            let inf = &self.info[i];
            let approach = self
                .dist_to_container(&inf.pre_grasp)
                .min((inf.pre_grasp - n.pos[0]).norm())
                .min((inf.pre_grasp - n.pos[1]).norm());
            let transfer =
                ((inf.pre_grasp - inf.above_target).norm() - max_off).max(self.dist_to_container(&inf.pre_grasp));
            travel += approach + inf.pick_vertical + transfer + inf.release_vertical;
        }
        travel += pushes as f64 * (self.push_vertical + d);
        for k in 0..2 {
            let arm = if k == 0 { Arm::Left } else { Arm::Right };
            let more = table.iter().any(|&i| pick_arm(inst, i) == arm) || (any_released && n.used[k]);
            if more {
                travel += self.dist_to_container(&self.home[k]);
            } else if n.used[k] {
                travel += (self.home[k] - n.pos[k]).norm();
            }
        }
        Cost {
            len: table.len() + pushes,
            area,
            travel,
        }
    }

    fn f_of(&self, n: &Node) -> Cost {
        if n.goal {
            return n.g;
        }
        let h = self.h(n);
        Cost {
            len: n.g.len + h.len,
            area: n.g.area.max(h.area),
            travel: n.g.travel + h.travel,
        }
    }

    /// Feasible actions in a state (cached: they depend on object states only).
    fn successors(&self, state: &[ObjState]) -> Rc<Vec<(Action, Option<f64>)>> {
        let k = obj_key(state);
        if let Some(v) = self.succ_cache.borrow().get(&k) {
            return v.clone();
        }
        let v = Rc::new(self.successors_uncached(state));
        self.succ_cache.borrow_mut().insert(k, v.clone());
        v
    }

    /// Feasible actions in a state, with the push margin of each.
    fn successors_uncached(&self, state: &[ObjState]) -> Vec<(Action, Option<f64>)> {
        let inst = self.inst;
        let layout = self.layout(state);
        let d = inst.gripper.min_offset;
        let mut out = Vec::new();
        for i in 0..inst.n() {
            if state[i] != ObjState::Table {
                continue;
            }
            let arm = pick_arm(inst, i);
            let mut modes = Vec::new();
            if !self.opts.no_direct {
                modes.push(PlaceMode::Direct);
            }
            for dir in PushDir::ALL {
                for m in 1..=self.settings.max_offset_steps {
                    modes.push(PlaceMode::Indirect {
                        push_dir: dir,
                        offset: d * m as f64,
                    });
                }
            }
            for mode in modes {
                let axes = match mode {
                    PlaceMode::Indirect { push_dir, .. } => [push_dir.axis(), push_dir.axis().other()],
                    PlaceMode::Direct => [Axis2::X, Axis2::Y],
                };
                // The grasp axis does not change cost: take the first feasible one.
                if let Some((a, m)) = axes.into_iter().find_map(|ax| {
                    let a = Action::Place {
                        object: i,
                        mode,
                        grasp_axis: ax,
                        arm,
                    };
                    layout.check(&a).ok().filter(|_| self.reach.ok_in(&a, &layout)).map(|m| (a, m))
                }) {
                    out.push((a, m));
                }
            }
        }
        for dir in PushDir::ALL {
            let released: Vec<usize> = (0..inst.n())
                .filter(|&i| matches!(state[i], ObjState::Released { push_dir, .. } if push_dir == dir))
                .collect();
            for line in lines(
                self.placement,
                &released,
                dir,
                if self.opts.no_multi_push { 1 } else { usize::MAX },
            ) {
                let back = *line.last().expect("non-empty");
                let ObjState::Released { offset, .. } = state[back] else {
                    continue;
                };
                let a = Action::Push {
                    pusher_at: push::centred_pusher(inst, self.placement, &line, dir),
                    objects: line,
                    push_dir: dir,
                    distance: offset,
                    arm: pick_arm(inst, back),
                };
                if let Ok(m) = layout.check(&a) {
                    if self.reach.ok(&a) {
                        out.push((a, m));
                    }
                }
            }
        }
        out
    }

    fn child(&self, n: &Node, a: &Action) -> Node {
        let mut layout = self.layout(&n.state);
        let mut ext = n.ext;
        if let Action::Place { object, mode, .. } = a {
            let r = layout.release_rect(*object, mode);
            ext = [ext[0].max(r.x1), ext[1].max(r.y1)];
        }
        layout.apply(a);
        let k = a.arm().index();
        let (len, end) = path_length(&n.pos[k], &action_keypoints(self.inst, self.placement, a));
        let mut pos = n.pos;
        pos[k] = end;
        let mut used = n.used;
        used[k] = true;
        let g = Cost {
            len: n.g.len + 1,
            area: ext[0] * ext[1],
            travel: n.g.travel + len,
        };
        let mut c = Node {
            state: layout.state,
            pos,
            used,
            ext,
            g,
            f: g,
            goal: false,
        };
        c.f = self.f_of(&c);
        c
    }

    fn goal_of(&self, n: &Node) -> Node {
        let mut travel = n.g.travel;
        for k in 0..2 {
            if n.used[k] {
                travel += (self.home[k] - n.pos[k]).norm();
            }
        }
        let g = Cost { travel, ..n.g };
        Node {
            goal: true,
            g,
            f: g,
            ..n.clone()
        }
    }

    fn all_done(n: &Node) -> bool {
        n.state.iter().all(|s| *s == ObjState::Done)
    }

    /// Greedy dive with bounded backtracking: the first incumbent.
    fn dive(&self, root: &Node, budget: &mut u64) -> Option<(Cost, Vec<(Action, Option<f64>)>)> {
        if Self::all_done(root) {
            return Some((self.goal_of(root).g, Vec::new()));
        }
        if *budget == 0 {
            return None;
        }
        *budget -= 1;
        let mut kids: Vec<(Node, Action, Option<f64>)> = self
            .successors(&root.state)
            .iter()
            .map(|(a, m)| (self.child(root, a), a.clone(), *m))
            .collect();
        kids.sort_by(|x, y| x.0.f.cmp_lex(&y.0.f));
        for (c, a, m) in kids {
            if let Some((cost, mut path)) = self.dive(&c, budget) {
                path.insert(0, (a, m));
                return Some((cost, path));
            }
        }
        None
    }
}

/// Component id of every object in `open`, joining objects whose targets touch along `dir`
/// (indexed by object; objects not in `open` get their own id).
fn component_map(placement: &Placement, open: &[usize], dir: PushDir) -> Vec<usize> {
    let axis = dir.axis();
    let lat = axis.other();
    let t = |i: usize| placement.targets[i].rect;
    let mut parent: Vec<usize> = (0..placement.targets.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for (k, &a) in open.iter().enumerate() {
        for &b in &open[k + 1..] {
            let (ra, rb) = (t(a), t(b));
            let touch = ((ra.hi(axis) - rb.lo(axis)).abs() <= EPS || (rb.hi(axis) - ra.lo(axis)).abs() <= EPS)
                && ra.overlap_on(&rb, lat) > EPS;
            if touch {
                let (x, y) = (find(&mut parent, a), find(&mut parent, b));
                if x != y {
                    parent[x] = y;
                }
            }
        }
    }
    (0..parent.len()).map(|i| find(&mut parent, i)).collect()
}

/// Every line (front to back, consecutive targets touching along `dir` with lateral overlap)
/// of objects from `members`, up to `max_len` long.
pub fn lines(placement: &Placement, members: &[usize], dir: PushDir, max_len: usize) -> Vec<Vec<usize>> {
    let axis = dir.axis();
    let lat = axis.other();
    let t = |i: usize| placement.targets[i].rect;
    let behind = |a: usize, b: usize| (t(b).lo(axis) - t(a).hi(axis)).abs() <= EPS && t(a).overlap_on(&t(b), lat) > EPS;
    let mut out = Vec::new();
    let mut stack: Vec<Vec<usize>> = members.iter().map(|&m| vec![m]).collect();
    while let Some(line) = stack.pop() {
        let last = *line.last().expect("non-empty");
        if line.len() < max_len {
            for &b in members {
                if !line.contains(&b) && behind(last, b) {
                    let mut l = line.clone();
                    l.push(b);
                    stack.push(l);
                }
            }
        }
        out.push(line);
    }
    out.sort();
    out
}

/// Run the A* search.
pub fn solve(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    settings: &AstarSettings,
    stop: &dyn Terminator,
) -> Result<SequenceResult> {
    let start = Instant::now();
    let mut s = Search::new(inst, placement, *opts, *settings);
    let (mx, my) = placement.extent();
    let mut root = Node {
        state: vec![ObjState::Table; inst.n()],
        pos: s.home,
        used: [false; 2],
        ext: [mx, my],
        g: Cost {
            len: 0,
            area: mx * my,
            travel: 0.0,
        },
        f: Cost {
            len: 0,
            area: 0.0,
            travel: 0.0,
        },
        goal: false,
    };
    root.f = s.f_of(&root);
    let first_bound = root.f;

    // A first plan from a greedy dive, so that a stopped search still returns one.
    let mut budget = settings.dive_nodes;
    let mut incumbent = s.dive(&root, &mut budget);

    // Phase 1: the minimum number of actions, by iterative deepening over object states.
    // Abandoned (the bound stays heuristic) if the time limit strikes.
    s.stop = Some(stop);
    let mut lstar = first_bound.len;
    while lstar <= 4 * inst.n() {
        let t = s.togo(&root.state, lstar);
        if s.stopped.get() {
            s.len_memo.borrow_mut().retain(|_, v| v.1);
            break;
        }
        if t <= lstar {
            s.lstar.set(Some(lstar));
            break;
        }
        lstar += 1;
    }
    s.stop = None;
    root.f = s.f_of(&root);
    let root_bound = root.f;

    let mut graph: DiGraph<Node, (Action, Option<f64>)> = DiGraph::new();
    let r = graph.add_node(root.clone());
    let mut open = BinaryHeap::new();
    let mut seq = 0u64;
    open.push(Open {
        f: root.f,
        seq,
        node: r,
    });
    let mut labels: HashMap<Vec<i64>, Vec<Label>> = HashMap::new();
    let mut nodes = 0u64;
    let mut status = SearchStatus::Complete;
    let mut goal: Option<NodeIndex> = None;
    while let Some(Open { f, node, .. }) = open.pop() {
        if let Some((c, _)) = &incumbent {
            if f.cmp_lex(c) != Ordering::Less {
                // Nothing open can beat the incumbent: it is optimal.
                open.push(Open { f, seq: 0, node });
                break;
            }
        }
        let n = graph[node].clone();
        if n.goal {
            goal = Some(node);
            break;
        }
        nodes += 1;
        if nodes >= opts.max_nodes {
            status = SearchStatus::NodeLimit;
            open.push(Open { f, seq: 0, node });
            break;
        }
        if nodes % 256 == 0 && stop.should_stop() {
            status = SearchStatus::TimeLimit;
            open.push(Open { f, seq: 0, node });
            break;
        }
        if Search::all_done(&n) {
            let gnode = s.goal_of(&n);
            let gi = graph.add_node(gnode.clone());
            graph.add_edge(
                node,
                gi,
                (
                    Action::Push {
                        objects: vec![],
                        push_dir: PushDir::MinusX,
                        distance: 0.0,
                        pusher_at: 0.0,
                        arm: Arm::Left,
                    },
                    None,
                ),
            );
            seq += 1;
            open.push(Open {
                f: gnode.f,
                seq,
                node: gi,
            });
            continue;
        }
        for (a, m) in s.successors(&n.state).iter().cloned() {
            let c = s.child(&n, &a);
            if s.lstar.get().map(|l| c.f.len > l).unwrap_or(false) {
                continue; // cannot finish in the proven minimum number of actions
            }
            if let Some((inc, _)) = &incumbent {
                if c.f.cmp_lex(inc) != Ordering::Less {
                    continue;
                }
            }
            let k = key(&c);
            let lab = Label::of(&c);
            let set = labels.entry(k).or_default();
            if set.iter().any(|l| l.dominates(&lab)) {
                continue;
            }
            set.retain(|l| !lab.dominates(l));
            set.push(lab);
            let f = c.f;
            let ci = graph.add_node(c);
            graph.add_edge(node, ci, (a, m));
            seq += 1;
            open.push(Open { f, seq, node: ci });
        }
    }
    // Best plan: the goal popped, else the incumbent.
    let plan: Option<(Cost, Vec<(Action, Option<f64>)>)> = match goal {
        Some(gi) => {
            // Every node but the root has one incoming edge; the goal's is a dummy.
            let mut path = Vec::new();
            let mut cur = gi;
            let mut first = true;
            while let Some(e) = graph.edges_directed(cur, Direction::Incoming).next() {
                if !first {
                    path.push(e.weight().clone());
                }
                first = false;
                cur = e.source();
            }
            path.reverse();
            Some((graph[gi].g, path))
        }
        None => incumbent.take(),
    };
    let Some((cost, path)) = plan else {
        return Err(Error::Infeasible {
            reason: if status == SearchStatus::Complete {
                "no order of feasible actions packs every object".into()
            } else {
                format!("search stopped ({status:?}) after {nodes} nodes before any plan was found")
            },
        });
    };
    let bound = if goal.is_some() {
        cost
    } else if status == SearchStatus::Complete {
        cost // the incumbent was proven optimal: nothing open could beat it
    } else {
        open.iter()
            .map(|o| o.f)
            .min_by(|a, b| a.cmp_lex(b))
            .unwrap_or(root_bound)
    };
    if std::env::var_os("PUSHPACK_DEBUG").is_some() {
        eprintln!(
            "astar: root bound {root_bound:?}, result {cost:?}, incumbent from dive {:?}, {nodes} nodes",
            incumbent.as_ref().map(|i| i.0)
        );
    }
    let (actions, margins): (Vec<Action>, Vec<Option<f64>>) = path.into_iter().unzip();
    let m = metrics(inst, placement, &actions);
    debug_assert_eq!(m.seq_len, cost.len);
    Ok(SequenceResult {
        actions,
        margins,
        metrics: m,
        status,
        nodes,
        assignments: 0,
        time_s: start.elapsed().as_secs_f64(),
        bound: Some(bound),
    })
}

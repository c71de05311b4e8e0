//! Best-first (A*) search over partial plans, choosing the packing actions and their order
//! together, with admissible bounds on every cost component.
//!
//! A state is where every object is (table / released with a push direction and offset / at its
//! target) and where each arm's TCP is. Edges are the feasible actions of SPEC §5 in that state:
//! place direct, place indirect with a direction and an offset `m·d` (`m = 1..=max(max_offset_steps,
//! rank)`, where the rank is the length of the longest line ending at the object), push any line of released objects whose targets touch along the push direction. The cost is
//! the lexicographic triple (actions, swept area, travel): actions and travel add up along a
//! path, swept area is a running maximum. The heuristic bounds each component from below
//! (docs/algorithms.md), which bounds the triple lexicographically, so the first goal popped is
//! optimal. Object states reached again keep a Pareto set of (actions, extents, travel, arm
//! positions) labels; a label dominated even after paying for the arms' distance is dropped. A greedy dive gives an incumbent first, so nodes whose bound is
//! not below it are never opened. With a node or time limit the best plan found is returned with
//! the smallest open bound (status `node_limit`/`time_limit`).
//!
//! The explored state graph is a petgraph `DiGraph` (nodes = search nodes, edges = actions); the
//! plan is the path from the root to the goal node.

use super::{metrics, SearchStatus, SequenceOptions, SequenceResult};
use crate::actions::{push, Action, Layout, ObjState, PlaceMode};
use crate::control::Terminator;
use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::geometry::{Axis2, PushDir, EPS};
use crate::instance::Instance;
use crate::motion::keypoints::{action_keypoints, path_length, pick_arm, push_arms, transfer_z};
use crate::placement::Placement;
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
    /// Largest indirect offset as a multiple of the minimum offset `d` (default 3). An object
    /// that is the k-th of a line may also use offsets up to `k·d`, the paper's staggering.
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

/// A path label at an object state: what the future cost depends on besides the object
/// states themselves.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Label {
    len: usize,
    ext: [f64; 2],
    travel: f64,
    pos: [Vector3<f64>; 2],
}

impl Label {
    fn of(n: &Node) -> Label {
        Label {
            len: n.g.len,
            ext: n.ext,
            travel: n.g.travel,
            pos: n.pos,
        }
    }
    /// Every completion from the same object state costs no more with this label.
    ///
    /// The same actions run from either label (feasibility and reachability do not depend on
    /// where the arms are), with the same count and swept extents grown the same way. Travel
    /// is a sum of straight moves, so by the triangle inequality each arm's first move (or its
    /// return home, if it does nothing more) from here costs at most its distance to the other
    /// label's position more. An arm that has not moved stands at home, where the other label
    /// pays its return from anywhere else, so whether it moved does not matter.
    fn dominates(&self, o: &Label) -> bool {
        self.len <= o.len
            && self.ext[0] <= o.ext[0] + 1e-12
            && self.ext[1] <= o.ext[1] + 1e-12
            && self.travel + (self.pos[0] - o.pos[0]).norm() + (self.pos[1] - o.pos[1]).norm() <= o.travel + 1e-9
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
    /// `f` includes the phase-1 remaining-action count (see [`Search::f_of`]).
    exact: bool,
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
    /// No direct placement can ever work (both grasp axes blocked by walls or the opening).
    never_direct: bool,
    /// Extents (x1, y1) of the nearest indirect release in each direction that fits the floor.
    release_ext: Vec<[f64; 2]>,
    /// Per push direction (indexed like [`PushDir::ALL`]): whether any indirect release fits
    /// the floor, so the object can ever be pushed that way.
    push_dir_ok: [bool; 2],
    /// Pre-grasp (x, y) in C.
    pre_grasp_c: [f64; 2],
    /// Where in C (x, y, at transfer height) an action that places or pushes this object can
    /// end: above any of its releases, or just behind its target after a push.
    end_region: crate::geometry::Rect,
    /// Shortest horizontal move from the pre-grasp to above any release of the object.
    transfer_min: f64,
}

struct Search<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    opts: SequenceOptions,
    info: Vec<ObjectInfo>,
    /// Per push direction, the objects whose targets sit directly behind each object's (the
    /// edges of the lines one push moves, as in [`lines`]); bit `b` of `behind[k][a]`.
    behind: [Vec<u64>; 2],
    /// Objects by target `lo` along each push direction: a line's members come in this order.
    front_to_back: [Vec<usize>; 2],
    /// Every line a push could ever move, when the instance is small enough to list them
    /// (see [`push_lines`]); `None` falls back to the chains of `behind`.
    push_lines: Option<Vec<PushLine>>,
    /// Per object and grasp axis (X, Y) of a direct placement: `None` when walls or the
    /// opening rule the axis out for good, else the objects whose targets stand in a finger
    /// slab (empty unless `push_lines` is listed).
    slab_hits: Vec<[Option<u64>; 2]>,
    /// Per object, push direction (as in [`PushDir::ALL`]) and offset step `m` (index `m − 1`):
    /// what can stop an indirect release there (empty unless `push_lines` is listed and the
    /// steps fit the bit masks).
    release_hits: Vec<[Vec<PlaceHits>; 2]>,
    /// Per object, what can stop its direct placement (empty like `release_hits`).
    direct_hits: Vec<PlaceHits>,
    /// Per object, once asked: per place action the empty container allows and the robot
    /// reaches, the sets of other objects that, still on the table, block its pick (one per
    /// hand variant found, minimal sets only; `[0]` when a variant is free).
    pick_blockers: RefCell<Vec<Option<PickBlockers>>>,
    /// Per line of `push_lines`: the offset steps of its back member (bit `m`) asked so far,
    /// and those at which the robot reaches its push with some arm.
    line_reach: RefCell<Vec<(u64, u64)>>,
    /// Largest offset step per object and push direction (indexed like [`PushDir::ALL`]).
    steps: Vec<[usize; 2]>,
    home: [Vector3<f64>; 2],
    /// Each arm's home TCP (x, y) in C.
    home_c: [[f64; 2]; 2],
    /// Container floor at transfer height, as a world-frame rectangle test (min distance).
    container_corners: [Vector3<f64>; 4],
    push_vertical: f64,
    /// Reachability of actions by the robot (inverse kinematics), memoised.
    reach: crate::motion::reach_cache::ReachCache<'a>,
    /// Feasible actions per object state.
    succ_cache: RefCell<FxMap<Vec<u8>, Successors>>,
    /// Remaining-actions memo per object state: (proven lower bound, length of a plan found).
    len_memo: RefCell<LenMemo>,
    /// The proven minimum number of actions, once known.
    lstar: Cell<Option<usize>>,
    /// Phase 2's box: while set, every release must lie within `[0, x] × [0, y]` of C.
    area_box: Cell<Option<[f64; 2]>>,
    /// Successors allowed by `area_box` (cleared when it changes).
    box_succ: RefCell<FxMap<Vec<u8>, Successors>>,
    /// Phase 1's memo, kept aside while a box is set (the facts differ under a box).
    base_memo: RefCell<Option<LenMemo>>,
    /// Proven lower bound on the swept area of every plan of `lstar` actions (0 until phase 2).
    area_floor: Cell<f64>,
    /// Time limit watched by phase 1, and whether it (or the slice deadline) struck.
    stop: Option<&'a dyn Terminator>,
    stopped: Cell<bool>,
    /// End of the current phase-1 slice as a count of [`Search::fits`] calls (see
    /// [`Search::fits_within`]); counted rather than timed so that a run without a time limit
    /// is deterministic.
    deadline: Cell<Option<u64>>,
    calls: Cell<u64>,
    prof: Option<RefCell<Prof>>,
}

/// Time spent per part of the search, collected only when `PUSHPACK_PROFILE` is set (the clock
/// reads would otherwise cost more than some of the parts they measure).
#[derive(Default, Debug)]
struct Prof {
    check_s: f64,
    check_n: u64,
    reach_s: f64,
    reach_n: u64,
    /// Reachability queries slow enough to have run inverse kinematics (cache misses).
    reach_miss: u64,
    succ_s: f64,
    succ_n: u64,
    h_s: f64,
    h_n: u64,
    /// The bounds with phase 1's exact action count (a depth-first search each); `h_*` counts
    /// the cheap ones.
    hx_s: f64,
    hx_n: u64,
    child_s: f64,
    child_n: u64,
}

/// FxHash (the rustc hasher): the memo keys are short byte strings hashed millions of times,
/// where std's SipHash costs more than the lookups it serves. Not DoS-resistant, which does
/// not matter for keys the search makes itself.
#[derive(Default, Clone, Copy)]
struct FxHasher(u64);

impl std::hash::Hasher for FxHasher {
    fn finish(&self) -> u64 {
        // A multiply only carries low input bits upward, so the low bits (the bucket index)
        // would depend on the first few objects alone: finish with splitmix64's mixer.
        mix64(self.0)
    }
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.write_u64(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        for &b in chunks.remainder() {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, w: u64) {
        self.0 = (self.0.rotate_left(5) ^ w).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_usize(&mut self, w: usize) {
        self.write_u64(w as u64);
    }
}

/// splitmix64's finaliser: every output bit depends on every input bit.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

type FxMap<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<FxHasher>>;
/// An action with its push margin (`None` for places).
type Scored = (Action, Option<f64>);
/// The feasible actions of one state, shared between the caches that hold them.
type Successors = Rc<Vec<Scored>>;
/// Per object state: (proven lower bound on the remaining actions, length of a plan found).
type LenMemo = FxMap<Vec<u8>, (usize, usize)>;
/// Per place action, the minimal sets of objects whose presence on the table blocks its pick.
type PickBlockers = Rc<Vec<(PlaceKey, Vec<u64>)>>;

/// Compact key of the object states: one byte per object (table 0, done 1, released
/// `2 + direction + 2·m` for offset `m·d`). Offsets only ever come from the search's own place
/// modes, which are whole multiples of `d` (at most [`MAX_OFFSET_STEPS`]).
fn obj_key(state: &[ObjState], d: f64) -> Vec<u8> {
    state
        .iter()
        .map(|s| match s {
            ObjState::Table => 0,
            ObjState::Done => 1,
            ObjState::Released { push_dir, offset, .. } => {
                let m = (offset / d).round() as usize;
                debug_assert!((1..=MAX_OFFSET_STEPS).contains(&m));
                (2 + *push_dir as usize + 2 * m) as u8
            }
        })
        .collect()
}

/// Largest `max_offset_steps` the compact state key can represent.
pub const MAX_OFFSET_STEPS: usize = 100;

/// A plan and its cost.
type Incumbent = (Cost, Vec<Scored>);

/// Outcome of a time-boxed phase-1 question.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fit {
    /// A plan of this many actions (at most the budget) exists.
    Yes(usize),
    /// No plan fits the budget (proven).
    No,
    /// The slice or the time limit ended the search first.
    Stopped,
}

/// Child order of a greedy dive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DiveOrder {
    /// Lexicographically smallest cost bound first.
    Bound,
    /// Pushes first, then places nearest the container's origin corner.
    FrontFirst,
}

impl<'a> Search<'a> {
    fn new(inst: &'a Instance, placement: &'a Placement, opts: SequenceOptions, settings: AstarSettings) -> Self {
        let zt = transfer_z(inst);
        let g = &inst.gripper;
        let layout = Layout::new(inst, placement);
        let floor = inst.container.floor();
        let walls = inst.container.walls();
        let ranks = PushDir::ALL.map(|dir| line_rank(placement, dir));
        let steps: Vec<[usize; 2]> = (0..inst.n())
            .map(|i| [0, 1].map(|k| settings.max_offset_steps.max(ranks[k][i]).min(MAX_OFFSET_STEPS)))
            .collect();
        // Per push direction and object, the lateral range of the pusher of any line ending at
        // it: the pusher is centred on a weighted mean of the members' lateral centres, and the
        // members are objects in front of it (transitively).
        let front_to_back = PushDir::ALL.map(|dir| {
            let lo = |i: usize| placement.targets[i].rect.lo(dir.axis());
            let mut order: Vec<usize> = (0..inst.n()).collect();
            order.sort_by(|&a, &b| lo(a).total_cmp(&lo(b)));
            order
        });
        let pusher_range: [Vec<[f64; 2]>; 2] = [0, 1].map(|k| {
            let dir = PushDir::ALL[k];
            let lat = dir.axis().other();
            let centre = |i: usize| {
                let r = placement.targets[i].rect;
                (r.lo(lat) + r.hi(lat)) / 2.0
            };
            let order = &front_to_back[k];
            let mut range: Vec<[f64; 2]> = (0..inst.n()).map(|i| [centre(i), centre(i)]).collect();
            // Front to back: everything in front of `b` is done before it.
            for (k, &b) in order.iter().enumerate() {
                for &a in &order[..k] {
                    if behind(placement, dir, a, b) {
                        range[b] = [range[b][0].min(range[a][0]), range[b][1].max(range[a][1])];
                    }
                }
            }
            range
        });
        let info: Vec<ObjectInfo> = (0..inst.n())
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
                let nearest = PushDir::ALL.map(|d| t.rect.moved(d, -g.min_offset));
                let push_dir_ok = nearest.map(|r| r.inside(&floor));
                let release_ext = nearest
                    .iter()
                    .filter(|r| r.inside(&floor))
                    .map(|r| [r.x1, r.y1])
                    .collect();
                let pre_grasp = Vector3::new(o.table.x, o.table.y, zt);
                let pc = inst.container.from_world(&pre_grasp);
                let pre_grasp_c = [pc[0], pc[1]];
                // Releases go against the push direction (+x or +y in C) by up to the object's
                // largest offset; a push ends with the fingers half a thickness behind the
                // target, within its lateral extent.
                let reach = [0, 1].map(|k| {
                    if push_dir_ok[k] {
                        g.min_offset * steps[i][k] as f64
                    } else {
                        0.0
                    }
                });
                let half_t = g.finger_thickness / 2.0;
                // Bounding box of the release centres and of the push ends.
                let mut end_region = crate::geometry::Rect {
                    x0: c[0],
                    y0: c[1],
                    x1: c[0] + reach[0],
                    y1: c[1] + reach[1],
                };
                if push_dir_ok[0] {
                    let [lo, hi] = pusher_range[0][i];
                    end_region = end_region.union(&crate::geometry::Rect {
                        x0: t.rect.x1 + half_t,
                        x1: t.rect.x1 + half_t,
                        y0: lo,
                        y1: hi,
                    });
                }
                if push_dir_ok[1] {
                    let [lo, hi] = pusher_range[1][i];
                    end_region = end_region.union(&crate::geometry::Rect {
                        x0: lo,
                        x1: hi,
                        y0: t.rect.y1 + half_t,
                        y1: t.rect.y1 + half_t,
                    });
                }
                let seg = |u: [f64; 2], len: f64| {
                    let v = [pre_grasp_c[0] - c[0], pre_grasp_c[1] - c[1]];
                    let s = (v[0] * u[0] + v[1] * u[1]).clamp(0.0, len);
                    (v[0] - s * u[0]).hypot(v[1] - s * u[1])
                };
                let transfer_min = seg([1.0, 0.0], reach[0]).min(seg([0.0, 1.0], reach[1]));
                ObjectInfo {
                    pre_grasp_c,
                    end_region,
                    transfer_min,
                    pre_grasp,
                    pick_vertical: 2.0 * (zt - grasp_z),
                    release_vertical: 2.0 * (zt - release.z),
                    never_direct: never_direct || opts.no_direct,
                    release_ext,
                    push_dir_ok,
                }
            })
            .collect();
        let w = inst.container.width;
        let d = inst.container.depth;
        let container_corners = [[0.0, 0.0], [w, 0.0], [w, d], [0.0, d]].map(|[x, y]| {
            let p = inst.container.to_world([x, y, 0.0]);
            Vector3::new(p.x, p.y, zt)
        });
        let behind = PushDir::ALL.map(|dir| {
            (0..inst.n())
                .map(|a| {
                    (0..inst.n().min(64))
                        .filter(|&b| behind(placement, dir, a, b))
                        .fold(0u64, |m, b| m | 1 << b)
                })
                .collect()
        });
        let t_lines = Instant::now();
        let push_lines = push_lines(inst, placement, &opts, &info, &steps);
        if std::env::var_os("PUSHPACK_DEBUG").is_some() {
            eprintln!(
                "push lines: {:?} in {:.3}s",
                push_lines.as_ref().map(|l| l.len()),
                t_lines.elapsed().as_secs_f64()
            );
        }
        let slab_hits = if push_lines.is_some() {
            slab_hits(inst, placement)
        } else {
            Vec::new()
        };
        // Offset steps index the bit masks of `PlaceHits`.
        let (release_hits, direct_hits) = if push_lines.is_some() && steps.iter().flatten().all(|&m| m < 64) {
            let d = g.min_offset;
            let indirect = (0..inst.n())
                .map(|i| {
                    [0, 1].map(|k| {
                        (1..=steps[i][k])
                            .map(|m| place_hits(inst, placement, &steps, i, indirect_mode(k, m, d)))
                            .collect()
                    })
                })
                .collect();
            let direct = (0..inst.n())
                .map(|i| place_hits(inst, placement, &steps, i, PlaceMode::Direct))
                .collect();
            (indirect, direct)
        } else {
            (Vec::new(), Vec::new())
        };
        let n_lines = push_lines.as_ref().map_or(0, |l| l.len());
        Search {
            inst,
            placement,
            opts,
            info,
            behind,
            front_to_back,
            push_lines,
            slab_hits,
            release_hits,
            direct_hits,
            pick_blockers: RefCell::new(vec![None; inst.n()]),
            line_reach: RefCell::new(vec![(0, 0); n_lines]),
            steps,
            home: [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)],
            home_c: [Arm::Left, Arm::Right].map(|a| {
                let p = inst.container.from_world(&inst.robot.home_tcp(a));
                [p[0], p[1]]
            }),
            container_corners,
            push_vertical: 2.0 * (zt - (inst.container.floor_z + g.push_height)),
            reach: crate::motion::reach_cache::ReachCache::new(inst, placement),
            succ_cache: RefCell::new(FxMap::default()),
            // Phase 1 stores millions of states on twelve objects: start large enough that the
            // first rehashes do not matter.
            len_memo: RefCell::new(FxMap::with_capacity_and_hasher(1 << 16, Default::default())),
            lstar: Cell::new(None),
            area_box: Cell::new(None),
            box_succ: RefCell::new(FxMap::default()),
            base_memo: RefCell::new(None),
            area_floor: Cell::new(0.0),
            stop: None,
            stopped: Cell::new(false),
            deadline: Cell::new(None),
            calls: Cell::new(0),
            prof: std::env::var_os("PUSHPACK_PROFILE").map(|_| RefCell::new(Prof::default())),
        }
    }

    /// Run `f`, adding its time to a profile slot when profiling.
    fn timed<T>(&self, slot: fn(&mut Prof) -> (&mut f64, &mut u64), f: impl FnOnce() -> T) -> T {
        match &self.prof {
            None => f(),
            Some(p) => {
                let t = Instant::now();
                let v = f();
                let mut p = p.borrow_mut();
                let (s, n) = slot(&mut p);
                *s += t.elapsed().as_secs_f64();
                *n += 1;
                v
            }
        }
    }

    fn check(&self, layout: &Layout, a: &Action) -> Option<Option<f64>> {
        self.timed(|p| (&mut p.check_s, &mut p.check_n), || layout.check(a).ok())
    }

    /// Reachability of an action by the robot in `state` (memoised in [`ReachCache`]; objects
    /// still on the table may block a pick).
    fn reachable(&self, a: &Action, state: &[ObjState]) -> bool {
        let t = self.prof.as_ref().map(|_| Instant::now());
        let v = self.timed(|p| (&mut p.reach_s, &mut p.reach_n), || self.reach.ok_when(a, state));
        if let (Some(p), Some(t)) = (&self.prof, t) {
            // A memo hit takes well under a microsecond, inverse kinematics milliseconds.
            if t.elapsed().as_secs_f64() > 1e-4 {
                p.borrow_mut().reach_miss += 1;
            }
        }
        v
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

    /// Whether the objects can all reach their targets from `state` in at most `budget` more
    /// actions; `Some(n)` with the length `n ≤ budget` of a plan found, `None` when none fits.
    ///
    /// Depth-first with a memo over object states of proven facts `(lo, hi)`: no plan shorter
    /// than `lo`, a plan of length `hi` exists. The memo is sound whatever the path to a state,
    /// since feasibility does not depend on where the arms are (Bellman over object states).
    /// It answers the question asked and no more: the search stops at the first plan that fits,
    /// instead of looking for the shortest. That is all phase 1 needs (it deepens the budget
    /// from below, so the first budget that fits is the minimum `L*`) and all the main search
    /// needs (a node at depth `g` is on an `L*`-action plan iff `L* − g` fits, and then the
    /// remaining count is exactly `L* − g`, since no plan is shorter than `L*`).
    fn fits(&self, state: &[ObjState], budget: usize) -> Option<usize> {
        if state.iter().all(|s| *s == ObjState::Done) {
            return Some(0);
        }
        self.calls.set(self.calls.get() + 1);
        if self.deadline.get().is_some_and(|d| self.calls.get() >= d)
            // Polled from the first call on: a limit already spent stops at once.
            || (self.calls.get() % 256 == 1 && self.stop.is_some_and(|t| t.should_stop()))
        {
            self.stopped.set(true);
        }
        if self.stopped.get() {
            return None; // not stored: phase 1 is abandoned
        }
        let k = obj_key(state, self.inst.gripper.min_offset);
        let known = self.len_memo.borrow().get(&k).copied();
        let (lo, hi) = known.unwrap_or_else(|| (self.lower_len(state, 0), usize::MAX));
        if hi <= budget {
            return Some(hi);
        }
        if lo > budget {
            self.len_memo.borrow_mut().insert(k, (lo, hi));
            return None;
        }
        // Children with the smallest lower bound first: a refutation visits them all anyway,
        // and a budget that fits is found sooner (top-down, the budget is loose and the first
        // child that can use it well usually does).
        let mut kids: Vec<(usize, Vec<ObjState>, &Action)> = Vec::new();
        let succ = self.successors(state);
        for (a, _) in succ.iter() {
            let mut l = self.layout(state);
            l.apply(a);
            let lo = self.lower_len(&l.state, lo.saturating_sub(1));
            if lo < budget {
                kids.push((lo, l.state, a));
            }
        }
        kids.sort_by_key(|k| k.0);
        for (_, child, a) in kids {
            // Reachability (tens of ms of inverse kinematics the first time) is asked only of
            // an action that completes a plan: the children of a proof that the budget is too
            // small never are asked. The child's memo entry is a fact about its state either way.
            if let Some(v) = self.fits(&child, budget - 1) {
                if self.reachable(a, state) {
                    self.len_memo.borrow_mut().insert(k, (lo, v + 1));
                    return Some(v + 1);
                }
            }
        }
        if self.stopped.get() {
            return None;
        }
        self.len_memo.borrow_mut().insert(k, (lo.max(budget + 1), hi));
        None
    }

    /// The remaining-actions lower bound of `state`: the memo's, else table objects plus the
    /// push bound.
    ///
    /// `floor` is a bound already proven (0 when none): the parent's less one, since one action
    /// leads here from there. The push bound's search starts from it instead of refuting again
    /// the sizes below it.
    fn lower_len(&self, state: &[ObjState], floor: usize) -> usize {
        if state.iter().all(|s| *s == ObjState::Done) {
            return 0;
        }
        let k = obj_key(state, self.inst.gripper.min_offset);
        if let Some(&(lo, _)) = self.len_memo.borrow().get(&k) {
            return lo;
        }
        // Stored: a sibling order is asked for again on every visit of the parent.
        let table = state.iter().filter(|s| **s == ObjState::Table).count();
        let released = self.released(state); // both bounds read it
        let lo = if self.picks_deadlocked(state, &released) {
            DEAD_END
        } else {
            (table + self.push_lower_bound(state, &released, floor.saturating_sub(table)).0).max(floor)
        };
        self.len_memo.borrow_mut().insert(k, (lo, usize::MAX));
        lo
    }

    /// The table objects of `state` cannot all be picked: each of some of them is blocked, in
    /// every pick of an action not yet ruled out for good (by objects done, or released ones
    /// in the way both where they are and at their targets), by another of them still on the
    /// table. An object leaves the table only by its own pick, so picking whatever is free
    /// first (which only frees more) finds an order whenever one exists.
    fn picks_deadlocked(&self, state: &[ObjState], released: &[Rel]) -> bool {
        if self.release_hits.is_empty() {
            return false; // beyond the bit masks
        }
        let mut table = (0..state.len())
            .filter(|&i| state[i] == ObjState::Table)
            .fold(0u64, |m, i| m | 1 << i);
        if table.count_ones() < 2 {
            return false; // a lone object's reachability is the successors' business
        }
        let done = (0..state.len())
            .filter(|&i| state[i] == ObjState::Done)
            .fold(0u64, |m, i| m | 1 << i);
        // Per table object, the blocker sets of its picks that are still possible.
        let sets: Vec<(usize, Vec<u64>)> = bits(table)
            .map(|i| {
                let pb = self.pick_blockers(i);
                let live = pb
                    .iter()
                    .filter(|(key, _)| {
                        let hits = match *key {
                            PlaceKey::Direct(_) => &self.direct_hits[i],
                            PlaceKey::Indirect(k, m, _) => {
                                if !self.in_box(i, PushDir::ALL[k], self.inst.gripper.min_offset * m as f64) {
                                    return false;
                                }
                                &self.release_hits[i][k][m - 1]
                            }
                        };
                        hits.axis_open(key.axis(), done, &[], released)
                    })
                    .flat_map(|(_, b)| b.iter().copied())
                    .collect();
                (i, live)
            })
            .collect();
        loop {
            let free = sets
                .iter()
                .filter(|(i, b)| table >> i & 1 == 1 && b.iter().any(|&b| b & table & !(1 << i) == 0))
                .fold(0u64, |m, (i, _)| m | 1 << i);
            if free == 0 {
                return true;
            }
            table &= !free;
            if table == 0 {
                return false;
            }
        }
    }

    /// Whether the robot reaches the push of line `li` (`l`) with its back member at offset
    /// step `m`, with some arm (inverse kinematics through the reach cache on first use, as
    /// the successors ask it; memoised per line).
    fn line_reach(&self, li: usize, l: &PushLine, m: usize) -> bool {
        let (asked, ok) = self.line_reach.borrow()[li];
        if asked >> m & 1 == 1 {
            return ok >> m & 1 == 1;
        }
        let dir = PushDir::ALL[l.dir];
        let back = *l.order.last().expect("non-empty");
        let pusher_at = push::centred_pusher(self.inst, self.placement, &l.order, dir);
        let d = self.inst.gripper.min_offset;
        let r = push_arms(self.inst, back).into_iter().any(|arm| {
            self.reach.ok(&Action::Push {
                objects: l.order.clone(),
                push_dir: dir,
                distance: d * m as f64,
                pusher_at,
                arm,
            })
        });
        let mut lr = self.line_reach.borrow_mut();
        lr[li].0 |= 1 << m;
        lr[li].1 |= u64::from(r) << m;
        r
    }

    /// The released objects of `state`.
    fn released(&self, state: &[ObjState]) -> Vec<Rel> {
        let d = self.inst.gripper.min_offset;
        state
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match s {
                ObjState::Released { push_dir, offset, .. } => {
                    let (k, m) = step_of(*push_dir, *offset, d);
                    Some((i, k, m))
                }
                _ => None,
            })
            .collect()
    }

    /// [`Search::pick_blockers`] of object `i`, computed on first use (inverse kinematics
    /// through the reach cache).
    fn pick_blockers(&self, i: usize) -> Rc<Vec<(PlaceKey, Vec<u64>)>> {
        if let Some(b) = &self.pick_blockers.borrow()[i] {
            return b.clone();
        }
        let inst = self.inst;
        let empty = Layout::new(inst, self.placement);
        let d = inst.gripper.min_offset;
        let mut out = Vec::new();
        let keyed = (0..2).flat_map(|ax| place_modes(self.opts.no_direct, self.steps[i], d).map(move |m| (ax, m)));
        for (ax, mode) in keyed {
            let key = PlaceKey::of(mode, ax, d);
            let a = Action::Place {
                object: i,
                mode,
                grasp_axis: [Axis2::X, Axis2::Y][ax],
                arm: pick_arm(inst, i),
            };
            if empty.check(&a).is_err() {
                continue;
            }
            let Some(variants) = self.reach.table_blockers(&a) else {
                continue;
            };
            let mut sets: Vec<u64> = Vec::new();
            for b in variants {
                let m = b.iter().fold(0u64, |m, &j| m | 1 << j);
                if !sets.iter().any(|&s| s & !m == 0) {
                    sets.retain(|&s| m & !s != 0);
                    sets.push(m);
                }
            }
            out.push((key, sets));
        }
        let out = Rc::new(out);
        self.pick_blockers.borrow_mut()[i] = Some(out.clone());
        out
    }

    /// [`Search::fits`] from `state`, abandoned after `calls` more calls. Facts the memo gained
    /// before stay, so a later call with the same question resumes rather than restarts.
    fn fits_within(&self, state: &[ObjState], budget: usize, calls: u64) -> Fit {
        self.stopped.set(false);
        self.deadline.set(Some(self.calls.get() + calls));
        let r = self.fits(state, budget);
        self.deadline.set(None);
        match (r, self.stopped.replace(false)) {
            (Some(v), _) => Fit::Yes(v),
            (None, false) => Fit::No,
            (None, true) => Fit::Stopped,
        }
    }

    /// Whether the memo already knows a plan of at most `budget` actions from `state`.
    fn known_fits(&self, state: &[ObjState], budget: usize) -> bool {
        state.iter().all(|s| *s == ObjState::Done)
            || self
                .len_memo
                .borrow()
                .get(&obj_key(state, self.inst.gripper.min_offset))
                .is_some_and(|&(_, hi)| hi <= budget)
    }

    /// A plan of at most `len` actions from `root`, read off the memo after `fits` found one:
    /// every memo entry `hi` was stored for a reachable action into a child that fits in
    /// `hi − 1`, so the walk never dead-ends. Among the children that fit, the smallest cost
    /// bound goes first, so the plan is greedy in swept area and travel.
    fn plan_from_memo(&self, root: &Node, len: usize) -> Option<Incumbent> {
        let mut n = root.clone();
        let mut rem = len;
        let mut path = Vec::new();
        while !Self::all_done(&n) {
            let mut kids: Vec<(Node, Action, Option<f64>)> = self
                .successors(&n.state)
                .iter()
                .map(|(a, m)| (self.child(&n, a), a.clone(), *m))
                .collect();
            kids.sort_by(|x, y| x.0.f.cmp_lex(&y.0.f));
            let next = kids
                .into_iter()
                .find(|(c, a, _)| rem >= 1 && self.known_fits(&c.state, rem - 1) && self.reachable(a, &n.state));
            let Some((c, a, m)) = next else {
                debug_assert!(false, "memo walk dead-ended with {rem} actions left");
                return None;
            };
            path.push((a, m));
            n = c;
            rem -= 1;
        }
        Some((self.goal_of(&n).g, path))
    }

    /// Top-down step of phase 1: a plan one action shorter than `inc`, looked for by
    /// re-planning ever longer tails of it (the last action, the last two, …, the whole plan),
    /// so that the small questions near the end, which the memo then answers at once, come
    /// first. `Fit::No` proves that no plan is shorter than `inc`.
    fn shorten(&self, root: &Node, inc: &[Scored], calls: u64) -> (Fit, Option<Incumbent>) {
        let until = self.calls.get() + calls;
        let mut nodes = vec![root.clone()];
        for (a, _) in inc {
            let c = self.child(nodes.last().expect("root"), a);
            nodes.push(c);
        }
        let len = inc.len();
        for k in (0..len).rev() {
            match self.fits_within(
                &nodes[k].state,
                len - 1 - k,
                until.saturating_sub(self.calls.get()).max(1),
            ) {
                Fit::Yes(v) => {
                    let Some((cost, tail)) = self.plan_from_memo(&nodes[k], v) else {
                        return (Fit::Stopped, None);
                    };
                    let mut path = inc[..k].to_vec();
                    path.extend(tail);
                    return (Fit::Yes(k + v), Some((cost, path)));
                }
                Fit::No => {}
                Fit::Stopped => return (Fit::Stopped, None),
            }
        }
        (Fit::No, None)
    }

    /// The objects that need a push: released ones, and table objects no direct placement can
    /// take any more.
    fn must_push(&self, state: &[ObjState]) -> Vec<usize> {
        let done: Vec<usize> = (0..self.inst.n()).filter(|&i| state[i] == ObjState::Done).collect();
        let done_mask = done.iter().fold(0u64, |m, &i| m | 1u64 << (i % 64));
        (0..self.inst.n())
            .filter(|&i| match state[i] {
                ObjState::Released { .. } => true,
                ObjState::Table if self.push_lines.is_some() => {
                    self.info[i].never_direct || self.slab_hits[i].iter().flatten().all(|&m| m & done_mask != 0)
                }
                ObjState::Table => self.info[i].never_direct || self.direct_blocked(i, &done),
                ObjState::Done => false,
            })
            .collect()
    }

    /// Lower bound on the pushes still needed, and the objects that need one.
    /// `floor` is a number of pushes already proven necessary.
    /// `released` is [`Search::released`] of `state`.
    fn push_lower_bound(&self, state: &[ObjState], released: &[Rel], floor: usize) -> (usize, Vec<usize>) {
        if let Some(pl) = &self.push_lines {
            return self.line_cover_bound(pl, state, released, floor);
        }
        let inst = self.inst;
        let needs_push = self.must_push(state);
        if self.opts.no_multi_push {
            // One object per push: nothing is shared.
            return (needs_push.len(), needs_push);
        }
        if inst.n() > 64 || needs_push.len() > 64 {
            // Beyond the bit masks below: one push at least, shared as much as can be.
            return (usize::from(!needs_push.is_empty()), needs_push);
        }
        // One push moves one line: a chain of open targets, each directly behind the last,
        // all released for the same direction. Objects that can never be on one line together
        // (not on a common chain in any direction both may still take) need pushes of their
        // own, so any such pairwise-unshareable set bounds the pushes; take the largest.
        let open = (0..inst.n())
            .filter(|&i| state[i] != ObjState::Done)
            .fold(0u64, |m, i| m | 1 << i);
        let mut chain = [vec![0u64; inst.n()], vec![0u64; inst.n()]];
        for (k, desc) in chain.iter_mut().enumerate() {
            // Back to front, so every object behind `a` already has its own set.
            for &a in self.front_to_back[k].iter().rev() {
                let mut m = self.behind[k][a] & open;
                let mut d = m;
                while m != 0 {
                    let b = m.trailing_zeros() as usize;
                    m &= m - 1;
                    d |= desc[b];
                }
                desc[a] = d;
            }
        }
        let allows = |i: usize, k: usize| match state[i] {
            ObjState::Released { push_dir, .. } => push_dir == PushDir::ALL[k],
            _ => self.info[i].push_dir_ok[k],
        };
        let share = |a: usize, b: usize| {
            (0..2).any(|k| allows(a, k) && allows(b, k) && (chain[k][a] >> b & 1 == 1 || chain[k][b] >> a & 1 == 1))
        };
        let adj: Vec<u64> = needs_push
            .iter()
            .enumerate()
            .map(|(x, &a)| {
                needs_push
                    .iter()
                    .enumerate()
                    .filter(|&(y, &b)| x != y && share(a, b))
                    .fold(0u64, |m, (y, _)| m | 1 << y)
            })
            .collect();
        (max_independent(&adj), needs_push)
    }

    /// [`Search::push_lower_bound`] from the lines a push can still move (`push_lines`).
    ///
    /// A line is usable when all its members are open and may take its direction, and some gap
    /// pattern of it is blocked by no object already at its target (done objects never move
    /// again). Push demands are the objects that need a push, and the pairs of table objects
    /// that block each other's direct placement for good: object `i` placed directly needs,
    /// on the axis it uses, every object in a finger slab still away, so if `j` stands in every
    /// usable slab of `i` and `i` in every usable slab of `j`, whichever is placed directly
    /// first makes the other's impossible, and one of the two needs a push. Two demands that no
    /// usable line serves together need two pushes, so a largest set of pairwise unshareable
    /// demands bounds the pushes. A demand that no usable line serves at all makes the state a
    /// dead end ([`DEAD_END`]).
    fn line_cover_bound(
        &self,
        lines: &[PushLine],
        state: &[ObjState],
        released: &[Rel],
        floor: usize,
    ) -> (usize, Vec<usize>) {
        let mut done = 0u64;
        let mut allow = [0u64; 2];
        for (i, s) in state.iter().enumerate() {
            match s {
                ObjState::Done => done |= 1 << i,
                ObjState::Released { push_dir, .. } => {
                    allow[PushDir::ALL
                        .iter()
                        .position(|d| d == push_dir)
                        .expect("a push direction")] |= 1 << i
                }
                ObjState::Table => {
                    for (k, a) in allow.iter_mut().enumerate() {
                        if self.info[i].push_dir_ok[k] {
                            *a |= 1 << i;
                        }
                    }
                }
            }
        }
        // Per table object, the objects in every finger slab still usable (`None`: no usable
        // slab left, so the object needs a push).
        // Per table object, the objects in every finger slab still usable (`None`: no usable
        // slab left, so the object needs a push). A slab is lost for good to an object done,
        // or to one released that stands in it both where it is and at its target.
        let blocking = |i: usize| -> Option<u64> {
            if self.info[i].never_direct {
                return None;
            }
            self.slab_hits[i]
                .iter()
                .enumerate()
                .filter_map(|(ax, m)| m.map(|m| (ax, m)))
                .filter(|&(ax, m)| {
                    m & done == 0
                        && self.direct_hits.get(i).is_none_or(|h| {
                            h.axes[ax].as_ref().is_none_or(|(_, rel)| {
                                released
                                    .iter()
                                    .all(|&(j, k, mj)| m >> j & 1 == 0 || rel[j][k] >> mj & 1 == 0)
                            })
                        })
                })
                .fold(None, |acc: Option<u64>, (_, m)| Some(acc.map_or(m, |a| a & m)))
        };
        let mut demands: Vec<u64> = Vec::new();
        let mut needs_push = Vec::new();
        let mut direct_need = Vec::new();
        for (i, s) in state.iter().enumerate() {
            match s {
                ObjState::Released { .. } => needs_push.push(i),
                ObjState::Table => match blocking(i) {
                    None => needs_push.push(i),
                    Some(m) => direct_need.push((i, m)),
                },
                ObjState::Done => {}
            }
        }
        demands.extend(needs_push.iter().map(|&i| 1u64 << i));
        for (x, &(i, mi)) in direct_need.iter().enumerate() {
            for &(j, mj) in &direct_need[x + 1..] {
                if demands.len() < 64 && mi >> j & 1 == 1 && mj >> i & 1 == 1 {
                    demands.push(1 << i | 1 << j);
                }
            }
        }
        // Per object, the demands it serves (bit per demand).
        let mut demands_of = [0u64; 64];
        for (y, &dm) in demands.iter().enumerate() {
            for o in bits(dm) {
                demands_of[o] |= 1 << y;
            }
        }
        let mut served = 0u64;
        let mut adj = vec![0u64; demands.len()];
        // Usable lines, each with the objects that block every usable pattern of it once done.
        let mut usable: Vec<(u64, u64)> = Vec::new();
        for (li, l) in lines.iter().enumerate() {
            if l.members & !allow[l.dir] != 0 {
                continue;
            }
            let Some(stuck) = l
                .blockers
                .iter()
                .filter(|&&b| b & done == 0)
                .fold(None, |acc: Option<u64>, &b| Some(acc.map_or(b, |a| a & b)))
            else {
                continue;
            };
            if !self.line_releasable(li, l, state, done, released) {
                continue;
            }
            usable.push((l.members, stuck));
            let here = bits(l.members).fold(0u64, |h, o| h | demands_of[o]);
            served |= here;
            let mut m = here;
            while m != 0 {
                let y = m.trailing_zeros() as usize;
                m &= m - 1;
                adj[y] |= here & !(1 << y);
            }
        }
        let all = if demands.len() == 64 {
            u64::MAX
        } else {
            (1u64 << demands.len()) - 1
        };
        if served != all {
            return (DEAD_END, needs_push);
        }
        let unshareable = max_independent(&adj);
        if usable.len() > 64 {
            return (unshareable.max(floor), needs_push); // beyond the line masks of the cover search
        }
        let open = (0..state.len()).fold(0u64, |m, i| m | 1 << i) & !done;
        let mut block = [0u64; 64];
        for &(i, m) in &direct_need {
            block[i] = m & open;
        }
        let must = needs_push.iter().fold(0u64, |m, &i| m | 1 << i);
        let mut lines_of = [0u64; 64];
        for (l, &(members, _)) in usable.iter().enumerate() {
            for o in bits(members) {
                lines_of[o] |= 1 << l;
            }
        }
        let cover = Cover {
            open,
            must,
            block: &block,
            lines: &usable,
            lines_of: &lines_of,
            steps: Cell::new(0),
        };
        (cover.min_lines(unshareable.max(floor)), needs_push)
    }

    /// Whether the table members of line `l` can still be released in front of, between and
    /// behind its released members for one push: at offsets that do not decrease toward the
    /// back (the push check's rule), each where some grasp axis is blocked neither by an
    /// object done now (done for good), nor by a released member of the line (which stays
    /// where it is until this very push moves it), nor by another released object both where
    /// it is and at its target (it is at one of the two until the end). A necessary condition
    /// for the line's push in any plan from `state`.
    fn line_releasable(&self, li: usize, l: &PushLine, state: &[ObjState], done: u64, released: &[Rel]) -> bool {
        if self.release_hits.is_empty() {
            return true;
        }
        let d = self.inst.gripper.min_offset;
        let (fixed, either): (Vec<Rel>, Vec<Rel>) = released.iter().partition(|r| l.members >> r.0 & 1 == 1);
        let step = |j: usize| fixed.iter().find(|r| r.0 == j).map(|r| r.2);
        // Greedy from the front, each table member at its smallest workable offset: the only
        // constraints between members are the order of the offsets, so any workable assignment
        // lies pointwise at or above this one.
        let mut lo = 1;
        for (t, &i) in l.order.iter().enumerate() {
            match state[i] {
                ObjState::Released { .. } => {
                    let m = step(i).expect("released");
                    if m < lo || (t + 1 == l.order.len() && !self.line_reach(li, l, m)) {
                        return false;
                    }
                    lo = m;
                }
                ObjState::Table => {
                    let cap = self.steps[i][l.dir];
                    let hi = l.order[t + 1..].iter().find_map(|&j| step(j)).unwrap_or(cap).min(cap);
                    let hits = &self.release_hits[i][l.dir];
                    // The back member's offset is the push distance: the robot must reach it.
                    let back = t + 1 == l.order.len();
                    match (lo..=hi).find(|&m| {
                        self.in_box(i, PushDir::ALL[l.dir], d * m as f64)
                            && hits[m - 1].open_with(done, &fixed, &either)
                            && (!back || self.line_reach(li, l, m))
                    }) {
                        Some(m) => lo = m,
                        None => return false,
                    }
                }
                ObjState::Done => return false,
            }
        }
        true
    }

    /// With `exact`, and once the minimum number of actions is proven, the remaining pushes come
    /// from phase 1's memoised depth-first search; without, from the cheap push bound alone.
    fn h(&self, n: &Node, exact: bool) -> Cost {
        let inst = self.inst;
        let table: Vec<usize> = (0..inst.n()).filter(|&i| n.state[i] == ObjState::Table).collect();
        // Pushes still needed: exact (given the proven minimum) once that is known, else the
        // push bound (memoised with phase 1's facts in `lower_len`).
        let mut pushes = self.lower_len(&n.state, 0).saturating_sub(table.len());
        let needs_push = self.must_push(&n.state);
        if let Some(l) = self.lstar.get().filter(|_| exact) {
            let budget = l.saturating_sub(n.g.len);
            // Remaining actions: exactly `budget` when it fits (no plan beats L*), else more.
            let t = if self.fits(&n.state, budget).is_some() {
                budget
            } else {
                budget + 1
            };
            pushes = pushes.max(t.saturating_sub(table.len()));
        }
        let any_released = n.state.iter().any(|s| matches!(s, ObjState::Released { .. }));
        // Area: every object on the table that needs a push must be released somewhere; each
        // one alone forces at least its cheapest direction (offsets beyond d only grow it).
        let grown = |e: &[f64; 2]| n.ext[0].max(e[0]) * n.ext[1].max(e[1]);
        // Phase 2 proves that no plan of `L*` actions sweeps less than `area_floor`.
        let mut area = (n.ext[0] * n.ext[1]).max(self.area_floor.get());
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
        // Every action ends above the end region of an object not yet done (its release, or
        // just behind it after a push), so the move into a pick starts from the arm's current
        // position or from one of those regions.
        let d = inst.gripper.min_offset;
        let open: Vec<usize> = (0..inst.n()).filter(|&i| n.state[i] != ObjState::Done).collect();
        let from_ends = |p: [f64; 2], except: usize| {
            open.iter()
                .filter(|&&j| j != except)
                .map(|&j| self.info[j].end_region.distance_to(p))
                .fold(f64::INFINITY, f64::min)
        };
        let mut travel = 0.0;
        for &i in &table {
            let inf = &self.info[i];
            let arm = pick_arm(inst, i).index();
            let approach = from_ends(inf.pre_grasp_c, i).min((inf.pre_grasp - n.pos[arm]).norm());
            let transfer = inf.transfer_min.max(self.dist_to_container(&inf.pre_grasp));
            travel += approach + inf.pick_vertical + transfer + inf.release_vertical;
        }
        travel += pushes as f64 * (self.push_vertical + d);
        for k in 0..2 {
            let arm = if k == 0 { Arm::Left } else { Arm::Right };
            let picks = table.iter().any(|&i| pick_arm(inst, i) == arm);
            // An arm that still acts ends its last action above the end region of an object not
            // done now; one that may only push may also stop now, where it stands.
            let home_c = self.home_c[k];
            let from_last = || {
                open.iter()
                    .map(|&j| self.info[j].end_region.distance_to(home_c))
                    .fold(f64::INFINITY, f64::min)
            };
            if picks {
                travel += self.dist_to_container(&self.home[k]).max(from_last());
            } else if any_released && n.used[k] {
                let stop_now = (self.home[k] - n.pos[k]).norm();
                travel += self.dist_to_container(&self.home[k]).max(from_last().min(stop_now));
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

    /// Lower bound on the cost of every completion of `n`. Children get the cheap bound
    /// (`exact = false`) when generated and the phase-1 bound only when popped: most children
    /// are never popped (their cheap bound already reaches the incumbent, or the search ends
    /// first), and phase 1 on a state costs a depth-first search.
    fn f_of(&self, n: &Node, exact: bool) -> Cost {
        if n.goal {
            return n.g;
        }
        let slot: fn(&mut Prof) -> (&mut f64, &mut u64) = if exact {
            |p| (&mut p.hx_s, &mut p.hx_n)
        } else {
            |p| (&mut p.h_s, &mut p.h_n)
        };
        let h = self.timed(slot, || self.h(n, exact));
        Cost {
            len: n.g.len + h.len,
            area: n.g.area.max(h.area),
            travel: n.g.travel + h.travel,
        }
    }

    /// Actions the layout allows in a state, reachable or not (cached: they depend on object
    /// states only).
    fn successors(&self, state: &[ObjState]) -> Successors {
        let k = obj_key(state, self.inst.gripper.min_offset);
        let boxed = self.area_box.get().is_some();
        if boxed {
            if let Some(v) = self.box_succ.borrow().get(&k) {
                return v.clone();
            }
        }
        let cached = self.succ_cache.borrow().get(&k).cloned();
        let v = cached.unwrap_or_else(|| {
            let v = Rc::new(self.timed(|p| (&mut p.succ_s, &mut p.succ_n), || self.successors_uncached(state)));
            self.succ_cache.borrow_mut().insert(k.clone(), v.clone());
            v
        });
        if !boxed {
            return v;
        }
        let kept: Successors = Rc::new(
            v.iter()
                .filter(|(a, _)| match a {
                    Action::Place {
                        object,
                        mode: PlaceMode::Indirect { push_dir, offset },
                        ..
                    } => self.in_box(*object, *push_dir, *offset),
                    _ => true,
                })
                .cloned()
                .collect(),
        );
        self.box_succ.borrow_mut().insert(k, kept.clone());
        kept
    }

    /// Whether the release of object `i` for a push along `dir` at `offset` lies within the
    /// current `area_box` (always, without one). Direct placements lie within the placement's
    /// extent, the smallest box there is.
    fn in_box(&self, i: usize, dir: PushDir, offset: f64) -> bool {
        self.area_box.get().is_none_or(|[x, y]| {
            let r = self.placement.targets[i].rect.moved(dir, -offset);
            r.x1 <= x + 1e-12 && r.y1 <= y + 1e-12
        })
    }

    /// Restrict every release to `b` (or lift the restriction), with a memo of its own: the
    /// facts of one box do not hold in another, and phase 1's come back when it is lifted.
    fn set_box(&self, b: Option<[f64; 2]>) {
        self.box_succ.borrow_mut().clear();
        let mut memo = self.len_memo.borrow_mut();
        let mut base = self.base_memo.borrow_mut();
        match b {
            Some(_) if base.is_none() => *base = Some(std::mem::take(&mut *memo)),
            Some(_) => memo.clear(),
            None => {
                if let Some(m) = base.take() {
                    *memo = m;
                }
            }
        }
        self.area_box.set(b);
    }

    /// Feasible actions in a state, with the push margin of each.
    fn successors_uncached(&self, state: &[ObjState]) -> Vec<Scored> {
        let inst = self.inst;
        let layout = self.layout(state);
        let d = inst.gripper.min_offset;
        let mut out = Vec::new();
        for (i, _) in state.iter().enumerate().filter(|(_, st)| **st == ObjState::Table) {
            let arm = pick_arm(inst, i);
            for mode in place_modes(self.opts.no_direct, self.steps[i], d) {
                let axes = match mode {
                    PlaceMode::Indirect { push_dir, .. } => [push_dir.axis(), push_dir.axis().other()],
                    PlaceMode::Direct => [Axis2::X, Axis2::Y],
                };
                // The grasp axis changes neither state nor cost: keep every axis the layout
                // allows, in order of preference; [`Search::usable`] takes the first reachable.
                for ax in axes {
                    let a = Action::Place {
                        object: i,
                        mode,
                        grasp_axis: ax,
                        arm,
                    };
                    if let Some(m) = self.check(&layout, &a) {
                        out.push((a, m));
                    }
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
                let mk = |arm| Action::Push {
                    pusher_at: push::centred_pusher(inst, self.placement, &line, dir),
                    objects: line.clone(),
                    push_dir: dir,
                    distance: offset,
                    arm,
                };
                // The layout check does not depend on the arm; each arm is its own successor
                // because the arms' positions, and so the travel, differ.
                let arms = push_arms(inst, back);
                if let Some(m) = self.check(&layout, &mk(arms[0])) {
                    out.extend(arms.into_iter().map(|arm| (mk(arm), m)));
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
            exact: false,
        };
        c.f = self.f_of(&c, false);
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

    /// Order key of [`DiveOrder::FrontFirst`]: pushes first, then places by how far their
    /// target lies from the container's origin corner (pushes go toward it, so an object
    /// released early near the back would stand in the way of later ones).
    fn front_key(&self, a: &Action) -> f64 {
        match a {
            Action::Push { .. } => f64::NEG_INFINITY,
            Action::Place { object, .. } => {
                let r = self.placement.targets[*object].rect;
                r.x0 + r.y0
            }
        }
    }

    /// Phase 2: the least swept area of any plan of `l` (= `L*`) actions, as the smallest box
    /// `[0, x] × [0, y]` that holds every release of one. The swept extents of a plan are the
    /// placement's extent grown by its releases, so `x` is the placement's or a release's `x1`
    /// (likewise `y`), and the plan's area is `x·y` of its own box. Boxes go by area, each
    /// asked as phase 1's question with the releases outside it left out; a refuted box
    /// refutes every box inside it. The first box that fits has the least area: it becomes
    /// [`Search::area_floor`], and the incumbent becomes a plan in it. When it is the only box
    /// of that area, it stays set for the main search (every plan left has that area, so the
    /// search orders by travel alone and its exact bound prunes what cannot stay inside);
    /// otherwise phase 1's state comes back. Stopped by the time limit, the floor is the area
    /// of the box being asked. Returns the number of boxes of the least area that fit.
    fn min_area_box(&self, root: &Node, l: usize, incumbent: &mut Option<Incumbent>, trace: bool) -> usize {
        let d = self.inst.gripper.min_offset;
        let floor = self.inst.container.floor();
        let (mx, my) = self.placement.extent();
        let (mut xs, mut ys) = (vec![mx], vec![my]);
        for i in 0..self.inst.n() {
            for (k, dir) in PushDir::ALL.into_iter().enumerate() {
                for m in 1..=self.steps[i][k] {
                    let r = self.placement.targets[i].rect.moved(dir, -(d * m as f64));
                    if r.inside(&floor) {
                        xs.push(r.x1);
                        ys.push(r.y1);
                    }
                }
            }
        }
        for v in [&mut xs, &mut ys] {
            v.sort_by(f64::total_cmp);
            v.dedup_by(|a, b| (*a - *b).abs() <= 1e-12);
        }
        let lo = self.h(root, false).area;
        let hi = incumbent
            .as_ref()
            .filter(|(c, _)| c.len == l)
            .map_or(f64::INFINITY, |(c, _)| c.area);
        let mut pairs: Vec<[f64; 2]> = xs
            .iter()
            .filter(|&&x| x >= mx - 1e-12)
            .flat_map(|&x| ys.iter().filter(|&&y| y >= my - 1e-12).map(move |&y| [x, y]))
            .filter(|[x, y]| x * y >= lo - 1e-12 && x * y <= hi + 1e-12)
            .collect();
        pairs.sort_by(|a, b| (a[0] * a[1]).total_cmp(&(b[0] * b[1])));
        let mut refuted: Vec<[f64; 2]> = Vec::new();
        let inside = |p: &[f64; 2], q: &[f64; 2]| p[0] <= q[0] + 1e-12 && p[1] <= q[1] + 1e-12;
        let mut best: Option<f64> = None;
        let mut fitting: Vec<[f64; 2]> = Vec::new();
        for p in pairs {
            let area = p[0] * p[1];
            if best.is_some_and(|b| area > b + 1e-12) {
                break;
            }
            if refuted.iter().any(|r| inside(&p, r)) {
                continue;
            }
            self.set_box(Some(p));
            match self.fits_within(&root.state, l, u64::MAX / 2) {
                Fit::Yes(_) => {
                    if best.is_none() {
                        best = Some(area);
                        self.area_floor.set(area);
                        if incumbent
                            .as_ref()
                            .is_none_or(|(c, _)| c.len > l || c.area > area + 1e-12)
                        {
                            if let Some(plan) = self.plan_from_memo(root, l) {
                                *incumbent = Some(plan);
                            }
                        }
                    }
                    fitting.push(p);
                }
                Fit::No => refuted.push(p),
                Fit::Stopped => {
                    // Every box of less area is refuted.
                    self.area_floor
                        .set(self.area_floor.get().max(area.min(best.unwrap_or(area))));
                    self.set_box(None);
                    return 0;
                }
            }
            if trace {
                eprintln!(
                    "phase 2: box {:.4} x {:.4} = {:.2} cm²: {}",
                    p[0],
                    p[1],
                    area * 1e4,
                    if fitting.last() == Some(&p) { "fits" } else { "refuted" }
                );
            }
        }
        if best.is_none() {
            // Every box up to the incumbent's refuted but its own: only by rounding.
            self.set_box(None);
            return 0;
        }
        if fitting.len() == 1 {
            // Phase 2's facts about this box are the main search's.
            self.set_box(Some(fitting[0]));
        } else {
            self.set_box(None);
        }
        fitting.len()
    }

    /// Greedy dive with bounded backtracking: the first incumbent.
    fn dive(&self, root: &Node, budget: &mut u64, order: DiveOrder) -> Option<Incumbent> {
        if Self::all_done(root) {
            return Some((self.goal_of(root).g, Vec::new()));
        }
        if *budget == 0 || self.stop.is_some_and(|t| t.should_stop()) {
            return None;
        }
        let key = obj_key(&root.state, self.inst.gripper.min_offset);
        if self.len_memo.borrow().get(&key).is_some_and(|&(lo, _)| lo >= DEAD_END) {
            return None; // reached before by another order and found dead
        }
        *budget -= 1;
        let mut kids: Vec<(Node, Action, Option<f64>)> = self
            .successors(&root.state)
            .iter()
            .map(|(a, m)| (self.child(root, a), a.clone(), *m))
            .filter(|(c, _, _)| c.f.len < DEAD_END)
            .collect();
        // Stable sort: the grasp axes of one placement stay in order of preference.
        match order {
            DiveOrder::Bound => kids.sort_by(|x, y| x.0.f.cmp_lex(&y.0.f)),
            DiveOrder::FrontFirst => kids.sort_by(|x, y| {
                self.front_key(&x.1)
                    .total_cmp(&self.front_key(&y.1))
                    .then(x.0.f.cmp_lex(&y.0.f))
            }),
        }
        // Placements (object, mode) already dived into: another grasp axis leads to the same
        // state at the same cost.
        let mut tried: Vec<(usize, PlaceMode)> = Vec::new();
        for (c, a, m) in kids {
            if let Action::Place { object, mode, .. } = &a {
                if tried.contains(&(*object, *mode)) {
                    continue;
                }
            }
            // Reachability is asked only of the child about to be entered.
            if !self.reachable(&a, &root.state) {
                continue;
            }
            if let Action::Place { object, mode, .. } = &a {
                tried.push((*object, *mode));
            }
            if let Some((cost, mut path)) = self.dive(&c, budget, order) {
                path.insert(0, (a, m));
                return Some((cost, path));
            }
        }
        // Every child was entered and failed in full (the budget never ran out, so none was
        // cut short): no plan finishes from this state, whatever the order that led here. The
        // fact is phase 1's too, and other orders that reach this state skip it.
        if *budget > 0 && !self.stop.is_some_and(|t| t.should_stop()) {
            let old = self.len_memo.borrow_mut().insert(key, (DEAD_END, usize::MAX));
            debug_assert!(old.is_none_or(|(_, hi)| hi == usize::MAX), "a dead end with a plan");
        }
        None
    }
}

/// Size of a largest independent set of the graph with neighbour masks `adj` (at most 64
/// vertices). Exact: a vertex of degree 0 or 1 is in some largest set, so it is taken without
/// branching; otherwise the search branches on a vertex of largest degree (in or out), pruned
/// by the vertices left.
fn max_independent(adj: &[u64]) -> usize {
    fn go(adj: &[u64], p: u64, size: usize, best: &mut usize) {
        if size + p.count_ones() as usize <= *best {
            return;
        }
        if p == 0 {
            *best = size;
            return;
        }
        let mut m = p;
        let (mut lo, mut hi) = ((u32::MAX, 0usize), (0u32, 0usize));
        while m != 0 {
            let v = m.trailing_zeros() as usize;
            m &= m - 1;
            let deg = (adj[v] & p).count_ones();
            if deg < lo.0 {
                lo = (deg, v);
            }
            if deg >= hi.0 {
                hi = (deg, v);
            }
        }
        if lo.0 <= 1 {
            let v = lo.1;
            return go(adj, p & !(1 << v) & !adj[v], size + 1, best);
        }
        let v = hi.1;
        go(adj, p & !(1 << v) & !adj[v], size + 1, best);
        go(adj, p & !(1 << v), size, best);
    }
    debug_assert!(adj.len() <= 64);
    let mut best = 0;
    go(
        adj,
        if adj.len() == 64 {
            u64::MAX
        } else {
            (1u64 << adj.len()) - 1
        },
        0,
        &mut best,
    );
    best
}

/// The indices of the set bits of `m`, lowest first.
fn bits(mut m: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (m != 0).then(|| {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            i
        })
    })
}

/// Depth-first steps [`Cover::min_lines`] may take on one state before it settles for the
/// size it has not yet refuted (still a lower bound).
const MAX_COVER_STEPS: usize = 48;

/// The push bound of one state as a covering problem: which usable lines, pushed, could finish
/// the objects still open (see [`Cover::min_lines`]).
struct Cover<'s> {
    /// Objects not at their targets.
    open: u64,
    /// Objects that must be pushed: released ones, and table objects no direct placement can
    /// ever take.
    must: u64,
    /// Per table object that may still be placed directly: the open objects that stand in every
    /// finger slab it could use, so they must reach their targets after it is placed.
    block: &'s [u64],
    /// Usable lines (at most 64): members, and the objects that block every usable gap
    /// pattern once done.
    lines: &'s [(u64, u64)],
    /// Per object, the usable lines it is a member of (bit per line).
    lines_of: &'s [u64],
    steps: Cell<usize>,
}

impl Cover<'_> {
    /// A lower bound on the pushes still needed: the fewest disjoint usable lines that cover
    /// every object that must be pushed and leave the rest placeable directly in some order,
    /// starting from `from` (a bound already proven). [`DEAD_END`] when no set of lines does.
    ///
    /// Every plan pushes a set of disjoint lines (a pushed object is done for good), each
    /// usable now (done objects stay done), covering the objects that must be pushed; every
    /// other open object is placed directly. Each object reaches its target once: a direct one
    /// when it is placed, a line's members when the line is pushed. Those moments must respect
    /// two orders: a directly placed object goes down before every object in its finger slabs
    /// is done (`block`), and a line is pushed before each object that blocks all its usable
    /// gap patterns is done. A cycle among them means no plan pushes exactly those lines. So
    /// the pushes of any plan form a cover in this sense, and the fewest lines of one bound
    /// its pushes from below. Found by iterative deepening on the number of lines; past
    /// [`MAX_COVER_STEPS`] the search returns the smallest size it has not refuted.
    fn min_lines(&self, from: usize) -> usize {
        let max = self.open.count_ones() as usize;
        for k in from..=max {
            match self.search(k, 0, &mut Vec::new()) {
                Some(true) | None => return k,
                Some(false) => {}
            }
        }
        DEAD_END
    }

    /// Whether `left` more disjoint lines, added to `chosen` (members `cov`), make a cover;
    /// `None` when the step budget ran out first.
    fn search(&self, left: usize, cov: u64, chosen: &mut Vec<usize>) -> Option<bool> {
        let steps = self.steps.get() + 1;
        self.steps.set(steps);
        if steps > MAX_COVER_STEPS {
            return None;
        }
        // Lines disjoint from those chosen.
        let taken = bits(cov).fold(0u64, |t, o| t | self.lines_of[o]);
        let candidates = |o: usize| self.lines_of[o] & !taken;
        let todo = self.must & !cov;
        let branch_on: u64 = if todo != 0 {
            if left == 0 {
                return Some(false);
            }
            // The object with the fewest lines left: any cover has one of them.
            let mut best: Option<(u32, u64)> = None;
            for o in bits(todo) {
                let c = candidates(o);
                if best.is_none_or(|(bc, _)| c.count_ones() < bc) {
                    best = Some((c.count_ones(), c));
                }
            }
            best.expect("todo is not empty").1
        } else {
            match self.cycle(cov, chosen) {
                None => return Some(true),
                // A cycle through lines alone: no line added later changes it.
                Some(0) => return Some(false),
                Some(_) if left == 0 => return Some(false),
                // A cover must take one of the cycle's direct objects into a line.
                Some(directs) => bits(directs).fold(0u64, |ls, o| ls | candidates(o)),
            }
        };
        for l in bits(branch_on) {
            chosen.push(l);
            let r = self.search(left - 1, cov | self.lines[l].0, chosen);
            chosen.pop();
            match r {
                Some(false) => {}
                other => return other,
            }
        }
        Some(false)
    }

    /// The directly placed objects on some cycle of the order constraints (`Some(0)` for a
    /// cycle of lines alone), or `None` when the constraints can all be met.
    fn cycle(&self, cov: u64, chosen: &[usize]) -> Option<u64> {
        // One node per moment something reaches its target, named by an object: a direct
        // object by itself, a line by its lowest member.
        let mut rep = [0u8; 64];
        for o in bits(self.open) {
            rep[o] = o as u8;
        }
        for &l in chosen {
            let members = self.lines[l].0;
            for o in bits(members) {
                rep[o] = members.trailing_zeros() as u8;
            }
        }
        let to_nodes = |m: u64| bits(m).fold(0u64, |out, o| out | 1 << rep[o]);
        let mut out = [0u64; 64];
        let mut nodes = 0u64;
        for o in bits(self.open & !cov) {
            out[o] = to_nodes(self.block[o]);
            nodes |= 1 << o;
        }
        for &l in chosen {
            let (members, stuck) = self.lines[l];
            let r = members.trailing_zeros() as usize;
            out[r] = to_nodes(stuck & self.open);
            nodes |= 1 << r;
        }
        // Peel off nodes without a predecessor or without a successor among those left: what
        // stays lies on a cycle or between cycles, and every node of it has a successor in it.
        let mut r = nodes;
        loop {
            let has_in = bits(r).fold(0u64, |h, u| h | out[u] & r);
            let keep = bits(r & has_in)
                .filter(|&u| out[u] & r != 0)
                .fold(0u64, |k, u| k | 1 << u);
            if keep == r {
                break;
            }
            r = keep;
        }
        if r == 0 {
            return None;
        }
        // Walk successors inside `r` until a node repeats: the walk from there is a cycle.
        let mut path: Vec<usize> = Vec::new();
        let mut seen = 0u64;
        let mut v = r.trailing_zeros() as usize;
        while seen >> v & 1 == 0 {
            seen |= 1 << v;
            path.push(v);
            v = (out[v] & r).trailing_zeros() as usize;
        }
        let start = path.iter().position(|&u| u == v).expect("v was seen");
        Some(
            path[start..]
                .iter()
                .filter(|&&u| cov >> u & 1 == 0)
                .fold(0u64, |m, &u| m | 1 << u),
        )
    }
}

/// Per object and grasp axis, what [`Search::slab_hits`] holds.
fn slab_hits(inst: &Instance, placement: &Placement) -> Vec<[Option<u64>; 2]> {
    let g = &inst.gripper;
    let walls = inst.container.walls();
    (0..inst.n())
        .map(|i| {
            let t = placement.targets[i];
            [Axis2::X, Axis2::Y].map(|ax| {
                if t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS {
                    return None;
                }
                let slabs = crate::actions::finger_slabs(g, &t.rect, t.height, ax);
                if slabs.iter().any(|s| walls.iter().any(|w| w.intersects(s))) {
                    return None;
                }
                Some((0..inst.n()).filter(|&j| j != i).fold(0u64, |m, j| {
                    let tj = placement.targets[j];
                    let b = crate::geometry::Box3::extrude(&tj.rect, 0.0, tj.height);
                    if slabs.iter().any(|s| b.intersects(s)) {
                        m | 1 << j
                    } else {
                        m
                    }
                }))
            })
        })
        .collect()
}

/// What stops one place action (an object, a place mode), per grasp axis (X, Y): `None` when
/// the axis cannot work with nothing else in the container, else the objects whose targets
/// block it once done, and per other object `j` and push direction `k`, the offset steps (bit
/// `m`) at which `j`, released there, blocks it.
///
/// A place check fails exactly when the static part fails or some single object's footprint or
/// box stands in the way (overlap, finger slabs), so checks against one object at a time decide
/// it for any set of them.
struct PlaceHits {
    axes: [Option<(u64, Vec<[u64; 2]>)>; 2],
}

/// A released object: index, push direction (as in [`PushDir::ALL`]), offset step.
type Rel = (usize, usize, usize);

/// One place action of a known object: direct, or indirect with push direction (as in
/// [`PushDir::ALL`]) and offset step; and the grasp axis (0 for X, 1 for Y).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PlaceKey {
    Direct(usize),
    Indirect(usize, usize, usize),
}

impl PlaceKey {
    fn axis(self) -> usize {
        match self {
            PlaceKey::Direct(ax) | PlaceKey::Indirect(_, _, ax) => ax,
        }
    }

    /// The key of `mode` with grasp axis `ax` (offsets in steps of `d`).
    fn of(mode: PlaceMode, ax: usize, d: f64) -> PlaceKey {
        match mode {
            PlaceMode::Direct => PlaceKey::Direct(ax),
            PlaceMode::Indirect { push_dir, offset } => {
                let (k, m) = step_of(push_dir, offset, d);
                PlaceKey::Indirect(k, m, ax)
            }
        }
    }
}

/// An indirect place mode by push direction (index into [`PushDir::ALL`]) and offset step.
fn indirect_mode(k: usize, m: usize, d: f64) -> PlaceMode {
    PlaceMode::Indirect {
        push_dir: PushDir::ALL[k],
        offset: d * m as f64,
    }
}

/// The push direction (index into [`PushDir::ALL`]) and offset step of a release.
fn step_of(push_dir: PushDir, offset: f64, d: f64) -> (usize, usize) {
    let k = PushDir::ALL
        .iter()
        .position(|x| *x == push_dir)
        .expect("a push direction");
    (k, (offset / d).round() as usize)
}

/// Every place mode of an object with `steps` offset steps per push direction: direct first
/// (unless forbidden), then each direction's offsets, nearest first.
fn place_modes(no_direct: bool, steps: [usize; 2], d: f64) -> impl Iterator<Item = PlaceMode> {
    (!no_direct)
        .then_some(PlaceMode::Direct)
        .into_iter()
        .chain((0..2).flat_map(move |k| (1..=steps[k]).map(move |m| indirect_mode(k, m, d))))
}

impl PlaceHits {
    /// Whether some grasp axis can still work, given that the objects in `done` stay at their
    /// targets, those in `fixed` stay where they are released, and those in `either` are
    /// released now and will be at their targets after their push: one of the two positions
    /// must leave the axis free.
    fn open_with(&self, done: u64, fixed: &[Rel], either: &[Rel]) -> bool {
        (0..2).any(|ax| self.axis_open(ax, done, fixed, either))
    }

    /// [`PlaceHits::open_with`] for grasp axis `ax` (0 for X, 1 for Y) alone.
    fn axis_open(&self, ax: usize, done: u64, fixed: &[Rel], either: &[Rel]) -> bool {
        self.axes[ax].as_ref().is_some_and(|(d, rel)| {
            d & done == 0
                && fixed.iter().all(|&(j, k, m)| rel[j][k] >> m & 1 == 0)
                && either
                    .iter()
                    .all(|&(j, k, m)| d >> j & 1 == 0 || rel[j][k] >> m & 1 == 0)
        })
    }
}

/// [`PlaceHits`] of placing object `i` in `mode` (offset steps of other objects up to `steps`).
fn place_hits(inst: &Instance, placement: &Placement, steps: &[[usize; 2]], i: usize, mode: PlaceMode) -> PlaceHits {
    let n = inst.n();
    let d = inst.gripper.min_offset;
    let floor = inst.container.floor();
    let axes = [Axis2::X, Axis2::Y].map(|ax| {
        let a = Action::Place {
            object: i,
            mode,
            grasp_axis: ax,
            arm: pick_arm(inst, i),
        };
        let mut layout = Layout::new(inst, placement);
        layout.check(&a).ok()?;
        let mut done = 0u64;
        let mut rel = vec![[0u64; 2]; n];
        for j in (0..n).filter(|&j| j != i) {
            layout.state[j] = ObjState::Done;
            if layout.check(&a).is_err() {
                done |= 1 << j;
            }
            for (k, dir) in PushDir::ALL.into_iter().enumerate() {
                for mj in 1..=steps[j][k] {
                    let r = placement.targets[j].rect.moved(dir, -(d * mj as f64));
                    if !r.inside(&floor) {
                        continue; // never released there
                    }
                    layout.state[j] = ObjState::Released {
                        rect: r,
                        push_dir: dir,
                        offset: d * mj as f64,
                    };
                    if layout.check(&a).is_err() {
                        rel[j][k] |= 1 << mj;
                    }
                }
            }
            layout.state[j] = ObjState::Table;
        }
        Some((done, rel))
    });
    PlaceHits { axes }
}

/// Remaining-pushes bound of a state from which no plan exists: far above any budget, and small
/// enough that sums of costs never overflow.
const DEAD_END: usize = 1 << 20;

/// Most lines, and gap patterns over all lines, [`push_lines`] lists before giving up (the
/// static checks cost one layout check per pattern and object).
const MAX_LINE_PATTERNS: usize = 4096;

/// A line a push could move, with what can stop it for good.
struct PushLine {
    /// Index of the push direction in [`PushDir::ALL`].
    dir: usize,
    /// Members (bit per object).
    members: u64,
    /// Members front to back.
    order: Vec<usize>,
    /// Per gap pattern that passes the push check with nothing else in the container: the
    /// objects whose targets, once done, make that pattern fail (empty when no pattern passes
    /// the line is left out).
    blockers: Vec<u64>,
}

/// Every line of the placement that some push could move, with the objects that block each of
/// its feasible gap patterns once at their targets; `None` when there are too many to list.
///
/// A line's push check (walls, pusher, swept space, stability) depends on the rest of the
/// container only through obstacles, and only its gap pattern (which consecutive members start
/// apart) changes the stability phases. Each pattern is checked at its smallest offsets (the
/// front at `d`, one `d` more at every gap): larger offsets of the same pattern sweep a superset
/// of the space (release to target, pusher start to end), so an object that blocks the
/// smallest offsets blocks every offset of the pattern. Released objects elsewhere only block
/// for a while and are ignored: the result is a relaxation, as a bound needs.
fn push_lines(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    info: &[ObjectInfo],
    steps: &[[usize; 2]],
) -> Option<Vec<PushLine>> {
    let n = inst.n();
    if n > 64 {
        return None;
    }
    let all: Vec<usize> = (0..n).collect();
    let max_len = if opts.no_multi_push { 1 } else { usize::MAX };
    let mut per_dir = Vec::new();
    let mut patterns = 0usize;
    for (k, dir) in PushDir::ALL.into_iter().enumerate() {
        for line in lines(placement, &all, dir, max_len) {
            if line.iter().any(|&i| !info[i].push_dir_ok[k]) {
                continue;
            }
            if line.len() > 13 {
                return None;
            }
            patterns += 1 << (line.len() - 1);
            if patterns > MAX_LINE_PATTERNS {
                return None;
            }
            per_dir.push((k, dir, line));
        }
    }
    let mut out = Vec::new();
    let mut budget = MAX_RELEASE_CHECKS;
    let budget = &mut budget;
    for (k, dir, line) in per_dir {
        let members = line.iter().fold(0u64, |m, &i| m | 1 << i);
        let back = *line.last().expect("non-empty");
        let pusher_at = push::centred_pusher(inst, placement, &line, dir);
        let arm = push_arms(inst, back)[0];
        let mut blockers = Vec::new();
        for gaps in 0u64..1 << (line.len() - 1) {
            // Smallest offsets of the pattern, in steps of `d`.
            let mut smallest = Vec::with_capacity(line.len());
            for t in 0..line.len() {
                smallest.push(if t == 0 {
                    1
                } else {
                    smallest[t - 1] + (gaps >> (t - 1) & 1) as usize
                });
            }
            if line.iter().zip(&smallest).any(|(&i, &m)| m > steps[i][k]) {
                continue;
            }
            let (layout, a) = released_line(inst, placement, &line, dir, &smallest, pusher_at, arm);
            if layout.check(&a).is_err() {
                continue;
            }
            // Some offsets of the pattern must also let the members be put down, in some
            // order, and pushed (the finger slabs of touching releases collide, so touching
            // patterns often cannot be released at all). Past the work budget a pattern is
            // kept unchecked, which only weakens the bound.
            let mut offsets = smallest.clone();
            if *budget > 0 {
                let found = any_offsets(
                    inst,
                    placement,
                    &line,
                    k,
                    gaps,
                    steps,
                    &mut offsets,
                    0,
                    pusher_at,
                    arm,
                    budget,
                );
                // `false` with the budget spent means "not known": keep the pattern.
                if !found && *budget > 0 {
                    continue;
                }
            }
            let mut layout = layout;
            let mut b = 0u64;
            for j in (0..n).filter(|j| members >> j & 1 == 0) {
                layout.state[j] = ObjState::Done;
                if layout.check(&a).is_err() {
                    b |= 1 << j;
                }
                layout.state[j] = ObjState::Table;
            }
            blockers.push(b);
        }
        if !blockers.is_empty() {
            // A pattern blocked by a superset of another's blockers adds nothing.
            blockers.sort_by_key(|b| b.count_ones());
            let mut kept: Vec<u64> = Vec::new();
            for b in blockers {
                if !kept.iter().any(|&c| c & !b == 0) {
                    kept.push(b);
                }
            }
            out.push(PushLine {
                dir: k,
                order: line,
                members,
                blockers: kept,
            });
        }
    }
    Some(out)
}

/// Layout checks [`push_lines`] may spend on whether lines can be released.
const MAX_RELEASE_CHECKS: usize = 200_000;

/// A layout with the members of `line` released at `offsets` (steps of `d`) and nothing else in
/// the container, and the push of the line.
fn released_line<'a>(
    inst: &'a Instance,
    placement: &'a Placement,
    line: &[usize],
    dir: PushDir,
    offsets: &[usize],
    pusher_at: f64,
    arm: Arm,
) -> (Layout<'a>, Action) {
    let d = inst.gripper.min_offset;
    let layout = with_released(inst, placement, line.iter().copied().zip(offsets.iter().copied()), dir);
    let a = Action::Push {
        objects: line.to_vec(),
        push_dir: dir,
        distance: d * *offsets.last().expect("non-empty") as f64,
        pusher_at,
        arm,
    };
    (layout, a)
}

/// A layout with `(object, offset steps)` released for a push along `dir`, nothing else in
/// the container.
fn with_released<'a>(
    inst: &'a Instance,
    placement: &'a Placement,
    released: impl Iterator<Item = (usize, usize)>,
    dir: PushDir,
) -> Layout<'a> {
    let mut layout = Layout::new(inst, placement);
    for (i, m) in released {
        let offset = inst.gripper.min_offset * m as f64;
        let mode = PlaceMode::Indirect { push_dir: dir, offset };
        layout.state[i] = ObjState::Released {
            rect: layout.release_rect(i, &mode),
            push_dir: dir,
            offset,
        };
    }
    layout
}

/// Whether some offsets of gap pattern `gaps` (within each member's step limit), filled in from
/// position `t` on, let the line's members be released in some order and then pushed, with
/// nothing else in the container. Spends `budget` layout checks; `false` with the budget at
/// zero means "not known".
#[allow(clippy::too_many_arguments)]
fn any_offsets(
    inst: &Instance,
    placement: &Placement,
    line: &[usize],
    k: usize,
    gaps: u64,
    steps: &[[usize; 2]],
    offsets: &mut Vec<usize>,
    t: usize,
    pusher_at: f64,
    arm: Arm,
    budget: &mut usize,
) -> bool {
    if *budget == 0 {
        return false;
    }
    if t == line.len() {
        let dir = PushDir::ALL[k];
        let (layout, a) = released_line(inst, placement, line, dir, offsets, pusher_at, arm);
        *budget = budget.saturating_sub(1);
        if layout.check(&a).is_err() {
            return false;
        }
        let mut failed = vec![false; 1 << line.len()];
        return releasable(inst, placement, line, dir, offsets, 0, &mut failed, budget);
    }
    let lo = if t == 0 {
        1
    } else {
        offsets[t - 1] + (gaps >> (t - 1) & 1) as usize
    };
    // Without a gap the offset repeats the one in front; with one, any larger offset will do.
    let hi = if t > 0 && gaps >> (t - 1) & 1 == 0 {
        lo
    } else {
        steps[line[t]][k]
    };
    for m in lo..=hi.min(steps[line[t]][k]) {
        offsets[t] = m;
        if any_offsets(
            inst,
            placement,
            line,
            k,
            gaps,
            steps,
            offsets,
            t + 1,
            pusher_at,
            arm,
            budget,
        ) {
            return true;
        }
        if *budget == 0 {
            return false;
        }
    }
    false
}

/// Whether the members of `line` not in `placed` (bit per position) can be released at
/// `offsets` in some order after those in `placed`, with nothing else in the container.
#[allow(clippy::too_many_arguments)]
fn releasable(
    inst: &Instance,
    placement: &Placement,
    line: &[usize],
    dir: PushDir,
    offsets: &[usize],
    placed: usize,
    failed: &mut [bool],
    budget: &mut usize,
) -> bool {
    if placed == (1 << line.len()) - 1 {
        return true;
    }
    if failed[placed] || *budget == 0 {
        return false;
    }
    let d = inst.gripper.min_offset;
    let here = line
        .iter()
        .zip(offsets)
        .enumerate()
        .filter(|(t, _)| placed >> t & 1 == 1)
        .map(|(_, (&i, &m))| (i, m));
    let layout = with_released(inst, placement, here, dir);
    for (t, (&i, &m)) in line.iter().zip(offsets).enumerate() {
        if placed >> t & 1 == 1 {
            continue;
        }
        let mode = PlaceMode::Indirect {
            push_dir: dir,
            offset: d * m as f64,
        };
        let ok = [Axis2::X, Axis2::Y].into_iter().any(|ax| {
            *budget = budget.saturating_sub(1);
            layout
                .check(&Action::Place {
                    object: i,
                    mode,
                    grasp_axis: ax,
                    arm: pick_arm(inst, i),
                })
                .is_ok()
        });
        if ok && releasable(inst, placement, line, dir, offsets, placed | 1 << t, failed, budget) {
            return true;
        }
    }
    if *budget > 0 {
        failed[placed] = true;
    }
    false
}

/// Whether `b`'s target sits directly behind `a`'s along `dir` (touching, with lateral
/// overlap): the one edge every line of a push is made of.
fn behind(placement: &Placement, dir: PushDir, a: usize, b: usize) -> bool {
    let (ra, rb) = (placement.targets[a].rect, placement.targets[b].rect);
    (rb.lo(dir.axis()) - ra.hi(dir.axis())).abs() <= EPS && ra.overlap_on(&rb, dir.axis().other()) > EPS
}

/// For every object, the length of the longest line (as in [`lines`]) that ends at it: the
/// paper's staggered releases put the k-th object of a line at offset `k·d`, so an object may
/// need offsets up to its rank whatever the configured step limit.
pub fn line_rank(placement: &Placement, dir: PushDir) -> Vec<usize> {
    let axis = dir.axis();
    let t = |i: usize| placement.targets[i].rect;
    let n = placement.targets.len();
    // Front to back: a line's objects have strictly increasing `lo` along the axis.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| t(a).lo(axis).total_cmp(&t(b).lo(axis)));
    let mut rank = vec![1; n];
    for (k, &b) in order.iter().enumerate() {
        for &a in &order[..k] {
            if behind(placement, dir, a, b) {
                rank[b] = rank[b].max(rank[a] + 1);
            }
        }
    }
    rank
}

/// Every line (front to back, consecutive targets touching along `dir` with lateral overlap)
/// of objects from `members`, up to `max_len` long.
pub fn lines(placement: &Placement, members: &[usize], dir: PushDir, max_len: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut stack: Vec<Vec<usize>> = members.iter().map(|&m| vec![m]).collect();
    while let Some(line) = stack.pop() {
        let last = *line.last().expect("non-empty");
        if line.len() < max_len {
            for &b in members {
                if !line.contains(&b) && behind(placement, dir, last, b) {
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

/// The actions from the root to `node` (every node but the root has one incoming edge).
fn path_to(graph: &DiGraph<Node, Scored>, node: NodeIndex) -> Vec<Scored> {
    let mut path = Vec::new();
    let mut cur = node;
    while let Some(e) = graph.edges_directed(cur, Direction::Incoming).next() {
        path.push(e.weight().clone());
        cur = e.source();
    }
    path.reverse();
    path
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
    if settings.max_offset_steps == 0 || settings.max_offset_steps > MAX_OFFSET_STEPS {
        return Err(Error::input(
            "<settings>",
            "max_offset_steps",
            format!("must be 1..={MAX_OFFSET_STEPS}"),
        ));
    }
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
        exact: false,
    };
    root.f = s.f_of(&root, false);
    let first_bound = root.f;

    // A first plan from a greedy dive, so that a stopped search still returns one.
    let mut budget = settings.dive_nodes;
    s.stop = Some(stop);
    let mut incumbent = s.dive(&root, &mut budget, DiveOrder::Bound);
    if incumbent.is_none() {
        // Ordered by the cost bound, the dive can spend its budget backtracking among the last
        // few objects of a dead end; a second dive packs from the front.
        budget = settings.dive_nodes;
        incumbent = s.dive(&root, &mut budget, DiveOrder::FrontFirst);
    }
    let t_dive = start.elapsed().as_secs_f64();
    let dive_found = incumbent.is_some();
    let dive_used = settings.dive_nodes - budget;

    // Phase 1: the minimum number of actions L*, bracketed from both sides. Bottom-up asks
    // whether the smallest budget not yet refuted fits (each refutation is a proven lower
    // bound); top-down asks for a plan one action shorter than the incumbent and reads it off
    // the memo. They alternate in time slices that double every round, so a run stopped early
    // has a better plan and a bound both, and each abandoned slice's finished sub-proofs carry
    // over in the memo.
    let cap = 4 * inst.n();
    let mut len_lo = first_bound.len;
    // Slices in calls of `fits` (about 10 µs each on the paper's instances).
    let mut slice: u64 = 2_000;
    let mut improved = 0usize;
    let trace = std::env::var_os("PUSHPACK_DEBUG").is_some();
    loop {
        let hi = incumbent.as_ref().map(|(c, _)| c.len);
        if trace {
            eprintln!(
                "phase 1 at {:.2}s: proven >= {len_lo}, plan {hi:?}, {} calls, slice {slice}",
                start.elapsed().as_secs_f64(),
                s.calls.get()
            );
        }
        if let Some(h) = hi.filter(|&h| len_lo >= h) {
            s.lstar.set(Some(h)); // the incumbent's length is proven minimal
            break;
        }
        if len_lo > cap {
            break; // left to the main search
        }
        match s.fits_within(&root.state, len_lo, slice) {
            Fit::Yes(v) => {
                debug_assert_eq!(v, len_lo, "a plan shorter than a proven bound");
                s.lstar.set(Some(len_lo));
                if hi.is_none_or(|h| len_lo < h) {
                    incumbent = s.plan_from_memo(&root, len_lo).or(incumbent);
                    improved += 1;
                }
                break;
            }
            Fit::No => {
                len_lo += 1;
                continue;
            }
            Fit::Stopped if stop.should_stop() => break,
            Fit::Stopped => {}
        }
        let (fit, better) = match &incumbent {
            // One above the proven bound, "one action shorter" is the bottom-up question
            // again: asking it a second way would only halve the slice the proof gets.
            Some((c, _)) if c.len == len_lo + 1 => (Fit::Stopped, None),
            Some((_, path)) => s.shorten(&root, path, slice),
            None => (s.fits_within(&root.state, cap, slice), None),
        };
        match fit {
            Fit::Yes(v) => {
                incumbent = better.or_else(|| s.plan_from_memo(&root, v)).or(incumbent);
                improved += 1;
                continue; // the next round asks one action less, in the same slice
            }
            Fit::No => len_lo = hi.map_or(cap + 1, |h| h.max(len_lo)),
            Fit::Stopped if stop.should_stop() => break,
            Fit::Stopped => {}
        }
        slice *= 2;
    }
    let t_phase1 = start.elapsed().as_secs_f64() - t_dive;
    let boxes = match s.lstar.get() {
        Some(l) if s.push_lines.is_some() && !stop.should_stop() => s.min_area_box(&root, l, &mut incumbent, trace),
        _ => 0,
    };
    let t_phase2 = start.elapsed().as_secs_f64() - t_dive - t_phase1;
    s.stopped.set(false);
    root.f = s.f_of(&root, true);
    root.exact = true;
    if s.stopped.replace(false) {
        // The time limit struck inside the exact bound: it is not one, the cheap one is.
        root.f = s.f_of(&root, false);
        root.exact = false;
    }
    let root_bound = root.f;

    let mut graph: DiGraph<Node, Scored> = DiGraph::new();
    let r = graph.add_node(root.clone());
    let mut open = BinaryHeap::new();
    let mut seq = 0u64;
    open.push(Open {
        f: root.f,
        seq,
        node: r,
    });
    let mut labels: FxMap<Vec<u8>, Vec<Label>> = FxMap::default();
    let mut nodes = 0u64;
    // Popped nodes whose exact bound showed no `L*`-action plan through them, and those with one.
    let (mut dead_pops, mut live_pops) = (0u64, 0u64);
    let calls_phase1 = s.calls.get();
    let mut status = SearchStatus::Complete;
    let mut goal: Option<NodeIndex> = None;
    if stop.should_stop() {
        status = SearchStatus::TimeLimit; // the phases used the time; the root stays open
    }
    while status == SearchStatus::Complete {
        let Some(Open { f, node, .. }) = open.pop() else {
            break;
        };
        if f.len >= DEAD_END {
            // The least bound open is a proven dead end, so is every node still open: no plan
            // passes through any of them (the same facts refute budgets in phase 1).
            open.push(Open { f, seq: 0, node });
            break;
        }
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
        if !n.exact {
            if let Some(l) = s.lstar.get() {
                // Lazy evaluation of the phase-1 bound: tighten on the first pop, and go back
                // into the queue if it rose (still a lower bound, so the order stays admissible).
                let f2 = s.f_of(&n, true);
                if s.stopped.get() {
                    // The time limit struck inside the phase-1 search: f2 is not a bound.
                    status = SearchStatus::TimeLimit;
                    open.push(Open { f, seq: 0, node });
                    break;
                }
                graph[node].f = f2;
                graph[node].exact = true;
                if f2.len > l {
                    dead_pops += 1;
                    continue; // cannot finish in the proven minimum number of actions
                }
                live_pops += 1;
                if f2.cmp_lex(&f) == Ordering::Greater {
                    seq += 1;
                    open.push(Open { f: f2, seq, node });
                    continue;
                }
            }
        }
        nodes += 1;
        if nodes >= opts.max_nodes {
            status = SearchStatus::NodeLimit;
            open.push(Open { f, seq: 0, node });
            break;
        }
        // Every node: with twenty objects one expansion can take a second of inverse
        // kinematics, so checking every 256 nodes overran a 10 s limit by 12 s.
        if stop.should_stop() {
            status = SearchStatus::TimeLimit;
            open.push(Open { f, seq: 0, node });
            break;
        }
        if Search::all_done(&n) {
            let gnode = s.goal_of(&n);
            // A complete plan: the new incumbent if it is better, so that a search stopped by
            // its limit returns it and pruning tightens at once.
            if incumbent
                .as_ref()
                .is_none_or(|(c, _)| gnode.g.cmp_lex(c) == Ordering::Less)
            {
                incumbent = Some((gnode.g, path_to(&graph, node)));
            }
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
        // Every action the layout allows; reachability is asked last, of the children that
        // survive the bounds and the dominance test. Grasp axes of one placement come in order
        // of preference and give equal labels, so the first reachable one is kept and the
        // others are dominated.
        for (a, m) in s.successors(&n.state).iter().cloned() {
            let c = s.timed(|p| (&mut p.child_s, &mut p.child_n), || s.child(&n, &a));
            if s.lstar.get().map(|l| c.f.len > l).unwrap_or(false) {
                continue; // cannot finish in the proven minimum number of actions
            }
            if let Some((inc, _)) = &incumbent {
                if c.f.cmp_lex(inc) != Ordering::Less {
                    continue;
                }
            }
            let k = obj_key(&c.state, inst.gripper.min_offset);
            let lab = Label::of(&c);
            let set = labels.entry(k).or_default();
            if set.iter().any(|l| l.dominates(&lab)) {
                continue;
            }
            if !s.reachable(&a, &n.state) {
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
    let plan: Option<Incumbent> = match goal {
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
    // Printed before the outcome is known, so that a run stopped without a plan shows it too.
    if let Some(p) = &s.prof {
        let p = p.borrow();
        eprintln!(
            "astar profile: total {:.3}s = dive {t_dive:.3}s ({dive_used} nodes, plan: {dive_found}) + phase-1 {t_phase1:.3}s \
             (L* {:?}, proven ≥ {len_lo}, {improved} better plans, {} calls, last slice {slice}) + phase-2 {t_phase2:.3}s \
             ({boxes} least boxes, area ≥ {:.2} cm²) + search {:.3}s; \
             successors {:.3}s/{} (check {:.3}s/{}, reach {:.3}s/{} with {} IK), h cheap {:.3}s/{}, exact {:.3}s/{}, child {:.3}s/{}, \
             memo {} states, succ cache {}",
            start.elapsed().as_secs_f64(),
            s.lstar.get(),
            s.calls.get(),
            s.area_floor.get() * 1e4,
            start.elapsed().as_secs_f64() - t_dive - t_phase1 - t_phase2,
            p.succ_s,
            p.succ_n,
            p.check_s,
            p.check_n,
            p.reach_s,
            p.reach_n,
            p.reach_miss,
            p.h_s,
            p.h_n,
            p.hx_s,
            p.hx_n,
            p.child_s,
            p.child_n,
            s.len_memo.borrow().len(),
            s.succ_cache.borrow().len(),
        );
    }
    let Some((cost, path)) = plan else {
        // Without an incumbent nothing was cut, so every plan passes through an open node (or
        // the root, before the main search ran); phase 1 refuted every shorter budget.
        let min_len = open.iter().map(|o| o.f.len).min().unwrap_or(root_bound.len).max(len_lo);
        if status != SearchStatus::Complete && min_len < DEAD_END {
            return Err(status.no_plan("sequence (astar)", nodes, start.elapsed().as_secs_f64(), Some(min_len)));
        }
        // Searched to the end, or every node left is a proven dead end (the facts that refute
        // budgets in phase 1 and that the exhaustive test checks).
        return Err(Error::Infeasible {
            reason: if first_bound.len >= DEAD_END {
                "no order of feasible actions packs every object: from the start, the objects on \
                 the table block each other's picks for good, or no set of pushable lines covers \
                 the objects that need a push"
                    .into()
            } else {
                "no order of feasible actions packs every object".into()
            },
        });
    };
    // With a goal, or a complete search (the incumbent was proven optimal: nothing open could
    // beat it), the bound is the cost itself.
    let bound = if goal.is_some() || status == SearchStatus::Complete {
        cost
    } else {
        // A bound per component on the lexicographic optimum: it is the incumbent, or better
        // than it and then below some open node (nodes cut by the incumbent or by L* cannot
        // lead to it). The lexicographically smallest open f would not do: its area can exceed
        // the optimum's when its action count is lower.
        let fs: Vec<Cost> = if open.is_empty() {
            vec![root_bound]
        } else {
            open.iter().map(|o| o.f).collect()
        };
        let mut b = fs.iter().fold(cost, |b, f| Cost {
            len: b.len.min(f.len),
            area: b.area.min(f.area),
            travel: b.travel.min(f.travel),
        });
        // Proven by phase 1: L* when it finished, else every budget below `len_lo` refuted.
        b.len = b.len.max(s.lstar.get().unwrap_or(len_lo));
        b
    };
    if std::env::var_os("PUSHPACK_DEBUG").is_some() {
        eprintln!(
            "astar: root bound {root_bound:?}, result {cost:?}, incumbent from dive {:?}, {nodes} nodes; \
             main search: {live_pops} popped nodes on an L*-plan, {dead_pops} not, {} depth-first calls",
            incumbent.as_ref().map(|i| i.0),
            s.calls.get() - calls_phase1
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

#[cfg(test)]
mod tests {
    use super::max_independent;
    use proptest::prelude::*;

    /// Largest independent set by trying every subset.
    fn brute(adj: &[u64]) -> usize {
        (0u64..1 << adj.len())
            .filter(|&s| (0..adj.len()).all(|v| s >> v & 1 == 0 || adj[v] & s == 0))
            .map(|s| s.count_ones() as usize)
            .max()
            .unwrap_or(0)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        /// The push bound's independent set is exact, not greedy: it must match enumeration.
        #[test]
        fn max_independent_matches_enumeration(n in 0usize..13, edges in proptest::collection::vec(any::<bool>(), 78)) {
            let mut adj = vec![0u64; n];
            let mut e = edges.iter();
            for a in 0..n {
                for b in a + 1..n {
                    if *e.next().unwrap() {
                        adj[a] |= 1 << b;
                        adj[b] |= 1 << a;
                    }
                }
            }
            prop_assert_eq!(max_independent(&adj), brute(&adj));
        }
    }
}

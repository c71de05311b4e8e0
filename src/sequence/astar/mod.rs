//! Best-first (A*) search over partial plans, choosing the packing actions and their order
//! together, with admissible bounds on every cost component.
//!
//! A state is where every object is (table / released with a push direction and offset / at its
//! target) and where each arm's TCP is. Edges are the feasible actions (docs/algorithms.md) in that state:
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
use crate::control::{Event, Listener, Silent, Stage, Terminator, Ticker};
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

mod bounds;
mod cover;
mod expand;
mod hits;
mod lines;
mod search;
mod state;

use cover::*;
use hits::*;
pub use lines::*;
pub use search::*;

/// A* settings ([`crate::plan::PlanOptions::astar`]; a missing field takes its default).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AstarSettings {
    /// Largest indirect offset as a multiple of the minimum offset `d` (default 3, at most
    /// [`MAX_OFFSET_STEPS`]). An object that is the k-th of a line may also use offsets up to
    /// `k·d`, the paper's staggering.
    pub max_offset_steps: usize,
    /// Node budget of the greedy dive that provides the first incumbent (default 20,000).
    pub dive_nodes: u64,
    /// Developer diagnostics: print the search's phases and bounds to stderr (default off).
    pub trace: bool,
    /// Developer diagnostics: time the bound computations and print a profile to stderr at
    /// the end (default off; it costs a clock read per call).
    pub profile: bool,
}

impl Default for AstarSettings {
    fn default() -> Self {
        AstarSettings {
            max_offset_steps: 3,
            dive_nodes: 20_000,
            trace: false,
            profile: false,
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
    /// `opts.vetoes` as every state's layout holds them.
    vetoes: Option<std::sync::Arc<[crate::actions::veto::Veto]>>,
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

/// Time spent per part of the search, collected only with [`AstarSettings::profile`] (the clock
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

pub use crate::instance::MAX_OFFSET_STEPS;

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

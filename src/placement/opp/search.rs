//! The exact search for one box: the x-phase over left edges under the bar relaxation, then the
//! y-phase for each complete x-assignment (module doc of [`super`] says why it is exact).

use super::dominance::{dominated, Sig};
use super::*;
use smallvec::SmallVec;
use std::cell::Cell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

mod bounds;
mod probe;
mod sides;
mod stacks;
mod ygrid;
mod ymemo;
#[cfg(test)]
pub(super) use probe::left_out as probe_left_out;
mod yphase;

/// The memo's hasher: the multiply-and-rotate of rustc's FxHash. The keys are the search's own
/// integers (no adversary), and the default SipHash took 8 % of the contact enumeration's time
/// (perf, squares 1…15).
#[derive(Default, Clone, Copy)]
struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(b));
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// Most entries of [`Search::arena`] before the memo of profiles starts afresh: room for
/// [`DEAD_MAX`] profiles of 16 open objects (its offsets are `u32`).
const ARENA_MAX: usize = DEAD_MAX * 16;

/// The bit set of the first `n ≤ 64` indices.
fn low_bits(n: usize) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1 << n) - 1
    }
}

/// The open objects of an x-phase state, sorted `(end, depth)` in tolerance units, as where
/// they start in [`Search::arena`] and how many there are. The two entries before them hold
/// their [`Sig`] ([`sig_in_arena`]): kept there, not here, the lists in the hash table's slots
/// stay small (24-byte profiles in the slots cost the area stage more than the signature saved).
type Profile = (u32, u32);

/// Dead profiles listed for a state, at least, before [`Sig`] is asked first.
const SIG_FROM: usize = 4;

/// Profiles by (placed set, position), as [`Search`] keeps them: dead ones, or those its
/// probes got through.
type Profiles = HashMap<(u64, i32), SmallVec<[Profile; 2]>, BuildHasherDefault<FxHasher>>;

/// The profiles a search recorded dead at any bound, and those its probes got through, handed
/// to a later search of the same box ([`Search::take_dead_profiles`]).
#[derive(Default)]
pub(super) struct DeadProfiles {
    lists: [Profiles; 4],
    len: usize,
    arena: Vec<(i32, i32)>,
}

/// The entries of profile `p` in `arena`.
fn in_arena(arena: &[(i32, i32)], (start, len): Profile) -> &[(i32, i32)] {
    &arena[start as usize..(start + len) as usize]
}

/// Whether every end of the profile `b` is an end of `a` (both sorted `(end, depth)`): then the
/// x-phase below `a` moves through every position it moves through below `b`, which a record
/// dead only given the rows check needs before it cuts a state that loads the columns more
/// (docs/algorithms.md, *Rows ahead*).
fn ends_within(b: &[(i32, i32)], a: &[(i32, i32)]) -> bool {
    let mut ea = a.iter().map(|e| e.0).peekable();
    b.iter().all(|&(e, _)| {
        while ea.next_if(|&x| x < e).is_some() {}
        ea.peek() == Some(&e)
    })
}

/// The [`Sig`] of profile `p`, stored in `arena` just before it.
fn sig_in_arena(arena: &[(i32, i32)], (start, _): Profile) -> Sig {
    Sig::from_words(&arena[start as usize - 2..start as usize])
}

/// One branch of an x-phase node: an object started at the current position, `Some((item,
/// footprint))`, or the move to the next right edge, `None`. A path of them from the root is a
/// task of one box's search split between threads ([`Search::tasks`]).
pub(super) type Step = Option<(usize, usize)>;

/// The state of [`Search::tasks`]: the depth at which a node becomes a task (counted in nodes
/// with more than one branch, so that a chain of forced steps does not use it up), the most
/// tasks wanted, the current node's depth, the tasks so far, and per task an upper bound on
/// the contact of the packings below it (of its node's parent, for all but the leaves).
struct Split {
    at: u32,
    most: usize,
    depth: u32,
    tasks: Vec<Vec<Step>>,
    bounds: Vec<f64>,
}

/// What enumeration hands each packing to; `true` stops it.
pub type Visitor<'a> = dyn FnMut(&[Pos]) -> bool + 'a;

/// The exact search for one box.
pub struct Search<'a> {
    items: &'a [Item],
    w: f64,
    d: f64,
    t: f64,
    stop: &'a dyn Fn() -> bool,
    /// Search nodes visited (both phases).
    pub nodes: u64,
    /// A shared node count to keep up to date at every stop poll (for progress events), and
    /// its value when this search started.
    meter: Option<(&'a Cell<u64>, u64)>,
    stopped: bool,
    /// Previous item of the same class (identical objects are placed in index order).
    prev_same: Vec<Option<usize>>,
    /// Least area of each item among its fitting footprints.
    min_area: Vec<f64>,
    /// Least depth of each item among its fitting footprints.
    min_depth: Vec<f64>,
    /// Largest width + depth of each item among its fitting footprints (the contact bound of
    /// an unplaced item), computed once: the bound is evaluated at every x-node.
    max_sides: Vec<f64>,
    /// The items by least depth, deepest first (ties in index order).
    by_depth: Vec<usize>,
    /// Least width of each item among its fitting footprints, and the items by it, widest
    /// first (ties in index order).
    min_width: Vec<f64>,
    by_width: Vec<usize>,
    /// Scratch buffers of [`Self::capacity_refutes`].
    buf_pieces: Vec<(f64, f64)>,
    buf_fill: Vec<(usize, usize)>,
    /// The depths' common grid, for the subset sums of [`Self::capacity_refutes`] (`None`: no
    /// grid coarse enough; free depth then counts in full), and its bitset buffers.
    grid: Option<subset::Grid>,
    /// The widths' common grid, for [`Self::rows_refute`] (`None`: none, or more than 63 steps
    /// across the box, beyond one word).
    wgrid: Option<subset::Grid>,
    /// Whether the x-phase checks the rows ahead ([`Self::rows_refute`]; off only in tests),
    /// the nodes it cut, and the cuts that made a subtree's failure depend on it: row cuts and
    /// hits of records that counted one (`dominant[3]`).
    pub(super) rows_on: bool,
    pub(super) row_cuts: u64,
    rpruned: u64,
    /// States cut by a record of `dominant[3]` (counted for the tests).
    pub(super) row_dominance_cuts: u64,
    buf_bits: Vec<u64>,
    buf_tmp: Vec<u64>,
    /// First item of the largest class, kept in the lower-left quarter (mirror symmetry).
    anchor: Option<usize>,
    /// Per item: chosen footprint and left edge in the x-phase.
    opt: Vec<usize>,
    x0: Vec<f64>,
    placed: Vec<bool>,
    /// `placed` as bit sets (instances of at most 64 items; both 0 otherwise): by item, and the
    /// items not placed by rank in `by_depth` (bit `r`: `by_depth[r]` is not placed), so that
    /// the checks at every node visit only what they need. Kept by [`Self::set_placed`].
    placed_mask: u64,
    left_by_depth: u64,
    /// Rank of each item in `by_depth`.
    depth_rank: Vec<u32>,
    /// The x-phase's placed items as (right edge, depth), sorted by right edge: those still
    /// open at `t` are the suffix ending after it ([`Self::open_from`]). Kept in step with
    /// `placed` in the x-phase, so that the checks at every node need not scan and sort.
    xends: Vec<(f64, f64)>,
    y0: Vec<f64>,
    /// x-phase states (placed set, position, open objects, right sides ending at `t`) whose
    /// subtree the contact bound cut, with the waste and the contact bound at which it did.
    dead: HashMap<StateKey, (f64, f64), BuildHasherDefault<FxHasher>>,
    /// Key buffers of the x-phase nodes on the current path, kept for reuse.
    key_pool: Vec<Vec<(i32, i32)>>,
    /// The open-object profiles, per (placed set, position), of the states that failed without
    /// a contact cut: a state is dead when a recorded one with the same placed set and position
    /// had no more load anywhere ahead ([`dominated`]). Profiles kept, counted against [`DEAD_MAX`].
    /// Two lists: the search's, and the probes' (`search/probe.rs`), keyed by the placed set
    /// without the left-out items ([`Self::probe_set`]). Probes consult only theirs, the search
    /// both: what a probe finds dead is dead for the search too. A third, keyed as the probes',
    /// holds the states on the paths by which probes reached a complete x-assignment, where a
    /// probe would find the same again ([`Self::known_alive`]). A fourth, keyed as the search's,
    /// holds its dead states whose subtrees the rows check cut ([`Self::rows_refute`]): not
    /// dead under the bar relaxation, they cut only states whose open objects end where theirs
    /// do ([`ends_within`]; docs/algorithms.md, *Rows ahead*).
    dominant: [Profiles; 4],
    dominant_len: usize,
    /// The profiles of `dominant`, one after the other: a box per profile made allocation and
    /// freeing about a tenth of the contact enumeration's time (`perf`, squares 1…21). Those
    /// dropped as dominated stay until the memo starts afresh.
    arena: Vec<(i32, i32)>,
    /// Most records kept in each memo before it starts afresh ([`DEAD_MAX`]; lower only in
    /// tests, to show that a memo starting afresh changes no answer).
    pub(super) memo_cap: usize,
    /// Whether [`dominated`] states are cut (off only to test that it changes no answer), and
    /// how many were.
    pub(super) dominance: bool,
    /// Whether the capacity check sums in one word where the sums fit one (off only to test
    /// that path against the general loop).
    pub(super) word_sums: bool,
    pub(super) dominance_cuts: u64,
    /// Complete x-assignments handed to the y-phase so far.
    pub(super) yleaves: u64,
    /// The path from the root to the node the current task starts at, and how much of it the
    /// x-phase has followed: at the nodes on it only the path's branch is taken
    /// ([`Self::run_task`]). While splitting, the path to the current node.
    path: Vec<Step>,
    followed: usize,
    /// Set while [`Self::tasks`] splits the search.
    split: Option<Split>,
    /// Probes (enumeration, [`probe`]): the items a probe leaves out (bits by item, and by rank
    /// in `by_depth`), whether one runs, the node count at which it gives up and whether it
    /// did, and how many states probes refuted.
    probe_items: u64,
    probe_rank_bits: u64,
    probing: bool,
    probe_until: u64,
    probe_gave_up: bool,
    pub(super) probe_cuts: u64,
    /// Whether probes are skipped at states known alive (off only in tests, to show that it
    /// skips no probe that would refute), and how many were.
    pub(super) witnesses: bool,
    pub(super) probes_skipped: u64,
    /// Enumeration mode: every packing goes to the visitor (which returns `true` to stop);
    /// no mirror symmetry breaking, since what the visitor measures need not be symmetric.
    visit: Option<&'a mut Visitor<'a>>,
    dead_enabled: bool,
    /// Contact pruning (enumeration for the contact stage): branches whose contact-length upper
    /// bound does not beat this value are cut.
    cbound: Option<&'a Cell<f64>>,
    /// The box reaches the container's far walls (x = its width, y = its depth), which then
    /// count as contact.
    far: [bool; 2],
    /// [`Self::sides_now`], kept by the x-phase as it places and removes items (restored, not
    /// subtracted, so that no rounding accumulates).
    xsides: f64,
    /// Left sides of placed items that cannot be in full contact, summed (x-phase).
    ldef: f64,
    /// Whether the y-phase bounds the far walls' contact by what the x-assignment leaves them
    /// (`search/yphase.rs`; off only in tests) rather than counting it in full, and at how many
    /// y-phase roots it took contact off and the root was cut.
    pub(super) walls_on: bool,
    pub(super) walls_cuts: u64,
    /// The free depth of the columns just left of `t` (0 at `t = 0`), and `ldef` when the
    /// x-phase moved to `t`: see [`Self::rows_lost_ahead`].
    hprev: f64,
    ldef_at: f64,
    /// Depths of the items the x-phase placed at its current position, summed (their left
    /// sides share the right sides ending there).
    starts_at_t: f64,
    /// Bottom sides of items placed in the y-phase not in contact, summed.
    ydef: f64,
    /// The least width of the columns under whose bottoms every packing of the current
    /// x-assignment keeps gaps (`search/stacks.rs`, found at the y-phase's root): a bottom loss
    /// no path below avoids.
    ygaps: f64,
    /// Contact bound of the current complete x-assignment.
    ub_x: f64,
    /// Branches cut by the contact bound.
    cpruned: u64,
    /// Per item, for the current x-assignment (built by `ycheck`): the items covering its left
    /// edge (itself included), the other items overlapping it in x, and the items ending at its
    /// left edge.
    ycover: Vec<Vec<usize>>,
    yover: Vec<Vec<usize>>,
    yleft: Vec<Vec<usize>>,
    /// The items off the left wall, grouped by left edge (current x-assignment), and per group
    /// the right sides ending at that edge and the left contact the x-phase counted for it.
    ygroups: Vec<Vec<usize>>,
    ygroup_ends: Vec<(f64, f64)>,
    /// Per item, for the current x-assignment: its footprint, and the identical items before it
    /// with the same footprint and left edge (placed before it when they share a bottom).
    ydims: Vec<[f64; 2]>,
    ytwins: Vec<Vec<usize>>,
    /// The y-phase's floors, a row of one per item for each depth of its recursion.
    yfloor: Vec<f64>,
    /// The current x-assignment's columns, between consecutive item edges (enumeration under a
    /// contact bound only): width and the items covering it.
    ycols: Vec<(f64, Vec<usize>)>,
    /// The y-phase's grid ([`ygrid`]) for the current x-assignment.
    ygrid: ygrid::YGrid,
    /// The gapless-stacks bound at the y-phase's root ([`stacks`]): whether it is on (off only
    /// in tests), its scratch, and how many x-assignments it cut.
    pub(super) stacks_on: bool,
    stacks: stacks::Stacks,
    pub(super) stack_cuts: u64,
    /// The gapless-stacks bound below the root: whether it is on (off only in tests), and how
    /// many y-nodes it cut.
    pub(super) ystacks_on: bool,
    pub(super) ystack_cuts: u64,
    /// The unplaced items' footprints as steps of area and sides ([`sides`]), whether the
    /// x-phase's contact cut uses them (off only in tests), and how many nodes it cut so.
    sides: sides::Sides,
    pub(super) sides_on: bool,
    pub(super) sides_cuts: u64,
    /// Per item, the items starting at its right edge (current x-assignment).
    yright: Vec<Vec<usize>>,
    /// The y-phase's memo ([`ymemo`]): whether it is on (off only in tests), the states of the
    /// current x-assignment, key buffers for reuse, the contact the placed items have made and
    /// whether it is kept on the current path, its lookups and how many of them cut.
    pub(super) ymemo_on: bool,
    ymemo: ymemo::YMemo,
    ykey_pool: Vec<Vec<u64>>,
    ypast: f64,
    ypast_ok: bool,
    ylookups: u64,
    pub(super) ymemo_cuts: u64,
    /// Packings the y-phase has reached (complete y-assignments).
    yvisited: u64,
    /// Buffers of [`Self::ycheck`] kept between x-assignments: the placed flags and tops, the
    /// item edges, and emptied lists for the groups and columns.
    ydone: Vec<bool>,
    ytop: Vec<f64>,
    yedges: Vec<f64>,
    ypool: Vec<Vec<usize>>,
}

impl<'a> Search<'a> {
    /// Enumerate packings in `w × d` (every one whose objects all touch something on their left
    /// and below among them; once each up to swapping identical objects) into `visit`. With
    /// `bound`, only packings whose contact length (objects, the walls x = 0 and y = 0, and the
    /// far walls where `far` says the box reaches them) may exceed it are guaranteed to be
    /// visited; the visitor may raise it. `meter`: a node count kept up to date
    /// ([`Search::metered`]). Returns whether the enumeration finished (`false`: stopped by
    /// `stop`) and the nodes visited.
    #[allow(clippy::too_many_arguments)] // each is one independent input of the enumeration
    pub fn enumerate(
        items: &'a [Item],
        w: f64,
        d: f64,
        stop: &'a dyn Fn() -> bool,
        visit: &'a mut Visitor<'a>,
        bound: Option<&'a Cell<f64>>,
        far: [bool; 2],
        meter: Option<&'a Cell<u64>>,
    ) -> (bool, u64) {
        let mut s = Search::enumerator(items, w, d, stop, visit, bound, far).metered(meter);
        let complete = matches!(s.run(), Outcome::Infeasible);
        (complete, s.nodes)
    }

    /// The search [`Self::enumerate`] runs, not yet run.
    pub(super) fn enumerator(
        items: &'a [Item],
        w: f64,
        d: f64,
        stop: &'a dyn Fn() -> bool,
        visit: &'a mut Visitor<'a>,
        bound: Option<&'a Cell<f64>>,
        far: [bool; 2],
    ) -> Self {
        let mut s = Search::new(items, w, d, stop);
        s.anchor = None;
        s.visit = Some(visit);
        s.cbound = bound;
        s.far = far;
        s.set_probe(probe::left_out(items, w, d));
        s
    }

    /// Enumeration of every packing into `visit` without a contact bound (tests only).
    #[cfg(test)]
    pub(super) fn enumerating(mut self, visit: &'a mut Visitor<'a>) -> Self {
        self.anchor = None;
        self.visit = Some(visit);
        self
    }

    /// A search for `items` in `w × d`; `stop` is polled now and then.
    pub fn new(items: &'a [Item], w: f64, d: f64, stop: &'a dyn Fn() -> bool) -> Self {
        let n = items.len();
        let t = tol(w, d);
        let prev_same: Vec<Option<usize>> = (0..n)
            .map(|i| (0..i).rev().find(|&j| items[j].class == items[i].class))
            .collect();
        let min_area: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[0] * g[1]).fold(f64::INFINITY, f64::min))
            .collect();
        let min_depth: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[1]).fold(f64::INFINITY, f64::min))
            .collect();
        let mut by_depth: Vec<usize> = (0..n).collect();
        by_depth.sort_by(|&a, &b| min_depth[b].total_cmp(&min_depth[a]));
        let mut depth_rank = vec![0u32; n];
        for (r, &i) in by_depth.iter().enumerate() {
            depth_rank[i] = r as u32;
        }
        let min_width: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[0]).fold(f64::INFINITY, f64::min))
            .collect();
        let mut by_width: Vec<usize> = (0..n).collect();
        by_width.sort_by(|&a, &b| min_width[b].total_cmp(&min_width[a]));
        let max_sides: Vec<f64> = items
            .iter()
            .map(|it| fitting(it, w, d).map(|g| g[0] + g[1]).fold(0.0, f64::max))
            .collect();
        // The anchor is the first item of the class with the largest single area: mirroring
        // keeps footprints, so the bound below uses its narrowest fitting footprint.
        let anchor = (0..n)
            .filter(|&i| prev_same[i].is_none() && min_area[i].is_finite())
            .max_by(|&a, &b| min_area[a].total_cmp(&min_area[b]));
        let xsides = max_sides.iter().sum();
        Search {
            items,
            w,
            d,
            t,
            stop,
            nodes: 0,
            meter: None,
            stopped: false,
            prev_same,
            min_area,
            min_depth,
            max_sides,
            by_depth,
            min_width,
            by_width,
            buf_pieces: Vec::new(),
            buf_fill: Vec::new(),
            grid: subset::Grid::new(items, w, d),
            wgrid: subset::Grid::new(&super::turned(items), d, w).filter(|g| g.one_word()),
            rows_on: true,
            row_cuts: 0,
            rpruned: 0,
            row_dominance_cuts: 0,
            buf_bits: Vec::new(),
            buf_tmp: Vec::new(),
            anchor,
            opt: vec![0; n],
            x0: vec![0.0; n],
            placed: vec![false; n],
            placed_mask: 0,
            left_by_depth: if n <= 64 { low_bits(n) } else { 0 },
            depth_rank,
            xends: Vec::with_capacity(n),
            y0: vec![0.0; n],
            visit: None,
            probe_items: 0,
            probe_rank_bits: 0,
            probing: false,
            probe_until: 0,
            probe_gave_up: false,
            probe_cuts: 0,
            witnesses: true,
            probes_skipped: 0,
            dead: HashMap::default(),
            key_pool: Vec::new(),
            dominant: Default::default(),
            dominant_len: 0,
            arena: Vec::new(),
            memo_cap: DEAD_MAX,
            dominance: true,
            word_sums: true,
            dominance_cuts: 0,
            yleaves: 0,
            path: Vec::new(),
            followed: 0,
            split: None,
            // The state key is a 64-bit set; so large an instance is out of reach anyway.
            dead_enabled: n <= 64,
            cbound: None,
            far: [false; 2],
            xsides,
            ldef: 0.0,
            walls_on: true,
            walls_cuts: 0,
            hprev: 0.0,
            ldef_at: 0.0,
            starts_at_t: 0.0,
            ydef: 0.0,
            ub_x: 0.0,
            cpruned: 0,
            ycover: vec![Vec::new(); n],
            yover: vec![Vec::new(); n],
            yleft: vec![Vec::new(); n],
            ygroups: Vec::new(),
            ygroup_ends: Vec::new(),
            ydims: Vec::new(),
            ytwins: vec![Vec::new(); n],
            yfloor: Vec::new(),
            ycols: Vec::new(),
            ygrid: ygrid::YGrid::default(),
            stacks_on: true,
            stacks: stacks::Stacks::default(),
            stack_cuts: 0,
            ystacks_on: true,
            ystack_cuts: 0,
            ygaps: 0.0,
            sides: sides::Sides::new(items, w, d, t),
            sides_on: true,
            sides_cuts: 0,
            yright: vec![Vec::new(); n],
            ymemo_on: true,
            ymemo: HashMap::default(),
            ykey_pool: Vec::new(),
            ydone: Vec::new(),
            ytop: Vec::new(),
            yedges: Vec::new(),
            ypool: Vec::new(),
            ypast: 0.0,
            ypast_ok: false,
            ylookups: 0,
            ymemo_cuts: 0,
            yvisited: 0,
        }
    }

    /// Decide the box.
    pub fn run(&mut self) -> Outcome {
        if refuted_by_bounds(self.items, self.w, self.d) {
            return Outcome::Infeasible;
        }
        let rem: f64 = self.min_area.iter().sum();
        if self.xphase(0.0, 0, 0.0, rem, 0.0) {
            return Outcome::Packed(self.positions());
        }
        if self.stopped {
            Outcome::Stopped
        } else {
            Outcome::Infeasible
        }
    }

    /// The tasks [`Self::run`]'s search splits into, in the order it visits them: the paths
    /// to the nodes `at` branching nodes below the root (or to complete x-assignments above
    /// them), found under every cut but the memo's. Counting only nodes with more than one
    /// branch matters: with the root's branches alone (which object starts at x = 0), one of
    /// 22 held 46 % of the nodes of squares 1…22's packed box, and one of 247 with two levels
    /// (the 20 × 20 with the 19 × 19 on it, a full column with a single way on). Past `most`
    /// tasks the nodes still above that depth split no further (wide instances: many objects
    /// in many footprints would otherwise make millions).
    pub(super) fn tasks(&mut self, at: u32, most: usize) -> Vec<Vec<Step>> {
        self.tasks_bounded(at, most).0
    }

    /// [`Self::tasks`], and per task an upper bound on the contact of the packings below it
    /// (enumeration: what a search stopped before finishing the task can still promise).
    pub(super) fn tasks_bounded(&mut self, at: u32, most: usize) -> (Vec<Vec<Step>>, Vec<f64>) {
        if refuted_by_bounds(self.items, self.w, self.d) {
            return (Vec::new(), Vec::new());
        }
        // A subtree cut short by the split is not dead: no memo while splitting.
        let memo = std::mem::replace(&mut self.dead_enabled, false);
        self.split = Some(Split {
            at,
            most,
            depth: 0,
            tasks: Vec::new(),
            bounds: Vec::new(),
        });
        let rem: f64 = self.min_area.iter().sum();
        self.xphase(0.0, 0, 0.0, rem, 0.0);
        self.dead_enabled = memo;
        self.split.take().map_or_else(Default::default, |s| (s.tasks, s.bounds))
    }

    /// One task of [`Self::tasks`]: the search below the node at the end of `path`. The memo
    /// carries over between tasks: a dead state is dead whichever task reaches it.
    pub(super) fn run_task(&mut self, path: &[Step]) -> Outcome {
        self.stopped = false;
        self.path.clear();
        self.path.extend_from_slice(path);
        self.followed = 0;
        let rem: f64 = self.min_area.iter().sum();
        let found = self.xphase(0.0, 0, 0.0, rem, 0.0);
        self.path.clear();
        if found {
            Outcome::Packed(self.positions())
        } else if self.stopped {
            Outcome::Stopped
        } else {
            Outcome::Infeasible
        }
    }

    /// Forget the states recorded dead at a contact bound (`dead`), before a task whose bound
    /// is lower; those dead at any bound stay.
    pub(super) fn forget_bounded_memo(&mut self) {
        self.dead.clear();
    }

    /// The profiles this search recorded dead at any bound (its own and its probes') and those
    /// its probes got through, taken out of it, for a later search of the same items in the
    /// same box ([`Self::with_dead_profiles`]).
    pub(super) fn take_dead_profiles(&mut self) -> DeadProfiles {
        DeadProfiles {
            lists: std::mem::take(&mut self.dominant),
            len: std::mem::take(&mut self.dominant_len),
            arena: std::mem::take(&mut self.arena),
        }
    }

    /// Start from the profiles an earlier search of the same items, box and kind (decision or
    /// enumeration) recorded dead at any bound. Whether a state is dead that way depends on the
    /// state alone (no complete x-assignment extends it), not on the search that found it, its
    /// tasks or its contact bound, so they cut only subtrees without a packing here too; and
    /// whether a probe gets through a state depends on the probes' key alone.
    pub(super) fn with_dead_profiles(mut self, dead: DeadProfiles) -> Self {
        self.dominant = dead.lists;
        self.dominant_len = dead.len;
        self.arena = dead.arena;
        self
    }

    /// Where every item is now.
    fn positions(&self) -> Vec<Pos> {
        (0..self.items.len())
            .map(|i| Pos {
                opt: self.opt[i],
                x: self.x0[i],
                y: self.y0[i],
            })
            .collect()
    }

    /// The y-phase alone, for a given x-assignment (per item: footprint index and left edge): a
    /// packing with exactly these x-coordinates and footprints, or `Infeasible` (none exists),
    /// or `Stopped`. This is the subproblem of the Benders decomposition
    /// ([`crate::placement::milp`]'s HiGHS master decides the x-coordinates).
    pub fn y_for(&mut self, opt: &[usize], x0: &[f64]) -> Outcome {
        // The mirror rule of `run` pairs with the x-phase's; the master has no such rule.
        self.anchor = None;
        self.opt.copy_from_slice(opt);
        self.x0.copy_from_slice(x0);
        for i in 0..self.items.len() {
            self.set_placed(i, true);
        }
        // No x-phase kept the sides here.
        self.xsides = self.sides_now();
        if self.ycheck() {
            Outcome::Packed(self.positions())
        } else if self.stopped {
            Outcome::Stopped
        } else {
            Outcome::Infeasible
        }
    }

    fn tick(&mut self) -> bool {
        self.nodes += 1;
        if self.probing && self.nodes >= self.probe_until {
            self.probe_gave_up = true;
            self.stopped = true;
        }
        if self.nodes & 1023 == 0 {
            if let Some((m, base)) = self.meter {
                m.set(base + self.nodes);
            }
            if (self.stop)() {
                self.stopped = true;
            }
        }
        self.stopped
    }

    /// Keep `meter` at its current value plus this search's nodes, at every stop poll (the
    /// caller adds the final count when the search returns).
    pub fn metered(mut self, meter: Option<&'a Cell<u64>>) -> Self {
        self.meter = meter.map(|m| (m, m.get()));
        self
    }

    fn dims(&self, i: usize) -> [f64; 2] {
        self.items[i].opts[self.opt[i]]
    }

    /// Largest left edge the anchor may take with its narrowest fitting footprint.
    fn anchor_limit(&self, axis: usize) -> f64 {
        let cap = if axis == 0 { self.w } else { self.d };
        let a = self.anchor.expect("anchor exists when items do");
        let least = fitting(&self.items[a], self.w, self.d)
            .map(|g| g[axis])
            .fold(f64::INFINITY, f64::min);
        (cap - least) / 2.0 + self.t
    }

    /// x-phase at position `t` (every placed item starts at or before it): place an item at
    /// `t` (index at least `min_idx`, so that items sharing a left edge come in index order),
    /// or move `t` to the next right edge, leaving the column's free height unused for good.
    fn xphase(&mut self, t: f64, min_idx: usize, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        if self.tick() {
            return false;
        }
        debug_assert!(self.ends_in_step());
        debug_assert!(self.masks_in_step());
        debug_assert!(self.sides_in_step());
        let n = self.items.len();
        // The contact bound of this node: for the cut here and for the memo below.
        let ub = if self.cbound.is_some() { self.contact_ub() } else { 0.0 };
        // The contact cut comes after the cuts that hold at any bound: a subtree cut by a bound
        // is remembered only at that bound (below), so a node that capacity or a dead profile
        // also cuts is better cut by them.
        let contact_cut = |s: &mut Self| {
            let Some(cb) = s.cbound.filter(|_| !s.probing) else {
                return false;
            };
            let used = placed_area + rem_area + waste;
            let mut bound = ub - s.rows_lost_ahead(t, used);
            let mut cut = bound <= cb.get() + 1e-9;
            // The footprints' sides within the free area last: it costs a pass over the steps.
            if !cut && s.sides_on && s.sides.any() {
                bound -= s.sides_unreachable(s.w * s.d - used);
                cut = bound <= cb.get() + 1e-9;
                s.sides_cuts += cut as u64;
            }
            s.cpruned += cut as u64;
            cut
        };
        // The rows ahead (`rows_refute`): a cut the bar relaxation does not make, so a subtree it
        // cut is dead only given it (`dominant[3]`); last, after every cut that holds under the
        // relaxation. Only under a contact bound: in the area stage the records it costs the
        // bar's dominance cost more than it cuts (n20_k4_s0014's area stage 0.21 → 2.09 s).
        let used = placed_area + rem_area + waste;
        let rows_cut = |s: &mut Self| {
            let cut = s.rows_on && s.cbound.is_some() && !s.probing && s.rows_refute(t, used);
            s.rpruned += cut as u64;
            s.row_cuts += cut as u64;
            cut
        };
        if self.probing && self.xends.len() + (self.probe_items & !self.placed_mask).count_ones() as usize == n {
            return true;
        }
        if self.xends.len() == n {
            if let Some(ub) = self.split.is_some().then(|| self.contact_ub()) {
                let path = self.path.clone();
                if let Some(split) = &mut self.split {
                    split.tasks.push(path);
                    split.bounds.push(ub);
                }
                return false;
            }
            return !contact_cut(self) && self.ycheck();
        }
        let tol = self.t * (self.w + self.d);
        if placed_area + rem_area + waste > self.w * self.d + tol {
            return false;
        }
        // States reached again by another order of the objects behind `t`: the x-phase ahead
        // depends only on which objects are placed, where the placed ones end, and how deep they
        // are — and on the waste so far, which only makes pruning easier. A state whose subtree
        // failed without reaching the y-phase fails again at no less waste. When enumerating
        // under a contact bound, the contact cuts ahead depend on the state, on the right sides
        // ending at `t` (put in the key; with the open objects they fix the free depth left of
        // `t` that `rows_lost_ahead` counts) and on the contact bound of the placed part (`ub`,
        // recorded without that term); the bound to beat only rises, so a subtree cut at some
        // contact bound is cut again at no more.
        //
        //
        // A state that failed without a contact cut below it (always so without a contact
        // bound) has no complete x-assignment at all: every other cut is a necessary condition,
        // the waste one included. Such states are kept as profiles, and a state is also dead
        // when one of them with the same placed set and position had no more load at any column
        // ahead: each completion of it would complete that one (halved the nodes of the hardest
        // boxes of squares 1…18, docs/algorithms.md). Only the others, dead at some contact
        // bound, go to the exact-key memo.
        // The key in a buffer kept between nodes: an allocation per node cost about 2 % of the
        // contact enumeration's time (squares 1…18).
        let key = (min_idx == 0 && self.dead_enabled).then(|| {
            let mut k = self.key_pool.pop().unwrap_or_default();
            self.state_key(t, &mut k);
            k
        });
        let cut = if let Some(k) = &key {
            let profile = self.profile_of(k);
            // A probe consults only its own list; the search both (what a probe refutes is dead
            // for the search too, whichever way the left-out items were placed).
            let probes = (self.probe_items != 0)
                .then(|| self.dominant[1].get(&(self.probe_set(), k[1].0)))
                .flatten();
            let own = (!self.probing)
                .then(|| self.dominant[0].get(&(self.placed_mask, k[1].0)))
                .flatten();
            // Empty in the area stage, which does not check rows: no lookup there.
            let rowed = (!self.probing && !self.dominant[3].is_empty())
                .then(|| self.dominant[3].get(&(self.placed_mask, k[1].0)))
                .flatten();
            // The signature pays only before lists of a few profiles (computing it costs about
            // two scans); shorter ones are scanned as they are.
            let listed = probes.map_or(0, |l| l.len()) + own.map_or(0, |l| l.len()) + rowed.map_or(0, |l| l.len());
            let sig = (self.signed() && listed >= SIG_FROM).then(|| self.sig_of(profile, k[1].0));
            let at = |&p: &Profile| in_arena(&self.arena, p);
            let same = |a: &Profile| {
                if self.dominance {
                    let passes = || sig.is_none_or(|s| s.may_dominate(sig_in_arena(&self.arena, *a)));
                    debug_assert!(passes() || !dominated(profile, at(a)));
                    passes() && dominated(profile, at(a))
                } else {
                    at(a) == profile
                }
            };
            let dead_in = |l: Option<&SmallVec<[Profile; 2]>>| l.is_some_and(|l| l.iter().any(same));
            let exact_in = |l: Option<&SmallVec<[Profile; 2]>>| l.is_some_and(|l| l.iter().any(|a| at(a) == profile));
            let mut dead = dead_in(probes) || dead_in(own);
            let exact = exact_in(probes) || exact_in(own) || exact_in(rowed);
            // Dead only given the rows check: whatever it cuts depends on that check too.
            let by_rows = !dead && rowed.is_some_and(|l| l.iter().any(|a| same(a) && ends_within(profile, at(a))));
            dead |= by_rows;
            self.dominance_cuts += (dead && !exact) as u64;
            self.rpruned += by_rows as u64;
            self.row_dominance_cuts += by_rows as u64;
            // No capacity check here, where `t` has just advanced: the parent passed it with the
            // same objects and one more piece, and the waste check above sees most of what the
            // lost piece takes away. It refuted at most 0.5 % of these nodes on n20_k4_s0004,
            // s0005, s0017 and s0018 (5 % on s0008); without it the n20 set's area stages run
            // 3 % and its contact stages 5 % fewer instructions (docs/algorithms.md, *No
            // capacity check where `t` has just advanced*). Every placement below still checks
            // it, so this changes which nodes are cut, never the answer.
            dead || contact_cut(self)
                || (!self.probing && {
                    let record = self.dead.get(&k[..]).copied();
                    // A record that depends on the contact bound makes whatever it cuts depend on
                    // it too: count it as a contact cut, so that no ancestor is recorded as dead at
                    // any bound.
                    let hit = record.is_some_and(|(w0, u0)| w0 <= waste + tol && ub <= u0 + 1e-9);
                    self.cpruned += hit as u64;
                    hit
                })
                || rows_cut(self)
        } else {
            self.capacity_refutes(t, min_idx) || contact_cut(self) || rows_cut(self)
        };
        if cut {
            self.key_pool.extend(key);
            return false;
        }
        let (leaves_before, cut_before) = (self.yleaves, self.cpruned);
        // A node on a task's path sees one of its branches: not dead for that.
        let whole = self.followed == self.path.len();
        // A state the probe refutes is dead at any bound, like one that capacity cuts.
        if let Some(k) = &key {
            if whole && self.split.is_none() && self.probe_refutes(k, t, min_idx, placed_area, rem_area, waste) {
                // Refuted without the left-out items: a record for the probes' list.
                self.record_dead(k, waste, ub, true, false, true);
                self.key_pool.extend(key);
                return false;
            }
        }
        let rows_before = self.rpruned;
        let found = self.xbranch(t, min_idx, placed_area, rem_area, waste);
        if let Some(k) = key {
            // On the way to a probe's complete x-assignment: its probe would find it again.
            if found && self.probing {
                self.record_alive(&k);
            }
            if whole && !found && !self.stopped && self.yleaves == leaves_before {
                let rows = self.rpruned != rows_before;
                self.record_dead(&k, waste, ub, self.cpruned == cut_before, rows, self.probing);
            }
            self.key_pool.push(k);
        }
        found
    }

    /// The placed set as the probes' list keys it: without the items probes leave out. Whether
    /// a probe reaches a complete x-assignment depends on the other items placed, the position
    /// and the open objects' profile (the left-out items still open are in it), not on where
    /// the left-out items that ended behind the position went: their area behind it is placed
    /// or wasted alike. So a state a probe refuted refutes every state that differs from it
    /// only there, which the search meets once for each way of placing the smallest items
    /// (docs/algorithms.md, *The probes' dead states whichever way the smallest items went*).
    fn probe_set(&self) -> u64 {
        self.placed_mask & !self.probe_items
    }

    /// Record the state `key` as dead: at any bound (`any`: no contact cut below it), as a
    /// profile in the probes' list (`probed`: refuted without the left-out items) or the
    /// search's, or at its contact bound `ub`.
    fn record_dead(&mut self, key: &[(i32, i32)], waste: f64, ub: f64, any: bool, rows: bool, probed: bool) {
        let tol = self.t * (self.w + self.d);
        if any {
            // No complete x-assignment extends it, whatever the contact bound.
            let profile = self.profile_of(key);
            let at = self.keep_profile(profile, key[1].0);
            // A probe's dead state goes to the probes' list, which the search consults too; the
            // search's own dead states only to its own list (they may need the left-out items).
            // Dead given the rows check: a list of its own (the probes never check rows).
            let (m, set) = if probed {
                (1, self.probe_set())
            } else if rows {
                (3, self.placed_mask)
            } else {
                (0, self.placed_mask)
            };
            let signed = self.signed();
            let list = self.dominant[m].entry((set, key[1].0)).or_default();
            // Records this one dominates are redundant: whatever they cut, it cuts.
            let before = list.len();
            if self.dominance {
                let arena = &self.arena;
                // Without signatures (the area stage) every record is scanned.
                let sig = signed.then(|| sig_in_arena(arena, at));
                list.retain(|p| {
                    let passes = sig.is_none_or(|s| sig_in_arena(arena, *p).may_dominate(s));
                    let old = in_arena(arena, *p);
                    !(passes && dominated(old, profile) && (m != 3 || ends_within(old, profile)))
                });
            }
            self.dominant_len = self.dominant_len + 1 + list.len() - before;
            list.push(at);
        } else {
            if self.dead.len() >= self.memo_cap {
                self.dead.clear();
            }
            let e = self.dead.entry(key.into()).or_insert((waste, ub));
            // Keep the record that covers more (the waste is the same for one key: the area
            // behind `t` is placed or wasted, and the placed part ahead is in the key).
            if waste <= e.0 + tol && ub >= e.1 {
                *e = (waste, ub);
            }
        }
    }

    /// The open-object profile of a state key: the key without its head and contact marker
    /// ([`Self::state_key`]).
    fn profile_of<'k>(&self, key: &'k [(i32, i32)]) -> &'k [(i32, i32)] {
        &key[2..key.len() - self.cbound.is_some() as usize]
    }

    /// Whether dead profiles carry a [`Sig`]: only where the lists grow long, enumerating under
    /// a contact bound (in the area stage, computing it at every record cost more than it
    /// saved: n20_k4_s0008's and s0006's area stages 4–5 % slower, medians of fifteen).
    fn signed(&self) -> bool {
        self.dominance && self.cbound.is_some()
    }

    /// The [`Sig`] of `profile` at the position `t` (in tolerance units, as in the key).
    fn sig_of(&self, profile: &[(i32, i32)], t: i32) -> Sig {
        let q = |v: f64| (v / self.t + 0.5) as i64;
        Sig::of(profile, t as i64, q(self.w), q(self.d))
    }

    /// Put `profile` in the arena, for one of the lists of `dominant`. A full memo (or arena,
    /// within u32) starts afresh: the depth-first search meets again the states it left
    /// recently, not the first ones (the hardest box of squares 1…21, 71 × 47: 83 M nodes
    /// keeping the first 2 M states, 32 M starting afresh).
    fn keep_profile(&mut self, profile: &[(i32, i32)], t: i32) -> Profile {
        if self.dominant_len >= self.memo_cap || self.arena.len() + 2 + profile.len() > ARENA_MAX {
            self.dominant.iter_mut().for_each(HashMap::clear);
            self.dominant_len = 0;
            self.arena.clear();
        }
        let sig = if self.signed() {
            self.sig_of(profile, t)
        } else {
            Sig::NONE
        };
        let words = sig.words();
        self.arena.extend_from_slice(&words);
        let at: Profile = (self.arena.len() as u32, profile.len() as u32);
        self.arena.extend_from_slice(profile);
        at
    }

    /// Whether a probe at the state `key` would reach a complete x-assignment: a probe did from
    /// a state with the same key for the probes (placed set without the left-out items,
    /// position, profile), on its way there or at its start. What a probe answers depends on
    /// that key alone (*The probes' dead states whichever way the smallest items went*,
    /// docs/algorithms.md), so skipping it loses no cut.
    fn known_alive(&self, key: &[(i32, i32)]) -> bool {
        if !self.witnesses {
            return false;
        }
        let profile = self.profile_of(key);
        let list = self.dominant[2].get(&(self.probe_set(), key[1].0));
        list.is_some_and(|l| l.iter().any(|&a| in_arena(&self.arena, a) == profile))
    }

    /// Record the state `key` as one a probe reaches a complete x-assignment from (once).
    fn record_alive(&mut self, key: &[(i32, i32)]) {
        if self.known_alive(key) || !self.witnesses {
            return;
        }
        let at = self.keep_profile(self.profile_of(key), key[1].0);
        self.dominant[2]
            .entry((self.probe_set(), key[1].0))
            .or_default()
            .push(at);
        self.dominant_len += 1;
    }

    /// Place item `i` in footprint `k` at left edge `t` in the x-phase, with everything kept in
    /// step with it: `placed` and its bit sets, `xends` (sorted by right edge) and `xsides`.
    /// Returns what [`Self::unplace`] needs: where its end went, and `xsides` before (restored,
    /// not subtracted, so that no rounding accumulates). Always inline: left to the compiler,
    /// the x-phase took 2 % more instructions (callgrind, 54 × 46 of squares 1…19).
    #[inline(always)]
    fn place(&mut self, i: usize, k: usize, t: f64) -> (usize, f64) {
        let f = self.items[i].opts[k];
        let end = t + f[0];
        let at = self.xends.partition_point(|e| e.0 <= end);
        self.xends.insert(at, (end, f[1]));
        self.set_placed(i, true);
        self.opt[i] = k;
        self.x0[i] = t;
        let sides = self.xsides;
        self.xsides += f[0] + f[1] - self.max_sides[i];
        (at, sides)
    }

    /// Undo [`Self::place`] of item `i`.
    #[inline(always)]
    fn unplace(&mut self, i: usize, (at, sides): (usize, f64)) {
        self.xsides = sides;
        self.xends.remove(at);
        self.set_placed(i, false);
    }

    /// Mark item `i` placed or not, in `placed` and its bit sets.
    fn set_placed(&mut self, i: usize, on: bool) {
        self.placed[i] = on;
        if self.items.len() <= 64 {
            let (b, r) = (1u64 << i, 1u64 << self.depth_rank[i]);
            if on {
                self.placed_mask |= b;
                self.left_by_depth &= !r;
            } else {
                self.placed_mask &= !b;
                self.left_by_depth |= r;
            }
        }
    }

    /// Invariant: `xsides` is [`Self::sides_now`] up to rounding.
    fn sides_in_step(&self) -> bool {
        (self.xsides - self.sides_now()).abs() <= 1e-9 * (1.0 + self.xsides.abs())
    }

    /// Invariant: the bit sets of [`Self::set_placed`] say what `placed` says.
    fn masks_in_step(&self) -> bool {
        let n = self.items.len();
        n > 64
            || (0..n).all(|i| {
                let r = self.depth_rank[i];
                self.by_depth[r as usize] == i
                    && (self.placed_mask >> i & 1 == 1) == self.placed[i]
                    && (self.left_by_depth >> r & 1 == 1) != self.placed[i]
            }) && (self.left_by_depth | self.placed_mask) & !low_bits(n) == 0
    }

    /// Invariant: [`Self::xends`] holds exactly the placed items' right edges and depths, in
    /// order of right edge.
    fn ends_in_step(&self) -> bool {
        let mut want: Vec<(f64, f64)> = (0..self.items.len())
            .filter(|&j| self.placed[j])
            .map(|j| (self.x0[j] + self.dims(j)[0], self.dims(j)[1]))
            .collect();
        let mut have = self.xends.clone();
        let by = |a: &(f64, f64), b: &(f64, f64)| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1));
        want.sort_by(by);
        have.sort_by(by);
        self.xends.windows(2).all(|p| p[0].0 <= p[1].0) && want == have
    }

    /// Where the items still open at `t` (right edge after it) start in [`Self::xends`].
    fn open_from(&self, t: f64) -> usize {
        self.xends.partition_point(|e| e.0 <= t + self.t)
    }

    /// The depths of the placed items whose right side ends at `t`, summed: the last entries
    /// of `xends` before `from`, where the open ones start ([`Self::open_from`]).
    fn ends_at(&self, t: f64, from: usize) -> f64 {
        self.xends[..from]
            .iter()
            .rev()
            .take_while(|e| e.0 >= t - self.t)
            .map(|e| e.1)
            .sum()
    }

    /// The memo key of the x-phase state at `t` into `key` ([`StateKey`]), lengths in units of
    /// the tolerance.
    fn state_key(&self, t: f64, key: &mut Vec<(i32, i32)>) {
        // Lengths here are not negative, so rounding is truncation after adding one half: `round`
        // is a call into libm on the baseline x86-64 target (3 % of the contact enumeration's
        // instructions on squares 1…18).
        let q = |v: f64| (v / self.t + 0.5) as i32;
        let from = self.open_from(t);
        key.clear();
        key.push((self.placed_mask as i32, (self.placed_mask >> 32) as i32));
        key.push((q(t), 0));
        key.extend(self.xends[from..].iter().map(|&(e, h)| (q(e), q(h))));
        key[2..].sort_unstable();
        if self.cbound.is_some() {
            // Contact bounds at `t` depend on the right sides ending there.
            key.push((i32::MIN, q(self.ends_at(t, from))));
        }
    }

    /// The branches of [`Self::xphase`] at `t`: each object that may start there
    /// ([`Self::xchild`]), then the move to the next right edge ([`Self::xadvance`]).
    fn xbranch(&mut self, t: f64, min_idx: usize, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        if self.followed < self.path.len() || self.split.is_some() {
            return self.xbranch_steered(t, min_idx, placed_area, rem_area, waste);
        }
        let n = self.items.len();
        let from = self.open_from(t);
        let cap = self.d - self.xends[from..].iter().map(|e| e.1).sum::<f64>();
        let free_ends = self.free_ends(t, from);
        for i in min_idx..n {
            if self.left_out_now(i) {
                continue;
            }
            let Some(k_first) = self.first_footprint(i, t) else {
                continue;
            };
            for k in k_first..self.items[i].opts.len() {
                if !self.fits_at(self.items[i].opts[k], t, cap) {
                    continue;
                }
                if self.xchild(t, (i, k), free_ends, placed_area, rem_area, waste) {
                    return true;
                }
                if self.stopped {
                    return false;
                }
            }
        }
        self.xadvance(t, from, cap, placed_area, rem_area, waste)
    }

    /// [`Self::xbranch`] on a task's path (its branch only) or while splitting (each branch
    /// becomes a task at the split's depth). Out of line: the search proper never comes here.
    #[cold]
    #[inline(never)]
    fn xbranch_steered(&mut self, t: f64, min_idx: usize, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        let from = self.open_from(t);
        let cap = self.d - self.xends[from..].iter().map(|e| e.1).sum::<f64>();
        let free_ends = self.free_ends(t, from);
        let take = |s: &mut Self, step: Step| match step {
            Some(c) => s.xchild(t, c, free_ends, placed_area, rem_area, waste),
            None => s.xadvance(t, from, cap, placed_area, rem_area, waste),
        };
        if self.followed < self.path.len() {
            let step = self.path[self.followed];
            self.followed += 1;
            let found = take(self, step);
            self.followed -= 1;
            return found;
        }
        let mut steps: Vec<Step> = Vec::new();
        for i in min_idx..self.items.len() {
            if let Some(k_first) = self.first_footprint(i, t) {
                let fit = (k_first..self.items[i].opts.len()).filter(|&k| self.fits_at(self.items[i].opts[k], t, cap));
                steps.extend(fit.map(|k| Some((i, k))));
            }
        }
        if self.next_edge(from).is_some() {
            steps.push(None);
        }
        let ub = self.node_contact_bound(t, placed_area + rem_area + waste);
        let Some(split) = &mut self.split else {
            unreachable!("steered only on a path or while splitting")
        };
        let branching = (steps.len() > 1) as u32;
        split.depth += branching;
        let here = split.depth >= split.at || split.tasks.len() >= split.most;
        for step in steps {
            self.path.push(step);
            self.followed += 1;
            if here {
                let path = self.path.clone();
                let split = self.split.as_mut().expect("splitting");
                split.tasks.push(path);
                split.bounds.push(ub);
            } else {
                take(self, step);
            }
            self.path.pop();
            self.followed -= 1;
        }
        self.split.as_mut().expect("splitting").depth -= branching;
        false
    }

    /// The next right edge (the first open object's, `from`: [`Self::open_from`]), if the x-phase
    /// may move there: inside the box, and not past the anchor's half while the anchor waits.
    #[inline(always)]
    fn next_edge(&self, from: usize) -> Option<f64> {
        let next = self.xends.get(from).map_or(f64::INFINITY, |e| e.0);
        if !next.is_finite() || next > self.w - self.t {
            return None;
        }
        if let Some(a) = self.anchor {
            if !self.placed[a] && next > self.anchor_limit(0) {
                return None;
            }
        }
        Some(next)
    }

    /// Right sides ending at `t` not yet taken by the left sides of the items placed at `t`:
    /// the same for every branch at one node (each child restores what it places).
    fn free_ends(&self, t: f64, from: usize) -> f64 {
        if t <= self.t {
            f64::INFINITY
        } else {
            f64::max(self.ends_at(t, from) - self.starts_at_t, 0.0)
        }
    }

    /// The first footprint item `i` may take at `t`, or `None` when it may not start there:
    /// placed, an identical item before it not placed yet, or the anchor past its half.
    #[inline(always)]
    fn first_footprint(&self, i: usize, t: f64) -> Option<usize> {
        if self.placed[i] || self.prev_same[i].is_some_and(|p| !self.placed[p]) {
            return None;
        }
        if Some(i) == self.anchor && t > self.anchor_limit(0) {
            return None;
        }
        // Identical items started at one position also take their footprints in order:
        // swapping two of them leaves the packing as it was, so only one of the two labellings
        // is needed (up to 3.5x fewer nodes on the random sets, where each kind comes five
        // times in up to six footprints).
        Some(match self.prev_same[i] {
            Some(p) if (self.x0[p] - t).abs() <= self.t => self.opt[p],
            _ => 0,
        })
    }

    /// Whether footprint `f` fits at `t` under the open objects, which leave `cap` free.
    #[inline(always)]
    fn fits_at(&self, f: [f64; 2], t: f64, cap: f64) -> bool {
        f[0] <= self.w - t + self.t && f[1] <= cap + self.t
    }

    /// One branch at `t`: item `i` in footprint `k` starts there.
    #[inline(always)]
    fn xchild(
        &mut self,
        t: f64,
        (i, k): (usize, usize),
        free_ends: f64,
        placed_area: f64,
        rem_area: f64,
        waste: f64,
    ) -> bool {
        let f = self.items[i].opts[k];
        // Its left side touches only objects ending at `t` (all placed) or the wall; the
        // objects starting at `t` share the right sides of those ending there, so what the ones
        // placed at `t` before it took is not left for it.
        let left = free_ends.min(f[1]);
        let undo = self.place(i, k, t);
        self.ldef += f[1] - left;
        self.starts_at_t += f[1];
        let found = self.xphase(t, i + 1, placed_area + f[0] * f[1], rem_area - self.min_area[i], waste);
        self.ldef -= f[1] - left;
        self.starts_at_t -= f[1];
        if !found || self.probing {
            self.unplace(i, undo);
        }
        found
    }

    /// The last branch at `t`: move to the next right edge (nothing placed later starts before
    /// it), leaving the column's free depth `cap` unused for good.
    fn xadvance(&mut self, t: f64, from: usize, cap: f64, placed_area: f64, rem_area: f64, waste: f64) -> bool {
        let Some(next) = self.next_edge(from) else {
            return false;
        };
        let saved = (self.hprev, self.ldef_at, self.starts_at_t);
        (self.hprev, self.ldef_at, self.starts_at_t) = (cap, self.ldef, 0.0);
        let found = self.xphase(next, 0, placed_area, rem_area, waste + (next - t) * cap);
        (self.hprev, self.ldef_at, self.starts_at_t) = saved;
        found
    }
}

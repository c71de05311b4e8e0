//! One box on several threads, with the answer of one: the search is split into tasks (paths
//! from the root), which threads that each keep a search and its memo take in ranges.

use super::faces::{self, Faces};
use super::search::{DeadProfiles, Step};
use super::{Item, Outcome, Pos, Search};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::Relaxed};
use std::sync::Mutex;

/// The depth, in nodes with more than one branch, at which the search of one box is split into
/// tasks for the threads, and the most tasks wanted ([`Search::tasks`]): squares 1…22's packed
/// box makes 1,479, the random twenty-object sets at most about 900.
const SPLIT_AT: u32 = 3;
const SPLIT_MOST: usize = 1 << 16;

/// Nodes a box's decision runs on one thread before it is split between threads
/// ([`search`]): stop polls come every 1,024 nodes, so the lead ends at a node count alone.
pub(super) const LEAD_NODES: u64 = 1 << 12;

/// What the threads of one box share besides their work: the caller's stop, seen by all, the
/// stop polls of all (each 1024 nodes apart: the meter's estimate while they run), and who
/// takes which task.
struct Pool {
    ranges: Mutex<Ranges>,
    halted: AtomicBool,
    polls: AtomicU64,
}

/// Which tasks each thread takes: ranges of consecutive tasks, at first one per branch of the
/// root, each owned by one thread, which takes its tasks in order (the memo a thread keeps
/// serves the states its neighbouring tasks share: dealing the tasks out one by one cost 18 %
/// more nodes on squares 1…18). A thread whose range is done claims the next range no one
/// has, and when none is left takes the later half of the largest range another thread still
/// has.
struct Ranges {
    unclaimed: std::vec::IntoIter<(usize, usize)>,
    /// Per thread: the next task of its range and the range's end.
    owned: Vec<(usize, usize)>,
}

impl Pool {
    /// A pool for `tasks` (each a path from the root, in the search's order) on `threads`.
    fn new(tasks: &[Vec<Step>], threads: usize) -> Self {
        let mut ranges: Vec<(usize, usize)> = Vec::new();
        for (c, t) in tasks.iter().enumerate() {
            match ranges.last_mut() {
                Some(r) if tasks[r.0].first() == t.first() => r.1 = c + 1,
                _ => ranges.push((c, c + 1)),
            }
        }
        Pool {
            ranges: Mutex::new(Ranges {
                unclaimed: ranges.into_iter(),
                owned: vec![(0, 0); threads],
            }),
            halted: AtomicBool::new(false),
            polls: AtomicU64::new(0),
        }
    }

    /// The next task for thread `me`, if any is left and no stop came.
    fn take(&self, me: usize) -> Option<usize> {
        if self.halted.load(Relaxed) {
            return None;
        }
        let mut r = self.ranges.lock().expect("no thread panics holding it");
        if r.owned[me].0 >= r.owned[me].1 {
            let next = r.unclaimed.next().or_else(|| {
                let (victim, &(a, b)) = r
                    .owned
                    .iter()
                    .enumerate()
                    .max_by_key(|(_, o)| o.1.saturating_sub(o.0))
                    .filter(|(_, o)| o.1 > o.0)?;
                let mid = a + (b - a) / 2;
                r.owned[victim].1 = mid;
                Some((mid, b))
            })?;
            r.owned[me] = next;
        }
        let c = r.owned[me].0;
        r.owned[me].0 += 1;
        Some(c)
    }

    /// A thread's stop poll, on top of its own reasons (`more`).
    fn poll(&self, more: bool) -> bool {
        self.polls.fetch_add(1, Relaxed);
        more || self.halted.load(Relaxed)
    }

    /// Run `worker` on `threads` threads, this one included, and return the nodes they report.
    /// Only this thread polls `stop` (it need not be `Sync`): inside its own work, through
    /// the poll it hands `worker`, and every 2 ms while it waits for the others.
    fn run(
        &self,
        threads: usize,
        stop: &dyn Fn() -> bool,
        meter: Option<&Cell<u64>>,
        worker: &(dyn Fn(usize, &dyn Fn() -> bool) -> u64 + Sync),
    ) -> u64 {
        let base = meter.map_or(0, |m| m.get());
        let caller = || {
            if let Some(m) = meter {
                m.set(base + self.polls.load(Relaxed) * 1024);
            }
            if stop() {
                self.halted.store(true, Relaxed);
            }
            false
        };
        let never = || false;
        // A stop already asked for halts every thread before its first task: otherwise a
        // thread scheduled early could finish a small box before this one's first poll.
        caller();
        // Each other thread says when it is done, so that waiting ends at once on small boxes.
        let (done, finished) = std::sync::mpsc::channel::<()>();
        std::thread::scope(|scope| {
            let others: Vec<_> = (1..threads)
                .map(|me| {
                    let done = done.clone();
                    scope.spawn(move || {
                        let nodes = worker(me, &never);
                        // The receiver lives until every thread is joined.
                        let _ = done.send(());
                        nodes
                    })
                })
                .collect();
            drop(done);
            let mut nodes = worker(0, &caller);
            let mut waiting = others.len();
            while waiting > 0 {
                match finished.recv_timeout(std::time::Duration::from_millis(2)) {
                    Ok(()) => waiting -= 1,
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                        caller();
                    }
                    // A thread panicked: its panic is raised at the join below.
                    Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
                }
            }
            for h in others {
                nodes += h.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
            }
            nodes
        })
    }
}

/// [`Search::run`] on `threads` threads. The answer is the one of a single thread: the first
/// branch in order that packs gives the packing (the branches after it are called off, those
/// before it finish: a branch's first packing does not depend on what the memo holds, since
/// the memo cuts only subtrees without a complete x-assignment), and the box is infeasible
/// only when every branch is.
pub(super) fn search(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    meter: Option<&Cell<u64>>,
    threads: usize,
) -> (Outcome, u64) {
    search_led(items, w, d, stop, meter, threads, LEAD_NODES)
}

/// [`search`] with a lead of `lead` nodes on one thread before the split (0: none; polls come
/// every 1,024 nodes, so a lead ends at the first poll at or past it). Tests set it, to
/// decide boxes by the split with and without a lead whose dead profiles it inherits.
pub(super) fn search_led(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    meter: Option<&Cell<u64>>,
    threads: usize,
    lead: u64,
) -> (Outcome, u64) {
    if threads <= 1 || items.len() < 2 {
        let mut s = Search::new(items, w, d, stop).metered(meter);
        let r = s.run();
        return (r, s.nodes);
    }
    // A lead on this thread first: most boxes are decided within it, without the split, the
    // threads and their searches' set-up, which made two threads three to five times slower
    // than one on the small sets (docs/algorithms.md, *A lead on one thread*). What it decides
    // is the single thread's answer; what it leaves, the split below decides as one thread
    // would, and the dead profiles it found go to the split's first thread.
    let (mut lead_nodes, mut heirloom) = (0, None);
    if lead > 0 {
        let count = Cell::new(0);
        let base = meter.map_or(0, |m| m.get());
        let spent = || {
            if let Some(m) = meter {
                m.set(base + count.get());
            }
            count.get() >= lead || stop()
        };
        let mut first = Search::new(items, w, d, &spent).metered(Some(&count));
        let r = first.run();
        lead_nodes = first.nodes;
        if !matches!(r, Outcome::Stopped) || stop() {
            return (r, lead_nodes);
        }
        heirloom = Some(first.take_dead_profiles());
        if let Some(m) = meter {
            m.set(base + lead_nodes);
        }
    }
    let heirloom = Mutex::new(heirloom);
    let never = || false;
    let mut root = Search::new(items, w, d, &never);
    let branches = root.tasks(SPLIT_AT, SPLIT_MOST);
    let pool = Pool::new(&branches, threads);
    // The least branch that packed: branches after it are called off.
    let packed_at = AtomicUsize::new(usize::MAX);
    let results: Mutex<Vec<Option<Outcome>>> = Mutex::new(vec![None; branches.len()]);
    let worker = |me: usize, poll: &dyn Fn() -> bool| -> u64 {
        let current = Cell::new(usize::MAX);
        let own_stop = || pool.poll(poll() || packed_at.load(Relaxed) < current.get());
        let mut s = Search::new(items, w, d, &own_stop);
        if me == 0 {
            if let Some(dead) = heirloom.lock().expect("no thread panics holding it").take() {
                s = s.with_dead_profiles(dead);
            }
        }
        while let Some(c) = pool.take(me).filter(|&c| c < packed_at.load(Relaxed)) {
            current.set(c);
            let r = s.run_task(&branches[c]);
            let packed = matches!(r, Outcome::Packed(_));
            if packed {
                packed_at.fetch_min(c, Relaxed);
            }
            results.lock().expect("no thread panics holding it")[c] = Some(r);
            if packed {
                break;
            }
        }
        s.nodes
    };
    let nodes = pool.run(threads, stop, meter, &worker) + root.nodes + lead_nodes;
    for r in results.into_inner().expect("no thread panicked holding it") {
        match r {
            Some(Outcome::Infeasible) => {}
            Some(Outcome::Packed(p)) => return (Outcome::Packed(p), nodes),
            Some(Outcome::Stopped) | None => return (Outcome::Stopped, nodes),
        }
    }
    (Outcome::Infeasible, nodes)
}

/// A packing and its score.
pub type Scored = (f64, Vec<Pos>);

/// The packing of `items` in `w × d` with the highest `score` above `to_beat`, among every
/// packing whose objects all touch something on their left and below, on `threads` threads;
/// `score` is `None` for packings that do not count. The search cuts branches whose contact
/// length bound (far walls where `far` says) does not beat the best score so far, so `score`
/// must be at most the contact length. Returns the best score and packing (`None`: nothing
/// beats `to_beat`), whether the enumeration finished, the nodes visited, and an upper bound on
/// the score of the packings the enumeration did not rule out (`-∞` when it finished: with the
/// best found and `to_beat`, it bounds every packing's score, which is what a stopped search
/// can still promise).
///
/// Footprints that no combination able to beat `to_beat` uses are left out first (their sides
/// and the far walls bound the contact, and their areas must fit the box: docs/algorithms.md,
/// *Footprint combinations that can beat the incumbent*); the enumeration keeps its order over
/// the rest, so the answer is the same, except that objects of different classes left the
/// same footprints become one class: then the score is the same, and the packing may be
/// another of that score (objects swapped, or another met first).
///
/// Either axis may be the x-phase's: the packings and their scores are the same up to
/// transposition, but the cost is not (docs/algorithms.md, *Which axis the x-phase takes*).
/// The search first runs 2¹⁴ nodes along the given axis on one thread; when it handed the
/// y-phase at most one complete x-assignment per 100 nodes, it goes on along that axis on
/// every thread. Otherwise the pilot runs to 2¹⁶ nodes, and when the rate is still above that
/// (the x-phase lets through what the y-phase must refute one by one, and nothing remembers
/// those), it runs three times as many again; if it has not finished by then and the rate is
/// still above, the other axis's enumeration takes over (at once when the first 2¹⁶ nodes
/// came above 1.8 times that rate). Otherwise this one goes on where the pilot stopped.
///
/// The same answer on any number of threads: the pilot runs on one thread and polls its
/// budget every 1,024 nodes, so the axis is chosen alike; the answer is then the first
/// packing of the highest score in the order of one thread along that axis (the split
/// search's tasks keep its order, and ties with the tasks before a task lose, those with the
/// tasks after it win).
#[allow(clippy::too_many_arguments)] // each is one independent input of the enumeration
pub fn best_packing(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    score: &(dyn Fn(&[Pos]) -> Option<f64> + Sync),
    to_beat: f64,
    far: [bool; 2],
    meter: Option<&Cell<u64>>,
    threads: usize,
) -> (Option<Scored>, bool, u64, f64) {
    let to_beat = to_beat.max(0.0);
    let pilot = (PILOT_NODES, Y_RATE);
    match faces::restrict(items, w, d, to_beat, far, TIE) {
        Faces::All => {
            let (found, complete, nodes, _, open) =
                best_packing_piloted(items, w, d, stop, score, to_beat, far, meter, threads, pilot);
            (found, complete, nodes, open)
        }
        // No footprints with sides enough: nothing beats it, and nothing is left open.
        Faces::Nothing => (None, true, 0, f64::NEG_INFINITY),
        Faces::Only(kept) => {
            let score_kept = |pos: &[Pos]| score(&kept.back(pos));
            let (found, complete, nodes, _, open) = best_packing_piloted(
                &kept.items,
                w,
                d,
                stop,
                &score_kept,
                to_beat,
                far,
                meter,
                threads,
                pilot,
            );
            (found.map(|(c, pos)| (c, kept.back(&pos))), complete, nodes, open)
        }
    }
}

/// [`best_packing`] with every footprint of `items` and a pilot of `budget` nodes that turns
/// above `rate` complete x-assignments per node; also says whether it turned to the other axis
/// (before the open bound).
#[allow(clippy::too_many_arguments)] // best_packing's, and the pilot's budget and rate
pub(super) fn best_packing_piloted(
    items: &[Item],
    w: f64,
    d: f64,
    stop: &dyn Fn() -> bool,
    score: &(dyn Fn(&[Pos]) -> Option<f64> + Sync),
    to_beat: f64,
    far: [bool; 2],
    meter: Option<&Cell<u64>>,
    threads: usize,
    (budget, rate): (u64, f64),
) -> (Option<Scored>, bool, u64, bool, f64) {
    let to_beat = to_beat.max(0.0);
    if items.len() < 2 {
        let bound = Cell::new(to_beat);
        let mut best = None;
        let mut visit = |pos: &[Pos]| {
            if let Some(c) = score(pos).filter(|&c| c > bound.get() + TIE) {
                bound.set(c);
                best = Some((c, pos.to_vec()));
            }
            false
        };
        let (complete, nodes) = Search::enumerate(items, w, d, stop, &mut visit, Some(&bound), far, meter);
        // One item, stopped before it was placed: every side and far wall in contact.
        let open = if complete {
            f64::NEG_INFINITY
        } else {
            let sides = |it: &Item| it.opts.iter().map(|f| f[0] + f[1]).fold(0.0, f64::max);
            let walls = if far[0] { d } else { 0.0 } + if far[1] { w } else { 0.0 };
            items.iter().map(sides).sum::<f64>() + walls
        };
        return (best, complete, nodes, false, open);
    }
    let base = meter.map_or(0, |m| m.get());
    // The meter during a pilot that starts `at` nodes.
    let from = |at: u64| {
        move |n: u64| {
            if let Some(m) = meter {
                m.set(at + n);
            }
        }
    };
    let along = Best::new(items, w, d, score, to_beat, far);
    // A first quarter at or below the rate keeps the axis at once, so that two threads share
    // the other three quarters (docs/algorithms.md, *A first quarter at the rate keeps the
    // axis*); otherwise the pilot goes on to its whole budget.
    let early = budget / EARLY_PART;
    let (mut pilot, mut leaves) = along.pilot(early, stop, &from(base + along.root_nodes));
    let kept = !along.complete() && leaves as f64 <= rate * pilot as f64;
    if !kept {
        let (more, more_leaves) = along.pilot(budget - pilot.min(budget), stop, &from(base + along.root_nodes + pilot));
        pilot += more;
        leaves += more_leaves;
    }
    let mut nodes = along.root_nodes + pilot;
    let mut turn = !kept && !along.complete() && leaves as f64 > rate * pilot as f64;
    if turn && leaves as f64 <= SURE * rate * pilot as f64 {
        // Before giving up what the pilot did, the same axis gets three times as many nodes
        // again: a box it finishes within them is not worth the other axis's risk
        // (n20_k4_s0012 took 0.02 s along the longer side and 1.12 s turned). Far above the
        // rate, the box turns at once.
        let (more, more_leaves) = along.pilot(3 * budget, stop, &from(base + nodes));
        nodes += more;
        turn = !along.complete() && (leaves + more_leaves) as f64 > rate * (pilot + more) as f64;
    }
    if !turn {
        nodes += along.finish(threads, stop, meter);
        let (found, complete) = along.result();
        return (found, complete, nodes, false, along.open_bound());
    }
    let turned = super::turned(items);
    let transpose = |pos: &[Pos]| -> Vec<Pos> { pos.iter().map(|p| p.transposed()).collect() };
    let score_turned = |pos: &[Pos]| score(&transpose(pos));
    // What the pilot found, turned, is met again: starting just below it (ties win) cuts
    // more and leaves the first packing of the best score in this axis's order the answer.
    let pilot_best = along.result().0;
    let start = pilot_best.as_ref().map_or(to_beat, |p| to_beat.max(p.0 - 2.0 * TIE));
    let across = Best::new(&turned, d, w, &score_turned, start, [far[1], far[0]]);
    if let Some(m) = meter {
        m.set(base + nodes);
    }
    nodes += across.root_nodes + across.finish(threads, stop, meter);
    let (found, complete) = across.result();
    let found = found.map(|(c, pos)| (c, transpose(&pos)));
    // Stopped early, the pilot's best may be the better one.
    let found = match (found, pilot_best) {
        (Some(f), Some(p)) if !complete && p.0 > f.0 + TIE => Some(p),
        (None, p) if !complete => p,
        (f, _) => f,
    };
    (found, complete, nodes, true, across.open_bound())
}

/// Nodes of the pilot along the given axis ([`best_packing`]), on one thread. Over the
/// contact enumerations of the random sets n16 and n20 and the squares 14 … 19, pilots of
/// 2¹⁶, 2¹⁸ and 2²⁰ nodes came to 57.4 M, 59.2 M and 60.0 M nodes in all, and the pilot is the
/// part that two threads cannot share.
const PILOT_NODES: u64 = 1 << 16;

/// The pilot's first part, as a share of its budget, after which a rate at most [`Y_RATE`]
/// keeps the given axis at once. Over squares 10…20, the committed n12, n16 and n20 sets and
/// sixty generated files, a first quarter (2¹⁴ nodes) changed one axis, for the better
/// (docs/algorithms.md, *A first quarter at the rate keeps the axis*).
const EARLY_PART: u64 = 4;

/// Complete x-assignments per pilot node above which [`best_packing`] turns to the other axis
/// (docs/algorithms.md, *Which axis the x-phase takes* and *Gapless stacks*: until the
/// gapless-stacks bound ended most y-phases at their root, the rule was a share of y-phase
/// nodes above 60 %, and 70 % before the holes bound).
const Y_RATE: f64 = 0.01;

/// How many times [`Y_RATE`] a first pilot must exceed for the box to turn without the three
/// times longer second pilot (docs/algorithms.md, *A first pilot far above the rate turns at
/// once*). After the footprint combinations, the first pilots of the n16, n20 and twenty
/// generated files that the second pilot confirmed came to 1,281 … 2,419 complete
/// x-assignments per 2¹⁶ nodes, and those it sent back along the first axis (their box
/// finished within it) to 730 … 1,002.
const SURE: f64 = 1.8;

/// Scores closer than this are ties (contact lengths are sums of sizes).
const TIE: f64 = 1e-9;

/// One enumeration of [`best_packing`] split into tasks ([`Search::tasks`]), which threads
/// take in any order. A task cuts at the best score of the tasks before it and its own (ties
/// lose to them), and only strictly below the best of the tasks after it (ties win against
/// them); so the first best packing of the first task holding one is never cut, since no task
/// before it reaches its score, and the answer is that of one thread. The memo of states dead
/// at a contact bound needs the bound never to fall: a thread that moves to an earlier task
/// (taken from another thread's range) starts over at that task's bound and forgets them.
pub(super) struct Best<'a> {
    items: &'a [Item],
    w: f64,
    d: f64,
    score: &'a (dyn Fn(&[Pos]) -> Option<f64> + Sync),
    to_beat: f64,
    far: [bool; 2],
    pub(super) tasks: Vec<Vec<Step>>,
    /// Per task: an upper bound on the score of the packings below it ([`Search::tasks_bounded`]).
    bounds: Vec<f64>,
    /// Per task: whether it was enumerated to the end.
    done: Vec<AtomicBool>,
    root_nodes: u64,
    /// Per task: the best score found in it (bits of a non-negative f64 order as the value),
    /// and its first packing of that score.
    scores: Vec<AtomicU64>,
    found: Mutex<Vec<Option<Scored>>>,
    /// The dead profiles of the pilots, handed on from one to the next and then to the first
    /// thread of the rest (the twenty-object set on one thread: 16.69 M nodes in both stages
    /// with a fresh memo per search, 16.15 M handing them on).
    heirloom: Mutex<DeadProfiles>,
}

impl<'a> Best<'a> {
    /// The enumeration of `items` in `w × d`, split into its tasks.
    pub(super) fn new(
        items: &'a [Item],
        w: f64,
        d: f64,
        score: &'a (dyn Fn(&[Pos]) -> Option<f64> + Sync),
        to_beat: f64,
        far: [bool; 2],
    ) -> Self {
        let never = || false;
        let mut none = |_: &[Pos]| false;
        let mut root = Search::enumerator(items, w, d, &never, &mut none, None, far);
        let (tasks, bounds) = root.tasks_bounded(SPLIT_AT, SPLIT_MOST);
        Best {
            bounds,
            items,
            w,
            d,
            score,
            to_beat,
            far,
            scores: (0..tasks.len()).map(|_| AtomicU64::new(0)).collect(),
            found: Mutex::new(vec![None; tasks.len()]),
            done: (0..tasks.len()).map(|_| AtomicBool::new(false)).collect(),
            root_nodes: root.nodes,
            tasks,
            heirloom: Mutex::default(),
        }
    }

    /// The bound of task `c`: ties with tasks up to `c` are cut, ties with later ones not.
    fn bound_of(&self, c: usize) -> f64 {
        self.scores.iter().enumerate().fold(self.to_beat, |b, (k, s)| {
            let v = f64::from_bits(s.load(Relaxed));
            b.max(if k <= c { v } else { v - 2.0 * TIE })
        })
    }

    /// One thread's work: the tasks `next` hands out, in any order, with one search and its
    /// memo; `poll` is its stop, and `meter` is kept at the nodes so far at each poll. Returns
    /// the nodes visited and the complete x-assignments handed to the y-phase. An `heir`
    /// starts from the dead profiles the last heir left and leaves its own for the next one.
    pub(super) fn work(
        &self,
        poll: &dyn Fn() -> bool,
        next: &mut dyn FnMut() -> Option<usize>,
        meter: Option<&Cell<u64>>,
        heir: bool,
    ) -> (u64, u64) {
        let current = Cell::new(0usize);
        let bound = Cell::new(self.to_beat);
        let own_stop = || {
            bound.set(bound.get().max(self.bound_of(current.get())));
            poll()
        };
        let mut visit = |pos: &[Pos]| {
            if let Some(c) = (self.score)(pos).filter(|&c| c > bound.get() + TIE) {
                let k = current.get();
                bound.set(c);
                self.scores[k].fetch_max(c.to_bits(), Relaxed);
                self.found.lock().expect("no thread panics holding it")[k] = Some((c, pos.to_vec()));
            }
            false
        };
        let mut s = Search::enumerator(
            self.items,
            self.w,
            self.d,
            &own_stop,
            &mut visit,
            Some(&bound),
            self.far,
        )
        .metered(meter);
        let heirloom = || self.heirloom.lock().expect("no thread panics holding it");
        if heir {
            s = s.with_dead_profiles(std::mem::take(&mut *heirloom()));
        }
        while let Some(c) = next() {
            current.set(c);
            let b = self.bound_of(c);
            if b < bound.get() {
                bound.set(b);
                s.forget_bounded_memo();
            }
            bound.set(bound.get().max(b));
            if matches!(s.run_task(&self.tasks[c]), Outcome::Infeasible) {
                self.done[c].store(true, Relaxed);
            }
        }
        if heir {
            *heirloom() = s.take_dead_profiles();
        }
        (s.nodes, s.yleaves)
    }

    /// The tasks not done yet, in order, on this thread, until `budget` nodes or `stop`;
    /// `meter` is told the nodes so far. Returns the nodes visited and the complete x-assignments. Polls
    /// come every 1,024 nodes, so where it stops depends on the search alone.
    fn pilot(&self, budget: u64, stop: &dyn Fn() -> bool, meter: &dyn Fn(u64)) -> (u64, u64) {
        let count = Cell::new(0);
        let spent = || {
            meter(count.get());
            count.get() >= budget || stop()
        };
        let mut from = 0;
        let mut next = || {
            if spent() {
                return None;
            }
            let c = (from..self.tasks.len()).find(|&c| !self.done[c].load(Relaxed))?;
            from = c + 1;
            Some(c)
        };
        self.work(&spent, &mut next, Some(&count), true)
    }

    /// The tasks not done yet on `threads` threads, until the end or `stop`. Returns the nodes
    /// visited.
    fn finish(&self, threads: usize, stop: &dyn Fn() -> bool, meter: Option<&Cell<u64>>) -> u64 {
        if self.complete() {
            return 0;
        }
        let pool = Pool::new(&self.tasks, threads);
        let worker = |me: usize, poll: &dyn Fn() -> bool| {
            let mut next = || std::iter::from_fn(|| pool.take(me)).find(|&c| !self.done[c].load(Relaxed));
            self.work(&|| pool.poll(poll()), &mut next, None, me == 0).0
        };
        pool.run(threads, stop, meter, &worker)
    }

    /// An upper bound on the score of the packings in the tasks not enumerated to the end
    /// (`-∞` when none is left): with the best found, one on every packing's.
    fn open_bound(&self) -> f64 {
        (self.bounds.iter().zip(&self.done))
            .filter(|(_, d)| !d.load(Relaxed))
            .fold(f64::NEG_INFINITY, |b, (&u, _)| b.max(u))
    }

    /// Whether every task was enumerated to the end.
    fn complete(&self) -> bool {
        self.done.iter().all(|d| d.load(Relaxed))
    }

    /// The best packing of all tasks (the first of the highest score in their order), and
    /// whether every task finished.
    pub(super) fn result(&self) -> (Option<Scored>, bool) {
        let complete = self.complete();
        let mut best: Option<Scored> = None;
        for (c, p) in self
            .found
            .lock()
            .expect("no thread panicked holding it")
            .iter()
            .flatten()
            .cloned()
        {
            if best.as_ref().is_none_or(|b| c > b.0 + TIE) {
                best = Some((c, p));
            }
        }
        (best, complete)
    }
}

//! One box on several threads, with the answer of one: the root's branches (which object
//! starts at x = 0) are dealt out in order to threads that each keep a search and its memo.

use super::{Item, Outcome, Pos, Search};
use std::cell::Cell;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::Relaxed};
use std::sync::Mutex;

/// What the threads of one box share besides their work: the caller's stop, seen by all, and
/// the stop polls of all (each 1024 nodes apart: the meter's estimate while they run).
#[derive(Default)]
struct Pool {
    next: AtomicUsize,
    halted: AtomicBool,
    polls: AtomicU64,
}

impl Pool {
    /// The next branch to take, if any is left and no stop came.
    fn take(&self, branches: usize) -> Option<usize> {
        let c = self.next.fetch_add(1, Relaxed);
        (c < branches && !self.halted.load(Relaxed)).then_some(c)
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
        worker: &(dyn Fn(&dyn Fn() -> bool) -> u64 + Sync),
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
        // Each other thread says when it is done, so that waiting ends at once on small boxes.
        let (done, finished) = std::sync::mpsc::channel::<()>();
        std::thread::scope(|scope| {
            let others: Vec<_> = (1..threads)
                .map(|_| {
                    let done = done.clone();
                    scope.spawn(move || {
                        let nodes = worker(&never);
                        // The receiver lives until every thread is joined.
                        let _ = done.send(());
                        nodes
                    })
                })
                .collect();
            drop(done);
            let mut nodes = worker(&caller);
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
    if threads <= 1 || items.len() < 2 {
        let mut s = Search::new(items, w, d, stop).metered(meter);
        let r = s.run();
        return (r, s.nodes);
    }
    let never = || false;
    let mut root = Search::new(items, w, d, &never);
    let Some(branches) = root.root_branches() else {
        return (Outcome::Infeasible, root.nodes);
    };
    let pool = Pool::default();
    // The least branch that packed: branches after it are called off.
    let packed_at = AtomicUsize::new(usize::MAX);
    let results: Mutex<Vec<Option<Outcome>>> = Mutex::new(vec![None; branches.len()]);
    let worker = |poll: &dyn Fn() -> bool| -> u64 {
        let current = Cell::new(usize::MAX);
        let own_stop = || pool.poll(poll() || packed_at.load(Relaxed) < current.get());
        let mut s = Search::new(items, w, d, &own_stop);
        while let Some(c) = pool.take(branches.len()).filter(|&c| c < packed_at.load(Relaxed)) {
            current.set(c);
            let r = s.run_branch(branches[c]);
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
    let nodes = pool.run(threads, stop, meter, &worker) + root.nodes;
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
/// beats `to_beat`), whether the enumeration finished, and the nodes visited.
///
/// The same answer on any number of threads: the first packing of the highest score in the
/// order of one thread. A branch cuts at the best score of the branches before it and its own
/// (ties lose to them), and only strictly below the best of the branches after it (ties win
/// against them). That bound only rises as a thread moves to later branches, which the memo of
/// states dead at a contact bound needs; and the first best packing of the first branch holding
/// one is never cut, since no branch before it reaches its score.
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
) -> (Option<Scored>, bool, u64) {
    /// Scores closer than this are ties (contact lengths are sums of sizes).
    const TIE: f64 = 1e-9;
    let to_beat = to_beat.max(0.0);
    if threads <= 1 || items.len() < 2 {
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
        return (best, complete, nodes);
    }
    let never = || false;
    let mut none = |_: &[Pos]| false;
    let mut root = Search::enumerator(items, w, d, &never, &mut none, None, far);
    let Some(branches) = root.root_branches() else {
        return (None, true, root.nodes);
    };
    let root_nodes = root.nodes;
    drop(root);
    let pool = Pool::default();
    // Per branch: the best score found in it (bits of a non-negative f64 order as the value),
    // and its first packing of that score.
    let scores: Vec<AtomicU64> = (0..branches.len()).map(|_| AtomicU64::new(0)).collect();
    let found: Mutex<Vec<Option<Scored>>> = Mutex::new(vec![None; branches.len()]);
    // Branches enumerated to the end.
    let finished = AtomicUsize::new(0);
    // The bound of branch `c`: ties with branches up to `c` are cut, ties with later ones not.
    let bound_of = |c: usize| {
        scores.iter().enumerate().fold(to_beat, |b, (k, s)| {
            let v = f64::from_bits(s.load(Relaxed));
            b.max(if k <= c { v } else { v - 2.0 * TIE })
        })
    };
    let worker = |poll: &dyn Fn() -> bool| -> u64 {
        let current = Cell::new(0usize);
        let bound = Cell::new(to_beat);
        let own_stop = || {
            bound.set(bound.get().max(bound_of(current.get())));
            pool.poll(poll())
        };
        let mut visit = |pos: &[Pos]| {
            if let Some(c) = score(pos).filter(|&c| c > bound.get() + TIE) {
                let k = current.get();
                bound.set(c);
                scores[k].fetch_max(c.to_bits(), Relaxed);
                found.lock().expect("no thread panics holding it")[k] = Some((c, pos.to_vec()));
            }
            false
        };
        let mut s = Search::enumerator(items, w, d, &own_stop, &mut visit, Some(&bound), far);
        while let Some(c) = pool.take(branches.len()) {
            current.set(c);
            bound.set(bound.get().max(bound_of(c)));
            finished.fetch_add(
                matches!(s.run_branch(branches[c]), Outcome::Infeasible) as usize,
                Relaxed,
            );
        }
        s.nodes
    };
    let nodes = pool.run(threads, stop, meter, &worker) + root_nodes;
    let complete = finished.into_inner() == branches.len();
    let mut best: Option<Scored> = None;
    for (c, p) in found
        .into_inner()
        .expect("no thread panicked holding it")
        .into_iter()
        .flatten()
    {
        if best.as_ref().is_none_or(|b| c > b.0 + TIE) {
            best = Some((c, p));
        }
    }
    (best, complete, nodes)
}

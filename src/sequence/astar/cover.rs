//! Set cover and maximum independent sets behind the push bounds.

use super::*;

/// Size of a largest independent set of the graph with neighbour masks `adj` (at most 64
/// vertices). Exact: a vertex of degree 0 or 1 is in some largest set, so it is taken without
/// branching; otherwise the search branches on a vertex of largest degree (in or out), pruned
/// by the vertices left.
pub(super) fn max_independent(adj: &[u64]) -> usize {
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
pub(super) fn bits(mut m: u64) -> impl Iterator<Item = usize> {
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
pub(super) const MAX_COVER_STEPS: usize = 48;

/// The push bound of one state as a covering problem: which usable lines, pushed, could finish
/// the objects still open (see [`Cover::min_lines`]).
pub(super) struct Cover<'s> {
    /// Objects not at their targets.
    pub(super) open: u64,
    /// Objects that must be pushed: released ones, and table objects no direct placement can
    /// ever take.
    pub(super) must: u64,
    /// Per table object that may still be placed directly: the open objects that stand in every
    /// finger slab it could use, so they must reach their targets after it is placed.
    pub(super) block: &'s [u64],
    /// Usable lines (at most 64): members, and the objects that block every usable gap
    /// pattern once done.
    pub(super) lines: &'s [(u64, u64)],
    /// Per object, the usable lines it is a member of (bit per line).
    pub(super) lines_of: &'s [u64],
    pub(super) steps: Cell<usize>,
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
    pub(super) fn min_lines(&self, from: usize) -> usize {
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
    pub(super) fn search(&self, left: usize, cov: u64, chosen: &mut Vec<usize>) -> Option<bool> {
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
    pub(super) fn cycle(&self, cov: u64, chosen: &[usize]) -> Option<u64> {
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

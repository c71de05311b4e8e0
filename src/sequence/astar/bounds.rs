//! Admissible lower bounds on the number of actions: fits within a budget, pushes, line covers.

use super::*;

impl<'a> Search<'a> {
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
    pub(super) fn fits(&self, state: &[ObjState], budget: usize) -> Option<usize> {
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
    pub(super) fn lower_len(&self, state: &[ObjState], floor: usize) -> usize {
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
    pub(super) fn picks_deadlocked(&self, state: &[ObjState], released: &[Rel]) -> bool {
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
    pub(super) fn line_reach(&self, li: usize, l: &PushLine, m: usize) -> bool {
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
    pub(super) fn released(&self, state: &[ObjState]) -> Vec<Rel> {
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
    pub(super) fn pick_blockers(&self, i: usize) -> Rc<Vec<(PlaceKey, Vec<u64>)>> {
        if let Some(b) = &self.pick_blockers.borrow()[i] {
            return b.clone();
        }
        let inst = self.inst;
        let mut empty = Layout::new(inst, self.placement);
        empty.assume_held = true;
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
    pub(super) fn fits_within(&self, state: &[ObjState], budget: usize, calls: u64) -> Fit {
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
    pub(super) fn known_fits(&self, state: &[ObjState], budget: usize) -> bool {
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
    pub(super) fn plan_from_memo(&self, root: &Node, len: usize) -> Option<Incumbent> {
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
    pub(super) fn shorten(&self, root: &Node, inc: &[Scored], calls: u64) -> (Fit, Option<Incumbent>) {
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
    pub(super) fn must_push(&self, state: &[ObjState]) -> Vec<usize> {
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
    pub(super) fn push_lower_bound(&self, state: &[ObjState], released: &[Rel], floor: usize) -> (usize, Vec<usize>) {
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
    pub(super) fn line_cover_bound(
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
    pub(super) fn line_releasable(
        &self,
        li: usize,
        l: &PushLine,
        state: &[ObjState],
        done: u64,
        released: &[Rel],
    ) -> bool {
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
}

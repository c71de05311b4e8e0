//! The heuristic, successors of a state, children, and the greedy dives that give incumbents.

use super::*;

impl<'a> Search<'a> {
    /// With `exact`, and once the minimum number of actions is proven, the remaining pushes come
    /// from phase 1's memoised depth-first search; without, from the cheap push bound alone.
    pub(super) fn h(&self, n: &Node, exact: bool) -> Cost {
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
    pub(super) fn f_of(&self, n: &Node, exact: bool) -> Cost {
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
    pub(super) fn successors(&self, state: &[ObjState]) -> Successors {
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
    pub(super) fn in_box(&self, i: usize, dir: PushDir, offset: f64) -> bool {
        self.area_box.get().is_none_or(|[x, y]| {
            let r = self.placement.targets[i].rect.moved(dir, -offset);
            r.x1 <= x + 1e-12 && r.y1 <= y + 1e-12
        })
    }

    /// Restrict every release to `b` (or lift the restriction), with a memo of its own: the
    /// facts of one box do not hold in another, and phase 1's come back when it is lifted.
    pub(super) fn set_box(&self, b: Option<[f64; 2]>) {
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
    pub(super) fn successors_uncached(&self, state: &[ObjState]) -> Vec<Scored> {
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

    pub(super) fn child(&self, n: &Node, a: &Action) -> Node {
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

    pub(super) fn goal_of(&self, n: &Node) -> Node {
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

    pub(super) fn all_done(n: &Node) -> bool {
        n.state.iter().all(|s| *s == ObjState::Done)
    }

    /// Order key of [`DiveOrder::FrontFirst`]: pushes first, then places by how far their
    /// target lies from the container's origin corner (pushes go toward it, so an object
    /// released early near the back would stand in the way of later ones).
    pub(super) fn front_key(&self, a: &Action) -> f64 {
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
    pub(super) fn min_area_box(&self, root: &Node, l: usize, incumbent: &mut Option<Incumbent>, trace: bool) -> usize {
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
    pub(super) fn dive(&self, root: &Node, budget: &mut u64, order: DiveOrder) -> Option<Incumbent> {
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

//! The A* loop: open list, labels, limits, and the plan read back from the search graph.

use super::*;

/// The actions from the root to `node` (every node but the root has one incoming edge).
pub(super) fn path_to(graph: &DiGraph<Node, Scored>, node: NodeIndex) -> Vec<Scored> {
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
    solve_with(inst, placement, opts, settings, stop, &mut Silent)
}

/// [`solve`], telling `progress` how the search goes ([`Event::Progress`]: nodes, the best
/// plan's number of actions, the proven lower bound on it) at most every
/// [`crate::control::PROGRESS_INTERVAL`].
///
/// Long on purpose, for now: its phases (the dive for an incumbent, the deepening that proves
/// the fewest actions, the smallest swept-area box, the main best-first loop, and reading the
/// result back) share about twenty pieces of mutable state (open list, labels, incumbent,
/// counters, the graph), and splitting them needs a search-state struct of its own; the order
/// of operations must stay exactly as it is (the golden plans and the exhaustive cross-checks
/// pin it). Tracked in issue 22's note.
pub fn solve_with(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    settings: &AstarSettings,
    stop: &dyn Terminator,
    progress: &mut dyn Listener,
) -> Result<SequenceResult> {
    let start = Instant::now();
    let mut ticker = Ticker::new();
    let mut report = |nodes: u64, incumbent: Option<usize>, bound: usize| {
        progress.event(&Event::Progress {
            stage: Stage::Sequence,
            nodes,
            incumbent: incumbent.map(|l| l as f64),
            bound: Some(incumbent.map_or(bound, |l| l.min(bound)) as f64),
        })
    };
    if settings.max_offset_steps == 0 || settings.max_offset_steps > MAX_OFFSET_STEPS {
        return Err(Error::input(
            "<settings>",
            "max_offset_steps",
            format!("must be 1..={MAX_OFFSET_STEPS}"),
        ));
    }
    let mut s = Search::new(inst, placement, opts.clone(), *settings);
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
    let trace = settings.trace;
    loop {
        let hi = incumbent.as_ref().map(|(c, _)| c.len);
        if ticker.due() {
            report(0, hi, len_lo);
        }
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
        if ticker.due() {
            // Best-first: no plan costs less than the least bound open, the one just popped.
            let proven = f.len.max(s.lstar.get().unwrap_or(len_lo));
            report(nodes, incumbent.as_ref().map(|(c, _)| c.len), proven);
        }
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
    if settings.trace {
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

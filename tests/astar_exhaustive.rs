//! The A* sequencer against an exhaustive enumeration of assignments and orders.
//!
//! The enumeration is written here, independent of the search: from each state it tries every
//! action of the action space — every object on the table placed directly or indirectly in
//! either direction at every allowed offset, every line of released objects (front to back,
//! targets touching along the push direction) pushed by either arm — keeps those the layout
//! accepts and the robot reaches, and recurses.
//! It memoises the best completion per (object states, arm positions, swept extents so far):
//! the future depends on nothing else, so this is Bellman's principle, not pruning. The best
//! lexicographic (actions, swept area, travel) over all complete plans is compared with A* on
//! all three components, and every A* plan goes through the verifier.
//!
//! The same instances are also solved by searches stopped early (after a fixed number of
//! terminator queries, so the stop is deterministic): a stopped search may return a worse plan
//! than the optimum but never a better one, and every component of its bound must lie at or
//! below the optimum's.

mod common;

use nalgebra::Vector3;
use pushpack::actions::{push, Action, Layout, ObjState, PlaceMode};
use pushpack::control::TimeLimit;
use pushpack::geometry::{Axis2, PushDir, EPS};
use pushpack::instance::Instance;
use pushpack::motion::joint_plan::{action_reach_memo, IkMemo, Reach};
use pushpack::motion::keypoints::{action_keypoints, path_length, pick_arm, push_arms};
use pushpack::placement::{bl, Placement};
use pushpack::plan::{build_plan, PlacementSolver, PlanOptions, Sequencer};
use pushpack::robot::Arm;
use pushpack::sequence::astar::{self, AstarSettings};
use pushpack::sequence::{SearchStatus, SequenceOptions};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug)]
struct Best {
    len: usize,
    area: f64,
    travel: f64,
}

fn better(a: &Best, b: &Best) -> bool {
    better_by(a, b, 1e-9)
}

/// Lexicographically better, with travels closer than `tol` counted equal.
fn better_by(a: &Best, b: &Best, tol: f64) -> bool {
    if a.len != b.len {
        return a.len < b.len;
    }
    if (a.area - b.area).abs() > 1e-12 {
        return a.area < b.area;
    }
    a.travel < b.travel - tol
}

struct Enumerate<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    no_direct: bool,
    no_multi: bool,
    /// Offset steps every object may use (A*'s `max_offset_steps`).
    steps: usize,
    home: [Vector3<f64>; 2],
    memo: FastMap<Vec<i64>, Option<Best>>,
    /// Feasible actions per object state: they depend on nothing else.
    moves: FastMap<Vec<i64>, std::rc::Rc<Vec<Action>>>,
    reach: std::cell::RefCell<FastMap<Vec<u64>, Option<Reach>>>,
    ik: std::cell::RefCell<IkMemo>,
}

/// Multiplicative hashing of whole words with a final avalanche: the memo tables hold millions
/// of integer keys, and SipHash plus formatting keys took a third of this test's time.
#[derive(Default, Clone, Copy)]
struct Fx(u64);

impl std::hash::Hasher for Fx {
    fn finish(&self) -> u64 {
        // A final avalanche (splitmix64's): hashbrown indexes by the low bits, which the
        // multiplication alone leaves depending on the last word only.
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn write(&mut self, bytes: &[u8]) {
        // Integer slices arrive here as raw bytes: hash them a word at a time.
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            self.write_u64(u64::from_le_bytes(c.try_into().expect("8 bytes")));
        }
        for b in chunks.remainder() {
            self.write_u64(*b as u64);
        }
    }
    fn write_u64(&mut self, w: u64) {
        self.0 = (self.0.rotate_left(5) ^ w).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, w: i64) {
        self.write_u64(w as u64);
    }
    fn write_usize(&mut self, w: usize) {
        self.write_u64(w as u64);
    }
}

type FastMap<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<Fx>>;

/// Exact identity of an action (bit patterns of its lengths).
fn action_key(a: &Action) -> Vec<u64> {
    match a {
        Action::Place {
            object,
            mode,
            grasp_axis,
            arm,
        } => {
            let (dir, off) = match mode {
                PlaceMode::Direct => (0, 0),
                PlaceMode::Indirect { push_dir, offset } => (1 + *push_dir as u64, offset.to_bits()),
            };
            vec![0, *object as u64, dir, off, *grasp_axis as u64, arm.index() as u64]
        }
        Action::Push {
            objects,
            push_dir,
            distance,
            pusher_at,
            arm,
        } => {
            let mut k = vec![
                1,
                *push_dir as u64,
                distance.to_bits(),
                pusher_at.to_bits(),
                arm.index() as u64,
            ];
            k.extend(objects.iter().map(|&i| i as u64));
            k
        }
    }
}

/// Length of the longest chain of targets ending at `i`, each touching the next along `dir`'s
/// axis with a lateral overlap (plain recursion: a chain strictly advances along the axis).
fn rank(placement: &Placement, dir: PushDir, i: usize) -> usize {
    let axis = dir.axis();
    let lat = axis.other();
    let t = |j: usize| placement.targets[j].rect;
    (0..placement.targets.len())
        .filter(|&j| {
            (t(i).lo(axis) - t(j).hi(axis)).abs() <= EPS
                && t(i).hi(lat).min(t(j).hi(lat)) - t(i).lo(lat).max(t(j).lo(lat)) > EPS
        })
        .map(|j| 1 + rank(placement, dir, j))
        .max()
        .unwrap_or(1)
}

impl Enumerate<'_> {
    /// Reachability by inverse kinematics (memoised: it does not depend on the state), then
    /// the objects still on the table that block the pick. Computed here with every hand
    /// variant (not through `ReachCache`, which stops at the first variant free of table
    /// blockers), so that A*'s shortcut is cross-checked too.
    fn reachable(&self, a: &Action, layout: &Layout) -> bool {
        let k = action_key(a);
        let r = match self.reach.borrow().get(&k) {
            Some(v) => v.clone(),
            None => action_reach_memo(self.inst, self.placement, a, &self.ik, false),
        };
        self.reach.borrow_mut().insert(k, r.clone());
        r.is_some_and(|r| r.free_when(|j| layout.state[j] == ObjState::Table))
    }

    fn actions(&self, layout: &Layout) -> Vec<Action> {
        let inst = self.inst;
        let d = inst.gripper.min_offset;
        let mut out = Vec::new();
        for i in 0..inst.n() {
            if layout.state[i] != ObjState::Table {
                continue;
            }
            let mut modes = vec![];
            if !self.no_direct {
                modes.push(PlaceMode::Direct);
            }
            for dir in [PushDir::MinusX, PushDir::MinusY] {
                // The action space's offsets: up to steps·d, and up to k·d for the k-th object of
                // a line (the paper's staggering).
                for m in 1..=self.steps.max(rank(self.placement, dir, i)) {
                    modes.push(PlaceMode::Indirect {
                        push_dir: dir,
                        offset: d * m as f64,
                    });
                }
            }
            for mode in modes {
                for ax in [Axis2::X, Axis2::Y] {
                    let a = Action::Place {
                        object: i,
                        mode,
                        grasp_axis: ax,
                        arm: pick_arm(inst, i),
                    };
                    if layout.check(&a).is_ok() && self.reachable(&a, layout) {
                        out.push(a);
                        break; // the grasp axis changes neither state nor cost
                    }
                }
            }
        }
        for dir in [PushDir::MinusX, PushDir::MinusY] {
            let axis = dir.axis();
            let rel: Vec<usize> = (0..inst.n())
                .filter(|&i| matches!(layout.state[i], ObjState::Released { push_dir, .. } if push_dir == dir))
                .collect();
            // All sequences of distinct released objects, kept when consecutive targets touch.
            let mut stack: Vec<Vec<usize>> = rel.iter().map(|&i| vec![i]).collect();
            while let Some(line) = stack.pop() {
                let back = *line.last().unwrap();
                let ObjState::Released { offset, .. } = layout.state[back] else {
                    unreachable!()
                };
                for arm in push_arms(inst, back) {
                    let a = Action::Push {
                        pusher_at: push::centred_pusher(inst, self.placement, &line, dir),
                        objects: line.clone(),
                        push_dir: dir,
                        distance: offset,
                        arm,
                    };
                    if layout.check(&a).is_ok() && self.reachable(&a, layout) {
                        out.push(a);
                    }
                }
                if self.no_multi {
                    continue;
                }
                for &b in &rel {
                    let (tb, tl) = (self.placement.targets[b].rect, self.placement.targets[back].rect);
                    if !line.contains(&b) && (tb.lo(axis) - tl.hi(axis)).abs() <= EPS {
                        let mut l = line.clone();
                        l.push(b);
                        stack.push(l);
                    }
                }
            }
        }
        out
    }

    fn best(&mut self, layout: &Layout, pos: [Vector3<f64>; 2], used: [bool; 2], ext: [f64; 2]) -> Option<Best> {
        if layout.state.iter().all(|s| *s == ObjState::Done) {
            let mut travel = 0.0;
            for k in 0..2 {
                if used[k] {
                    travel += (self.home[k] - pos[k]).norm();
                }
            }
            return Some(Best {
                len: 0,
                area: ext[0] * ext[1],
                travel,
            });
        }
        let mut key: Vec<i64> = layout
            .state
            .iter()
            .map(|s| match s {
                ObjState::Table => 0,
                ObjState::Done => 1,
                ObjState::Released { push_dir, offset, .. } => 2 + *push_dir as i64 + 2 * (offset * 1e6).round() as i64,
            })
            .collect();
        let acts = match self.moves.get(&key) {
            Some(v) => v.clone(),
            None => {
                let v = std::rc::Rc::new(self.actions(layout));
                self.moves.insert(key.clone(), v.clone());
                v
            }
        };
        for k in 0..2 {
            key.extend(pos[k].iter().map(|c| (c * 1e6).round() as i64));
            key.push(used[k] as i64);
        }
        key.extend(ext.iter().map(|c| (c * 1e9).round() as i64));
        if let Some(v) = self.memo.get(&key) {
            return *v;
        }
        let mut result: Option<Best> = None;
        for a in acts.iter() {
            let mut next = layout.clone();
            let mut e = ext;
            if let Action::Place { object, mode, .. } = a {
                let r = layout.release_rect(*object, mode);
                e = [e[0].max(r.x1), e[1].max(r.y1)];
            }
            next.apply(a);
            let k = a.arm().index();
            let (len, end) = path_length(&pos[k], &action_keypoints(self.inst, self.placement, a));
            let mut p = pos;
            p[k] = end;
            let mut u = used;
            u[k] = true;
            if let Some(rest) = self.best(&next, p, u, e) {
                let c = Best {
                    len: rest.len + 1,
                    area: rest.area,
                    travel: rest.travel + len,
                };
                if result.map(|r| better(&c, &r)).unwrap_or(true) {
                    result = Some(c);
                }
            }
        }
        self.memo.insert(key, result);
        result
    }
}

fn exhaustive(inst: &Instance, placement: &Placement, no_direct: bool, no_multi: bool, steps: usize) -> Option<Best> {
    let home = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    let mut e = Enumerate {
        inst,
        placement,
        no_direct,
        no_multi,
        steps,
        home,
        memo: FastMap::default(),
        moves: FastMap::default(),
        reach: Default::default(),
        ik: Default::default(),
    };
    let (mx, my) = placement.extent();
    e.best(&Layout::new(inst, placement), home, [false; 2], [mx, my])
}

/// Fires on its `n`-th query: a stop at a reproducible point of the search.
struct StopAfter {
    n: u64,
    asked: std::cell::Cell<u64>,
}

impl pushpack::control::Terminator for StopAfter {
    fn should_stop(&self) -> bool {
        self.asked.set(self.asked.get() + 1);
        self.asked.get() >= self.n
    }
}

fn verify_result(inst: &Instance, placement: &Placement, r: &pushpack::sequence::SequenceResult, what: &str) {
    let mut po = PlanOptions::from_instance(inst);
    po.placement = PlacementSolver::Bl;
    po.sequencer = Sequencer::Astar;
    // A cross-check of the packing optimum. A*'s action space knows reach but not yet the arms'
    // collisions along joint moves (issue 24: on seed 75 a three-object push would take the
    // left hand through a wall), so this is a packing study. The verifier still replays the
    // trajectories and reports robot issues; they just do not fail a packing study.
    po.packing_only = true;
    let pr = pushpack::placement::PlacementResult {
        placement: placement.clone(),
        status: pushpack::placement::PlacementStatus::Feasible,
        lower_bound: 0.0,
        solver: "bl".into(),
        time_s: 0.0,
        nodes: 0,
        subproblems: 0,
    };
    let plan = build_plan(inst, &po, &pr, r);
    let report = pushpack::verify::verify(inst, &plan);
    assert!(report.is_valid(), "{what}: {report}");
}

/// A search stopped after `n` terminator queries against the optimum `b`.
fn check_stopped(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    settings: &AstarSettings,
    b: &Best,
    n: u64,
    what: &str,
) {
    let stop = StopAfter {
        n,
        asked: std::cell::Cell::new(0),
    };
    match astar::solve(inst, placement, opts, settings, &stop) {
        Err(pushpack::Error::Stopped { .. }) => eprintln!("{what}: stopped without a plan"),
        Err(e) => panic!("{what}: stopped search failed: {e}"),
        Ok(r) => {
            let m = &r.metrics;
            let plan = Best {
                len: m.seq_len,
                area: m.swept_area,
                travel: m.travel,
            };
            assert!(
                !better_by(&plan, b, 1e-6),
                "{what}: stopped plan {plan:?} beats the optimum {b:?}"
            );
            let bound = r.bound.expect("A* reports a bound");
            eprintln!("{what}: {:?}, plan {plan:?}, bound {bound:?}, optimum {b:?}", r.status);
            assert!(bound.len <= b.len, "{what}: bound {bound:?} above the optimum {b:?}");
            assert!(
                bound.area <= b.area + 1e-12,
                "{what}: bound {bound:?} above the optimum {b:?}"
            );
            assert!(
                bound.travel <= b.travel + 1e-6,
                "{what}: bound {bound:?} above the optimum {b:?}"
            );
            if r.status == SearchStatus::Complete {
                assert!(
                    !better_by(b, &plan, 1e-6),
                    "{what}: complete but {plan:?} is worse than {b:?}"
                );
            }
            verify_result(inst, placement, &r, what);
        }
    }
}

/// Objects of the random instance of `seed` (3..=7).
fn objects_of(seed: u64) -> usize {
    3 + (seed as usize % 5)
}

/// The README's test command checks the 60 seeds of 3–5 objects; the 40 seeds of 6 and 7
/// objects take most of the time (the enumeration grows exponentially), so they form the
/// exhaustive tier that `.ci/run` runs after it with `--ignored`. Together: all 100 seeds.
#[test]
fn astar_matches_exhaustive_enumeration_up_to_five_objects() {
    // All 60 had plans when the tiers were split; below 95 % the check has lost its force.
    let checked = check_seeds(|n| n <= 5);
    if checked.is_some_and(|c| c < 57) {
        panic!("only {checked:?} of 60 instances had plans");
    }
}

#[test]
#[ignore = "exhaustive tier (6 and 7 objects, several minutes): .ci/run runs it with --ignored"]
fn astar_matches_exhaustive_enumeration_on_six_and_seven_objects() {
    // All 40 had plans when the tiers were split.
    let checked = check_seeds(|n| n > 5);
    if checked.is_some_and(|c| c < 38) {
        panic!("only {checked:?} of 40 instances had plans");
    }
}

/// Cross-checks A* against enumeration on the seeds whose object count passes `sizes`; returns
/// how many had plans (`None` when `SEEDS` restricts the run, so no count is expected).
fn check_seeds(sizes: impl Fn(usize) -> bool) -> Option<usize> {
    let mut checked = 0;
    // SEEDS=3,8 reruns single seeds while debugging.
    let only: Option<Vec<u64>> = std::env::var("SEEDS")
        .ok()
        .map(|v| v.split(',').map(|x| x.parse().unwrap()).collect());
    for seed in 0..100u64 {
        if only.as_ref().is_some_and(|o| !o.contains(&seed)) || !sizes(objects_of(seed)) {
            continue;
        }
        let n = objects_of(seed);
        let kinds = 1 + (seed as usize % 3);
        let inst = common::parse(&common::random_instance_text_step(
            500 + seed,
            n,
            kinds.min(n),
            "upright",
            5,
        ));
        let placement = bl::solve(&inst, seed, 16, &TimeLimit::new(30.0)).unwrap().placement;
        let (nd, nm) = (seed % 7 == 3, seed % 5 == 4);
        let opts = SequenceOptions {
            no_direct: nd,
            no_multi_push: nm,
            max_nodes: 5_000_000,
            vetoes: Vec::new(),
        };
        // Offsets beyond the line rank: up to 2d on the smaller instances; on six and seven
        // objects only the ranks' offsets (each extra step multiplies the enumerated states).
        let steps = if n <= 5 { 2 } else { 1 };
        let settings = AstarSettings {
            max_offset_steps: steps,
            ..AstarSettings::default()
        };
        let t0 = std::time::Instant::now();
        let expect = exhaustive(&inst, &placement, nd, nm, steps);
        let t1 = std::time::Instant::now();
        let got = astar::solve(&inst, &placement, &opts, &settings, &TimeLimit::new(120.0));
        eprintln!(
            "seed {seed} n={n} exhaustive {:.2}s astar {:.2}s",
            (t1 - t0).as_secs_f64(),
            t1.elapsed().as_secs_f64()
        );
        match (expect, got) {
            // Nothing to find: A* must prove it (a stop would prove nothing).
            (None, Err(pushpack::Error::Infeasible { .. })) => {}
            (Some(b), Ok(r)) => {
                assert_eq!(r.status, SearchStatus::Complete, "seed {seed}");
                let m = r.metrics;
                assert_eq!(m.seq_len, b.len, "seed {seed} (n={n}): actions");
                assert!(
                    (m.swept_area - b.area).abs() < 1e-12,
                    "seed {seed}: area {} vs {}",
                    m.swept_area,
                    b.area
                );
                assert!(
                    (m.travel - b.travel).abs() < 1e-6,
                    "seed {seed}: travel {} vs {}",
                    m.travel,
                    b.travel
                );
                verify_result(&inst, &placement, &r, &format!("seed {seed}"));
                // Stopped in the dive, in phase 1 and in the main search, on different seeds.
                let n_stop = [2, 20, 200, 2000][seed as usize % 4];
                check_stopped(
                    &inst,
                    &placement,
                    &opts,
                    &settings,
                    &b,
                    n_stop,
                    &format!("seed {seed} stopped at {n_stop}"),
                );
                checked += 1;
            }
            (e, g) => panic!("seed {seed}: exhaustive {e:?} vs A* {:?}", g.map(|r| r.metrics)),
        }
    }
    eprintln!("{checked} instances had plans");
    only.is_none().then_some(checked)
}

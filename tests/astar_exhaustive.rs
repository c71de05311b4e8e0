//! The A* sequencer against an exhaustive enumeration of assignments and orders.
//!
//! The enumeration is written here, independent of the search: from each state it tries every
//! action of the action space — every object on the table placed directly or indirectly in
//! either direction at every allowed offset, every line of released objects (front to back,
//! targets touching along the push direction) — keeps those the layout accepts, and recurses.
//! It memoises the best completion per (object states, arm positions, swept extents so far):
//! the future depends on nothing else, so this is Bellman's principle, not pruning. The best
//! lexicographic (actions, swept area, travel) over all complete plans is compared with A* on
//! all three components, and every A* plan goes through the verifier.

mod common;

use nalgebra::Vector3;
use pushpack::actions::{push, Action, Layout, ObjState, PlaceMode};
use pushpack::control::TimeLimit;
use pushpack::geometry::{Axis2, PushDir, EPS};
use pushpack::instance::Instance;
use pushpack::placement::{bl, Placement};
use pushpack::plan::{build_plan, PlacementSolver, PlanOptions, Sequencer};
use pushpack::robot::keypoints::{action_keypoints, path_length, pick_arm};
use pushpack::robot::motion::{action_reach_memo, IkMemo, Reach};
use pushpack::robot::Arm;
use pushpack::sequence::astar::{self, AstarSettings};
use pushpack::sequence::{SearchStatus, SequenceOptions};
use std::collections::HashMap;

const STEPS: usize = 2;

#[derive(Clone, Copy, Debug)]
struct Best {
    len: usize,
    area: f64,
    travel: f64,
}

fn better(a: &Best, b: &Best) -> bool {
    if a.len != b.len {
        return a.len < b.len;
    }
    if (a.area - b.area).abs() > 1e-12 {
        return a.area < b.area;
    }
    a.travel < b.travel - 1e-9
}

struct Enumerate<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    no_direct: bool,
    no_multi: bool,
    home: [Vector3<f64>; 2],
    memo: HashMap<Vec<i64>, Option<Best>>,
    reach: std::cell::RefCell<HashMap<String, Option<Reach>>>,
    ik: std::cell::RefCell<IkMemo>,
}

impl Enumerate<'_> {
    /// Reachability by inverse kinematics (memoised: it does not depend on the state), then
    /// the objects still on the table that block the pick.
    fn reachable(&self, a: &Action, layout: &Layout) -> bool {
        let k = format!("{a:?}");
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
                for m in 1..=STEPS {
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
                let a = Action::Push {
                    pusher_at: push::centred_pusher(inst, self.placement, &line, dir),
                    objects: line.clone(),
                    push_dir: dir,
                    distance: offset,
                    arm: pick_arm(inst, back),
                };
                if layout.check(&a).is_ok() && self.reachable(&a, layout) {
                    out.push(a);
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
        for k in 0..2 {
            key.extend(pos[k].iter().map(|c| (c * 1e6).round() as i64));
            key.push(used[k] as i64);
        }
        key.extend(ext.iter().map(|c| (c * 1e9).round() as i64));
        if let Some(v) = self.memo.get(&key) {
            return *v;
        }
        let mut result: Option<Best> = None;
        for a in self.actions(layout) {
            let mut next = layout.clone();
            let mut e = ext;
            if let Action::Place { object, mode, .. } = &a {
                let r = layout.release_rect(*object, mode);
                e = [e[0].max(r.x1), e[1].max(r.y1)];
            }
            next.apply(&a);
            let k = a.arm().index();
            let (len, end) = path_length(&pos[k], &action_keypoints(self.inst, self.placement, &a));
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

fn exhaustive(inst: &Instance, placement: &Placement, no_direct: bool, no_multi: bool) -> Option<Best> {
    let home = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    let mut e = Enumerate {
        inst,
        placement,
        no_direct,
        no_multi,
        home,
        memo: HashMap::new(),
        reach: Default::default(),
        ik: Default::default(),
    };
    let (mx, my) = placement.extent();
    e.best(&Layout::new(inst, placement), home, [false; 2], [mx, my])
}

#[test]
fn astar_matches_exhaustive_enumeration() {
    let mut checked = 0;
    for seed in 0..100u64 {
        let n = 3 + (seed as usize % 5); // 3..=7 objects
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
        };
        let settings = AstarSettings {
            max_offset_steps: STEPS,
            ..AstarSettings::default()
        };
        let expect = exhaustive(&inst, &placement, nd, nm);
        let got = astar::solve(&inst, &placement, &opts, &settings, &TimeLimit::new(120.0));
        match (expect, got) {
            (None, Err(_)) => {}
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
                let mut po = PlanOptions::from_instance(&inst);
                po.placement = PlacementSolver::Bl;
                po.sequencer = Sequencer::Astar;
                let pr = pushpack::placement::PlacementResult {
                    placement: placement.clone(),
                    status: pushpack::placement::PlacementStatus::Feasible,
                    lower_bound: 0.0,
                    solver: "bl".into(),
                    time_s: 0.0,
                    nodes: 0,
                    subproblems: 0,
                };
                let plan = build_plan(&inst, &po, &pr, &r);
                let report = pushpack::verify::verify(&inst, &plan);
                assert!(report.is_valid(), "seed {seed}: {report}");
                checked += 1;
            }
            (e, g) => panic!("seed {seed}: exhaustive {e:?} vs A* {:?}", g.map(|r| r.metrics)),
        }
    }
    assert!(checked >= 90, "only {checked} instances had plans");
}

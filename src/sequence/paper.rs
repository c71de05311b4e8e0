//! The paper's sequencer: Algorithm 1 (packing-action assignment) + Algorithm 2 (depth-first
//! branch-and-bound over action orders, minimising gripper travel).
//!
//! Algorithm 1 enumerates, for every object, direct placing or indirect placing with a row (−x)
//! or column (−y) push. Indirect objects with the same direction whose targets touch along it
//! form lines; a line is pushed in one action when the push is stable (the analytic condition of
//! [`crate::actions::push`]), else it is split greedily from the front. Every assignment with a
//! multi-object line also yields its all-single-push variant, so forbidding multi-object pushes
//! can never shorten the best plan. Released objects of a line either touch (*stacked*, all at
//! offset `d`) or leave a gap `d` for the fingers between them (*staggered*, offsets `d, 2d, …`).
//! Candidates are tried in lexicographic order of (sequence length, swept area); Algorithm 2
//! orders the actions of each candidate of the first (length, area) group that admits a
//! feasible order, keeping the least travel.
//!
//! Algorithm 2 is the paper's depth-first search with cost-so-far pruning, children visited
//! nearest-first, plus one exact addition so that it terminates on eight objects: a
//! transposition table on (actions done, last action of each arm), the whole state that future
//! feasibility and cost depend on, pruning a node reached again at no lower cost.

use super::{metrics, SearchStatus, SequenceOptions, SequenceResult};
use crate::actions::{push, Action, Layout, PlaceMode};
use crate::control::{Event, Listener, Silent, Stage, Terminator, Ticker};
use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::geometry::{PushDir, EPS};
use crate::instance::Instance;
use crate::motion::keypoints::{action_keypoints, path_length, pick_arm, push_arms};
use crate::placement::Placement;
use nalgebra::Vector3;
use std::collections::HashMap;
use std::time::Instant;

/// A packing-action candidate: every object's placing mode and the pushes, unordered.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Places: object and mode.
    pub places: Vec<(usize, PlaceMode)>,
    /// Pushes: line (front to back), direction, distance, pusher lateral position.
    pub pushes: Vec<(Vec<usize>, PushDir, f64, f64)>,
    /// Number of actions.
    pub seq_len: usize,
    /// Swept area (m²).
    pub area: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Choice {
    Direct,
    Indirect(PushDir),
}

/// Chains of indirect objects with direction `dir`, front to back.
fn chains(placement: &Placement, members: &[usize], dir: PushDir) -> Vec<Vec<usize>> {
    let axis = dir.axis();
    let lat = axis.other();
    let t = |i: usize| placement.targets[i].rect;
    // succ[a] = the member directly behind a with the largest lateral overlap.
    let mut succ: HashMap<usize, (usize, f64)> = HashMap::new();
    for &a in members {
        for &b in members {
            if a == b {
                continue;
            }
            let ov = t(a).overlap_on(&t(b), lat);
            if (t(b).lo(axis) - t(a).hi(axis)).abs() <= EPS && ov > EPS {
                let better = succ.get(&a).map(|&(_, o)| ov > o + EPS).unwrap_or(true);
                if better {
                    succ.insert(a, (b, ov));
                }
            }
        }
    }
    // Keep, for each b, only its best predecessor.
    let mut pred: HashMap<usize, (usize, f64)> = HashMap::new();
    let mut keys: Vec<usize> = succ.keys().copied().collect();
    keys.sort();
    for a in keys {
        let (b, ov) = succ[&a];
        let better = pred.get(&b).map(|&(_, o)| ov > o + EPS).unwrap_or(true);
        if better {
            pred.insert(b, (a, ov));
        }
    }
    let next: HashMap<usize, usize> = pred.iter().map(|(&b, &(a, _))| (a, b)).collect();
    let mut out = Vec::new();
    let mut heads: Vec<usize> = members.iter().copied().filter(|m| !pred.contains_key(m)).collect();
    heads.sort();
    for h in heads {
        let mut line = vec![h];
        let mut cur = h;
        while let Some(&n) = next.get(&cur) {
            line.push(n);
            cur = n;
        }
        out.push(line);
    }
    out
}

/// Split a chain into lines that are stable when pushed, greedily from the front.
fn split_stable(
    inst: &Instance,
    placement: &Placement,
    chain: &[usize],
    dir: PushDir,
    staggered: bool,
) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < chain.len() {
        let mut end = start + 1;
        while end < chain.len() {
            let line = &chain[start..=end];
            let at = push::centred_pusher(inst, placement, line, dir);
            // The gaps `build` releases the line with: one `d` between staggered objects.
            let gap = if staggered { inst.gripper.min_offset } else { 0.0 };
            let gaps = vec![gap; line.len() - 1];
            if push::line_verdict(inst, placement, line, dir, at, &gaps).accepted(inst.settings.min_push_margin) {
                end += 1;
            } else {
                break;
            }
        }
        out.push(chain[start..end].to_vec());
        start = end;
    }
    out
}

/// Build the candidate for given lines (per direction) and direct objects.
fn build(
    inst: &Instance,
    placement: &Placement,
    direct: &[usize],
    lines: &[(Vec<usize>, PushDir, bool)],
) -> Option<Candidate> {
    let d = inst.gripper.min_offset;
    let floor = inst.container.floor();
    let mut places: Vec<(usize, PlaceMode)> = direct.iter().map(|&i| (i, PlaceMode::Direct)).collect();
    let mut pushes = Vec::new();
    let (mut mx, mut my) = placement.extent();
    for (line, dir, staggered) in lines {
        let mut dist = d;
        for (m, &i) in line.iter().enumerate() {
            let offset = if *staggered { d * (m as f64 + 1.0) } else { d };
            let r = placement.targets[i].rect.moved(*dir, -offset);
            if !r.inside(&floor) {
                return None;
            }
            mx = mx.max(r.x1);
            my = my.max(r.y1);
            places.push((i, PlaceMode::Indirect { push_dir: *dir, offset }));
            dist = offset;
        }
        let at = push::centred_pusher(inst, placement, line, *dir);
        pushes.push((line.clone(), *dir, dist, at));
    }
    places.sort_by_key(|p| p.0);
    let seq_len = places.len() + pushes.len();
    Some(Candidate {
        places,
        pushes,
        seq_len,
        area: mx * my,
    })
}

impl Candidate {
    /// Exact identity of a candidate (bit patterns of its lengths), for duplicate detection.
    fn key(&self) -> Vec<u64> {
        let mut k = Vec::with_capacity(3 * self.places.len() + 4 * self.pushes.len() + 2);
        for (i, mode) in &self.places {
            k.push(*i as u64);
            match mode {
                PlaceMode::Direct => k.extend([0, 0]),
                PlaceMode::Indirect { push_dir, offset } => {
                    k.extend([1 + *push_dir as u64, offset.to_bits()]);
                }
            }
        }
        k.push(u64::MAX);
        for (line, dir, dist, at) in &self.pushes {
            k.extend(line.iter().map(|&i| i as u64));
            k.extend([u64::MAX - 1 - *dir as u64, dist.to_bits(), at.to_bits()]);
        }
        k
    }
}

/// Why Algorithm 1 stopped before it had every candidate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CandidatesStop {
    /// The terminator fired.
    Time,
    /// There are more candidates than the cap allows to keep.
    Candidates,
}

/// Most candidates Algorithm 1 keeps. They are all held in memory at once: at the cap a
/// 16-object run peaks at 2.7 GB (about 1.3 kB per candidate), and without a cap one filled
/// 22 GB within a minute and was killed. Up to 12 objects the whole space fits (at most
/// `3 · 3^12` ≈ 1.6 million candidates).
pub const MAX_CANDIDATES: usize = 2_000_000;

/// Algorithm 1: every candidate of the assignment space (`3^N` assignments: minutes at ten
/// objects), or why it stopped first: the clock, or more than `max_candidates` candidates
/// ([`solve`] passes [`MAX_CANDIDATES`]).
pub fn candidates(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    max_candidates: usize,
    stop: &dyn Terminator,
) -> std::result::Result<Vec<Candidate>, CandidatesStop> {
    candidates_with(inst, placement, opts, max_candidates, stop, &mut |_| {})
}

/// [`candidates`], calling `examined` with the number of assignments examined so far every
/// 256 assignments (Algorithm 1 alone can take seconds: the live display needs a pulse).
fn candidates_with(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    max_candidates: usize,
    stop: &dyn Terminator,
    examined: &mut dyn FnMut(u64),
) -> std::result::Result<Vec<Candidate>, CandidatesStop> {
    let n = inst.n();
    let mut choices = Vec::new();
    if !opts.no_direct {
        choices.push(Choice::Direct);
    }
    choices.push(Choice::Indirect(PushDir::MinusX));
    choices.push(Choice::Indirect(PushDir::MinusY));
    let floor = inst.container.floor();
    let d = inst.gripper.min_offset;
    // Per object, the choices that can possibly work (release at offset d inside the floor).
    let options: Vec<Vec<Choice>> = (0..n)
        .map(|i| {
            choices
                .iter()
                .copied()
                .filter(|c| match c {
                    Choice::Direct => true,
                    Choice::Indirect(dir) => placement.targets[i].rect.moved(*dir, -d).inside(&floor),
                })
                .collect()
        })
        .collect();
    let mut out = Vec::new();
    let mut seen = Seen::default();
    let mut idx = vec![0usize; n];
    if options.iter().any(|o| o.is_empty()) {
        return Ok(out);
    }
    let mut count = 0u64;
    loop {
        count += 1;
        if count % 256 == 0 {
            examined(count);
            if stop.should_stop() {
                return Err(CandidatesStop::Time);
            }
        }
        let assign: Vec<Choice> = (0..n).map(|i| options[i][idx[i]]).collect();
        let direct: Vec<usize> = (0..n).filter(|&i| assign[i] == Choice::Direct).collect();
        // Lines per direction, in two variants: greedy stable multi-pushes, and all singles.
        let mut multi: Vec<(Vec<usize>, PushDir, bool)> = Vec::new();
        let mut multi_st: Vec<(Vec<usize>, PushDir, bool)> = Vec::new();
        let mut singles: Vec<(Vec<usize>, PushDir, bool)> = Vec::new();
        for dir in PushDir::ALL {
            let members: Vec<usize> = (0..n).filter(|&i| assign[i] == Choice::Indirect(dir)).collect();
            for &m in &members {
                singles.push((vec![m], dir, false));
            }
            if !opts.no_multi_push {
                for chain in chains(placement, &members, dir) {
                    for line in split_stable(inst, placement, &chain, dir, false) {
                        multi.push((line, dir, false));
                    }
                    for line in split_stable(inst, placement, &chain, dir, true) {
                        multi_st.push((line, dir, true));
                    }
                }
            }
        }
        let mut variants = vec![singles];
        if !opts.no_multi_push {
            variants.push(multi);
            variants.push(multi_st);
        }
        for v in &variants {
            if let Some(c) = build(inst, placement, &direct, v) {
                // Hashed, not `out.contains`: the linear scan made Algorithm 1 quadratic in the
                // number of candidates (minutes at ten objects).
                if seen.insert(&c, &out) {
                    if out.len() >= max_candidates {
                        return Err(CandidatesStop::Candidates);
                    }
                    out.push(c);
                }
            }
        }
        // Next assignment (mixed-radix counter).
        let mut k = 0;
        loop {
            if k == n {
                return Ok(out);
            }
            idx[k] += 1;
            if idx[k] < options[k].len() {
                break;
            }
            idx[k] = 0;
            k += 1;
        }
    }
}

/// Exact duplicate detection over the kept candidates without a copy of each key: a 64-bit hash
/// of the key maps to the first kept candidate with that hash, compared to the new one in full,
/// and only the rare different candidates sharing a hash keep their full keys. Keeping
/// every key instead cost about a third of Algorithm 1's memory.
#[derive(Default)]
struct Seen {
    first: HashMap<u64, usize>,
    collided: std::collections::HashSet<Vec<u64>>,
}

impl Seen {
    /// True when `c` is new; it is then recorded as the candidate `out.len()`, the index it gets
    /// when pushed.
    fn insert(&mut self, c: &Candidate, out: &[Candidate]) -> bool {
        use std::hash::{Hash, Hasher};
        let key = c.key();
        let mut h = std::collections::hash_map::DefaultHasher::new();
        key.hash(&mut h);
        match self.first.entry(h.finish()) {
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(out.len());
                true
            }
            std::collections::hash_map::Entry::Occupied(e) => out[*e.get()] != *c && self.collided.insert(key),
        }
    }
}

/// Concrete action of a candidate's item, with a grasp axis chosen for the current layout.
#[derive(Debug, Clone)]
enum Item {
    Place(usize, PlaceMode, Arm),
    Push(Action),
}

struct Dfs<'a> {
    reach: &'a crate::motion::reach_cache::ReachCache<'a>,
    inst: &'a Instance,
    placement: &'a Placement,
    items: Vec<Item>,
    home: [Vector3<f64>; 2],
    best_cost: f64,
    best: Option<(Vec<Action>, Vec<Option<f64>>)>,
    nodes: u64,
    max_nodes: u64,
    stopped: Option<SearchStatus>,
    memo: HashMap<(u128, [u8; 2]), f64>,
    stop: &'a dyn Terminator,
    progress: Progress<'a>,
}

/// What Algorithm 2 tells a listener while it orders actions ([`solve_with`]).
struct Progress<'a> {
    listener: &'a mut dyn Listener,
    ticker: Ticker,
    /// Assignments of Algorithm 1 plus the nodes of the candidates already ordered.
    nodes_before: u64,
    /// Number of actions of the best order so far.
    incumbent: Option<usize>,
}

impl Progress<'_> {
    fn tick(&mut self, nodes: u64) {
        if self.ticker.due() {
            self.listener.event(&Event::Progress {
                stage: Stage::Sequence,
                nodes: self.nodes_before + nodes,
                incumbent: self.incumbent.map(|l| l as f64),
                bound: None,
            });
        }
    }
}

const NO_ACTION: u8 = u8::MAX;

impl<'a> Dfs<'a> {
    fn concrete(&self, layout: &Layout, item: &Item) -> Option<(Action, Option<f64>)> {
        match item {
            Item::Place(object, mode, arm) => {
                let axes = match mode {
                    PlaceMode::Indirect { push_dir, .. } => [push_dir.axis(), push_dir.axis().other()],
                    PlaceMode::Direct => [crate::geometry::Axis2::X, crate::geometry::Axis2::Y],
                };
                axes.into_iter().find_map(|ax| {
                    let a = Action::Place {
                        object: *object,
                        mode: *mode,
                        grasp_axis: ax,
                        arm: *arm,
                    };
                    layout
                        .check(&a)
                        .ok()
                        .filter(|_| self.reach.ok_in(&a, layout))
                        .map(|m| (a, m))
                })
            }
            Item::Push(a) => layout
                .check(a)
                .ok()
                .filter(|_| self.reach.ok(a))
                .map(|m| (a.clone(), m)),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn rec(
        &mut self,
        layout: &Layout,
        done: u128,
        pos: [Vector3<f64>; 2],
        last: [u8; 2],
        cost: f64,
        seq: &mut Vec<Action>,
        margins: &mut Vec<Option<f64>>,
    ) {
        if self.stopped.is_some() {
            return;
        }
        self.nodes += 1;
        self.progress.tick(self.nodes);
        if self.nodes >= self.max_nodes {
            self.stopped = Some(SearchStatus::NodeLimit);
            return;
        }
        if self.nodes % 1024 == 0 && self.stop.should_stop() {
            self.stopped = Some(SearchStatus::TimeLimit);
            return;
        }
        if cost >= self.best_cost - 1e-12 {
            return;
        }
        let n = self.items.len();
        if done.count_ones() as usize == n {
            let mut total = cost;
            for k in 0..2 {
                if last[k] != NO_ACTION {
                    total += (self.home[k] - pos[k]).norm();
                }
            }
            if total < self.best_cost - 1e-12 {
                self.best_cost = total;
                self.best = Some((seq.clone(), margins.clone()));
                self.progress.incumbent = Some(seq.len());
            }
            return;
        }
        let key = (done, last);
        if let Some(&c) = self.memo.get(&key) {
            if c <= cost + 1e-12 {
                return;
            }
        }
        self.memo.insert(key, cost);
        let mut children = Vec::new();
        for i in 0..n {
            if done & (1u128 << i) != 0 {
                continue;
            }
            if let Some((a, m)) = self.concrete(layout, &self.items[i]) {
                let k = a.arm().index();
                let (len, end) = path_length(&pos[k], &action_keypoints(self.inst, self.placement, &a));
                children.push((len, i, a, m, end));
            }
        }
        children.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        for (len, i, a, m, end) in children {
            let k = a.arm().index();
            let mut next = layout.clone();
            next.apply(&a);
            let mut npos = pos;
            npos[k] = end;
            let mut nlast = last;
            nlast[k] = i as u8;
            seq.push(a);
            margins.push(m);
            self.rec(&next, done | (1u128 << i), npos, nlast, cost + len, seq, margins);
            seq.pop();
            margins.pop();
        }
    }
}

/// Run Algorithms 1 and 2.
pub fn solve(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    stop: &dyn Terminator,
) -> Result<SequenceResult> {
    solve_with(inst, placement, opts, stop, &mut Silent)
}

/// [`solve`], telling `listener` how it goes, at most every
/// [`crate::control::PROGRESS_INTERVAL`] ([`Event::Progress`]): `nodes` counts Algorithm 1's
/// assignments examined, then adds Algorithm 2's depth-first nodes over every candidate, so it
/// only grows; `incumbent` is the best order's number of actions; `bound` is always `None`: the
/// sequencer proves none.
pub fn solve_with(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    stop: &dyn Terminator,
    listener: &mut dyn Listener,
) -> Result<SequenceResult> {
    let start = Instant::now();
    let mut incumbent = None;
    let mut ticker = Ticker::new();
    let stage = "sequence (paper, Algorithm 1)";
    let mut assignments = 0;
    let mut pulse = |count: u64| {
        assignments = count;
        if ticker.due() {
            listener.event(&Event::Progress {
                stage: Stage::Sequence,
                nodes: count,
                incumbent: None,
                bound: None,
            });
        }
    };
    let cands = candidates_with(inst, placement, opts, MAX_CANDIDATES, stop, &mut pulse);
    let mut cands = cands.map_err(|why| match why {
        CandidatesStop::Time => SearchStatus::TimeLimit.no_plan(stage, 0, start.elapsed().as_secs_f64(), None),
        CandidatesStop::Candidates => Error::Stopped {
            stage: stage.into(),
            limit: crate::status::Limit::Candidates,
            nodes: 0,
            elapsed_s: start.elapsed().as_secs_f64(),
            min_actions: None,
        },
    })?;
    if cands.is_empty() {
        return Err(Error::Infeasible {
            reason: "no packing-action assignment keeps every release inside the container".into(),
        });
    }
    cands.sort_by(|a, b| a.seq_len.cmp(&b.seq_len).then(a.area.total_cmp(&b.area)));
    let home = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    let reach = crate::motion::reach_cache::ReachCache::new(inst, placement);
    let mut nodes = 0u64;
    let mut evaluated = 0u64;
    let mut status = SearchStatus::Complete;
    let mut g = 0;
    while g < cands.len() {
        let mut h = g;
        while h < cands.len() && cands[h].seq_len == cands[g].seq_len && (cands[h].area - cands[g].area).abs() <= 1e-12
        {
            h += 1;
        }
        let mut best: Option<(f64, Vec<Action>, Vec<Option<f64>>)> = None;
        for c in &cands[g..h] {
            if c.places.len() + c.pushes.len() > 128 {
                return Err(Error::Infeasible {
                    reason: "the paper sequencer handles at most 128 actions".into(),
                });
            }
            evaluated += 1;
            let mut items: Vec<Item> = c
                .places
                .iter()
                .map(|&(i, m)| Item::Place(i, m, pick_arm(inst, i)))
                .collect();
            for (line, dir, dist, at) in &c.pushes {
                let mk = |arm| Action::Push {
                    objects: line.clone(),
                    push_dir: *dir,
                    distance: *dist,
                    pusher_at: *at,
                    arm,
                };
                // The paper fixes one arm per action: the picking arm, or the other one when
                // only it reaches the push (a push's reach does not depend on the state, so the
                // choice is the same in every order).
                let arms = push_arms(inst, *line.last().expect("non-empty line"));
                let arm = arms.iter().copied().find(|&arm| reach.ok(&mk(arm))).unwrap_or(arms[0]);
                items.push(Item::Push(mk(arm)));
            }
            let mut dfs = Dfs {
                reach: &reach,
                inst,
                placement,
                items,
                home,
                best_cost: best.as_ref().map(|b| b.0).unwrap_or(f64::INFINITY),
                best: None,
                nodes: 0,
                max_nodes: opts.max_nodes.saturating_sub(nodes).max(1),
                stopped: None,
                memo: HashMap::new(),
                stop,
                progress: Progress {
                    listener: &mut *listener,
                    ticker,
                    nodes_before: assignments + nodes,
                    incumbent,
                },
            };
            let mut layout = Layout::new(inst, placement);
            layout.vetoes = opts.layout_vetoes();
            dfs.rec(&layout, 0, home, [NO_ACTION; 2], 0.0, &mut Vec::new(), &mut Vec::new());
            nodes += dfs.nodes;
            (ticker, incumbent) = (dfs.progress.ticker, dfs.progress.incumbent);
            if let Some((seq, margins)) = dfs.best {
                best = Some((dfs.best_cost, seq, margins));
            }
            if let Some(s) = dfs.stopped {
                status = s;
                break;
            }
        }
        if let Some((_, actions, margins)) = best {
            let m = metrics(inst, placement, &actions);
            return Ok(SequenceResult {
                actions,
                margins,
                metrics: m,
                status,
                nodes,
                assignments: evaluated,
                time_s: start.elapsed().as_secs_f64(),
                bound: None,
            });
        }
        if status != SearchStatus::Complete {
            return Err(status.no_plan("sequence (paper)", nodes, start.elapsed().as_secs_f64(), None));
        }
        g = h;
    }
    Err(Error::Infeasible {
        reason: "no candidate assignment admits a feasible action order".into(),
    })
}

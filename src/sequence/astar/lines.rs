//! Push lines: objects whose targets touch along a push direction, and which can be released.

use super::*;

/// Remaining-pushes bound of a state from which no plan exists: far above any budget, and small
/// enough that sums of costs never overflow.
pub(super) const DEAD_END: usize = 1 << 20;

/// Most lines, and gap patterns over all lines, [`push_lines`] lists before giving up (the
/// static checks cost one layout check per pattern and object).
pub(super) const MAX_LINE_PATTERNS: usize = 4096;

/// A line a push could move, with what can stop it for good.
pub(super) struct PushLine {
    /// Index of the push direction in [`PushDir::ALL`].
    pub(super) dir: usize,
    /// Members (bit per object).
    pub(super) members: u64,
    /// Members front to back.
    pub(super) order: Vec<usize>,
    /// Per gap pattern that passes the push check with nothing else in the container: the
    /// objects whose targets, once done, make that pattern fail (empty when no pattern passes
    /// the line is left out).
    pub(super) blockers: Vec<u64>,
}

/// Every line of the placement that some push could move, with the objects that block each of
/// its feasible gap patterns once at their targets; `None` when there are too many to list.
///
/// A line's push check (walls, pusher, swept space, stability) depends on the rest of the
/// container only through obstacles, and only its gap pattern (which consecutive members start
/// apart) changes the stability phases. Each pattern is checked at its smallest offsets (the
/// front at `d`, one `d` more at every gap): larger offsets of the same pattern sweep a superset
/// of the space (release to target, pusher start to end), so an object that blocks the
/// smallest offsets blocks every offset of the pattern. Released objects elsewhere only block
/// for a while and are ignored: the result is a relaxation, as a bound needs.
pub(super) fn push_lines(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    info: &[ObjectInfo],
    steps: &[[usize; 2]],
) -> Option<Vec<PushLine>> {
    let n = inst.n();
    if n > 64 {
        return None;
    }
    let all: Vec<usize> = (0..n).collect();
    let max_len = if opts.no_multi_push { 1 } else { usize::MAX };
    let mut per_dir = Vec::new();
    let mut patterns = 0usize;
    for (k, dir) in PushDir::ALL.into_iter().enumerate() {
        for line in lines(placement, &all, dir, max_len) {
            if line.iter().any(|&i| !info[i].push_dir_ok[k]) {
                continue;
            }
            if line.len() > 13 {
                return None;
            }
            patterns += 1 << (line.len() - 1);
            if patterns > MAX_LINE_PATTERNS {
                return None;
            }
            per_dir.push((k, dir, line));
        }
    }
    let mut out = Vec::new();
    let mut budget = MAX_RELEASE_CHECKS;
    let budget = &mut budget;
    for (k, dir, line) in per_dir {
        let members = line.iter().fold(0u64, |m, &i| m | 1 << i);
        let back = *line.last().expect("non-empty");
        let pusher_at = push::centred_pusher(inst, placement, &line, dir);
        let arm = push_arms(inst, back)[0];
        let mut blockers = Vec::new();
        for gaps in 0u64..1 << (line.len() - 1) {
            // Smallest offsets of the pattern, in steps of `d`.
            let mut smallest = Vec::with_capacity(line.len());
            for t in 0..line.len() {
                smallest.push(if t == 0 {
                    1
                } else {
                    smallest[t - 1] + (gaps >> (t - 1) & 1) as usize
                });
            }
            if line.iter().zip(&smallest).any(|(&i, &m)| m > steps[i][k]) {
                continue;
            }
            let (layout, a) = released_line(inst, placement, &line, dir, &smallest, pusher_at, arm);
            if layout.check(&a).is_err() {
                continue;
            }
            // Some offsets of the pattern must also let the members be put down, in some
            // order, and pushed (the finger slabs of touching releases collide, so touching
            // patterns often cannot be released at all). Past the work budget a pattern is
            // kept unchecked, which only weakens the bound.
            let mut offsets = smallest.clone();
            if *budget > 0 {
                let found = any_offsets(
                    inst,
                    placement,
                    &line,
                    k,
                    gaps,
                    steps,
                    &mut offsets,
                    0,
                    pusher_at,
                    arm,
                    budget,
                );
                // `false` with the budget spent means "not known": keep the pattern.
                if !found && *budget > 0 {
                    continue;
                }
            }
            let mut layout = layout;
            let mut b = 0u64;
            for j in (0..n).filter(|j| members >> j & 1 == 0) {
                layout.state[j] = ObjState::Done;
                if layout.check(&a).is_err() {
                    b |= 1 << j;
                }
                layout.state[j] = ObjState::Table;
            }
            blockers.push(b);
        }
        if !blockers.is_empty() {
            // A pattern blocked by a superset of another's blockers adds nothing.
            blockers.sort_by_key(|b| b.count_ones());
            let mut kept: Vec<u64> = Vec::new();
            for b in blockers {
                if !kept.iter().any(|&c| c & !b == 0) {
                    kept.push(b);
                }
            }
            out.push(PushLine {
                dir: k,
                order: line,
                members,
                blockers: kept,
            });
        }
    }
    Some(out)
}

/// Layout checks [`push_lines`] may spend on whether lines can be released.
pub(super) const MAX_RELEASE_CHECKS: usize = 200_000;

/// A layout with the members of `line` released at `offsets` (steps of `d`) and nothing else in
/// the container, and the push of the line.
pub(super) fn released_line<'a>(
    inst: &'a Instance,
    placement: &'a Placement,
    line: &[usize],
    dir: PushDir,
    offsets: &[usize],
    pusher_at: f64,
    arm: Arm,
) -> (Layout<'a>, Action) {
    let d = inst.gripper.min_offset;
    let layout = with_released(inst, placement, line.iter().copied().zip(offsets.iter().copied()), dir);
    let a = Action::Push {
        objects: line.to_vec(),
        push_dir: dir,
        distance: d * *offsets.last().expect("non-empty") as f64,
        pusher_at,
        arm,
    };
    (layout, a)
}

/// A layout with `(object, offset steps)` released for a push along `dir`, nothing else in
/// the container.
pub(super) fn with_released<'a>(
    inst: &'a Instance,
    placement: &'a Placement,
    released: impl Iterator<Item = (usize, usize)>,
    dir: PushDir,
) -> Layout<'a> {
    let mut layout = Layout::new(inst, placement);
    // The blockers found here are single objects taken for good: only a monotone side rule
    // keeps them a relaxation.
    layout.assume_held = true;
    for (i, m) in released {
        let offset = inst.gripper.min_offset * m as f64;
        let mode = PlaceMode::Indirect { push_dir: dir, offset };
        layout.state[i] = ObjState::Released {
            rect: layout.release_rect(i, &mode),
            push_dir: dir,
            offset,
        };
    }
    layout
}

/// Whether some offsets of gap pattern `gaps` (within each member's step limit), filled in from
/// position `t` on, let the line's members be released in some order and then pushed, with
/// nothing else in the container. Spends `budget` layout checks; `false` with the budget at
/// zero means "not known".
#[allow(clippy::too_many_arguments)]
pub(super) fn any_offsets(
    inst: &Instance,
    placement: &Placement,
    line: &[usize],
    k: usize,
    gaps: u64,
    steps: &[[usize; 2]],
    offsets: &mut Vec<usize>,
    t: usize,
    pusher_at: f64,
    arm: Arm,
    budget: &mut usize,
) -> bool {
    if *budget == 0 {
        return false;
    }
    if t == line.len() {
        let dir = PushDir::ALL[k];
        let (layout, a) = released_line(inst, placement, line, dir, offsets, pusher_at, arm);
        *budget = budget.saturating_sub(1);
        if layout.check(&a).is_err() {
            return false;
        }
        let mut failed = vec![false; 1 << line.len()];
        return releasable(inst, placement, line, dir, offsets, 0, &mut failed, budget);
    }
    let lo = if t == 0 {
        1
    } else {
        offsets[t - 1] + (gaps >> (t - 1) & 1) as usize
    };
    // Without a gap the offset repeats the one in front; with one, any larger offset will do.
    let hi = if t > 0 && gaps >> (t - 1) & 1 == 0 {
        lo
    } else {
        steps[line[t]][k]
    };
    for m in lo..=hi.min(steps[line[t]][k]) {
        offsets[t] = m;
        if any_offsets(
            inst,
            placement,
            line,
            k,
            gaps,
            steps,
            offsets,
            t + 1,
            pusher_at,
            arm,
            budget,
        ) {
            return true;
        }
        if *budget == 0 {
            return false;
        }
    }
    false
}

/// Whether the members of `line` not in `placed` (bit per position) can be released at
/// `offsets` in some order after those in `placed`, with nothing else in the container.
#[allow(clippy::too_many_arguments)]
pub(super) fn releasable(
    inst: &Instance,
    placement: &Placement,
    line: &[usize],
    dir: PushDir,
    offsets: &[usize],
    placed: usize,
    failed: &mut [bool],
    budget: &mut usize,
) -> bool {
    if placed == (1 << line.len()) - 1 {
        return true;
    }
    if failed[placed] || *budget == 0 {
        return false;
    }
    let d = inst.gripper.min_offset;
    let here = line
        .iter()
        .zip(offsets)
        .enumerate()
        .filter(|(t, _)| placed >> t & 1 == 1)
        .map(|(_, (&i, &m))| (i, m));
    let layout = with_released(inst, placement, here, dir);
    for (t, (&i, &m)) in line.iter().zip(offsets).enumerate() {
        if placed >> t & 1 == 1 {
            continue;
        }
        let mode = PlaceMode::Indirect {
            push_dir: dir,
            offset: d * m as f64,
        };
        let ok = [Axis2::X, Axis2::Y].into_iter().any(|ax| {
            *budget = budget.saturating_sub(1);
            layout
                .check(&Action::Place {
                    object: i,
                    mode,
                    grasp_axis: ax,
                    arm: pick_arm(inst, i),
                })
                .is_ok()
        });
        if ok && releasable(inst, placement, line, dir, offsets, placed | 1 << t, failed, budget) {
            return true;
        }
    }
    if *budget > 0 {
        failed[placed] = true;
    }
    false
}

/// Whether `b`'s target sits directly behind `a`'s along `dir` (touching, with lateral
/// overlap): the one edge every line of a push is made of.
pub(super) fn behind(placement: &Placement, dir: PushDir, a: usize, b: usize) -> bool {
    let (ra, rb) = (placement.targets[a].rect, placement.targets[b].rect);
    (rb.lo(dir.axis()) - ra.hi(dir.axis())).abs() <= EPS && ra.overlap_on(&rb, dir.axis().other()) > EPS
}

/// For every object, the length of the longest line (as in [`lines`]) that ends at it: the
/// paper's staggered releases put the k-th object of a line at offset `k·d`, so an object may
/// need offsets up to its rank whatever the configured step limit.
pub fn line_rank(placement: &Placement, dir: PushDir) -> Vec<usize> {
    let axis = dir.axis();
    let t = |i: usize| placement.targets[i].rect;
    let n = placement.targets.len();
    // Front to back: a line's objects have strictly increasing `lo` along the axis.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| t(a).lo(axis).total_cmp(&t(b).lo(axis)));
    let mut rank = vec![1; n];
    for (k, &b) in order.iter().enumerate() {
        for &a in &order[..k] {
            if behind(placement, dir, a, b) {
                rank[b] = rank[b].max(rank[a] + 1);
            }
        }
    }
    rank
}

/// Every line (front to back, consecutive targets touching along `dir` with lateral overlap)
/// of objects from `members`, up to `max_len` long.
pub fn lines(placement: &Placement, members: &[usize], dir: PushDir, max_len: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut stack: Vec<Vec<usize>> = members.iter().map(|&m| vec![m]).collect();
    while let Some(line) = stack.pop() {
        let last = *line.last().expect("non-empty");
        if line.len() < max_len {
            for &b in members {
                if !line.contains(&b) && behind(placement, dir, last, b) {
                    let mut l = line.clone();
                    l.push(b);
                    stack.push(l);
                }
            }
        }
        out.push(line);
    }
    out.sort();
    out
}

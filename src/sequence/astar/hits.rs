//! Which finger slabs and releases of a place hit which objects, precomputed per placement.

use super::*;

/// Per object and grasp axis, what [`Search::slab_hits`] holds.
pub(super) fn slab_hits(inst: &Instance, placement: &Placement) -> Vec<[Option<u64>; 2]> {
    let g = &inst.gripper;
    let walls = inst.container.walls();
    (0..inst.n())
        .map(|i| {
            let t = placement.targets[i];
            [Axis2::X, Axis2::Y].map(|ax| {
                if t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS {
                    return None;
                }
                let slabs = crate::actions::finger_slabs(g, &t.rect, t.height, ax);
                if slabs.iter().any(|s| walls.iter().any(|w| w.intersects(s))) {
                    return None;
                }
                Some((0..inst.n()).filter(|&j| j != i).fold(0u64, |m, j| {
                    let tj = placement.targets[j];
                    let b = crate::geometry::Box3::extrude(&tj.rect, 0.0, tj.height);
                    if slabs.iter().any(|s| b.intersects(s)) {
                        m | 1 << j
                    } else {
                        m
                    }
                }))
            })
        })
        .collect()
}

/// What stops one place action (an object, a place mode), per grasp axis (X, Y): `None` when
/// the axis cannot work with nothing else in the container, else the objects whose targets
/// block it once done, and per other object `j` and push direction `k`, the offset steps (bit
/// `m`) at which `j`, released there, blocks it.
///
/// A place check fails exactly when the static part fails or some single object's footprint or
/// box stands in the way (overlap, finger slabs), so checks against one object at a time decide
/// it for any set of them.
pub(super) struct PlaceHits {
    pub(super) axes: [Option<(u64, Vec<[u64; 2]>)>; 2],
}

/// A released object: index, push direction (as in [`PushDir::ALL`]), offset step.
pub(super) type Rel = (usize, usize, usize);

/// One place action of a known object: direct, or indirect with push direction (as in
/// [`PushDir::ALL`]) and offset step; and the grasp axis (0 for X, 1 for Y).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PlaceKey {
    Direct(usize),
    Indirect(usize, usize, usize),
}

impl PlaceKey {
    pub(super) fn axis(self) -> usize {
        match self {
            PlaceKey::Direct(ax) | PlaceKey::Indirect(_, _, ax) => ax,
        }
    }

    /// The key of `mode` with grasp axis `ax` (offsets in steps of `d`).
    pub(super) fn of(mode: PlaceMode, ax: usize, d: f64) -> PlaceKey {
        match mode {
            PlaceMode::Direct => PlaceKey::Direct(ax),
            PlaceMode::Indirect { push_dir, offset } => {
                let (k, m) = step_of(push_dir, offset, d);
                PlaceKey::Indirect(k, m, ax)
            }
        }
    }
}

/// An indirect place mode by push direction (index into [`PushDir::ALL`]) and offset step.
pub(super) fn indirect_mode(k: usize, m: usize, d: f64) -> PlaceMode {
    PlaceMode::Indirect {
        push_dir: PushDir::ALL[k],
        offset: d * m as f64,
    }
}

/// The push direction (index into [`PushDir::ALL`]) and offset step of a release.
pub(super) fn step_of(push_dir: PushDir, offset: f64, d: f64) -> (usize, usize) {
    let k = PushDir::ALL
        .iter()
        .position(|x| *x == push_dir)
        .expect("a push direction");
    (k, (offset / d).round() as usize)
}

/// Every place mode of an object with `steps` offset steps per push direction: direct first
/// (unless forbidden), then each direction's offsets, nearest first.
pub(super) fn place_modes(no_direct: bool, steps: [usize; 2], d: f64) -> impl Iterator<Item = PlaceMode> {
    (!no_direct)
        .then_some(PlaceMode::Direct)
        .into_iter()
        .chain((0..2).flat_map(move |k| (1..=steps[k]).map(move |m| indirect_mode(k, m, d))))
}

impl PlaceHits {
    /// Whether some grasp axis can still work, given that the objects in `done` stay at their
    /// targets, those in `fixed` stay where they are released, and those in `either` are
    /// released now and will be at their targets after their push: one of the two positions
    /// must leave the axis free.
    pub(super) fn open_with(&self, done: u64, fixed: &[Rel], either: &[Rel]) -> bool {
        (0..2).any(|ax| self.axis_open(ax, done, fixed, either))
    }

    /// [`PlaceHits::open_with`] for grasp axis `ax` (0 for X, 1 for Y) alone.
    pub(super) fn axis_open(&self, ax: usize, done: u64, fixed: &[Rel], either: &[Rel]) -> bool {
        self.axes[ax].as_ref().is_some_and(|(d, rel)| {
            d & done == 0
                && fixed.iter().all(|&(j, k, m)| rel[j][k] >> m & 1 == 0)
                && either
                    .iter()
                    .all(|&(j, k, m)| d >> j & 1 == 0 || rel[j][k] >> m & 1 == 0)
        })
    }
}

/// [`PlaceHits`] of placing object `i` in `mode` (offset steps of other objects up to `steps`).
pub(super) fn place_hits(
    inst: &Instance,
    placement: &Placement,
    steps: &[[usize; 2]],
    i: usize,
    mode: PlaceMode,
) -> PlaceHits {
    let n = inst.n();
    let d = inst.gripper.min_offset;
    let floor = inst.container.floor();
    let axes = [Axis2::X, Axis2::Y].map(|ax| {
        let a = Action::Place {
            object: i,
            mode,
            grasp_axis: ax,
            arm: pick_arm(inst, i),
        };
        let mut layout = Layout::new(inst, placement);
        layout.check(&a).ok()?;
        let mut done = 0u64;
        let mut rel = vec![[0u64; 2]; n];
        for j in (0..n).filter(|&j| j != i) {
            layout.state[j] = ObjState::Done;
            if layout.check(&a).is_err() {
                done |= 1 << j;
            }
            for (k, dir) in PushDir::ALL.into_iter().enumerate() {
                for mj in 1..=steps[j][k] {
                    let r = placement.targets[j].rect.moved(dir, -(d * mj as f64));
                    if !r.inside(&floor) {
                        continue; // never released there
                    }
                    layout.state[j] = ObjState::Released {
                        rect: r,
                        push_dir: dir,
                        offset: d * mj as f64,
                    };
                    if layout.check(&a).is_err() {
                        rel[j][k] |= 1 << mj;
                    }
                }
            }
            layout.state[j] = ObjState::Table;
        }
        Some((done, rel))
    });
    PlaceHits { axes }
}

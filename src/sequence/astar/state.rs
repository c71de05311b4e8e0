//! Building the search and the questions it asks of one state: feasibility, reach, layout.

use super::*;

impl<'a> Search<'a> {
    pub(super) fn new(
        inst: &'a Instance,
        placement: &'a Placement,
        opts: SequenceOptions,
        settings: AstarSettings,
    ) -> Self {
        let zt = transfer_z(inst);
        let g = &inst.gripper;
        let mut layout = Layout::new(inst, placement);
        layout.assume_held = true;
        let ranks = PushDir::ALL.map(|dir| line_rank(placement, dir));
        let steps: Vec<[usize; 2]> = (0..inst.n())
            .map(|i| [0, 1].map(|k| settings.max_offset_steps.max(ranks[k][i]).min(MAX_OFFSET_STEPS)))
            .collect();
        let front_to_back = PushDir::ALL.map(|dir| {
            let lo = |i: usize| placement.targets[i].rect.lo(dir.axis());
            let mut order: Vec<usize> = (0..inst.n()).collect();
            order.sort_by(|&a, &b| lo(a).total_cmp(&lo(b)));
            order
        });
        let pusher_range = pusher_range(inst, placement, &front_to_back);
        let info: Vec<ObjectInfo> = (0..inst.n())
            .map(|i| object_info(inst, placement, &opts, &layout, &steps[i], &pusher_range, i))
            .collect();
        let w = inst.container.width;
        let d = inst.container.depth;
        let container_corners = [[0.0, 0.0], [w, 0.0], [w, d], [0.0, d]].map(|[x, y]| {
            let p = inst.container.to_world([x, y, 0.0]);
            Vector3::new(p.x, p.y, zt)
        });
        let behind = PushDir::ALL.map(|dir| {
            (0..inst.n())
                .map(|a| {
                    (0..inst.n().min(64))
                        .filter(|&b| behind(placement, dir, a, b))
                        .fold(0u64, |m, b| m | 1 << b)
                })
                .collect()
        });
        let t_lines = Instant::now();
        let push_lines = push_lines(inst, placement, &opts, &info, &steps);
        if settings.trace {
            eprintln!(
                "push lines: {:?} in {:.3}s",
                push_lines.as_ref().map(|l| l.len()),
                t_lines.elapsed().as_secs_f64()
            );
        }
        let slab_hits = if push_lines.is_some() {
            slab_hits(inst, placement)
        } else {
            Vec::new()
        };
        let (release_hits, direct_hits) = if push_lines.is_some() {
            place_hit_tables(inst, placement, &steps)
        } else {
            (Vec::new(), Vec::new())
        };
        let n_lines = push_lines.as_ref().map_or(0, |l| l.len());
        Search {
            inst,
            placement,
            vetoes: opts.layout_vetoes(),
            opts,
            info,
            behind,
            front_to_back,
            push_lines,
            slab_hits,
            release_hits,
            direct_hits,
            pick_blockers: RefCell::new(vec![None; inst.n()]),
            line_reach: RefCell::new(vec![(0, 0); n_lines]),
            steps,
            home: [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)],
            home_c: [Arm::Left, Arm::Right].map(|a| {
                let p = inst.container.from_world(&inst.robot.home_tcp(a));
                [p[0], p[1]]
            }),
            container_corners,
            push_vertical: 2.0 * (zt - (inst.container.floor_z + g.push_height)),
            reach: crate::motion::reach_cache::ReachCache::new(inst, placement),
            succ_cache: RefCell::new(FxMap::default()),
            // Phase 1 stores millions of states on twelve objects: start large enough that the
            // first rehashes do not matter.
            len_memo: RefCell::new(FxMap::with_capacity_and_hasher(1 << 16, Default::default())),
            lstar: Cell::new(None),
            area_box: Cell::new(None),
            box_succ: RefCell::new(FxMap::default()),
            base_memo: RefCell::new(None),
            area_floor: Cell::new(0.0),
            stop: None,
            stopped: Cell::new(false),
            deadline: Cell::new(None),
            calls: Cell::new(0),
            prof: settings.profile.then(|| RefCell::new(Prof::default())),
        }
    }

    /// Run `f`, adding its time to a profile slot when profiling.
    pub(super) fn timed<T>(&self, slot: fn(&mut Prof) -> (&mut f64, &mut u64), f: impl FnOnce() -> T) -> T {
        match &self.prof {
            None => f(),
            Some(p) => {
                let t = Instant::now();
                let v = f();
                let mut p = p.borrow_mut();
                let (s, n) = slot(&mut p);
                *s += t.elapsed().as_secs_f64();
                *n += 1;
                v
            }
        }
    }

    pub(super) fn check(&self, layout: &Layout, a: &Action) -> Option<Option<f64>> {
        self.timed(|p| (&mut p.check_s, &mut p.check_n), || layout.check(a).ok())
    }

    /// Reachability of an action by the robot in `state` (memoised in [`ReachCache`]; objects
    /// still on the table may block a pick).
    pub(super) fn reachable(&self, a: &Action, state: &[ObjState]) -> bool {
        let t = self.prof.as_ref().map(|_| Instant::now());
        let v = self.timed(|p| (&mut p.reach_s, &mut p.reach_n), || self.reach.ok_when(a, state));
        if let (Some(p), Some(t)) = (&self.prof, t) {
            // A memo hit takes well under a microsecond, inverse kinematics milliseconds.
            if t.elapsed().as_secs_f64() > 1e-4 {
                p.borrow_mut().reach_miss += 1;
            }
        }
        v
    }

    /// Distance from `p` to the container floor rectangle lifted to transfer height.
    pub(super) fn dist_to_container(&self, p: &Vector3<f64>) -> f64 {
        let c = &self.container_corners;
        // Work in the container's own axes: project onto its edges.
        let ex = c[1] - c[0];
        let ey = c[3] - c[0];
        let v = p - c[0];
        let u = (v.dot(&ex) / ex.norm_squared()).clamp(0.0, 1.0);
        let w = (v.dot(&ey) / ey.norm_squared()).clamp(0.0, 1.0);
        (c[0] + ex * u + ey * w - p).norm()
    }

    /// Direct placing of table object `i` is impossible for good: on both grasp axes a finger
    /// slab hits a wall or one of the `done` objects (or the object is too wide to grasp).
    pub(super) fn direct_blocked(&self, i: usize, done: &[usize]) -> bool {
        let g = &self.inst.gripper;
        let t = self.placement.targets[i];
        let walls = self.inst.container.walls();
        [Axis2::X, Axis2::Y].iter().all(|&ax| {
            if t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS {
                return true;
            }
            crate::actions::finger_slabs(g, &t.rect, t.height, ax).iter().any(|s| {
                walls.iter().any(|w| w.intersects(s))
                    || done.iter().any(|&j| {
                        let tj = self.placement.targets[j];
                        crate::geometry::Box3::extrude(&tj.rect, 0.0, tj.height).intersects(s)
                    })
            })
        })
    }

    pub(super) fn layout(&self, state: &[ObjState]) -> Layout<'a> {
        let mut l = Layout::new(self.inst, self.placement);
        l.state = state.to_vec();
        l.vetoes = self.vetoes.clone();
        l
    }
}

/// Per push direction and object, the lateral range of the pusher of any line ending at it: the
/// pusher is centred on a weighted mean of the members' lateral centres, and the members are
/// objects in front of it (transitively).
fn pusher_range(inst: &Instance, placement: &Placement, front_to_back: &[Vec<usize>; 2]) -> [Vec<[f64; 2]>; 2] {
    [0, 1].map(|k| {
        let dir = PushDir::ALL[k];
        let lat = dir.axis().other();
        let centre = |i: usize| {
            let r = placement.targets[i].rect;
            (r.lo(lat) + r.hi(lat)) / 2.0
        };
        let order = &front_to_back[k];
        let mut range: Vec<[f64; 2]> = (0..inst.n()).map(|i| [centre(i), centre(i)]).collect();
        // Front to back: everything in front of `b` is done before it.
        for (k, &b) in order.iter().enumerate() {
            for &a in &order[..k] {
                if behind(placement, dir, a, b) {
                    range[b] = [range[b][0].min(range[a][0]), range[b][1].max(range[a][1])];
                }
            }
        }
        range
    })
}

/// What the search keeps of object `i`: its pick and release points, where its pushes can end,
/// and which of its placements the gripper or the walls rule out.
fn object_info(
    inst: &Instance,
    placement: &Placement,
    opts: &SequenceOptions,
    layout: &Layout,
    steps: &[usize; 2],
    pusher_range: &[Vec<[f64; 2]>; 2],
    i: usize,
) -> ObjectInfo {
    let g = &inst.gripper;
    let zt = transfer_z(inst);
    let floor = inst.container.floor();
    let walls = inst.container.walls();
    let o = &inst.objects[i];
    let (_, h_table) = o.table_footprint();
    let grasp_z = inst.robot.table_z + h_table - g.grasp_depth;
    let t = placement.targets[i];
    let c = t.rect.center();
    let release = inst.container.to_world([c[0], c[1], t.height - g.grasp_depth]);
    let never_direct = [Axis2::X, Axis2::Y].iter().all(|&ax| {
        t.rect.extent(ax) + 2.0 * g.release_clearance > g.max_opening + EPS
            || layout
                .finger_slabs(&t.rect, t.height, ax)
                .iter()
                .any(|s| walls.iter().any(|w| w.intersects(s)))
    });
    let nearest = PushDir::ALL.map(|d| t.rect.moved(d, -g.min_offset));
    let push_dir_ok = nearest.map(|r| r.inside(&floor));
    let release_ext = nearest
        .iter()
        .filter(|r| r.inside(&floor))
        .map(|r| [r.x1, r.y1])
        .collect();
    let pre_grasp = Vector3::new(o.table.x, o.table.y, zt);
    let pc = inst.container.from_world(&pre_grasp);
    let pre_grasp_c = [pc[0], pc[1]];
    // Releases go against the push direction (+x or +y in C) by up to the object's
    // largest offset; a push ends with the fingers half a thickness behind the
    // target, within its lateral extent.
    let reach = [0, 1].map(|k| {
        if push_dir_ok[k] {
            g.min_offset * steps[k] as f64
        } else {
            0.0
        }
    });
    let half_t = g.finger_thickness / 2.0;
    // Bounding box of the release centres and of the push ends.
    let mut end_region = crate::geometry::Rect {
        x0: c[0],
        y0: c[1],
        x1: c[0] + reach[0],
        y1: c[1] + reach[1],
    };
    if push_dir_ok[0] {
        let [lo, hi] = pusher_range[0][i];
        end_region = end_region.union(&crate::geometry::Rect {
            x0: t.rect.x1 + half_t,
            x1: t.rect.x1 + half_t,
            y0: lo,
            y1: hi,
        });
    }
    if push_dir_ok[1] {
        let [lo, hi] = pusher_range[1][i];
        end_region = end_region.union(&crate::geometry::Rect {
            x0: lo,
            x1: hi,
            y0: t.rect.y1 + half_t,
            y1: t.rect.y1 + half_t,
        });
    }
    let seg = |u: [f64; 2], len: f64| {
        let v = [pre_grasp_c[0] - c[0], pre_grasp_c[1] - c[1]];
        let s = (v[0] * u[0] + v[1] * u[1]).clamp(0.0, len);
        (v[0] - s * u[0]).hypot(v[1] - s * u[1])
    };
    let transfer_min = seg([1.0, 0.0], reach[0]).min(seg([0.0, 1.0], reach[1]));
    ObjectInfo {
        pre_grasp_c,
        end_region,
        transfer_min,
        pre_grasp,
        pick_vertical: 2.0 * (zt - grasp_z),
        release_vertical: 2.0 * (zt - release.z),
        never_direct: never_direct || opts.no_direct,
        release_ext,
        push_dir_ok,
    }
}

/// Per object, what can stop each of its indirect placements (per push direction and offset
/// step) and its direct placement; empty when an offset step would not fit the bit masks of
/// `PlaceHits`.
fn place_hit_tables(
    inst: &Instance,
    placement: &Placement,
    steps: &[[usize; 2]],
) -> (Vec<[Vec<PlaceHits>; 2]>, Vec<PlaceHits>) {
    if !steps.iter().flatten().all(|&m| m < 64) {
        return (Vec::new(), Vec::new());
    }
    let d = inst.gripper.min_offset;
    let indirect = (0..inst.n())
        .map(|i| {
            [0, 1].map(|k| {
                (1..=steps[i][k])
                    .map(|m| place_hits(inst, placement, steps, i, indirect_mode(k, m, d)))
                    .collect()
            })
        })
        .collect();
    let direct = (0..inst.n())
        .map(|i| place_hits(inst, placement, steps, i, PlaceMode::Direct))
        .collect();
    (indirect, direct)
}

//! The replay of a plan action by action: where every object is, and every condition of every step.

use super::*;

impl<'a> Replay<'a> {
    pub(super) fn new(inst: &'a Instance, placement: &'a Placement, out: Vec<Violation>) -> Self {
        Replay {
            inst,
            placement,
            state: vec![Where::Table; inst.n()],
            out,
            extent: (0.0, 0.0),
            top: slabs::slab_top(inst),
        }
    }

    pub(super) fn flag(&mut self, step: Option<usize>, class: ViolationClass, message: String) {
        self.out.push(Violation { step, class, message });
    }

    pub(super) fn id(&self, i: usize) -> &'a str {
        &self.inst.objects[i].id
    }

    pub(super) fn target(&self, i: usize) -> Rect {
        self.placement.targets[i].rect
    }

    /// Current footprint of an object in the container.
    pub(super) fn rect_of(&self, i: usize) -> Option<Rect> {
        match self.state[i] {
            Where::Table => None,
            Where::Released { rect, .. } => Some(rect),
            Where::AtTarget => Some(self.target(i)),
        }
    }

    pub(super) fn grow(&mut self, r: &Rect) {
        self.extent = (self.extent.0.max(r.x1), self.extent.1.max(r.y1));
    }

    /// Walls and objects in the container (except `skip`) that `slab` intersects.
    pub(super) fn hits(&self, slab: &Box3, skip: &[usize]) -> Vec<String> {
        let mut names = Vec::new();
        for (k, w) in self.inst.container.walls().iter().enumerate() {
            if w.intersects(slab) {
                names.push(slabs::WALL_NAMES[k].to_string());
            }
        }
        for j in 0..self.inst.n() {
            if skip.contains(&j) {
                continue;
            }
            if let Some(r) = self.rect_of(j) {
                if Box3::extrude(&r, 0.0, self.placement.targets[j].height).intersects(slab) {
                    names.push(format!("object {}", self.id(j)));
                }
            }
        }
        names
    }

    /// Whole-document consistency that does not need the replay.
    pub(super) fn check_document(&mut self, plan: &Plan, actions: &[Action]) {
        use ViolationClass::Format;
        for (k, e) in plan.placements.iter().enumerate() {
            if let Some(o) = self.inst.objects.iter().find(|o| o.id == e.object) {
                let kind = &self.inst.kinds[o.kind].name;
                if &e.kind != kind {
                    self.flag(
                        None,
                        Format,
                        format!("placements[{k}]: object {} is of kind {kind}, not {}", e.object, e.kind),
                    );
                }
            }
        }
        for (k, (a, e)) in actions.iter().zip(&plan.actions).enumerate() {
            let step = Some(k + 1);
            if e.step != k + 1 {
                self.flag(step, Format, format!("action {} is numbered step {}", k + 1, e.step));
            }
            if !self.inst.robot.arms.contains(&a.arm()) {
                self.flag(
                    step,
                    Format,
                    format!("arm {} is not allowed by the instance", a.arm().name()),
                );
            }
            match a {
                Action::Place {
                    mode: PlaceMode::Direct,
                    ..
                } if plan.options.no_direct => {
                    self.flag(
                        step,
                        Format,
                        "direct place although the plan's options forbid direct placing".into(),
                    );
                }
                Action::Push { objects, .. } if objects.len() > 1 && plan.options.no_multi_push => {
                    self.flag(
                        step,
                        Format,
                        "multi-object push although the plan's options forbid multi-object pushing".into(),
                    );
                }
                _ => {}
            }
        }
    }

    pub(super) fn step(&mut self, step: usize, a: &Action, e: &ActionEntry) {
        match a {
            Action::Place {
                object,
                mode,
                grasp_axis,
                ..
            } => self.place(step, *object, *mode, *grasp_axis, e),
            Action::Push {
                objects,
                push_dir,
                distance,
                pusher_at,
                ..
            } => self.push(step, objects, *push_dir, *distance, *pusher_at, e),
        }
    }

    pub(super) fn place(&mut self, step: usize, i: usize, mode: PlaceMode, axis: Axis2, e: &ActionEntry) {
        use ViolationClass::*;
        let s = Some(step);
        let g = self.inst.gripper;
        let id = self.id(i);
        match self.state[i] {
            Where::Table => {}
            Where::Released { rect, .. } => self.flag(
                s,
                Precedence,
                format!(
                    "{id} is placed again while released at {} waiting for its push",
                    fmt_rect(&rect)
                ),
            ),
            Where::AtTarget => self.flag(
                s,
                Precedence,
                format!("{id} is placed again although already at its target"),
            ),
        }
        let t = self.placement.targets[i];
        let rel = match mode {
            PlaceMode::Direct => t.rect,
            PlaceMode::Indirect { push_dir, offset } => {
                if offset < g.min_offset - EPS {
                    self.flag(
                        s,
                        FingerSlab,
                        format!(
                            "{id}: indirect offset {offset:.4} m is below the gripper's minimum {:.4} m",
                            g.min_offset
                        ),
                    );
                }
                let u = push_dir.unit();
                t.rect.translated(-u[0] * offset, -u[1] * offset)
            }
        };
        match e.release {
            None => self.flag(s, Format, format!("place of {id} records no release footprint")),
            Some(rec) => {
                let d = [rec.x0 - rel.x0, rec.y0 - rel.y0, rec.x1 - rel.x1, rec.y1 - rel.y1];
                if d.iter().any(|v| v.is_nan() || v.abs() > EPS) {
                    self.flag(
                        s,
                        Format,
                        format!(
                            "place of {id} records release {} but its mode gives {}",
                            fmt_rect(&rec),
                            fmt_rect(&rel)
                        ),
                    );
                }
            }
        }
        let width = rel.extent(axis);
        if width + 2.0 * g.release_clearance > g.max_opening + EPS {
            self.flag(
                s,
                FingerSlab,
                format!(
                    "{id} is {width:.4} m wide along the grasp axis {}: with clearance it exceeds the opening {:.4} m",
                    axis_name(axis),
                    g.max_opening
                ),
            );
        }
        if !rel.inside(&self.inst.container.floor()) {
            self.flag(
                s,
                Wall,
                format!(
                    "release footprint of {id} {} leaves the container floor",
                    fmt_rect(&rel)
                ),
            );
        }
        for j in 0..self.inst.n() {
            if j == i {
                continue;
            }
            if let Some(rj) = self.rect_of(j) {
                if rj.overlaps(&rel) {
                    let msg = format!(
                        "release footprint of {id} {} overlaps {} at {}",
                        fmt_rect(&rel),
                        self.id(j),
                        fmt_rect(&rj)
                    );
                    self.flag(s, Overlap, msg);
                }
            }
        }
        let fingers = slabs::finger_slabs(&g, &rel, t.height, axis, self.top);
        for (side, slab) in ["-", "+"].iter().zip(&fingers) {
            for hit in self.hits(slab, &[i]) {
                self.flag(
                    s,
                    FingerSlab,
                    format!("finger on the {side}{} side of {id} hits {hit}", axis_name(axis)),
                );
            }
        }
        self.state[i] = match mode {
            PlaceMode::Direct => Where::AtTarget,
            PlaceMode::Indirect { push_dir, offset } => Where::Released {
                rect: rel,
                dir: push_dir,
                offset,
            },
        };
        self.grow(&rel);
    }

    /// Replay a push: the line is released for it, its offsets and distance agree, the pusher
    /// and the objects sweep through nothing, the push model accepts it and the plan records
    /// what it recomputes. The objects end at their targets.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn push(&mut self, step: usize, line: &[usize], dir: PushDir, distance: f64, at: f64, e: &ActionEntry) {
        let s = Some(step);
        let Some((rel, offsets)) = self.pushed_releases(s, line, dir) else {
            return; // geometry of the push is undefined; the objects stay where they are
        };
        self.check_line_offsets(s, line, &offsets, distance);
        self.check_push_space(s, line, dir, at, &rel);
        self.check_side_contacts(s, line, dir, &rel);
        self.check_push_stability(s, line, dir, at, &offsets, e);
        for &i in line {
            self.state[i] = Where::AtTarget;
            let t = self.target(i);
            self.grow(&t);
        }
    }

    /// Where the pushed objects were released, and their offsets, when every one was released
    /// for this push (else `None`, with what is wrong flagged); also flags a line whose targets
    /// do not touch.
    fn pushed_releases(&mut self, s: Option<usize>, line: &[usize], dir: PushDir) -> Option<(Vec<Rect>, Vec<f64>)> {
        use ViolationClass::*;
        let axis = dir.axis();
        for (k, &i) in line.iter().enumerate() {
            if line[..k].contains(&i) {
                self.flag(
                    s,
                    Precedence,
                    format!("{} appears twice in the pushed line", self.id(i)),
                );
                return None;
            }
        }
        // Every pushed object must be released for this push.
        let mut rel = Vec::new();
        let mut offsets = Vec::new();
        for &i in line {
            let id = self.id(i);
            match self.state[i] {
                Where::Released { rect, dir: d, offset } if d == dir => {
                    rel.push(rect);
                    offsets.push(offset);
                }
                Where::Released { dir: d, .. } => self.flag(
                    s,
                    Precedence,
                    format!(
                        "{id} is pushed {} but was released for a {} push",
                        dir_name(dir),
                        dir_name(d)
                    ),
                ),
                Where::Table => self.flag(s, Precedence, format!("{id} is pushed while still on the table")),
                Where::AtTarget => self.flag(s, Precedence, format!("{id} is pushed although already at its target")),
            }
        }
        // Line contiguity: consecutive targets touch along the push axis with lateral overlap.
        for w in line.windows(2) {
            let (a, b) = (self.target(w[0]), self.target(w[1]));
            if (a.hi(axis) - b.lo(axis)).abs() > EPS || a.overlap_on(&b, axis.other()) <= EPS {
                self.flag(
                    s,
                    Precedence,
                    format!(
                        "{} and {} are not a line: their targets do not touch along {} with lateral overlap",
                        self.id(w[0]),
                        self.id(w[1]),
                        axis_name(axis)
                    ),
                );
            }
        }
        (rel.len() == line.len()).then_some((rel, offsets))
    }

    /// Offsets do not decrease toward the back, and the push distance is the back object's.
    fn check_line_offsets(&mut self, s: Option<usize>, line: &[usize], offsets: &[f64], distance: f64) {
        use ViolationClass::Precedence;
        let names: Vec<&str> = line.iter().map(|&i| self.id(i)).collect();
        let back = *line.last().expect("a push moves at least one object");
        let back_off = *offsets.last().expect("same length as line");
        for k in 1..offsets.len() {
            if offsets[k] < offsets[k - 1] - EPS {
                self.flag(
                    s,
                    Precedence,
                    format!(
                        "offsets decrease toward the back of the line: {} at {:.4} m behind {} at {:.4} m",
                        names[k],
                        offsets[k],
                        names[k - 1],
                        offsets[k - 1]
                    ),
                );
            }
        }
        if (distance - back_off).abs() > EPS {
            self.flag(
                s,
                Precedence,
                format!(
                    "push distance {distance:.4} m differs from the back object's ({}) offset {back_off:.4} m",
                    self.id(back)
                ),
            );
        }
    }

    /// No pushed object slides along a box that nothing holds against the push (nor into a
    /// slot, when the instance forbids them): the push model's side contacts
    /// (`actions::push::side`), asked with the verifier's own record of the container.
    fn check_side_contacts(&mut self, s: Option<usize>, line: &[usize], dir: PushDir, rel: &[Rect]) {
        use crate::actions::push::side::{side_failure, SideFailure, SideRule, Standing};
        let settings = &self.inst.settings;
        if !settings.side_contacts {
            return;
        }
        let moving: Vec<(usize, Rect)> = line
            .iter()
            .zip(rel)
            .map(|(&i, r)| (i, r.union(&self.target(i))))
            .collect();
        let standing: Vec<Standing> = (0..self.state.len())
            .filter(|i| !line.contains(i))
            .filter_map(|i| match self.state[i] {
                Where::Table => None,
                Where::Released { rect, .. } => Some(Standing {
                    object: i,
                    rect,
                    at_target: false,
                }),
                Where::AtTarget => Some(Standing {
                    object: i,
                    rect: self.target(i),
                    at_target: true,
                }),
            })
            .collect();
        let rule = SideRule {
            clearance: settings.side_clearance,
            assume_held: false,
            forbid_slots: settings.forbid_slots,
        };
        let message = match side_failure(&self.inst.container.floor(), &moving, &standing, dir, &rule) {
            None => return,
            Some(SideFailure::Drags { moving, neighbour }) => format!(
                "{} slides along {} at less than the side clearance, and nothing holds {} against the push",
                self.id(moving),
                self.id(neighbour),
                self.id(neighbour)
            ),
            Some(SideFailure::Wedged { moving }) => {
                format!("{} slides into a slot (faces on both of its sides)", self.id(moving))
            }
        };
        self.flag(s, ViolationClass::SideContact, message);
    }

    /// The pusher lowers behind the back object without a hit, and neither the pushed objects
    /// nor the pusher sweep through anything.
    fn check_push_space(&mut self, s: Option<usize>, line: &[usize], dir: PushDir, at: f64, rel: &[Rect]) {
        use ViolationClass::*;
        let g = self.inst.gripper;
        let back = *line.last().expect("a push moves at least one object");
        // Lowering the closed fingers behind the back object.
        let back_rel = rel[rel.len() - 1];
        let lower = slabs::pusher_slab(&g, &back_rel, dir, at, g.release_clearance, self.top);
        let lower_hits = self.hits(&lower, &[]);
        for hit in &lower_hits {
            self.flag(
                s,
                FingerSlab,
                format!("pusher lowered behind {} at {at:.4} hits {hit}", self.id(back)),
            );
        }
        // Swept rectangles of the pushed objects.
        let floor = self.inst.container.floor();
        for (k, &i) in line.iter().enumerate() {
            let swept = rel[k].union(&self.target(i));
            if !swept.inside(&floor) {
                self.flag(
                    s,
                    Wall,
                    format!(
                        "push sweeps {} through {} outside the floor",
                        self.id(i),
                        fmt_rect(&swept)
                    ),
                );
            }
            for j in 0..self.inst.n() {
                if line.contains(&j) {
                    continue;
                }
                if let Some(rj) = self.rect_of(j) {
                    if rj.overlaps(&swept) {
                        let msg = format!("push sweeps {} through {} at {}", self.id(i), self.id(j), fmt_rect(&rj));
                        self.flag(s, SweptSpace, msg);
                    }
                }
            }
        }
        // The pusher's own sweep, from lowered to the back object's target.
        let end = slabs::pusher_slab(&g, &self.target(back), dir, at, 0.0, self.top);
        for hit in self.hits(&slabs::hull(&lower, &end), line) {
            if !lower_hits.contains(&hit) {
                self.flag(
                    s,
                    SweptSpace,
                    format!("pusher moving along {} hits {hit}", dir_name(dir)),
                );
            }
        }
    }

    /// The push model accepts the push, and the plan records the margin and travel phase it
    /// recomputes.
    #[allow(clippy::too_many_arguments)]
    fn check_push_stability(
        &mut self,
        s: Option<usize>,
        line: &[usize],
        dir: PushDir,
        at: f64,
        offsets: &[f64],
        e: &ActionEntry,
    ) {
        use ViolationClass::PushStability;
        let names: Vec<&str> = line.iter().map(|&i| self.id(i)).collect();
        let back = *line.last().expect("a push moves at least one object");
        // Stability with the planner's mechanical model and the instance's tolerances, phases
        // from the gaps between releases, each lasting its gap (docs/push_stability.md §5.4).
        let gaps: Vec<f64> = offsets.windows(2).map(|w| (w[1] - w[0]).max(0.0)).collect();
        let verdict = push::line_verdict(self.inst, self.placement, line, dir, at, &gaps);
        let margin = verdict.margin;
        let min = self.inst.settings.min_push_margin;
        match &verdict.travel {
            Some(t) if !t.passes => self.flag(
                s,
                PushStability,
                format!(
                    "push of [{}] with the pusher at {at:.4}: {} alone turns {:.3}° and drifts {:.4} mm while it closes its {:.4} mm gap, {:.0} % of the limits {:.3}° and {:.4} mm",
                    names.join(", "),
                    self.id(back),
                    t.rotation.to_degrees(),
                    t.drift * 1e3,
                    t.travel * 1e3,
                    t.usage * 100.0,
                    self.inst.settings.max_push_rotation.to_degrees(),
                    self.inst.settings.max_push_drift * 1e3
                ),
            ),
            _ if margin.is_nan() || margin <= min => self.flag(
                s,
                PushStability,
                format!(
                    "push of [{}] with the pusher at {at:.4} has margin {margin:.4} m, not above the minimum {min:.4} m",
                    names.join(", ")
                ),
            ),
            _ => {}
        }
        self.check_travel_record(s, e, back, verdict.travel.as_ref());
        match e.margin {
            None => self.flag(s, PushStability, "push records no stability margin".into()),
            Some(m) if !close_margin(m, margin) => self.flag(
                s,
                PushStability,
                format!("recorded margin {m:.6} m differs from the recomputed {margin:.6} m"),
            ),
            _ => {}
        }
    }

    /// The recorded travel phase of a push agrees with the recomputed one: present exactly when
    /// the back object's phase is judged by its travel, same object, gap and usage.
    fn check_travel_record(&mut self, s: Option<usize>, e: &ActionEntry, back: usize, t: Option<&TravelCheck>) {
        use ViolationClass::PushStability;
        let msg = match (&e.travel_phase, t) {
            (None, None) => return,
            (None, Some(t)) => format!(
                "push records no travel phase, but {} closes its {:.4} mm gap alone and is judged by its travel",
                self.id(back),
                t.travel * 1e3
            ),
            (Some(r), None) => format!(
                "push records a travel phase of {}, but no phase of it is judged by its travel",
                r.object
            ),
            (Some(r), Some(t)) => {
                let same = r.object == self.id(back)
                    && close_margin(r.gap, t.travel)
                    && close(r.rotation, t.rotation)
                    && close_margin(r.drift, t.drift)
                    && close(r.usage, t.usage);
                if same {
                    return;
                }
                format!(
                    "recorded travel phase ({} over {:.6} m, usage {:.4}) differs from the recomputed ({} over {:.6} m, usage {:.4})",
                    r.object,
                    r.gap,
                    r.usage,
                    self.id(back),
                    t.travel,
                    t.usage
                )
            }
        };
        self.flag(s, PushStability, msg);
    }

    pub(super) fn check_final(&mut self) {
        for i in 0..self.inst.n() {
            let msg = match self.state[i] {
                Where::AtTarget => continue,
                Where::Table => format!("{} is never placed in the container", self.id(i)),
                Where::Released { rect, dir, .. } => format!(
                    "{} ends released at {}, never pushed {} to its target",
                    self.id(i),
                    fmt_rect(&rect),
                    dir_name(dir)
                ),
            };
            self.flag(None, ViolationClass::FinalPose, msg);
        }
    }

    pub(super) fn check_metrics(&mut self, plan: &Plan, actions: &[Action]) {
        use ViolationClass::Metrics as M;
        let mut m = Metrics {
            seq_len: actions.len(),
            n_place_direct: 0,
            n_place_indirect: 0,
            n_push: 0,
            n_multi_push: 0,
            swept_area: self.extent.0 * self.extent.1,
            travel: total_travel(self.inst, self.placement, actions),
        };
        for a in actions {
            match a {
                Action::Place {
                    mode: PlaceMode::Direct,
                    ..
                } => m.n_place_direct += 1,
                Action::Place { .. } => m.n_place_indirect += 1,
                Action::Push { objects, .. } => {
                    m.n_push += 1;
                    if objects.len() > 1 {
                        m.n_multi_push += 1;
                    }
                }
            }
        }
        let rec = plan.metrics;
        for (name, got, want) in [
            ("seq_len", rec.seq_len, m.seq_len),
            ("n_place_direct", rec.n_place_direct, m.n_place_direct),
            ("n_place_indirect", rec.n_place_indirect, m.n_place_indirect),
            ("n_push", rec.n_push, m.n_push),
            ("n_multi_push", rec.n_multi_push, m.n_multi_push),
        ] {
            if got != want {
                self.flag(None, M, format!("metrics.{name} is {got}, the plan has {want}"));
            }
        }
        for (name, got, want) in [
            ("swept_area", rec.swept_area, m.swept_area),
            ("travel", rec.travel, m.travel),
        ] {
            if !close(got, want) {
                self.flag(None, M, format!("metrics.{name} is {got:.6}, recomputed {want:.6}"));
            }
        }
        // Per-action travel, from each arm's previous key point along the recorded key poses.
        let mut pos = [Arm::Left, Arm::Right].map(|a| self.inst.robot.home_tcp(a));
        for (k, (a, e)) in actions.iter().zip(&plan.actions).enumerate() {
            let arm = a.arm().index();
            let (len, endp) = path_length(&pos[arm], &e.key_poses);
            pos[arm] = endp;
            if !close(e.cost, len) {
                self.flag(
                    Some(k + 1),
                    M,
                    format!("recorded cost {:.6} m, its key poses give {len:.6} m", e.cost),
                );
            }
        }
        let area = self.placement.occupied_area();
        if !close(plan.placement.occupied_area, area) {
            self.flag(
                None,
                M,
                format!(
                    "placement.occupied_area is {:.6}, recomputed {area:.6}",
                    plan.placement.occupied_area
                ),
            );
        }
        let contact = self.placement.contact_length(self.inst);
        if !close(plan.placement.contact_length, contact) {
            self.flag(
                None,
                M,
                format!(
                    "placement.contact_length is {:.6}, recomputed {contact:.6}",
                    plan.placement.contact_length
                ),
            );
        }
    }
}

//! The independent verifier: valid plans pass; each deliberately broken plan is caught with the
//! right violation class.
//!
//! Two sources of plans:
//! * the planner's own plans for the paper instances (and their ablations), mutated in ways that
//!   do not depend on which plan the planner happens to return (each mutation searches the plan
//!   for a step it applies to, and asserts that one exists);
//! * a hand-made placement and hand-made action lists for the 4-object instance, for conditions
//!   the paper plans never come close to (a push sweeping through an object, phase stability).
//!
//! Modified action lists are turned back into a consistent `plan.json` with `build_plan`, so the
//! recorded fields (release, costs, metrics) agree with the actions and only the intended
//! violation remains.

mod common;

use pushpack::actions::{push, Action, PlaceMode};
use pushpack::geometry::{Axis2, BodyAxis, Orientation, PushDir, Rect, EPS};
use pushpack::instance::Instance;
use pushpack::motion::keypoints::pick_arm;
use pushpack::placement::{Placement, PlacementResult, PlacementStatus, Target};
use pushpack::plan::{build_plan, optimize, Plan, PlanOptions, PlanOutcome, Sequencer};
use pushpack::sequence::{self, SequenceResult};
use pushpack::verify::{verify, Report, ViolationClass as V};
use std::collections::{BTreeSet, HashMap};
use std::sync::{Arc, Mutex, OnceLock};

const EXP1: &str = "instances/paper/exp1_4objects.toml";
const EXP2: &str = "instances/paper/exp2_8objects.toml";

/// Instance, no_direct, no_multi_push, sequencer (None = the instance's default).
type Key = (&'static str, bool, bool, Option<Sequencer>);

/// The planner's outcome for an instance, ablation flags and sequencer, computed once per test
/// binary (concurrent tests asking for the same plan wait for one computation).
fn planned_with(
    path: &'static str,
    no_direct: bool,
    no_multi_push: bool,
    seq: Option<Sequencer>,
) -> (Instance, PlanOutcome) {
    type Cell = Arc<OnceLock<(Instance, PlanOutcome)>>;
    // Keyed by the Debug text of the sequencer (`Sequencer` is not `Hash`).
    /// (instance, no-direct, no-multi-push, sequencer) → the plan made once.
    type Key = (&'static str, bool, bool, String);
    static CACHE: OnceLock<Mutex<HashMap<Key, Cell>>> = OnceLock::new();
    let cell = CACHE
        .get_or_init(|| Mutex::new(HashMap::new()))
        .lock()
        .unwrap()
        .entry((path, no_direct, no_multi_push, format!("{seq:?}")))
        .or_default()
        .clone();
    cell.get_or_init(|| {
        let inst = Instance::load(path).unwrap();
        let mut opts = PlanOptions::from_instance(&inst);
        opts.no_direct = no_direct;
        opts.no_multi_push = no_multi_push;
        if let Some(seq) = seq {
            opts.sequencer = seq;
        }
        let out = optimize(&inst, &opts).unwrap();
        (inst, out)
    })
    .clone()
}

/// The plan `PlanOptions::from_instance` asks for.
fn default_plan(path: &'static str) -> (Instance, PlanOutcome) {
    planned_with(path, false, false, None)
}

fn classes(r: &Report) -> BTreeSet<V> {
    r.violations.iter().map(|v| v.class).collect()
}

#[track_caller]
fn assert_has(r: &Report, class: V) {
    assert!(r.has(class), "expected a {class} violation, got:\n{r}");
}

#[track_caller]
fn assert_only(r: &Report, expected: &[V]) {
    let want: BTreeSet<V> = expected.iter().copied().collect();
    assert_eq!(classes(r), want, "unexpected violation classes:\n{r}");
}

/// Offset of each object's latest indirect place before position `upto` of `actions`.
fn offsets_before(actions: &[Action], upto: usize) -> HashMap<usize, f64> {
    let mut off = HashMap::new();
    for a in &actions[..upto] {
        if let Action::Place { object, mode, .. } = a {
            match mode {
                PlaceMode::Indirect { offset, .. } => off.insert(*object, *offset),
                PlaceMode::Direct => off.remove(object),
            };
        }
    }
    off
}

/// Turn an action list into a consistent plan document (recorded releases, margins, costs and
/// metrics all derived from the actions).
fn build(inst: &Instance, pr: &PlacementResult, opts: &PlanOptions, actions: Vec<Action>) -> Plan {
    let p = &pr.placement;
    let margins = actions
        .iter()
        .enumerate()
        .map(|(k, a)| match a {
            Action::Push {
                objects,
                push_dir,
                pusher_at,
                ..
            } => {
                let off = offsets_before(&actions, k);
                let gaps: Vec<f64> = objects
                    .windows(2)
                    .map(|w| (off.get(&w[1]).copied().unwrap_or(0.0) - off.get(&w[0]).copied().unwrap_or(0.0)).max(0.0))
                    .collect();
                Some(push::line_verdict(inst, p, objects, *push_dir, *pusher_at, &gaps).margin)
            }
            Action::Place { .. } => None,
        })
        .collect();
    // Start from a real result so that fields added to it later need no change here.
    let (_, base) = default_plan(EXP1);
    let mut sr: SequenceResult = base.sequence.clone();
    sr.metrics = sequence::metrics(inst, p, &actions);
    sr.actions = actions;
    sr.margins = margins;
    // A hand-made action list proves nothing: no bound, and a search that did not finish.
    sr.bound = None;
    sr.status = sequence::SearchStatus::NodeLimit;
    build_plan(inst, opts, pr, &sr)
}

/// Rebuild a planner outcome's plan from a modified action list.
fn rebuild(inst: &Instance, out: &PlanOutcome, actions: Vec<Action>) -> Plan {
    build(inst, &out.placement, &out.plan.options, actions)
}

fn actions_of(inst: &Instance, out: &PlanOutcome) -> Vec<Action> {
    out.plan.actions(inst).unwrap()
}

fn obj(inst: &Instance, id: &str) -> usize {
    inst.objects.iter().position(|o| o.id == id).unwrap()
}

/// Footprint of every object in the container just before step index `k` of a valid plan.
fn occupied_before(inst: &Instance, p: &Placement, actions: &[Action], k: usize) -> Vec<Option<Rect>> {
    let mut at = vec![None; inst.n()];
    for a in &actions[..k] {
        match a {
            Action::Place { object, mode, .. } => {
                let t = p.targets[*object].rect;
                at[*object] = Some(match mode {
                    PlaceMode::Direct => t,
                    PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
                });
            }
            Action::Push { objects, .. } => {
                for &i in objects {
                    at[i] = Some(p.targets[i].rect);
                }
            }
        }
    }
    at
}

// ---------------------------------------------------------------------------------------------
// Valid plans.

#[test]
fn planner_plans_for_the_paper_instances_are_valid() {
    // Every ablation with the paper's sequencer, and with the default sequencer where it is
    // quick (the default sequencer's exp2 ablations take over a minute each).
    let ablations = [(false, false), (true, false), (false, true), (true, true)];
    let mut cases: Vec<Key> = Vec::new();
    for path in [EXP1, EXP2] {
        for (nd, nm) in ablations {
            cases.push((path, nd, nm, Some(Sequencer::Paper)));
        }
        cases.push((path, false, false, None));
    }
    for (nd, nm) in ablations {
        cases.push((EXP1, nd, nm, None));
    }
    for (path, nd, nm, seq) in cases {
        let (inst, out) = planned_with(path, nd, nm, seq);
        let r = verify(&inst, &out.plan);
        assert!(
            r.is_valid(),
            "{path} no_direct={nd} no_multi_push={nm} sequencer={seq:?}:\n{r}"
        );
        assert_eq!(r.steps_checked, out.plan.actions.len());
        assert!(r.to_string().contains("valid"));
    }
}

#[test]
fn a_plan_survives_a_json_round_trip() {
    let (inst, out) = default_plan(EXP2);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plan.json");
    out.plan.save(&path).unwrap();
    let back = Plan::load(&path).unwrap();
    let r = verify(&inst, &back);
    assert!(r.is_valid(), "{r}");
}

#[test]
fn rebuilding_an_unchanged_plan_keeps_it_valid() {
    // The test harness itself must not introduce violations.
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let plan = rebuild(&inst, &out, actions_of(&inst, &out));
        let r = verify(&inst, &plan);
        assert!(r.is_valid(), "{path}:\n{r}");
    }
}

#[test]
fn report_serialises_classes_in_snake_case() {
    let v = serde_json::to_string(&V::FingerSlab).unwrap();
    assert_eq!(v, "\"finger_slab\"");
    let back: V = serde_json::from_str("\"push_stability\"").unwrap();
    assert_eq!(back, V::PushStability);
    assert_eq!(V::FinalPose.to_string(), "final_pose");
}

// ---------------------------------------------------------------------------------------------
// Format.

#[test]
fn unknown_object_is_a_format_violation_and_stops_the_replay() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    plan.actions[0].objects[0] = "no-such-box".into();
    let r = verify(&inst, &plan);
    assert_only(&r, &[V::Format]);
    assert_eq!(r.steps_checked, 0);
    assert!(r.violations[0].message.contains("no-such-box"), "{r}");
}

#[test]
fn bad_placement_entries_are_format_violations() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    plan.placements.pop();
    let r = verify(&inst, &plan);
    assert_only(&r, &[V::Format]);
    assert_eq!(r.steps_checked, 0);
}

#[test]
fn recorded_release_that_contradicts_the_mode_is_a_format_violation() {
    let (inst, out) = default_plan(EXP2);
    let mut plan = out.plan.clone();
    let k = plan.actions.iter().position(|e| e.kind == "place").unwrap();
    let rel = plan.actions[k].release.as_mut().unwrap();
    rel.x0 += 0.01;
    rel.x1 += 0.01;
    let r = verify(&inst, &plan);
    assert_only(&r, &[V::Format]);
    assert_eq!(r.violations[0].step, Some(k + 1));
}

#[test]
fn misnumbered_steps_wrong_kind_and_foreign_digest_are_format_violations() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    plan.actions[1].step = 7;
    let r = verify(&inst, &plan);
    assert_only(&r, &[V::Format]);
    assert_eq!(r.violations[0].step, Some(2));

    let mut plan = out.plan.clone();
    plan.instance.digest = "0".repeat(64);
    assert_only(&verify(&inst, &plan), &[V::Format]);

    let mut plan = out.plan.clone();
    plan.placements[0].kind = "no-such-kind".into();
    assert_only(&verify(&inst, &plan), &[V::Format]);
}

#[test]
fn ablation_options_are_enforced() {
    // A plan with a direct place that claims to be a no-direct plan.
    let (inst, out) = default_plan(EXP2);
    assert!(
        out.plan.metrics.n_place_direct > 0,
        "the default exp2 plan places directly"
    );
    let mut plan = out.plan.clone();
    plan.options.no_direct = true;
    assert_only(&verify(&inst, &plan), &[V::Format]);
    // And one with a multi-object push that claims to be a no-multi-push plan.
    let (inst, out) = default_plan(EXP1);
    assert!(out.plan.metrics.n_multi_push > 0, "the default exp1 plan pushes a line");
    let mut plan = out.plan.clone();
    plan.options.no_multi_push = true;
    assert_only(&verify(&inst, &plan), &[V::Format]);
}

// ---------------------------------------------------------------------------------------------
// Placement.

#[test]
fn overlapping_targets_are_a_placement_violation() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    // Move the second target onto the first.
    let (x, y) = (plan.placements[0].x, plan.placements[0].y);
    plan.placements[1].x = x;
    plan.placements[1].y = y;
    let r = verify(&inst, &plan);
    assert_has(&r, V::Placement);
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Placement && v.message.contains("overlaps")),
        "{r}"
    );
}

#[test]
fn a_gap_in_the_placement_is_not_bl_stable() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    // Shift the object with the largest x extent further right, leaving a gap on its -x side.
    let k = (0..plan.placements.len())
        .max_by(|&a, &b| {
            let e = |i: usize| plan.placements[i].x + plan.placements[i].size_x;
            e(a).total_cmp(&e(b))
        })
        .unwrap();
    plan.placements[k].x += 0.005;
    assert!(plan.placements[k].x + plan.placements[k].size_x <= inst.container.width);
    let r = verify(&inst, &plan);
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Placement && v.message.contains("BL-stable")),
        "{r}"
    );
}

// ---------------------------------------------------------------------------------------------
// Overlap.

#[test]
fn releasing_on_top_of_another_object_is_an_overlap() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let p = &out.placement.placement;
        let mut actions = actions_of(&inst, &out);
        let floor = inst.container.floor();
        // Find a place whose object could be released (moving it +x or +y from its target) onto
        // an object already in the container.
        let mut found = None;
        'search: for k in 0..actions.len() {
            let Action::Place { object: i, .. } = actions[k] else {
                continue;
            };
            let t = p.targets[i].rect;
            for (j, rj) in occupied_before(&inst, p, &actions, k).into_iter().enumerate() {
                let Some(rj) = rj else { continue };
                for dir in PushDir::ALL {
                    let ax = dir.axis();
                    let offset = rj.lo(ax) - t.lo(ax) + 0.001;
                    if offset <= 0.0 {
                        continue;
                    }
                    let rel = t.moved(dir, -offset);
                    if rel.inside(&floor) && rel.overlaps(&rj) {
                        found = Some((k, i, j, dir, offset));
                        break 'search;
                    }
                }
            }
        }
        let (k, i, j, dir, offset) = found.expect("some place can be moved onto an earlier object");
        if let Action::Place { mode, .. } = &mut actions[k] {
            *mode = PlaceMode::Indirect { push_dir: dir, offset };
        }
        let plan = rebuild(&inst, &out, actions);
        let r = verify(&inst, &plan);
        let hit = r
            .violations
            .iter()
            .find(|v| v.class == V::Overlap)
            .unwrap_or_else(|| panic!("{path}: no overlap reported:\n{r}"));
        assert_eq!(hit.step, Some(k + 1));
        assert!(hit.message.contains(&inst.objects[i].id) && hit.message.contains(&inst.objects[j].id));
    }
}

// ---------------------------------------------------------------------------------------------
// Wall.

#[test]
fn release_outside_the_floor_is_a_wall_violation() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let mut actions = actions_of(&inst, &out);
        let k = actions.iter().position(|a| matches!(a, Action::Place { .. })).unwrap();
        if let Action::Place { mode, .. } = &mut actions[k] {
            *mode = PlaceMode::Indirect {
                push_dir: PushDir::MinusX,
                offset: inst.container.width,
            };
        }
        let r = verify(&inst, &rebuild(&inst, &out, actions));
        assert!(
            r.violations.iter().any(|v| v.class == V::Wall && v.step == Some(k + 1)),
            "{path}:\n{r}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Finger slabs.

#[test]
fn turning_the_grasp_axis_toward_a_wall_is_a_finger_slab_violation() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let p = &out.placement.placement;
        let mut actions = actions_of(&inst, &out);
        // A place whose release touches a wall across its grasp axis: turning the grasp puts a
        // finger into that wall.
        let k = actions
            .iter()
            .position(|a| match a {
                Action::Place {
                    object,
                    mode,
                    grasp_axis,
                    ..
                } => {
                    let t = p.targets[*object].rect;
                    let rel = match mode {
                        PlaceMode::Direct => t,
                        PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
                    };
                    rel.lo(grasp_axis.other()).abs() <= EPS
                }
                _ => false,
            })
            .expect("some release touches a wall");
        if let Action::Place { grasp_axis, .. } = &mut actions[k] {
            *grasp_axis = grasp_axis.other();
        }
        let r = verify(&inst, &rebuild(&inst, &out, actions));
        assert!(
            r.violations
                .iter()
                .any(|v| v.class == V::FingerSlab && v.step == Some(k + 1) && v.message.contains("wall")),
            "{path}:\n{r}"
        );
    }
}

#[test]
fn lowering_the_pusher_into_a_wall_is_a_finger_slab_violation() {
    let (inst, out) = default_plan(EXP1);
    let mut actions = actions_of(&inst, &out);
    let k = actions.iter().position(|a| matches!(a, Action::Push { .. })).unwrap();
    if let Action::Push { pusher_at, .. } = &mut actions[k] {
        *pusher_at = 0.0; // centred on the wall line: half the pusher is inside the wall
    }
    let r = verify(&inst, &rebuild(&inst, &out, actions));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::FingerSlab && v.step == Some(k + 1) && v.message.contains("pusher")),
        "{r}"
    );
}

#[test]
fn too_small_an_offset_is_a_finger_slab_violation() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    let k = plan
        .actions
        .iter()
        .position(|e| e.mode.as_deref() == Some("indirect"))
        .unwrap();
    let off = plan.actions[k].offset.unwrap();
    let small = inst.gripper.min_offset / 2.0;
    plan.actions[k].offset = Some(small);
    // Keep the recorded release consistent so only the offset itself is wrong.
    let d = plan.actions[k].push_dir.unwrap();
    let rel = plan.actions[k].release.unwrap().moved(d, off - small);
    plan.actions[k].release = Some(rel);
    let r = verify(&inst, &plan);
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::FingerSlab && v.message.contains("minimum")),
        "{r}"
    );
}

// ---------------------------------------------------------------------------------------------
// Push stability.

#[test]
fn off_centre_pusher_is_unstable() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let p = &out.placement.placement;
        let mut actions = actions_of(&inst, &out);
        let k = actions.iter().position(|a| matches!(a, Action::Push { .. })).unwrap();
        if let Action::Push {
            objects,
            push_dir,
            pusher_at,
            ..
        } = &mut actions[k]
        {
            // Pusher centred on the back object's lateral edge: the line of action misses it.
            let back = p.targets[*objects.last().unwrap()].rect;
            *pusher_at = back.hi(push_dir.axis().other());
        }
        let plan = rebuild(&inst, &out, actions);
        assert!(plan.actions[k].margin.unwrap() < 0.0);
        let r = verify(&inst, &plan);
        assert!(
            r.violations
                .iter()
                .any(|v| v.class == V::PushStability && v.step == Some(k + 1)),
            "{path}:\n{r}"
        );
    }
}

#[test]
fn a_wrong_recorded_margin_is_reported() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    let k = plan.actions.iter().position(|e| e.kind == "push").unwrap();
    *plan.actions[k].margin.as_mut().unwrap() += 0.001;
    assert_only(&verify(&inst, &plan), &[V::PushStability]);
    plan.actions[k].margin = None;
    assert_only(&verify(&inst, &plan), &[V::PushStability]);
}

#[test]
fn a_stricter_minimum_margin_rejects_the_plan() {
    let (inst, out) = default_plan(EXP1);
    let min = out
        .plan
        .actions
        .iter()
        .filter_map(|e| e.margin)
        .fold(f64::INFINITY, f64::min);
    let mut strict = inst.clone();
    strict.settings.min_push_margin = min + 0.0005;
    assert_only(&verify(&strict, &out.plan), &[V::PushStability]);
}

// ---------------------------------------------------------------------------------------------
// Precedence.

#[test]
fn pushing_before_placing_is_a_precedence_violation() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let mut actions = actions_of(&inst, &out);
        let k = actions.iter().position(|a| matches!(a, Action::Push { .. })).unwrap();
        let push = actions.remove(k);
        actions.insert(0, push);
        let r = verify(&inst, &rebuild(&inst, &out, actions));
        assert!(
            r.violations
                .iter()
                .any(|v| v.class == V::Precedence && v.step == Some(1) && v.message.contains("on the table")),
            "{path}:\n{r}"
        );
        assert_has(&r, V::FinalPose); // the objects stay released, never pushed
    }
}

#[test]
fn placing_twice_and_pushing_twice_are_precedence_violations() {
    let (inst, out) = default_plan(EXP2);
    let actions = actions_of(&inst, &out);
    let first_place = actions
        .iter()
        .find(|a| matches!(a, Action::Place { .. }))
        .unwrap()
        .clone();
    let mut twice = actions.clone();
    twice.push(first_place);
    let r = verify(&inst, &rebuild(&inst, &out, twice));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.step == Some(actions.len() + 1) && v.message.contains("again")),
        "{r}"
    );

    let push = actions
        .iter()
        .find(|a| matches!(a, Action::Push { .. }))
        .unwrap()
        .clone();
    let mut twice = actions.clone();
    twice.push(push);
    let r = verify(&inst, &rebuild(&inst, &out, twice));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.message.contains("already at its target")),
        "{r}"
    );
}

#[test]
fn a_malformed_line_is_a_precedence_violation() {
    let (inst, out) = default_plan(EXP1);
    let actions = actions_of(&inst, &out);
    let k = actions
        .iter()
        .position(|a| matches!(a, Action::Push { objects, .. } if objects.len() >= 2))
        .expect("the exp1 plan pushes a line");
    // Reversed line: targets no longer touch front-to-back.
    let mut rev = actions.clone();
    if let Action::Push { objects, .. } = &mut rev[k] {
        objects.reverse();
    }
    let r = verify(&inst, &rebuild(&inst, &out, rev));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.step == Some(k + 1) && v.message.contains("not a line")),
        "{r}"
    );
    // Wrong distance.
    let mut far = actions.clone();
    if let Action::Push { distance, .. } = &mut far[k] {
        *distance += 0.01;
    }
    let r = verify(&inst, &rebuild(&inst, &out, far));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.message.contains("distance")),
        "{r}"
    );
    // Pushing an object that was released for the other direction.
    let mut other = actions.clone();
    if let Action::Push { objects, push_dir, .. } = &other[k].clone() {
        let i = objects[0];
        for a in other.iter_mut() {
            if let Action::Place {
                object,
                mode: PlaceMode::Indirect { push_dir: d, .. },
                ..
            } = a
            {
                if *object == i {
                    *d = if *push_dir == PushDir::MinusX {
                        PushDir::MinusY
                    } else {
                        PushDir::MinusX
                    };
                }
            }
        }
    }
    let r = verify(&inst, &rebuild(&inst, &out, other));
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.message.contains("released for")),
        "{r}"
    );
}

// ---------------------------------------------------------------------------------------------
// Final pose.

#[test]
fn stopping_before_the_last_push_leaves_objects_off_target() {
    for path in [EXP1, EXP2] {
        let (inst, out) = default_plan(path);
        let mut actions = actions_of(&inst, &out);
        // Drop the last push and everything after it (later places may need its objects gone).
        let k = actions.iter().rposition(|a| matches!(a, Action::Push { .. })).unwrap();
        let dropped = actions[k].objects();
        actions.truncate(k);
        let r = verify(&inst, &rebuild(&inst, &out, actions));
        assert_has(&r, V::FinalPose);
        for i in dropped {
            let id = &inst.objects[i].id;
            assert!(
                r.violations
                    .iter()
                    .any(|v| v.class == V::FinalPose && v.message.starts_with(&format!("{id} ends released"))),
                "{path}: {id} not reported:\n{r}"
            );
        }
        // Only the end state is wrong (the recorded metrics were rebuilt for the shorter plan,
        // but the planner's swept area counts every target, reached or not).
        for v in &r.violations {
            assert!(matches!(v.class, V::FinalPose | V::Metrics), "{path}:\n{r}");
        }
    }
}

#[test]
fn dropping_a_place_leaves_an_object_on_the_table() {
    let (inst, out) = default_plan(EXP2);
    let mut actions = actions_of(&inst, &out);
    let k = actions
        .iter()
        .rposition(|a| {
            matches!(
                a,
                Action::Place {
                    mode: PlaceMode::Direct,
                    ..
                }
            )
        })
        .expect("exp2 places directly");
    let gone = actions.remove(k).objects()[0];
    let r = verify(&inst, &rebuild(&inst, &out, actions));
    assert!(
        r.violations.iter().any(|v| v.class == V::FinalPose
            && v.message.contains(&inst.objects[gone].id)
            && v.message.contains("never placed")),
        "{r}"
    );
}

// ---------------------------------------------------------------------------------------------
// Metrics.

#[test]
fn altered_metrics_are_reported() {
    let (inst, out) = default_plan(EXP2);
    let mut plan = out.plan.clone();
    plan.metrics.travel *= 1.0 + 1e-4;
    // The plan also claims an optimum its altered cost no longer meets.
    assert_only(&verify(&inst, &plan), &[V::Metrics, V::Claim]);
    // Within the 1e-6 relative tolerance is fine.
    let mut plan = out.plan.clone();
    plan.metrics.travel *= 1.0 + 1e-8;
    assert!(verify(&inst, &plan).is_valid());

    for change in 0..5 {
        let mut plan = out.plan.clone();
        match change {
            0 => plan.metrics.seq_len += 1,
            1 => plan.metrics.swept_area += 0.001,
            2 => plan.metrics.n_push += 1,
            3 => plan.actions[0].cost += 0.01,
            _ => plan.placement.occupied_area += 0.001,
        }
        // A changed length, area or occupied area also breaks the claimed bound or gap.
        let r = verify(&inst, &plan);
        let c = classes(&r);
        assert!(
            c.contains(&V::Metrics) && c.iter().all(|x| matches!(x, V::Metrics | V::Claim)),
            "change {change}: {r}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Hand-made scenarios on the 4-object instance: 2a, 2b (6 x 4 x 3 cm) along the front wall,
// 1a, 1b (8 x 5 x 4 cm) behind them.

/// Flat layout: 2a, 2b along the front wall, 1a, 1b behind them, all lying on their largest face.
const FLAT: [(&str, BodyAxis, f64, f64); 4] = [
    ("2a", BodyAxis::Z, 0.0, 0.0),
    ("2b", BodyAxis::Z, 0.06, 0.0),
    ("1a", BodyAxis::Z, 0.0, 0.04),
    ("1b", BodyAxis::Z, 0.08, 0.04),
];

/// One row along the front wall: 2a, 1a standing on end (8 cm high), 2b, 1b standing.
const ROW: [(&str, BodyAxis, f64, f64); 4] = [
    ("2a", BodyAxis::Z, 0.0, 0.0),
    ("1a", BodyAxis::X, 0.06, 0.0),
    ("2b", BodyAxis::Z, 0.11, 0.0),
    ("1b", BodyAxis::X, 0.17, 0.0),
];

/// exp1 with every orientation allowed: the hand-made placements lay the boxes flat, which the
/// bundled file (objects standing, `upright`) does not allow.
fn exp1_any() -> Instance {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(EXP1);
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("orientations = \"upright\"", "orientations = \"any\"");
    Instance::parse(&text, false, EXP1, path.parent()).unwrap()
}

/// A hand-made placement of the 4-object instance: object, vertical body axis, corner.
fn hand_placement(inst: &Instance, layout: &[(&str, BodyAxis, f64, f64)]) -> PlacementResult {
    let mut targets = vec![None; inst.n()];
    for &(id, up, x, y) in layout {
        let up = Orientation { up, yaw90: false };
        let o = &inst.objects[obj(inst, id)];
        let (fp, h) = up.dims(o.size);
        targets[obj(inst, id)] = Some(Target {
            orientation: up,
            rect: Rect::new(x, y, fp[0], fp[1]),
            height: h,
        });
    }
    let placement = Placement {
        targets: targets.into_iter().map(Option::unwrap).collect(),
    };
    assert!(
        placement.violations(inst).is_empty(),
        "{:?}",
        placement.violations(inst)
    );
    // Start from a real result so that fields added to it later need no change here.
    let (_, out) = default_plan(EXP1);
    let mut pr = out.placement.clone();
    pr.placement = placement;
    pr.status = PlacementStatus::Feasible;
    pr.solver = "hand".into();
    pr
}

fn place(inst: &Instance, id: &str, mode: PlaceMode, grasp_axis: Axis2) -> Action {
    let object = obj(inst, id);
    Action::Place {
        object,
        mode,
        grasp_axis,
        arm: pick_arm(inst, object),
    }
}

fn indirect(push_dir: PushDir, offset: f64) -> PlaceMode {
    PlaceMode::Indirect { push_dir, offset }
}

fn push_line(inst: &Instance, ids: &[&str], push_dir: PushDir, distance: f64, pusher_at: f64) -> Action {
    let objects: Vec<usize> = ids.iter().map(|id| obj(inst, id)).collect();
    Action::Push {
        arm: pick_arm(inst, *objects.last().unwrap()),
        objects,
        push_dir,
        distance,
        pusher_at,
    }
}

fn hand_verify(layout: &[(&str, BodyAxis, f64, f64)], actions: Vec<Action>) -> Report {
    let inst = exp1_any();
    let pr = hand_placement(&inst, layout);
    // Flat layouts of boxes that stand on edge on the table: packing conditions are what these
    // tests are about, and a top-down pick could not turn the boxes over.
    let mut opts = PlanOptions::from_instance(&inst);
    opts.packing_only = true;
    let plan = build(&inst, &pr, &opts, actions);
    verify(&inst, &plan)
}

/// 1b and 2b direct; 2a and 1a released staggered for a column push; the pair pushed together
/// with the pusher at `at`.
fn column_pair(inst: &Instance, at: f64) -> Vec<Action> {
    column_pair_gap(inst, at, 0.015)
}

/// [`column_pair`] with 1a released `gap` behind 2a.
fn column_pair_gap(inst: &Instance, at: f64, gap: f64) -> Vec<Action> {
    vec![
        place(inst, "1b", PlaceMode::Direct, Axis2::Y),
        place(inst, "2b", PlaceMode::Direct, Axis2::X),
        place(inst, "2a", indirect(PushDir::MinusY, 0.015), Axis2::Y),
        place(inst, "1a", indirect(PushDir::MinusY, 0.015 + gap), Axis2::Y),
        push_line(inst, &["2a", "1a"], PushDir::MinusY, 0.015 + gap, at),
    ]
}

#[test]
fn hand_made_column_push_is_valid_with_a_centred_pusher() {
    let inst = exp1_any();
    let pr = hand_placement(&inst, &FLAT);
    let at = push::centred_pusher(
        &inst,
        &pr.placement,
        &[obj(&inst, "2a"), obj(&inst, "1a")],
        PushDir::MinusY,
    );
    let r = hand_verify(&FLAT, column_pair(&inst, at));
    assert!(r.is_valid(), "{r}");
}

#[test]
fn every_push_phase_must_be_stable() {
    // Pusher at x = 0.029: the whole pair (friction centroid x ≈ 0.0362) would be pushed with a
    // margin of 0.0028 m > 0.002 m, but the releases are staggered, so 1a first moves alone and
    // its own centroid (x = 0.04) lies 1 mm outside the pusher face [0.019, 0.039]: it turns
    // about the finger's edge while it closes its gap. Over 30 mm that is about 1.4°, beyond
    // the default 1° (docs/push_stability.md §5.4).
    let (inst, _) = default_plan(EXP1);
    let r = hand_verify(&FLAT, column_pair_gap(&inst, 0.029, 0.03));
    assert_only(&r, &[V::PushStability]);
    assert_eq!(r.violations[0].step, Some(5));
    let m = &r.violations[0].message;
    assert!(
        m.contains("1a alone turns") && m.contains("30.0000 mm gap") && m.contains("% of the limits"),
        "{r}"
    );
}

#[test]
fn a_short_phase_is_judged_by_its_travel_and_recorded() {
    // The same push with a 15 mm gap: 1a turns about 0.7° and drifts 0.3 mm before it meets 2a,
    // within the default 1° and 1 mm, so the push's margin is the closed-up pair's.
    let inst = exp1_any();
    let pr = hand_placement(&inst, &FLAT);
    let mut opts = PlanOptions::from_instance(&inst);
    opts.packing_only = true;
    let plan = build(&inst, &pr, &opts, column_pair_gap(&inst, 0.029, 0.015));
    let r = verify(&inst, &plan);
    assert!(r.is_packing_valid(), "{r}");
    let e = &plan.actions[4];
    let t = e
        .travel_phase
        .as_ref()
        .expect("the back object's phase is judged by its travel");
    assert_eq!(t.object, "1a");
    assert!((t.gap - 0.015).abs() < 1e-12);
    assert!((0.5..0.9).contains(&t.rotation.to_degrees()) && t.usage < 1.0, "{t:?}");
    assert!((e.margin.unwrap() - 0.0028).abs() < 1e-4, "{:?}", e.margin);
    // A stricter rotation limit from the instance rejects it, naming the phase and its usage.
    let mut strict = inst.clone();
    strict.settings.max_push_rotation = 0.5f64.to_radians();
    let r = verify(&strict, &plan);
    assert_has(&r, V::PushStability);
    assert!(
        r.violations
            .iter()
            .any(|v| v.message.contains("1a alone turns") && v.step == Some(5)),
        "{r}"
    );
    // A tampered record of the phase is caught, and so is a missing one.
    let mut tampered = plan.clone();
    tampered.actions[4].travel_phase.as_mut().unwrap().usage *= 0.5;
    assert_only(&verify(&inst, &tampered), &[V::PushStability]);
    tampered.actions[4].travel_phase = None;
    assert_only(&verify(&inst, &tampered), &[V::PushStability]);
}

#[test]
fn a_push_through_another_object_is_a_swept_space_violation() {
    let (inst, _) = default_plan(EXP1);
    // 2a released far to the right of 2b and pushed -x: it sweeps through 2b.
    let actions = vec![
        place(&inst, "1a", PlaceMode::Direct, Axis2::Y),
        place(&inst, "1b", PlaceMode::Direct, Axis2::Y),
        place(&inst, "2b", PlaceMode::Direct, Axis2::X),
        place(&inst, "2a", indirect(PushDir::MinusX, 0.14), Axis2::X),
        push_line(&inst, &["2a"], PushDir::MinusX, 0.14, 0.02),
    ];
    let r = hand_verify(&FLAT, actions);
    assert_only(&r, &[V::SweptSpace]);
    assert!(
        r.violations
            .iter()
            .all(|v| v.step == Some(5) && v.message.contains("2b")),
        "{r}"
    );
    // Both the object's sweep and the pusher's sweep are reported.
    assert!(r.violations.iter().any(|v| v.message.contains("pusher")), "{r}");
    assert!(r.violations.iter().any(|v| v.message.contains("sweeps 2a")), "{r}");
}

#[test]
fn a_finger_beside_a_taller_object_is_blocked() {
    // 2b (3 cm high) first, then 1b directly with fingers along y: the -y finger goes down to
    // 4 - 1.5 = 2.5 cm, below 2b's top.
    let inst = exp1_any();
    let pr = hand_placement(&inst, &FLAT);
    let at = push::centred_pusher(
        &inst,
        &pr.placement,
        &[obj(&inst, "2a"), obj(&inst, "1a")],
        PushDir::MinusY,
    );
    let mut actions = column_pair(&inst, at);
    actions.swap(0, 1);
    let r = hand_verify(&FLAT, actions);
    assert_only(&r, &[V::FingerSlab]);
    assert!(
        r.violations[0].message.contains("2b") && r.violations[0].step == Some(2),
        "{r}"
    );
}

#[test]
fn an_object_wider_than_the_gripper_opening_is_a_finger_slab_violation() {
    let (inst, out) = default_plan(EXP1);
    let p = &out.placement.placement;
    // Narrow the gripper just below the widest grasp of the plan.
    let (k, widest) = actions_of(&inst, &out)
        .iter()
        .enumerate()
        .filter_map(|(k, a)| match a {
            Action::Place { object, grasp_axis, .. } => Some((k, p.targets[*object].rect.extent(*grasp_axis))),
            _ => None,
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    let mut narrow = inst.clone();
    narrow.gripper.max_opening = widest + 2.0 * inst.gripper.release_clearance - 0.001;
    let r = verify(&narrow, &out.plan);
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::FingerSlab && v.step == Some(k + 1) && v.message.contains("opening")),
        "{r}"
    );
}

#[test]
fn offsets_decreasing_toward_the_back_of_a_line_are_a_precedence_violation() {
    let inst = exp1_any();
    let pr = hand_placement(&inst, &FLAT);
    let at = push::centred_pusher(
        &inst,
        &pr.placement,
        &[obj(&inst, "2a"), obj(&inst, "1a")],
        PushDir::MinusY,
    );
    let mut actions = column_pair(&inst, at);
    actions[2] = place(&inst, "2a", indirect(PushDir::MinusY, 0.03), Axis2::Y);
    actions[3] = place(&inst, "1a", indirect(PushDir::MinusY, 0.015), Axis2::Y);
    actions[4] = push_line(&inst, &["2a", "1a"], PushDir::MinusY, 0.015, at);
    let r = hand_verify(&FLAT, actions);
    assert!(
        r.violations
            .iter()
            .any(|v| v.class == V::Precedence && v.step == Some(5) && v.message.contains("decrease")),
        "{r}"
    );
    assert_has(&r, V::Overlap); // the releases of such a line necessarily overlap
}

#[test]
fn a_finger_above_a_lower_object_is_not_blocked() {
    // 1a and 1b stand 8 cm high: their fingers reach down to 8 - 1.5 = 6.5 cm, above the 3 cm
    // high 2a and 2b beside them, so they can be placed directly against them (3-D check).
    let (inst, _) = default_plan(EXP1);
    let actions = vec![
        place(&inst, "2a", indirect(PushDir::MinusX, 0.015), Axis2::X),
        push_line(&inst, &["2a"], PushDir::MinusX, 0.015, 0.02),
        place(&inst, "1a", PlaceMode::Direct, Axis2::X),
        place(&inst, "2b", indirect(PushDir::MinusX, 0.015), Axis2::X),
        push_line(&inst, &["2b"], PushDir::MinusX, 0.015, 0.02),
        place(&inst, "1b", PlaceMode::Direct, Axis2::X),
    ];
    let r = hand_verify(&ROW, actions.clone());
    assert!(r.is_valid(), "{r}");
    // The same with 2b placed directly while 1a is already there: 2b's -x finger (from
    // 3 - 1.5 = 1.5 cm up) would go into 1a.
    let mut blocked = actions;
    blocked[3] = place(&inst, "2b", PlaceMode::Direct, Axis2::X);
    blocked.remove(4);
    let r = hand_verify(&ROW, blocked);
    assert_only(&r, &[V::FingerSlab]);
    assert!(
        r.violations
            .iter()
            .all(|v| v.step == Some(4) && v.message.contains("1a")),
        "{r}"
    );
}

#[test]
fn every_violation_is_reported_not_just_the_first() {
    let (inst, out) = default_plan(EXP1);
    let mut plan = out.plan.clone();
    plan.metrics.travel += 1.0;
    plan.metrics.seq_len += 1;
    let k = plan.actions.iter().position(|e| e.kind == "push").unwrap();
    *plan.actions[k].margin.as_mut().unwrap() += 0.001;
    plan.actions[0].step = 99;
    let r = verify(&inst, &plan);
    // The claimed optimum no longer meets its bound either.
    assert_only(&r, &[V::Claim, V::Format, V::PushStability, V::Metrics]);
    assert_eq!(r.violations.iter().filter(|v| v.class == V::Metrics).count(), 2);
    let text = r.to_string();
    assert!(
        text.contains("INVALID") && text.contains("push_stability") && text.contains("step 1"),
        "{text}"
    );
}

// ---------------------------------------------------------------------------------------------
// Phases judged by their travel (docs/push_stability.md §5.4), issue 25's two lines: the back box
// of a two-box line, pushed 30 mm off its centre line by the finger centred on the line's
// friction centroid, first closes a gap alone.

/// The line of `instances/pushes/short_phase_passes.json` in a container: front `f` (100 ×
/// 100 mm, 1.5 kg) and back `b` (100 × 100 mm, 0.5 kg) in a −x line, `b` 40 mm to the −y side of
/// `f`; `c` under `f` and `d` under `b` hold them Bottom-Left stable.
fn travel_pair_instance() -> Instance {
    let text = r#"
name = "travel-pair"
[container]
width = 0.30
depth = 0.20
wall_height = 0.10
wall_thickness = 0.01
center = [0.30, 0.0]
[friction]
mu_floor = 0.5
mu_obj = 0.5
mu_finger = 0.5
[gripper]
finger_thickness = 0.01
finger_width = 0.02
finger_length = 0.06
max_opening = 0.12
grasp_depth = 0.015
release_clearance = 0.005
[[kinds]]
name = "heavy"
size = [0.1, 0.1, 0.05]
mass = 1.5
[[kinds]]
name = "light"
size = [0.1, 0.1, 0.05]
mass = 0.5
[[kinds]]
name = "wide"
size = [0.1, 0.065, 0.05]
mass = 0.2
[[kinds]]
name = "thin"
size = [0.1, 0.025, 0.05]
mass = 0.2
[[objects]]
id = "f"
kind = "heavy"
x = 0.20
y = 0.27
[[objects]]
id = "b"
kind = "light"
x = 0.36
y = 0.30
[[objects]]
id = "c"
kind = "wide"
x = 0.20
y = -0.27
[[objects]]
id = "d"
kind = "thin"
x = 0.36
y = -0.30
"#;
    Instance::parse(text, false, "travel_pair.toml", None).unwrap()
}

/// The four objects at their targets: `c` [0, 0.1] × [0, 0.065], `f` above it, `d` [0.1, 0.2]
/// × [0, 0.025], `b` above it; the f–b line overlaps over y ∈ [0.065, 0.125].
fn travel_pair_placement(inst: &Instance) -> PlacementResult {
    let up = Orientation {
        up: BodyAxis::Z,
        yaw90: false,
    };
    let at = |id: &str, x: f64, y: f64| {
        let (fp, h) = up.dims(inst.objects[obj(inst, id)].size);
        (
            obj(inst, id),
            Target {
                orientation: up,
                rect: Rect::new(x, y, fp[0], fp[1]),
                height: h,
            },
        )
    };
    let mut targets: Vec<(usize, Target)> = vec![
        at("f", 0.0, 0.065),
        at("b", 0.1, 0.025),
        at("c", 0.0, 0.0),
        at("d", 0.1, 0.0),
    ];
    targets.sort_by_key(|t| t.0);
    let placement = Placement {
        targets: targets.into_iter().map(|t| t.1).collect(),
    };
    common::hand_result(inst, placement)
}

/// `c` pushed in; `f` released 15 mm out, `b` `gap` behind it (fingers on its y faces, so the gap
/// can be tiny), the pair pushed with the finger at their friction centroid y = 0.105, 30 mm off
/// `b`'s centre line; then `d`.
fn travel_pair_actions(inst: &Instance, gap: f64) -> Vec<Action> {
    let x = PushDir::MinusX;
    vec![
        place(inst, "c", indirect(x, 0.015), Axis2::X),
        push_line(inst, &["c"], x, 0.015, 0.0325),
        place(inst, "f", indirect(x, 0.015), Axis2::X),
        place(inst, "b", indirect(x, 0.015 + gap), Axis2::Y),
        push_line(inst, &["f", "b"], x, 0.015 + gap, 0.105),
        place(inst, "d", indirect(x, 0.015), Axis2::X),
        push_line(inst, &["d"], x, 0.015, 0.0125),
    ]
}

#[test]
fn the_back_box_closing_a_short_gap_alone_is_judged_by_its_travel_in_the_planner_and_the_verifier() {
    use pushpack::actions::Layout;
    let inst = travel_pair_instance();
    let pr = travel_pair_placement(&inst);
    let p = &pr.placement;
    let pair = [obj(&inst, "f"), obj(&inst, "b")];
    assert!((push::centred_pusher(&inst, p, &pair, PushDir::MinusX) - 0.105).abs() < 1e-12);
    let mut opts = PlanOptions::from_instance(&inst);
    opts.packing_only = true;
    for (gap, stable) in [(0.0002, true), (0.01, false)] {
        let actions = travel_pair_actions(&inst, gap);
        // The planner's own feasibility check, step by step.
        let mut layout = Layout::new(&inst, p);
        for a in &actions[..4] {
            layout.check(a).unwrap_or_else(|e| panic!("gap {gap}: {a:?}: {e:?}"));
            layout.apply(a);
        }
        let verdict = layout.push_verdict(&pair, PushDir::MinusX, 0.105);
        let t = verdict.travel.clone().expect("b's phase alone is judged by its travel");
        assert_eq!(layout.check(&actions[4]).is_ok(), stable, "gap {gap}: {verdict:?}");
        assert_eq!(t.passes, stable);
        // The verifier on the whole plan.
        let plan = build(&inst, &pr, &opts, actions);
        let r = verify(&inst, &plan);
        if stable {
            // 0.058° and 0.05 mm: far inside 1° and 1 mm; the closed-up pair's 10 mm margin is
            // the push's.
            assert!(r.is_packing_valid(), "{r}");
            assert!(t.rotation.to_degrees() < 0.07 && t.usage < 0.1, "{t:?}");
            assert!((verdict.margin - 0.01).abs() < 1e-7, "{verdict:?}");
            let rec = plan.actions[4].travel_phase.as_ref().expect("recorded");
            assert_eq!(rec.object, "b");
            assert!((rec.usage - t.usage).abs() < 1e-12);
        } else {
            // About 3°: the box visibly turns before it meets f.
            assert!((2.5..3.5).contains(&t.rotation.to_degrees()), "{t:?}");
            assert_only(&r, &[V::PushStability]);
            let v = &r.violations[0];
            assert_eq!(v.step, Some(5));
            assert!(
                v.message.contains("b alone turns") && v.message.contains("10.0000 mm gap"),
                "{r}"
            );
        }
    }
}

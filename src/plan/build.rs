//! Assembling the plan file from the stages' results: targets, action entries with their key
//! points and costs, statistics, and the joint trajectories.

use super::file::*;
use super::{placement_status, sequence_status, PlanOptions};
use crate::actions::{Action, PlaceMode};
use crate::control::{Event, Listener, Silent, Stage, Ticker};
use crate::geometry::Arm;
use crate::instance::Instance;
use crate::motion::keypoints::{action_keypoints, path_length};
use crate::placement::{Placement, PlacementResult};
use crate::sequence::SequenceResult;
use crate::status::Status;

/// Assemble the plan file from stage results.
pub fn build_plan(inst: &Instance, opts: &PlanOptions, pr: &PlacementResult, sr: &SequenceResult) -> Plan {
    build_plan_with(inst, opts, pr, sr, &mut Silent)
}

/// [`build_plan`], telling `listener` how the joint plan goes: [`Event::Progress`] with stage
/// [`Stage::Motion`] and `nodes` = actions planned so far, at most every
/// [`crate::control::PROGRESS_INTERVAL`].
pub fn build_plan_with(
    inst: &Instance,
    opts: &PlanOptions,
    pr: &PlacementResult,
    sr: &SequenceResult,
    listener: &mut dyn Listener,
) -> Plan {
    let p = &pr.placement;
    let placements = placement_entries(inst, p);
    let actions = action_entries(inst, p, sr);
    let mut ticker = Ticker::new();
    let mut planned = |k: usize| {
        if ticker.due() {
            listener.event(&Event::Progress {
                stage: Stage::Motion,
                nodes: k as u64,
                incumbent: None,
                bound: None,
            });
        }
    };
    let (robot, trajectories) = crate::robot::ik::with_threads(opts.threads, || {
        crate::motion::plan_trajectories_with(inst, p, &sr.actions, &opts.trajectory, &mut planned)
    });
    let placement_status = placement_status(pr);
    let (sequence_status, sequence_stop) = sequence_status(opts.sequencer, sr.status);
    Plan {
        format_version: FORMAT_VERSION,
        tool: ToolInfo {
            name: "pushpack".into(),
            version: env!("CARGO_PKG_VERSION").into(),
        },
        instance: InstanceRef {
            name: inst.name.clone(),
            source: inst.source.clone(),
            digest: inst.digest.clone(),
        },
        status: Status::combine(&[placement_status, sequence_status]),
        options: opts.clone(),
        placement: PlacementSummary {
            status: placement_status,
            occupied_area: p.occupied_area(),
            lower_bound: pr.lower_bound,
            gap: pr.gap(),
            contact_length: p.contact_length(inst),
            solver: pr.solver.clone(),
            alternative: 0,
        },
        placements,
        actions,
        metrics: sr.metrics,
        solver: SolverStats {
            placement: StageStats {
                status: placement_status,
                stopped_by: None,
                time_s: pr.time_s,
                nodes: pr.nodes,
                bound: Some(pr.lower_bound),
                gap: Some(pr.gap()),
                assignments: None,
                cost_bound: None,
                physics_vetoes: Vec::new(),
            },
            sequence: StageStats {
                status: sequence_status,
                stopped_by: sequence_stop,
                time_s: sr.time_s,
                nodes: sr.nodes,
                bound: sr.bound.map(|b| b.travel),
                gap: sr.bound.map(|b| {
                    if b.len == sr.metrics.seq_len
                        && (b.area - sr.metrics.swept_area).abs() <= 1e-12
                        && sr.metrics.travel > 0.0
                    {
                        ((sr.metrics.travel - b.travel) / sr.metrics.travel).max(0.0)
                    } else {
                        1.0
                    }
                }),
                assignments: Some(sr.assignments),
                cost_bound: sr.bound,
                physics_vetoes: Vec::new(),
            },
        },
        robot: Some(robot),
        trajectories,
    }
}

/// One target per object, in instance order, named by id and kind.
fn placement_entries(inst: &Instance, p: &Placement) -> Vec<PlacementEntry> {
    p.targets
        .iter()
        .enumerate()
        .map(|(i, t)| PlacementEntry {
            object: inst.objects[i].id.clone(),
            kind: inst.kinds[inst.objects[i].kind].name.clone(),
            orientation: t.orientation,
            x: t.rect.x0,
            y: t.rect.y0,
            size_x: t.rect.width(),
            size_y: t.rect.depth(),
            height: t.height,
        })
        .collect()
}

/// The actions in order with their key poses and costs; each push with its margin and, replayed
/// along the actions, its travel phase (which depends on where its objects were released).
fn action_entries(inst: &Instance, p: &Placement, sr: &SequenceResult) -> Vec<ActionEntry> {
    let mut pos = [inst.robot.home_tcp(Arm::Left), inst.robot.home_tcp(Arm::Right)];
    // Replayed along the actions: a push's travel phase depends on where its objects were released.
    let mut layout = crate::actions::Layout::new(inst, p);
    sr.actions
        .iter()
        .zip(&sr.margins)
        .enumerate()
        .map(|(k, (a, m))| {
            let kps = action_keypoints(inst, p, a);
            let (cost, end) = path_length(&pos[a.arm().index()], &kps);
            pos[a.arm().index()] = end;
            let ids = a.objects().iter().map(|&i| inst.objects[i].id.clone()).collect();
            let entry = match a {
                Action::Place {
                    object,
                    mode,
                    grasp_axis,
                    arm,
                } => {
                    let (mode_s, dir, off) = match mode {
                        PlaceMode::Direct => ("direct", None, None),
                        PlaceMode::Indirect { push_dir, offset } => ("indirect", Some(*push_dir), Some(*offset)),
                    };
                    ActionEntry {
                        step: k + 1,
                        kind: "place".into(),
                        objects: ids,
                        mode: Some(mode_s.into()),
                        push_dir: dir,
                        offset: off,
                        distance: None,
                        grasp_axis: Some(*grasp_axis),
                        pusher_at: None,
                        release: Some(layout.release_rect(*object, mode)),
                        margin: None,
                        push_model: None,
                        travel_phase: None,
                        arm: *arm,
                        cost,
                        key_poses: kps,
                    }
                }
                Action::Push {
                    objects,
                    push_dir,
                    distance,
                    pusher_at,
                    arm,
                } => ActionEntry {
                    step: k + 1,
                    kind: "push".into(),
                    objects: ids,
                    mode: None,
                    push_dir: Some(*push_dir),
                    offset: None,
                    distance: Some(*distance),
                    grasp_axis: None,
                    pusher_at: Some(*pusher_at),
                    release: None,
                    margin: *m,
                    push_model: Some("2d".into()),
                    travel_phase: layout
                        .push_verdict(objects, *push_dir, *pusher_at)
                        .travel
                        .map(|t| TravelPhase {
                            object: inst.objects[*objects.last().expect("non-empty")].id.clone(),
                            gap: t.travel,
                            rotation: t.rotation,
                            drift: t.drift,
                            usage: t.usage,
                        }),
                    arm: *arm,
                    cost,
                    key_poses: kps,
                },
            };
            layout.apply(a);
            entry
        })
        .collect()
}

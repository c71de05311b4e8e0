//! The planner's reach predicate sees the objects already packed: in a cell whose objects stand
//! taller than the hand housing comes down at a push, an action whose hand would hit a packed
//! neighbour is refused in that state and allowed while the neighbour is still on the table,
//! and the joint plan agrees on both.

mod common;

use pushpack::actions::{Action, ObjState, PlaceMode};
use pushpack::geometry::{Axis2, BodyAxis, Orientation, PushDir, Rect};
use pushpack::motion::plan_trajectories;
use pushpack::motion::reach_cache::ReachCache;
use pushpack::motion::trajectory::TrajectoryOptions;
use pushpack::placement::{Placement, Target};
use pushpack::plan::{sequence_placement, PlanOptions};
use pushpack::robot::Arm;
use pushpack::verify::verify;

/// A 11.5 cm tower (walls 12 cm) and a 3 cm block in the container: a push of the block at
/// 5 mm puts the hand housing (0.10 m above the fingertips) 10.5 cm above the floor.
const CELL: &str = r#"
format_version = 1
name = "tall-neighbour"
[container]
width = 0.30
depth = 0.20
wall_height = 0.12
wall_thickness = 0.01
center = [0.30, 0.0]
[friction]
mu_floor = 0.35
mu_obj = 0.4
mu_finger = 0.6
[gripper]
finger_thickness = 0.01
finger_width = 0.02
finger_length = 0.06
max_opening = 0.09
grasp_depth = 0.015
release_clearance = 0.005
[[kinds]]
name = "tower"
size = [0.06, 0.05, 0.115]
mass = 0.1
[[kinds]]
name = "base"
size = [0.06, 0.05, 0.03]
mass = 0.05
[[kinds]]
name = "block"
size = [0.06, 0.04, 0.03]
mass = 0.05
[[objects]]
id = "tower"
kind = "tower"
x = 0.25
y = 0.30
[[objects]]
id = "block"
kind = "block"
x = 0.25
y = -0.28
[[objects]]
id = "b0"
kind = "base"
x = 0.35
y = -0.28
[[objects]]
id = "b1"
kind = "base"
x = 0.35
y = 0.28
"#;

fn target(x: f64, y: f64, w: f64, d: f64, h: f64) -> Target {
    Target {
        orientation: Orientation {
            up: BodyAxis::Z,
            yaw90: false,
        },
        rect: Rect::new(x, y, w, d),
        height: h,
    }
}

/// The block pushed −x by 3 cm to x ∈ [0.10, 0.16]; the tower 1.5 cm behind the pusher's back
/// face at the push start (the pusher plate is at x ∈ [0.195, 0.205]; the tower from 0.22):
/// room for the plate, not for the housing above it, which hangs 0.10 m above the fingertips.
fn cell() -> (pushpack::instance::Instance, Placement) {
    let inst = common::parse(CELL);
    let placement = Placement {
        targets: vec![
            target(0.22, 0.06, 0.06, 0.05, 0.115),
            target(0.10, 0.06, 0.06, 0.04, 0.03),
            target(0.0, 0.0, 0.06, 0.05, 0.03),
            target(0.06, 0.0, 0.06, 0.05, 0.03),
        ],
    };
    (inst, placement)
}

const OFFSET: f64 = 0.03;

fn place(object: usize, mode: PlaceMode, arm: Arm) -> Action {
    Action::Place {
        object,
        mode,
        grasp_axis: Axis2::Y,
        arm,
    }
}

fn push(arm: Arm) -> Action {
    Action::Push {
        objects: vec![1],
        push_dir: PushDir::MinusX,
        distance: OFFSET,
        pusher_at: 0.08,
        arm,
    }
}

#[test]
fn a_push_whose_hand_would_hit_a_packed_tower_is_refused_once_the_tower_is_there() {
    let (inst, placement) = cell();
    let reach = ReachCache::new(&inst, &placement);
    let released = ObjState::Released {
        rect: placement.targets[1].rect.moved(PushDir::MinusX, -OFFSET),
        push_dir: PushDir::MinusX,
        offset: OFFSET,
    };
    let indirect = PlaceMode::Indirect {
        push_dir: PushDir::MinusX,
        offset: OFFSET,
    };
    let mut checked = 0;
    for arm in [Arm::Left, Arm::Right] {
        let a = push(arm);
        if !reach.ok(&a) {
            continue;
        }
        checked += 1;
        assert!(
            reach.ok_when(&a, &[ObjState::Table, released, ObjState::Table, ObjState::Table]),
            "{arm:?}: the tower is still on the table"
        );
        assert!(
            !reach.ok_when(&a, &[ObjState::Done, released, ObjState::Table, ObjState::Table]),
            "{arm:?}: the tower is packed behind the pusher"
        );
        // The joint plan agrees on both orders.
        let opts = TrajectoryOptions::default();
        let tower_first = [
            place(0, PlaceMode::Direct, Arm::Left),
            place(1, indirect, Arm::Right),
            push(arm),
        ];
        let (_, tr) = plan_trajectories(&inst, &placement, &tower_first, &opts);
        let pushed = tr.iter().find(|t| t.action == Some(2)).expect("a record of the push");
        let why = pushed.error.as_deref().unwrap_or_default();
        assert!(
            why.contains("tower"),
            "{arm:?}: the joint plan must fail on the tower, got {:?}",
            pushed.error
        );
        let tower_last = [
            place(1, indirect, Arm::Right),
            push(arm),
            place(0, PlaceMode::Direct, Arm::Left),
        ];
        let (_, tr) = plan_trajectories(&inst, &placement, &tower_last, &opts);
        assert!(
            tr.iter().all(|t| t.error.is_none()),
            "{arm:?}: {:?}",
            tr.iter().map(|t| &t.error).collect::<Vec<_>>()
        );
    }
    assert!(checked > 0, "some arm reaches the push");
}

/// End to end in a tall cell: the plan the planner finds passes the independent verifier as
/// executable, and no push runs while the tower (placed last) stands in the container.
#[test]
fn the_planner_packs_the_tall_cell_in_an_order_the_robot_can_run() {
    let (inst, _) = cell();
    // Bottom row: b0, b1, tower; the block above b0, pushed −x into the corner.
    let placement = Placement {
        targets: vec![
            target(0.12, 0.0, 0.06, 0.05, 0.115),
            target(0.0, 0.05, 0.06, 0.04, 0.03),
            target(0.0, 0.0, 0.06, 0.05, 0.03),
            target(0.06, 0.0, 0.06, 0.05, 0.03),
        ],
    };
    let opts = PlanOptions::from_instance(&inst);
    let out = sequence_placement(&inst, &opts, common::hand_result(&inst, placement)).expect("a plan");
    let report = verify(&inst, &out.plan);
    assert!(report.is_executable(), "{report}");
    let order: Vec<(String, Vec<String>)> = out
        .plan
        .actions
        .iter()
        .map(|a| (a.kind.clone(), a.objects.clone()))
        .collect();
    let tower = order
        .iter()
        .position(|(_, o)| o.contains(&"tower".to_string()))
        .expect("the tower is placed");
    let pushes: Vec<usize> = (0..order.len()).filter(|&k| order[k].0 == "push").collect();
    assert!(pushes.iter().all(|&k| k < tower), "pushes before the tower: {order:?}");
}

//! Robot stage throughput: IK solves per second (warm-started along a path, as the joint planner
//! uses it, and cold with every seed, as the reachability predicate starts), and the time to
//! produce the whole joint plan of the paper's second experiment (8 objects, 10 actions), and
//! the action planner's reachability predicate over all of its place actions.
//!
//! `cargo bench --bench robot -- --warm-up-time 1 --measurement-time 5`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nalgebra::Vector3;
use pushpack::actions::{Action, PlaceMode};
use pushpack::geometry::{Axis2, PushDir};
use pushpack::instance::Instance;
use pushpack::motion::{plan_trajectories, TrajectoryOptions};
use pushpack::plan::{optimize, PlanOptions};
use pushpack::robot::ik::{top_down_pose, IkSolver};
use pushpack::robot::{Arm, RobotModel, DEFAULT_TCP_OFFSET};
use std::hint::black_box;

/// 64 top-down targets over the container and the left half of the table.
fn targets() -> Vec<nalgebra::Isometry3<f64>> {
    let mut v = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            let p = Vector3::new(
                0.18 + 0.025 * i as f64,
                -0.08 + 0.06 * j as f64,
                -0.17 + 0.01 * (i % 3) as f64,
            );
            v.push(top_down_pose(&p, 0.2 * j as f64));
        }
    }
    v
}

fn bench(c: &mut Criterion) {
    let model = RobotModel::bundled();
    let solver = IkSolver::new(&model, Arm::Left, &DEFAULT_TCP_OFFSET);
    let ts = targets();
    let sols: Vec<[f64; 6]> = ts.iter().map(|t| solver.solve(t).expect("reachable")).collect();
    let mut g = c.benchmark_group("ik");
    g.throughput(Throughput::Elements(ts.len() as u64));
    // Warm start: each target from the solution of its neighbour in the same row (6 cm and
    // 0.2 rad of yaw away), as along a path.
    g.bench_function(BenchmarkId::new("solve_near", ts.len()), |b| {
        b.iter(|| {
            for k in 0..ts.len() {
                let prev = if k % 8 == 0 { &sols[k + 1] } else { &sols[k - 1] };
                black_box(solver.solve_near(black_box(&ts[k]), prev).ok());
            }
        })
    });
    // Cold: every seed tried, the solution with the largest joint margin kept.
    g.bench_function(BenchmarkId::new("solve_all_seeds", ts.len()), |b| {
        b.iter(|| {
            for t in &ts {
                black_box(solver.solve(black_box(t)).ok());
            }
        })
    });
    // First solution from any seed.
    g.bench_function(BenchmarkId::new("solve_any", ts.len()), |b| {
        b.iter(|| {
            for t in &ts {
                black_box(solver.solve_any(black_box(t)).ok());
            }
        })
    });
    g.finish();

    let path = format!("{}/instances/paper/exp2_8objects.toml", env!("CARGO_MANIFEST_DIR"));
    let inst = Instance::load(&path).expect("exp2 loads");
    let out = optimize(&inst, &PlanOptions::from_instance(&inst)).expect("exp2 plans");
    let placement = out.placement.placement.clone();
    let actions = out.sequence.actions.clone();
    let mut g = c.benchmark_group("joint_plan");
    g.sample_size(10);
    g.bench_function("exp2_8objects", |b| {
        b.iter(|| plan_trajectories(&inst, &placement, black_box(&actions), &TrajectoryOptions::default()))
    });
    g.bench_function("exp2_8objects_check", |b| {
        b.iter(|| pushpack::verify::trajectories::check_trajectories(&inst, black_box(&out.plan)))
    });
    g.finish();

    // The action planner's reachability predicate over every place action of exp2's placement
    // (13 release modes × 2 grasp axes per object), without and with the shared IK memo.
    let mut places = Vec::new();
    for i in 0..inst.n() {
        let mut modes = vec![PlaceMode::Direct];
        for d in PushDir::ALL {
            for k in 1..=3 {
                modes.push(PlaceMode::Indirect {
                    push_dir: d,
                    offset: inst.gripper.min_offset * k as f64,
                });
            }
        }
        for mode in modes {
            for grasp_axis in [Axis2::X, Axis2::Y] {
                places.push(Action::Place {
                    object: i,
                    mode,
                    grasp_axis,
                    arm: pushpack::motion::keypoints::pick_arm(&inst, i),
                });
            }
        }
    }
    let mut g = c.benchmark_group("reach_predicate");
    g.sample_size(10);
    g.throughput(Throughput::Elements(places.len() as u64));
    g.bench_function(BenchmarkId::new("action_reach", places.len()), |b| {
        b.iter(|| {
            places
                .iter()
                .filter(|a| pushpack::motion::joint_plan::action_reach(&inst, &placement, a).is_some())
                .count()
        })
    });
    g.bench_function(BenchmarkId::new("reach_cache", places.len()), |b| {
        b.iter(|| {
            let cache = pushpack::motion::reach_cache::ReachCache::new(&inst, &placement);
            places.iter().filter(|a| cache.ok(a)).count()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

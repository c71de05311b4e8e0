//! An integrator's program: build an instance in code, plan it under a deadline and a cancel
//! flag, inspect the actions and the joint trajectories, verify, and handle every error.
//!
//! Needs only the library (`pushpack = { default-features = false }`):
//! `cargo run --release --example integrator --no-default-features`.

use pushpack::control::{CancelFlag, Event, Recorder};
use pushpack::instance::{InstanceBuilder, Orientations, Units};
use pushpack::plan::{optimize_with, PlanOptions};
use pushpack::verify::verify;
use pushpack::Error;
use std::process::ExitCode;

/// The cell's boxes, in millimetres, as a cell controller would hand them over.
fn build(sizes: &[[f64; 3]]) -> Result<pushpack::instance::Instance, Error> {
    let mut b = InstanceBuilder::new("integrator-demo")
        .units(Units::Millimetres)
        .container(300.0, 200.0, 100.0, 10.0, [300.0, 0.0])
        .friction(0.35, 0.4, 0.6)
        .gripper_mm_default()
        .seed(7)
        .time_limit(10.0);
    for (k, s) in sizes.iter().enumerate() {
        b = b.kind(format!("k{k}"), *s, 0.05);
    }
    // Table slots in each arm's zone (y > 0 left, y < 0 right).
    let slots = [[230.0, 280.0], [230.0, -280.0], [310.0, 280.0], [310.0, -280.0]];
    for (k, xy) in slots.iter().enumerate().take(sizes.len()) {
        b = b.object(format!("box{k}"), format!("k{k}"), *xy, Orientations::Upright);
    }
    b.build()
}

fn run() -> Result<ExitCode, Error> {
    // Bad input is an error that names the field, never a panic or a silently wrong plan.
    match build(&[[60.0, -40.0, 30.0]]) {
        Err(e @ Error::Input { .. }) => println!("rejected as expected: {e}"),
        other => panic!("a negative edge must be rejected, got {other:?}"),
    }

    let inst = build(&[
        [60.0, 40.0, 30.0],
        [60.0, 40.0, 30.0],
        [50.0, 40.0, 30.0],
        [50.0, 40.0, 30.0],
    ])?;
    let opts = PlanOptions::from_instance(&inst);
    let cancel = CancelFlag::new(); // hand a clone to the cell's abort button
    let mut events = Recorder::default();
    let out = match optimize_with(&inst, &opts, &cancel, &mut events) {
        Ok(out) => out,
        // A limit or a proof that no plan exists is an outcome, not a fault.
        Err(e) if e.status().is_some() => {
            println!("no plan: {} ({e})", e.status().expect("checked"));
            return Ok(ExitCode::from(3));
        }
        Err(e @ Error::Solver { .. }) => {
            eprintln!("solver failure (not a proof of anything): {e}");
            return Ok(ExitCode::from(1));
        }
        Err(e) => return Err(e),
    };
    for e in &events.0 {
        if let Event::StageFinished {
            stage, status, time_s, ..
        } = e
        {
            println!("{:<10} {status} in {time_s:.2} s", stage.name());
        }
    }
    let plan = &out.plan;
    println!(
        "plan: {} ({} actions, travel {:.3} m)",
        plan.status, plan.metrics.seq_len, plan.metrics.travel
    );
    for a in &plan.actions {
        println!(
            "  step {:>2}: {} {:?} with the {} arm, {} key poses",
            a.step,
            a.kind,
            a.objects,
            a.arm.name(),
            a.key_poses.len()
        );
    }
    let points: usize = plan.trajectories.iter().map(|t| t.points.len()).sum();
    let end = plan.trajectories.iter().map(|t| t.t_end).fold(0.0, f64::max);
    println!(
        "joint trajectories: {} segments, {points} points, robot time {end:.1} s",
        plan.trajectories.len()
    );

    let report = verify(&inst, plan);
    if !report.is_valid() {
        eprintln!("the verifier rejects the plan:\n{report}");
        return Ok(ExitCode::from(1));
    }
    println!("verified");
    Ok(if plan.status.has_solution() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn main() -> ExitCode {
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(if e.is_input() { 2 } else { 1 })
        }
    }
}

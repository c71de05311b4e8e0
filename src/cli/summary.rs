//! What `pushpack plan` prints: the run's summary, the travel phases of its pushes, and the
//! ablation table.

use pushpack::error::Error;
use pushpack::instance::Instance;
use pushpack::plan::{optimize, Plan, PlanOptions, PlanOutcome};

/// The paper's Table II: sequence length with and without direct placing / multi-object pushes.
pub(super) fn print_ablations(inst: &Instance, base: &PlanOptions) -> Result<(), Error> {
    println!(
        "| motion method | actions | direct | indirect | pushes (multi) | swept area (cm²) | travel (m) | status |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, nd, nm) in [
        ("full method", false, false),
        ("w/o direct placing", true, false),
        ("w/o pushing multiple objects", false, true),
        ("w/o both", true, true),
    ] {
        let mut o = base.clone();
        o.no_direct = nd;
        o.no_multi_push = nm;
        let out = optimize(inst, &o)?;
        let m = out.plan.metrics;
        println!(
            "| {name} | {} | {} | {} | {} ({}) | {:.1} | {:.3} | {} |",
            m.seq_len,
            m.n_place_direct,
            m.n_place_indirect,
            m.n_push,
            m.n_multi_push,
            m.swept_area * 1e4,
            m.travel,
            out.plan.solver.sequence.status
        );
    }
    Ok(())
}

/// One line per push whose back object first closes a gap alone (`travel_phase` in plan.json):
/// how far it moves, how much it turns and drifts meanwhile, and the share of the instance's
/// tolerances that uses (docs/push_stability.md §5.4). A share near 100 % is the push to watch
/// when the plan is run.
pub(super) fn print_travel_phases(plan: &Plan) {
    for a in &plan.actions {
        if let Some(t) = &a.travel_phase {
            println!("{}", travel_line(a.step, t));
        }
    }
}

pub(super) fn travel_line(step: usize, t: &pushpack::plan::TravelPhase) -> String {
    format!(
        "travel     push {step}: {} closes {:.1} mm alone, turning {:.2}° and drifting {:.2} mm ({:.0} % of the tolerances)",
        t.object,
        t.gap * 1e3,
        t.rotation.to_degrees(),
        t.drift * 1e3,
        t.usage * 100.0
    )
}

pub(super) fn print_summary(inst: &Instance, o: &PlanOutcome) {
    let m = &o.plan.metrics;
    let ps = &o.plan.placement;
    println!("instance   {} ({} objects)", inst.name, inst.n());
    println!(
        "status     {} (placement {}, sequence {})",
        o.plan.status, ps.status, o.plan.solver.sequence.status
    );
    println!(
        "placement  {}: occupied area {:.1} cm² ({}; lower bound {:.1} cm², gap {:.1} %), contact {:.1} cm",
        ps.solver,
        ps.occupied_area * 1e4,
        ps.status,
        ps.lower_bound * 1e4,
        ps.gap * 100.0,
        ps.contact_length * 100.0
    );
    match ps.alternative {
        0 => {}
        1 => println!("           alternative 1: the placement stage's result was proven to have no plan"),
        k => println!(
            "           alternative {k}: the placement stage's result and the {} alternative{} before this one were proven to have no plan",
            k - 1,
            if k == 2 { "" } else { "s" }
        ),
    }
    println!(
        "sequence   {} actions: {} direct places, {} indirect places, {} pushes ({} multi-object)",
        m.seq_len, m.n_place_direct, m.n_place_indirect, m.n_push, m.n_multi_push
    );
    println!("swept area {:.1} cm²   travel {:.3} m", m.swept_area * 1e4, m.travel);
    print_travel_phases(&o.plan);
    let ss = &o.plan.solver.sequence;
    if let Some(b) = ss.cost_bound.filter(|_| ss.status != pushpack::status::Status::Optimal) {
        // Stopped early: the per-component bounds the plan is measured against.
        println!(
            "bound      ≥ {} actions (gap {:.1} %), ≥ {:.1} cm² swept, ≥ {:.3} m travel",
            b.len,
            100.0 * (m.seq_len - b.len.min(m.seq_len)) as f64 / m.seq_len.max(1) as f64,
            b.area * 1e4,
            b.travel
        );
    }
    println!(
        "time       placement {:.3} s ({} nodes), sequence {:.3} s ({} nodes, {} assignments{})",
        o.plan.solver.placement.time_s,
        o.plan.solver.placement.nodes,
        o.plan.solver.sequence.time_s,
        o.plan.solver.sequence.nodes,
        o.plan.solver.sequence.assignments.unwrap_or(0),
        match o.plan.solver.sequence.stopped_by {
            Some(l) => format!(
                ", stopped by the {} limit",
                serde_json::to_value(l)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default()
            ),
            None => String::new(),
        }
    );
}

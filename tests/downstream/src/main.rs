//! Plans the paper's eight-object instance through the library API and checks the plan, as the
//! README's "Library use" section shows.

use pushpack::{
    instance::Instance,
    plan::{optimize, PlanOptions},
    verify::verify,
};

fn main() -> Result<(), pushpack::Error> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../../instances/paper/exp2_8objects.toml").into());
    let inst = Instance::load(&path)?;
    let out = optimize(&inst, &PlanOptions::from_instance(&inst))?;
    let report = verify(&inst, &out.plan);
    println!(
        "{}: {} actions, travel {:.2} m, valid: {}",
        inst.name,
        out.plan.metrics.seq_len,
        out.plan.metrics.travel,
        report.is_valid()
    );
    if report.is_valid() {
        Ok(())
    } else {
        std::process::exit(1)
    }
}

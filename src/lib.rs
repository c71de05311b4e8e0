//! # pushpack — dense box packing by picking, placing and pushing
//!
//! Boxes `i = 1…n` with footprints `wᵢ × dᵢ` (one per allowed orientation) lie on a table; an
//! open container of width `W` and depth `D` waits for them. pushpack solves, lexicographically,
//!
//! 1. **placement**: `min max(xᵢ + wᵢ) · max(yᵢ + dᵢ)` over orientations and positions with
//!    `0 ≤ xᵢ, xᵢ + wᵢ ≤ W`, `0 ≤ yᵢ, yᵢ + dᵢ ≤ D` and pairwise non-overlap, then the largest
//!    contact length among minimum-area placements — proven by an exact search, or its bound
//!    and gap reported;
//! 2. **sequence**: actions (place directly; release at `target − δ·u` and push along
//!    `u ∈ {−x, −y}`, alone or in a line) and their order, minimising the number of actions,
//!    then the swept area, then the gripper travel, subject to finger slabs, swept space, reach
//!    and quasi-static push stability (Coulomb friction, convex programs);
//! 3. **motion**: joint trajectories of a Kawada NEXTAGE Open for every action.
//!
//! Every result carries a [`Status`] saying what is proven: `optimal` only with a bound that
//! meets the objective; Bottom-Left and the paper's sequencer are `heuristic`.
//!
//! The folder listing is the pipeline, bottom to top (each imports only modules below it):
//! [`geometry`], [`error`], [`status`] → [`control`] → [`robot`] (URDF model, FK, IK) →
//! [`instance`] → [`placement`] → [`actions`] → [`motion`] → [`sequence`] → [`plan`] (the
//! composer and `plan.json`) → [`verify`](mod@verify), `simulate` (the physics replay, with the
//! `sim` feature), [`render`] → `bench` → `report` (the last two, and
//! the `pushpack` command, only with the default `cli` feature).
//!
//! ```no_run
//! use pushpack::{optimize_with, CancelFlag, Instance, PlanOptions, Recorder};
//! let inst = Instance::load("instances/paper/exp2_8objects.toml")?;
//! let cancel = CancelFlag::new(); // cancel() from another thread stops with the best plan
//! let out = optimize_with(&inst, &PlanOptions::from_instance(&inst), &cancel, &mut Recorder::default())?;
//! println!("{}: {} actions", out.plan.status, out.plan.metrics.seq_len);
//! assert!(pushpack::verify(&inst, &out.plan).is_valid());
//! # Ok::<(), pushpack::Error>(())
//! ```
#![warn(missing_docs)]

pub mod actions;
#[cfg(feature = "cli")]
pub mod bench;
pub mod control;
pub mod error;
pub mod geometry;
pub mod instance;
pub mod motion;
pub mod placement;
pub mod plan;
pub mod render;
#[cfg(feature = "cli")]
pub mod report;
pub mod robot;
pub mod sequence;
pub mod simulate;
pub mod status;
pub mod verify;

pub use actions::Action;
pub use control::{CancelFlag, Event, Listener, Recorder, Silent, Terminator, TimeLimit};
pub use error::{Error, Result};
pub use instance::{Instance, InstanceBuilder};
pub use placement::Placement;
pub use plan::{optimize, optimize_with, Plan, PlanOptions, PlanOutcome};
pub use status::{Limit, Status};
pub use verify::{verify, Report};

//! # pushpack — dense box packing by picking, placing and pushing
//!
//! Given rectangular boxes on a table and an open container, pushpack plans how a dual-arm
//! robot (Kawada NEXTAGE Open) packs them with no gap between them, following and extending
//! *Planning Dense Object Packing by Pushing Objects*. The pipeline, one module per stage:
//!
//! 1. [`instance`] — load and validate the problem (TOML/JSON).
//! 2. [`placement`] — choose each box's orientation and footprint `[x, x+w] × [y, y+d]` in the
//!    container frame C, minimising the occupied area `max(x+w) · max(y+d)`, then maximising
//!    contact length, subject to non-overlap and Bottom-Left stability.
//! 3. [`actions`] — place a box directly, or release it at `target − d·u` and push it along
//!    `u ∈ {−x, −y}`, possibly with others in one line; feasibility (finger slabs, swept space)
//!    and push stability (quasi-static Coulomb friction).
//! 4. [`sequence`] — choose the actions and their order: lexicographically minimise the number
//!    of actions, the swept area, then the gripper travel.
//! 5. [`robot`] — NEXTAGE Open kinematics (URDF) and the TCP key points of each action.
//! 6. [`plan`] — the composer [`plan::optimize`] and the `plan.json` file.
//! 7. [`verify`] — an independent replay of a plan; [`render`] — SVG pictures.
//!
//! ```no_run
//! use pushpack::{instance::Instance, plan::{optimize, PlanOptions}};
//! let inst = Instance::load("instances/paper/exp2_8objects.toml")?;
//! let out = optimize(&inst, &PlanOptions::from_instance(&inst))?;
//! println!("{} actions", out.plan.metrics.seq_len);
//! # Ok::<(), pushpack::error::Error>(())
//! ```
#![warn(missing_docs)]

pub mod actions;
pub mod bench;
pub mod cli;
pub mod control;
pub mod error;
pub mod geometry;
pub mod instance;
pub mod motion;
pub mod placement;
pub mod plan;
pub mod render;
pub mod report;
pub mod robot;
pub mod sequence;
pub mod status;
pub mod verify;

pub use error::{Error, Result};

//! Independent verifier: replays a plan step by step against the instance and lists every violation.
//!
//! The replay keeps its own record of where every object is (on the table, released at a
//! footprint waiting for a push, or at its target) and re-derives every condition of SPEC §5
//! from the instance and the plan alone. It does not use the planner's floor state
//! (`actions::Layout`) nor its slab construction; it shares only the low-level value types and
//! predicates of [`crate::geometry`], the pure placement predicate
//! [`Placement::violations`], the push-mechanics model of [`crate::actions::push`] and the
//! key-point model of [`crate::motion::keypoints`] (which defines what "travel" means).
//!
//! Every violation is reported, not just the first; only a plan that cannot be read against the
//! instance at all ([`ViolationClass::Format`] from [`Plan::placement`] / [`Plan::actions`])
//! stops the replay.

mod claims;
mod physics;
mod slabs;
pub mod trajectories;

use crate::actions::push::travel::TravelCheck;
use crate::actions::{push, Action, PlaceMode};
use crate::geometry::Arm;
use crate::geometry::{Axis2, Box3, PushDir, Rect, EPS};
use crate::instance::Instance;
use crate::motion::keypoints::{path_length, total_travel};
use crate::placement::Placement;
use crate::plan::{ActionEntry, Plan, FORMAT_VERSION};
use crate::sequence::Metrics;
use serde::{Deserialize, Serialize};
use std::fmt;

mod replay;

/// Kind of condition a plan violates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ViolationClass {
    /// The plan cannot be read against the instance, or contradicts itself (digest, step numbers, kinds, recorded release footprints, arms, ablation options).
    Format,
    /// The targets break a placement condition (orientation, size, floor, height, overlap, BL stability).
    Placement,
    /// A released object overlaps an object already in the container.
    Overlap,
    /// A release footprint or a pushed object's swept rectangle leaves the container floor.
    Wall,
    /// A finger slab or the lowered pusher hits a wall or an object, the object does not fit the gripper opening, or an offset is below the gripper's minimum.
    FingerSlab,
    /// A push sweeps an object through another, or the moving pusher hits a wall or an object.
    SweptSpace,
    /// A pushed object slides along a neighbour that nothing holds against the push, or into a
    /// slot the instance forbids (`actions::push::side`).
    SideContact,
    /// A push is not stable by the required margin, or its recorded margin is wrong.
    PushStability,
    /// An action does not fit the state it runs in (placed twice, pushed before its place, malformed line).
    Precedence,
    /// After the last action some object is not at its target.
    FinalPose,
    /// Recorded metrics, costs or placement summary differ from the recomputed values.
    Metrics,
    /// A claimed status, bound or gap contradicts the plan's own numbers (an `optimal` with a
    /// gap, a bound above the objective, a heuristic called optimal).
    Claim,
    /// A joint trajectory violates a joint limit, disagrees with its recorded TCP poses (FK),
    /// jumps between points, or collides (checked by `robot::check_trajectories`).
    Robot,
    /// The physics replay (`simulate`) moves a box out of the push tolerances: an action turns
    /// or drifts a box it moves, disturbs one it should not, or a box ends off its target.
    Physics,
}

impl ViolationClass {
    /// The snake_case name used in files and messages.
    pub fn name(self) -> &'static str {
        match self {
            ViolationClass::Format => "format",
            ViolationClass::Placement => "placement",
            ViolationClass::Overlap => "overlap",
            ViolationClass::Wall => "wall",
            ViolationClass::FingerSlab => "finger_slab",
            ViolationClass::SweptSpace => "swept_space",
            ViolationClass::SideContact => "side_contact",
            ViolationClass::PushStability => "push_stability",
            ViolationClass::Precedence => "precedence",
            ViolationClass::FinalPose => "final_pose",
            ViolationClass::Metrics => "metrics",
            ViolationClass::Claim => "claim",
            ViolationClass::Robot => "robot",
            ViolationClass::Physics => "physics",
        }
    }
}

impl fmt::Display for ViolationClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One violated condition.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Violation {
    /// 1-based step of the action where it occurs (None for whole-plan conditions).
    pub step: Option<usize>,
    /// Which kind of condition.
    pub class: ViolationClass,
    /// Human-readable detail.
    pub message: String,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.step {
            Some(k) => write!(f, "step {k}: [{}] {}", self.class, self.message),
            None => write!(f, "plan: [{}] {}", self.class, self.message),
        }
    }
}

/// Result of verifying a plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Every violation of the packing plan found, in replay order.
    pub violations: Vec<Violation>,
    /// Number of actions replayed.
    pub steps_checked: usize,
    /// Problems of the joint trajectories (class `robot`): joint limits, FK mismatch, jumps,
    /// collisions. Kept apart because the sequencers do not yet plan around arm collisions
    /// (only around unreachable key poses); see docs/robot.md.
    #[serde(default)]
    pub robot_issues: Vec<Violation>,
    /// The plan declares itself a packing-only study (`options.packing_only`): robot issues
    /// are reported but do not make it invalid, and it is never executable.
    #[serde(default)]
    pub packing_only: bool,
    /// Whether the physics replay ran, and what it found (class `physics`).
    #[serde(default)]
    pub physics: PhysicsCheck,
    /// Every action and box the physics replay found out of tolerance (class `physics`).
    #[serde(default)]
    pub physics_issues: Vec<Violation>,
}

/// Whether the verifier replayed a plan in the physics engine ([`crate::simulate`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "replay")]
pub enum PhysicsCheck {
    /// Not replayed: the plan already fails another condition, is packing-only, or the caller
    /// turned the replay off ([`VerifyOptions::physics`]). Such a plan is never executable.
    #[default]
    NotRun,
    /// Replayed with the instance's settings and tolerances.
    Replayed {
        /// Every action and box within tolerance.
        ok: bool,
        /// The worst box at the end: distance from its target (mm) and rotation (°).
        worst_mm: f64,
        /// Its rotation (°).
        worst_deg: f64,
        /// Wall-clock time of the replay (s).
        wall_s: f64,
    },
}

/// What [`verify_with`] checks. Default: everything.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerifyOptions {
    /// Replay an otherwise executable plan in the physics engine (default true). Without it no
    /// plan is called executable.
    pub physics: bool,
}

impl Default for VerifyOptions {
    fn default() -> Self {
        VerifyOptions { physics: true }
    }
}

impl Report {
    /// True when the plan violates none of the conditions it claims to meet: every packing
    /// condition, and every robot, trajectory and physics condition unless it is packing-only.
    pub fn is_valid(&self) -> bool {
        self.violations.is_empty()
            && (self.packing_only || (self.robot_issues.is_empty() && self.physics_issues.is_empty()))
    }

    /// True when the packing is valid (whatever the robot issues).
    pub fn is_packing_valid(&self) -> bool {
        self.violations.is_empty()
    }

    /// True when the robot can run the plan: valid, not packing-only, no robot issue, and the
    /// physics replay ran and kept every box within tolerance. The one meaning of "executable"
    /// (planner, verifier, bench, report and export use it).
    pub fn is_executable(&self) -> bool {
        self.violations.is_empty()
            && self.robot_issues.is_empty()
            && !self.packing_only
            && self.physics_issues.is_empty()
            && matches!(self.physics, PhysicsCheck::Replayed { ok: true, .. })
    }

    /// Valid and free of robot issues, but the physics replay was not run: what a run with the
    /// replay turned off can say at most.
    pub fn is_robot_valid(&self) -> bool {
        self.violations.is_empty() && self.robot_issues.is_empty() && !self.packing_only
    }

    /// True when at least one violation of `class` was found.
    pub fn has(&self, class: ViolationClass) -> bool {
        self.violations.iter().any(|v| v.class == class)
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self.violations.len()
            + if self.packing_only {
                0
            } else {
                self.robot_issues.len() + self.physics_issues.len()
            };
        if self.is_executable() {
            write!(
                f,
                "plan is valid and executable ({} steps checked, physics replay within tolerance)",
                self.steps_checked
            )?;
        } else if self.is_robot_valid() && self.physics_issues.is_empty() {
            write!(
                f,
                "plan is valid for the robot, not called executable: the physics replay was not run ({} steps checked)",
                self.steps_checked
            )?;
        } else if self.is_valid() {
            write!(
                f,
                "plan is valid as a packing-only plan ({} steps checked)",
                self.steps_checked
            )?;
        } else {
            write!(
                f,
                "plan is INVALID: {n} violation{} ({} steps checked)",
                if n == 1 { "" } else { "s" },
                self.steps_checked
            )?;
            for v in &self.violations {
                write!(f, "\n  {v}")?;
            }
        }
        if !self.robot_issues.is_empty() {
            write!(
                f,
                "\nrobot and joint trajectories: {} problem(s){}:",
                self.robot_issues.len(),
                if self.packing_only {
                    " (a packing-only plan: not counted)"
                } else {
                    ""
                }
            )?;
            for v in &self.robot_issues {
                write!(f, "\n  {v}")?;
            }
        }
        if !self.physics_issues.is_empty() {
            write!(f, "\nphysics replay: {} problem(s):", self.physics_issues.len())?;
            for v in &self.physics_issues {
                write!(f, "\n  {v}")?;
            }
        }
        Ok(())
    }
}

/// Replay `plan` against `inst` and report every violated condition, the physics replay's
/// included ([`VerifyOptions::default`]).
pub fn verify(inst: &Instance, plan: &Plan) -> Report {
    verify_with(inst, plan, &VerifyOptions::default())
}

/// [`verify`] with a choice of checks. The physics replay runs last, and only on a plan that
/// passes every other condition and is not packing-only: it judges how the boxes move, which
/// is moot for a plan that is invalid already.
pub fn verify_with(inst: &Instance, plan: &Plan, opts: &VerifyOptions) -> Report {
    let mut report = verify_static(inst, plan);
    if opts.physics && report.is_robot_valid() {
        physics::check(inst, plan, &mut report);
    }
    report
}

fn verify_static(inst: &Instance, plan: &Plan) -> Report {
    let mut out = Vec::new();
    let fmt_err = |message: String| Violation {
        step: None,
        class: ViolationClass::Format,
        message,
    };
    // Version 1 plans are read too: `Plan::load` restates their statuses in version 2 terms.
    if !(1..=FORMAT_VERSION).contains(&plan.format_version) {
        out.push(fmt_err(format!(
            "format_version {} is not one of 1..={FORMAT_VERSION}",
            plan.format_version
        )));
    }
    if plan.instance.digest != inst.digest {
        out.push(fmt_err(format!(
            "plan is for instance digest {}, the instance has {}",
            short(&plan.instance.digest),
            short(&inst.digest)
        )));
    }
    let placement = match plan.placement(inst) {
        Ok(p) => p,
        Err(e) => {
            out.push(fmt_err(e.to_string()));
            return Report {
                violations: out,
                steps_checked: 0,
                robot_issues: Vec::new(),
                packing_only: plan.options.packing_only,
                physics: PhysicsCheck::NotRun,
                physics_issues: Vec::new(),
            };
        }
    };
    let actions = match plan.actions(inst) {
        Ok(a) => a,
        Err(e) => {
            out.push(fmt_err(e.to_string()));
            return Report {
                violations: out,
                steps_checked: 0,
                robot_issues: Vec::new(),
                packing_only: plan.options.packing_only,
                physics: PhysicsCheck::NotRun,
                physics_issues: Vec::new(),
            };
        }
    };
    let mut r = Replay::new(inst, &placement, out);
    r.check_document(plan, &actions);
    for v in placement.violations(inst) {
        r.flag(None, ViolationClass::Placement, v);
    }
    for (k, (a, e)) in actions.iter().zip(&plan.actions).enumerate() {
        r.step(k + 1, a, e);
    }
    r.check_final();
    r.check_metrics(plan, &actions);
    for message in claims::status_claims(plan) {
        r.flag(None, ViolationClass::Claim, message);
    }
    // An executable plan needs its joint trajectories; a packing-only one may leave them out,
    // and when present they are checked in full either way.
    let mut robot_issues = Vec::new();
    let mut robot = |k: Option<usize>, message: String| {
        robot_issues.push(Violation {
            step: k.map(|k| k + 1),
            class: ViolationClass::Robot,
            message,
        })
    };
    if plan.trajectories.is_empty() {
        if !plan.options.packing_only {
            robot(None, "no joint trajectories: a plan the robot is to run needs them (packing-only plans say so in options.packing_only)".into());
        }
    } else {
        for (k, message) in crate::verify::trajectories::check_trajectories(inst, plan) {
            robot(k, message);
        }
        for (k, message) in claims::robot_records(inst, plan) {
            robot(k, message);
        }
    }
    Report {
        violations: r.out,
        steps_checked: actions.len(),
        robot_issues,
        packing_only: plan.options.packing_only,
        physics: PhysicsCheck::NotRun,
        physics_issues: Vec::new(),
    }
}

fn short(digest: &str) -> String {
    digest.chars().take(12).collect()
}

/// Where an object is during the replay.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Where {
    Table,
    Released { rect: Rect, dir: PushDir, offset: f64 },
    AtTarget,
}

struct Replay<'a> {
    inst: &'a Instance,
    placement: &'a Placement,
    state: Vec<Where>,
    out: Vec<Violation>,
    /// Largest x and y extents of every footprint seen so far.
    extent: (f64, f64),
    top: f64,
}

fn fmt_rect(r: &Rect) -> String {
    format!("[{:.4}, {:.4}]x[{:.4}, {:.4}]", r.x0, r.x1, r.y0, r.y1)
}

fn dir_name(d: PushDir) -> &'static str {
    match d {
        PushDir::MinusX => "-x",
        PushDir::MinusY => "-y",
    }
}

fn axis_name(a: Axis2) -> &'static str {
    match a {
        Axis2::X => "x",
        Axis2::Y => "y",
    }
}

/// A recorded margin agrees with the recomputed one (1 nm plus 1e-6 relative; NaN never agrees).
fn close_margin(recorded: f64, computed: f64) -> bool {
    let d = (recorded - computed).abs();
    d.is_finite() && d <= 1e-9 + 1e-6 * computed.abs()
}

/// `a` and `b` agree within 1e-6 relative (with a tiny absolute floor for zeros).
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs()) + 1e-12
}

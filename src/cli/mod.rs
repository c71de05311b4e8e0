//! Command-line interface: parses arguments, calls the library, prints, and maps errors to exit
//! codes (0 ok, 1 plan invalid or infeasible, 2 bad input).

use clap::{Args, Parser, Subcommand};
use pushpack::error::Error;
use pushpack::instance::{Instance, MAX_OFFSET_STEPS, MAX_TIME_LIMIT};
use pushpack::plan::{optimize_stages, PlacementSolver, Plan, PlanOptions, Sequencer};
use pushpack::render::{render, render_placement};
use pushpack::simulate::SimOptions;
use std::path::{Path, PathBuf};

mod commands;
mod inputs;
mod progress;
mod summary;

use commands::*;
use inputs::*;
use summary::*;

/// Exit code for success.
pub const EXIT_OK: i32 = 0;
/// Exit code for a plan that fails verification or a problem without a feasible plan.
pub const EXIT_FAIL: i32 = 1;
/// Exit code for bad input (unreadable or invalid files).
pub const EXIT_BAD_INPUT: i32 = 2;
/// Exit code for a solver that failed (HiGHS returned an error): neither an answer about the
/// problem nor the user's fault, so scripts can retry or report it apart from "no plan".
pub const EXIT_SOLVER: i32 = 3;

#[derive(Parser, Debug)]
#[command(
    name = "pushpack",
    version,
    about = "Plan dense box packing by placing and pushing (Kawada NEXTAGE Open)"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Check an instance file and print a one-line summary.
    Validate {
        /// Instance file (.toml or .json).
        instance: PathBuf,
    },
    /// Stage 1 only: compute a placement.
    Place {
        /// Instance file.
        instance: PathBuf,
        /// Placement solver: `bl` (the paper's Bottom-Left) or `milp` (exact, warm-started by BL).
        #[arg(long, default_value = "bl", value_parser = ["bl", "milp"])]
        solver: String,
        /// Seed (default: the instance's planner.seed).
        #[arg(long)]
        seed: Option<u64>,
        /// Time limit in seconds (default: the instance's planner.time_limit).
        #[arg(long)]
        time_limit: Option<f64>,
        /// Print the result as JSON.
        #[arg(long)]
        json: bool,
        /// Exact solver only: what decides each enclosing box of the area stage, `search` (the
        /// combinatorial x-phase) or `highs` (a HiGHS MILP master with y-phase cuts).
        #[arg(long, value_parser = ["search", "highs"])]
        area_master: Option<String>,
        /// Exact solver only: time of the contact stage, `rest` (what the limit leaves), `area`
        /// (as long as the area stage, at least 1 s) or seconds.
        #[arg(long)]
        contact_budget: Option<String>,
        /// Exact solver only: set a HiGHS option, `NAME=VALUE`, on every HiGHS model of the
        /// placement (repeatable; for experiments, e.g. `output_flag=true`). HiGHS checks the
        /// value: one it rejects, or a run it fails, is a solver error (exit 3).
        #[arg(long = "highs-option", value_name = "NAME=VALUE")]
        highs_option: Vec<String>,
        /// Exact solver only: threads searching each enclosing box, in the area stage and the
        /// contact stage (the same answer on any number; default 1).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Plan everything, verify the plan, write plan.json and pictures.
    Plan {
        /// Instance file.
        instance: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        opts: PlanArgs,
        /// Do not write SVG pictures.
        #[arg(long)]
        no_render: bool,
        /// Also plan the paper's Table II ablations and print their sequence lengths.
        #[arg(long)]
        compare_ablations: bool,
    },
    /// Replay a plan against its instance and list every violated condition.
    Verify {
        /// Instance file.
        instance: PathBuf,
        /// plan.json.
        plan: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Judge the packing only: robot issues are reported but do not fail the plan (as for
        /// a plan made with `plan --packing-only`).
        #[arg(long)]
        packing_only: bool,
        /// Also print the physics replay's full report (as `pushpack simulate`). The verifier
        /// replays every otherwise valid plan anyway: a plan is executable only if every box
        /// stays within the push tolerances.
        #[arg(long)]
        simulate: bool,
        /// Skip the physics replay: the plan can then be valid but is never called executable.
        #[arg(long, conflicts_with = "simulate")]
        no_physics: bool,
    },
    /// Replay a plan in the rapier3d physics engine: every place and push executed by rigid
    /// fingers along the planned path; per action and box, rotation, drift and final error
    /// against the instance's push tolerances (exit 1 when any is exceeded).
    Simulate {
        /// plan.json.
        plan: PathBuf,
        /// Instance file (default: the file the plan names).
        #[arg(long)]
        instance: Option<PathBuf>,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Physics time step (s; default 1/240).
        #[arg(long)]
        dt: Option<f64>,
        /// Pusher speed along a push (m/s; default 0.02).
        #[arg(long)]
        push_speed: Option<f64>,
        /// Contact stiffness as a natural frequency (Hz; default 150).
        #[arg(long)]
        contact_hz: Option<f64>,
        /// Replay under six settings around these (half the step, a half and a quarter of the
        /// push speed, softer and stiffer contacts) and print one line each: a verdict that changes
        /// marks a fragile plan. Exits 1 unless every replay is within tolerance.
        #[arg(long, conflicts_with = "robust")]
        sweep: bool,
        /// Replay N times under the errors a real cell makes: every release off by up to 0.5 mm
        /// and 0.5°, friction off by up to 20 %, and the sweep's six settings in turn; print the
        /// share within tolerance. Exits 1 when the share is below --min-share.
        #[arg(long, value_name = "N")]
        robust: Option<usize>,
        /// Seed of the first perturbed replay (replay k uses seed + k; default 0).
        #[arg(long, requires = "robust")]
        seed: Option<u64>,
        /// Share of the perturbed replays that must stay within tolerance (default 1).
        #[arg(long, requires = "robust")]
        min_share: Option<f64>,
    },
    /// Export a plan's joint trajectories per arm (ROS JointTrajectory YAML/JSON, CSV, or ROS 2
    /// goals). Refuses a plan the robot cannot run unless `--packing-only`.
    Export {
        /// plan.json.
        plan: PathBuf,
        /// `ros-yaml`, `ros-json`, `csv` (ROS 1 messages or CSV, one file per arm) or `ros2-goal`
        /// (a ROS 2 FollowJointTrajectory goal per arm, the gripper commands, all as one
        /// blocking action list, and a manifest naming the action servers).
        #[arg(long, default_value = "ros-yaml")]
        format: String,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// The instance file (default: the path recorded in the plan). The export verifies the
        /// plan against it and takes the gripper's squeeze and effort from it.
        #[arg(long)]
        instance: Option<PathBuf>,
        /// Export even when the robot cannot run the plan (a packing study's plan).
        #[arg(long)]
        packing_only: bool,
        /// ROS 2: trajectory controller of the left arm.
        #[arg(long, default_value = "larm_controller")]
        left_controller: String,
        /// ROS 2: trajectory controller of the right arm.
        #[arg(long, default_value = "rarm_controller")]
        right_controller: String,
        /// ROS 2: gripper action controller of the left hand (`NAME/gripper_cmd`).
        #[arg(long, default_value = "lhand_controller")]
        left_gripper_controller: String,
        /// ROS 2: gripper action controller of the right hand.
        #[arg(long, default_value = "rhand_controller")]
        right_gripper_controller: String,
    },
    /// Decide one push from a scenario file (JSON): verdict, margin and certificate.
    PushCheck {
        /// Scenario file.
        scenario: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Draw a plan: placement.svg, storyboard.svg, swept.svg, and view.html (the plan in 3-D).
    Render {
        /// plan.json.
        plan: PathBuf,
        /// Instance file (default: the path recorded in the plan).
        #[arg(long)]
        instance: Option<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Write a seeded set of random instances (objects of a kind share their size).
    Generate {
        /// Objects per instance (1-24).
        #[arg(long)]
        objects: usize,
        /// Kinds per instance (1..=objects).
        #[arg(long)]
        kinds: usize,
        /// Number of instances; instance i uses seed S + i.
        #[arg(long, default_value_t = 1)]
        count: usize,
        /// Seed of the first instance.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
        /// Container inner width, depth and wall height in metres (default 0.30,0.20,0.10).
        #[arg(long, value_name = "W,D,H")]
        container: Option<String>,
        /// Range of the horizontal box edges in metres (default 0.030,0.060; at most 0.060).
        #[arg(long, value_name = "MIN,MAX")]
        size_range: Option<String>,
        /// Allowed orientations: `any` (a box may be laid on any face; plans may need a regrasp
        /// the robot cannot do) or `upright` (boxes keep their table face down).
        #[arg(long, default_value = "any", value_parser = ["any", "upright"])]
        orientations: String,
    },
    /// Run planners over instance sets in parallel and append one result row per run.
    Bench {
        /// Instance files or directories (searched one level deep for *.toml, *.json).
        #[arg(required = true)]
        instances: Vec<PathBuf>,
        /// Comma-separated planner specs PLACEMENT+SEQUENCER[+no-direct][+no-multi-push][+altN],
        /// e.g. bl+paper,milp+astar,milp+astar+no-direct,bl+astar+alt5.
        #[arg(long)]
        planners: String,
        /// Library time limit per stage in seconds (as `plan --time-limit`).
        #[arg(long, default_value_t = 60.0)]
        time_limit: f64,
        /// Wall-clock limit of one run's process in seconds; past it the run is killed and
        /// recorded as `timeout` (default 2 x time limit + 30).
        #[arg(long)]
        hard_limit: Option<f64>,
        /// Parallel runs (default: the number of cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Output directory of results.jsonl and results.csv.
        #[arg(long, default_value = "out/bench")]
        out: PathBuf,
        /// Run only shard K of N (0-based; the sorted run list, every N-th from K).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Continue the results already in --out: skip finished runs, redo a torn last row.
        #[arg(long)]
        resume: bool,
        /// Run at most this many pending runs, then stop (continue later with --resume).
        #[arg(long)]
        max_runs: Option<usize>,
    },
    /// One benchmark run, printed as a JSON result row (the child process of `bench`).
    #[command(hide = true)]
    BenchRun {
        /// Instance file.
        instance: PathBuf,
        /// Planner spec.
        #[arg(long)]
        planner: String,
        /// Time limit per stage in seconds.
        #[arg(long)]
        time_limit: f64,
    },
    /// Merge result files and write summary tables (summary.md) and SVG plots.
    Report {
        /// Result files (*.jsonl) or directories holding them (shards are merged).
        #[arg(required = true)]
        results: Vec<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "out/report")]
        out: PathBuf,
    },
}

#[derive(Args, Debug)]
struct PlanArgs {
    /// Seed (default: the instance's planner.seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Forbid direct placing (the paper's Table II ablation).
    #[arg(long)]
    no_direct: bool,
    /// Forbid multi-object pushes (the paper's Table II ablation).
    #[arg(long)]
    no_multi_push: bool,
    /// Time limit of the whole run in seconds (placement, sequence and joint trajectories).
    #[arg(long)]
    time_limit: Option<f64>,
    /// A packing-only study: robot issues (a box the gripper would have to turn over, a pose
    /// out of reach) are reported but do not fail the plan, which is then not executable.
    #[arg(long)]
    packing_only: bool,
    /// Placement solver (default: milp up to 10 objects, bl above).
    #[arg(long, value_parser = ["bl", "milp"])]
    placement: Option<String>,
    /// Sequencer: `astar` (default; provably optimal) or `paper` (Algorithms 1 + 2).
    #[arg(long, value_parser = ["astar", "paper"])]
    sequencer: Option<String>,
    /// Node limit of the sequence search.
    #[arg(long)]
    max_nodes: Option<u64>,
    /// When the sequencer proves the placement has no plan, try up to N further Bottom-Left
    /// placements, best first (default 0: keep the placement).
    #[arg(long, value_name = "N", default_value_t = 0)]
    placement_alternatives: usize,
    /// A* only: largest indirect offset in multiples of the minimum offset (default: the
    /// instance's planner.max_offset_steps, else 3).
    #[arg(long, value_name = "M")]
    max_offset_steps: Option<usize>,
    /// A* only, developer diagnostics: print the search's phases and bounds to stderr.
    #[arg(long)]
    astar_trace: bool,
    /// Threads of the exact placement's box searches and of the inverse kinematics' descents
    /// (default 1; the same plan on any number).
    #[arg(long)]
    threads: Option<usize>,
    /// A* only, developer diagnostics: time the bound computations and print a profile to
    /// stderr at the end.
    #[arg(long)]
    astar_profile: bool,
    /// Do not replay plans in the physics engine: neither inside the search (vetoing the pushes
    /// the replay rejects) nor in the verifier. The plan is then never called executable.
    #[arg(long)]
    no_physics: bool,
}

impl PlanArgs {
    fn options(&self, inst: &Instance) -> Result<PlanOptions, Error> {
        let mut o = PlanOptions::from_instance(inst);
        if let Some(s) = self.seed {
            o.seed = s;
        }
        o.no_direct |= self.no_direct;
        o.no_multi_push |= self.no_multi_push;
        if let Some(t) = positive_time(self.time_limit, "--time-limit")? {
            o.time_limit = t;
        }
        match self.placement.as_deref() {
            Some("bl") => o.placement = PlacementSolver::Bl,
            Some("milp") => o.placement = PlacementSolver::Milp,
            _ => {}
        }
        match self.sequencer.as_deref() {
            Some("paper") => o.sequencer = Sequencer::Paper,
            Some("astar") => o.sequencer = Sequencer::Astar,
            _ => {}
        }
        if let Some(n) = self.max_nodes {
            if n == 0 {
                return Err(Error::input("<command line>", "--max-nodes", "must be >= 1"));
            }
            o.max_nodes = n;
        }
        o.placement_alternatives = self.placement_alternatives;
        o.packing_only |= self.packing_only;
        o.physics &= !self.no_physics;
        if let Some(m) = self.max_offset_steps {
            if m == 0 || m > MAX_OFFSET_STEPS {
                return Err(Error::input(
                    "<command line>",
                    "--max-offset-steps",
                    format!("must be 1..={MAX_OFFSET_STEPS}, got {m}"),
                ));
            }
            o.astar.max_offset_steps = m;
        }
        o.astar.trace |= self.astar_trace;
        o.astar.profile |= self.astar_profile;
        if let Some(n) = self.threads {
            o.threads = threads_in_range(n)?;
        }
        Ok(o)
    }
}

/// A time limit from the command line: positive, finite and no larger than instance files allow
/// ([`MAX_TIME_LIMIT`]), since larger values cannot become a deadline.
fn positive_time(t: Option<f64>, flag: &str) -> Result<Option<f64>, Error> {
    match t {
        Some(t) if !(t.is_finite() && t > 0.0) => Err(Error::input(
            "<command line>",
            flag,
            format!("must be a positive number of seconds, got {t}"),
        )),
        Some(t) if t > MAX_TIME_LIMIT => Err(Error::input(
            "<command line>",
            flag,
            format!("{t:e} s is larger than the largest accepted limit, {MAX_TIME_LIMIT:e} s"),
        )),
        other => Ok(other),
    }
}

/// Run the CLI on the process arguments; returns the exit code.
pub fn main() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { EXIT_BAD_INPUT } else { EXIT_OK };
            let _ = e.print();
            return code;
        }
    };
    match run(cli.cmd) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            if e.is_input() {
                EXIT_BAD_INPUT
            } else if matches!(e, Error::Solver { .. }) {
                EXIT_SOLVER
            } else {
                EXIT_FAIL
            }
        }
    }
}

/// One arm per subcommand; the longer ones are `cmd_*` functions of their own.
fn run(cmd: Cmd) -> Result<i32, Error> {
    match cmd {
        Cmd::Validate { instance } => {
            let inst = Instance::load(&instance)?;
            println!(
                "{}: valid — {} objects of {} kinds, container {:.3} x {:.3} x {:.3} m, digest {}",
                instance.display(),
                inst.n(),
                inst.kinds.len(),
                inst.container.width,
                inst.container.depth,
                inst.container.wall_height,
                &inst.digest[..12]
            );
            Ok(EXIT_OK)
        }
        Cmd::Place {
            instance,
            solver,
            seed,
            time_limit,
            json,
            area_master,
            contact_budget,
            highs_option,
            threads,
        } => cmd_place(
            instance,
            solver,
            seed,
            time_limit,
            json,
            ExactArgs {
                area_master,
                contact_budget,
                highs_options: highs_option,
                threads,
            },
        ),
        Cmd::Plan {
            instance,
            out,
            opts,
            no_render,
            compare_ablations,
        } => cmd_plan(instance, out, opts, no_render, compare_ablations),
        cmd @ Cmd::Verify { .. } => cmd_verify(cmd),
        cmd @ Cmd::Simulate { .. } => cmd_simulate(cmd),
        cmd @ Cmd::Export { .. } => cmd_export(cmd),
        Cmd::PushCheck { scenario, json } => {
            let sc = pushpack::actions::push::load_scenario(&scenario)?;
            let report = pushpack::actions::push::check_scenario(&sc);
            if json {
                println!("{}", serde_json::to_string_pretty(&report).expect("serialisable"));
            } else {
                println!("{report}");
            }
            Ok(if report.stable() { EXIT_OK } else { EXIT_FAIL })
        }
        Cmd::Generate {
            objects,
            kinds,
            count,
            seed,
            out,
            container,
            size_range,
            orientations,
        } => {
            use pushpack::bench::sets::{generate_set, parse_numbers, SetParams};
            let p = SetParams {
                objects,
                kinds,
                count,
                seed,
                container: container
                    .as_deref()
                    .map(|c| parse_numbers::<3>(c, "--container"))
                    .transpose()?,
                size_range: size_range
                    .as_deref()
                    .map(|c| parse_numbers::<2>(c, "--size-range"))
                    .transpose()?,
                orientations: Some(orientations),
            };
            let files = generate_set(&p, &out)?;
            println!("wrote {} instances to {}", files.len(), out.display());
            Ok(EXIT_OK)
        }
        cmd @ Cmd::Bench { .. } => cmd_bench(cmd),
        Cmd::BenchRun {
            instance,
            planner,
            time_limit,
        } => {
            let spec = pushpack::bench::spec::PlannerSpec::parse(&planner, "--planner")?;
            let time_limit = positive_time(Some(time_limit), "--time-limit")?.unwrap_or(time_limit);
            let inst = Instance::load(&instance)?;
            let row = pushpack::bench::run::run_in_process(&instance.display().to_string(), &inst, &spec, time_limit);
            println!("{}", row.to_json_line());
            Ok(EXIT_OK)
        }
        Cmd::Report { results, out } => {
            let files = pushpack::report::write_report(&results, &out)?;
            for f in files {
                println!("wrote {}", f.display());
            }
            Ok(EXIT_OK)
        }
        Cmd::Render { plan, instance, out } => {
            let (p, inst) = load_plan_instance(&plan, instance.as_deref())?;
            std::fs::create_dir_all(&out).map_err(|e| Error::Io {
                path: out.clone(),
                source: e,
            })?;
            for f in render(&inst, &p, &out)? {
                println!("wrote {}", f.display());
            }
            Ok(EXIT_OK)
        }
    }
}

/// `pushpack plan`.
fn cmd_plan(
    instance: PathBuf,
    out: PathBuf,
    opts: PlanArgs,
    no_render: bool,
    compare_ablations: bool,
) -> Result<i32, Error> {
    let inst = Instance::load(&instance)?;
    let o = opts.options(&inst)?;
    if compare_ablations {
        print_ablations(&inst, &o)?;
    }
    std::fs::create_dir_all(&out).map_err(|e| Error::Io {
        path: out.clone(),
        source: e,
    })?;
    let cancel = progress::cancel_on_ctrl_c();
    let mut bar = progress::Progress::new();
    let (placed, result) = optimize_stages(&inst, &o, &cancel, &mut bar);
    bar.finish();
    let outcome = match (placed, result) {
        (_, Ok(x)) => x,
        (None, Err(e)) => return Err(e),
        (Some(placed), Err(e)) => {
            if let Some(status) = e.status() {
                eprintln!("status     {status}: no plan ({e})");
            }
            // No plan.json without a sequence, but the placement was found and is the
            // first thing a user looks at to see why: write it and say where.
            let path = out.join("placement.json");
            let json = serde_json::to_string_pretty(&placed).expect("serialisable");
            std::fs::write(&path, json + "\n").map_err(|e| Error::Io {
                path: path.clone(),
                source: e,
            })?;
            eprintln!("wrote      {} (the placement; no sequence was found)", path.display());
            if !no_render {
                let svg = render_placement(&inst, &placed, &out)?;
                eprintln!("wrote      {}", svg.display());
            }
            if matches!(e, Error::Infeasible { .. }) && o.placement_alternatives == 0 {
                eprintln!(
                    "hint       --placement-alternatives N tries the next N Bottom-Left placements when one is proven to have no plan"
                );
            }
            for stale in ["plan.json", "storyboard.svg", "swept.svg"] {
                if out.join(stale).exists() {
                    eprintln!(
                        "note       {} is from an earlier run, not this one",
                        out.join(stale).display()
                    );
                }
            }
            return Err(e);
        }
    };
    let path = out.join("plan.json");
    outcome.plan.save(&path)?;
    print_summary(&inst, &outcome);
    let report = pushpack::verify::verify_with(
        &inst,
        &outcome.plan,
        &pushpack::verify::VerifyOptions { physics: o.physics },
    );
    if let Some(t) = outcome.plan.robot_time_s() {
        println!("robot time {t:.1} s (both arms in turn, joint trajectories included)");
    }
    let vetoes = &outcome.plan.solver.sequence.physics_vetoes;
    if !vetoes.is_empty() {
        println!(
            "physics    {} action(s) the replay rejected were avoided in their neighbourhood:",
            vetoes.len()
        );
        for v in vetoes {
            println!("  {v}");
        }
    }
    if report.is_executable() {
        println!("verify     valid (packing, joint trajectories, physics replay): the robot can run it");
    } else if report.is_robot_valid() && report.physics_issues.is_empty() {
        println!(
            "verify     valid for the robot; the physics replay was not run (--no-physics), so not called executable"
        );
    } else if report.is_valid() {
        println!(
            "verify     valid as a packing-only plan, not executable ({} robot issue(s))",
            report.robot_issues.len()
        );
        for v in &report.robot_issues {
            println!("  {v}");
        }
    } else {
        println!("verify     {report}");
        if !report.physics_issues.is_empty() {
            println!(
                "hint       the physics replay moves a box out of tolerance: `pushpack simulate {}` shows every action",
                path.display()
            );
        }
        if !report.robot_issues.is_empty() && report.is_packing_valid() {
            println!("hint       the packing is valid; --packing-only accepts a plan the robot cannot run");
        }
    }
    println!("wrote      {}", path.display());
    if !no_render {
        for f in render(&inst, &outcome.plan, &out)? {
            println!("wrote      {}", f.display());
        }
    }
    Ok(if report.is_valid() { EXIT_OK } else { EXIT_FAIL })
}

/// `pushpack place`.
/// `place` options of the exact solver.
struct ExactArgs {
    area_master: Option<String>,
    contact_budget: Option<String>,
    highs_options: Vec<String>,
    threads: Option<usize>,
}

impl ExactArgs {
    /// The exact solver's settings, or the error naming the option.
    fn settings(&self, time_limit: f64, seed: u64) -> Result<pushpack::placement::milp::MilpSettings, Error> {
        use pushpack::placement::milp::{AreaMaster, ContactBudget, MilpSettings};
        let contact_budget = match self.contact_budget.as_deref() {
            None | Some("rest") => ContactBudget::Rest,
            Some("area") => ContactBudget::AreaTime,
            Some(v) => match v.parse::<f64>() {
                Ok(s) if s.is_finite() && s >= 0.0 => ContactBudget::Seconds(s),
                _ => {
                    return Err(Error::input(
                        "<command line>",
                        "--contact-budget",
                        format!("must be rest, area or a number of seconds >= 0, got {v:?}"),
                    ))
                }
            },
        };
        let mut highs_options = Vec::new();
        for o in &self.highs_options {
            let Some((name, value)) = o.split_once('=') else {
                return Err(Error::input(
                    "<command line>",
                    "--highs-option",
                    format!("must be NAME=VALUE, got {o:?}"),
                ));
            };
            highs_options.push((name.trim().to_string(), value.trim().to_string()));
        }
        let threads = self.threads.map_or(Ok(1), threads_in_range)?;
        let settings = MilpSettings {
            time_limit,
            contact_stage: true,
            seed,
            area_master: match self.area_master.as_deref() {
                Some("highs") => AreaMaster::Highs,
                _ => AreaMaster::Search,
            },
            contact_budget,
            highs_options,
            threads,
            ..MilpSettings::default()
        };
        settings.check_highs_options("<command line>", "--highs-option")?;
        Ok(settings)
    }

    fn given(&self) -> bool {
        self.area_master.is_some()
            || self.contact_budget.is_some()
            || !self.highs_options.is_empty()
            || self.threads.is_some()
    }
}

fn cmd_place(
    instance: PathBuf,
    solver: String,
    seed: Option<u64>,
    time_limit: Option<f64>,
    json: bool,
    exact: ExactArgs,
) -> Result<i32, Error> {
    let inst = Instance::load(&instance)?;
    let t = positive_time(time_limit, "--time-limit")?.unwrap_or(inst.settings.time_limit);
    let seed = seed.unwrap_or(inst.settings.seed);
    let (r, report) = if solver == "milp" {
        let settings = exact.settings(t, seed)?;
        pushpack::plan::solve_placement_exact(&inst, inst.settings.bl_orders, &settings, &pushpack::control::Never)
            .map(|(r, rep)| (r, Some(rep)))?
    } else if exact.given() {
        return Err(Error::input(
            "<command line>",
            "--area-master/--contact-budget/--highs-option/--threads",
            "only the exact solver has them: add --solver milp",
        ));
    } else {
        pushpack::plan::solve_placement_report(&inst, PlacementSolver::Bl, seed, inst.settings.bl_orders, t)?
    };
    if json {
        // The result, plus the objective it optimised (lexicographic: area, then
        // contact), the gap, and for the exact solver the bound over time.
        let mut v = serde_json::to_value(&r).expect("serialisable");
        v["objective"] = serde_json::json!({
            "occupied_area": r.placement.occupied_area(),
            "contact_length": r.placement.contact_length(&inst),
            "order": ["min occupied_area", "max contact_length"],
        });
        v["gap"] = serde_json::json!(r.gap());
        if let Some(rep) = report {
            v["report"] = serde_json::to_value(&rep).expect("serialisable");
        }
        println!("{}", serde_json::to_string_pretty(&v).expect("serialisable"));
    } else {
        let contact = r.placement.contact_length(&inst);
        // A contact stage stopped early says how much contact it could not rule out.
        let contact_bound = match report.as_ref().and_then(|rep| rep.contact_upper_bound) {
            Some(b) if b > contact + 1e-9 => format!(" (at most {b:.4} m)"),
            _ => String::new(),
        };
        println!(
            "placement ({}, {:?}): occupied area {:.6} m², lower bound {:.6} m² (gap {:.2} %), contact length {:.4} m{}, {} nodes, {} MILPs, {:.3} s",
            r.solver,
            r.status,
            r.placement.occupied_area(),
            r.lower_bound,
            100.0 * r.gap(),
            contact,
            contact_bound,
            r.nodes,
            r.subproblems,
            r.time_s
        );
        for (i, t) in r.placement.targets.iter().enumerate() {
            println!(
                "  {:>6}  {:>4}  x {:.4}  y {:.4}  {:.4} x {:.4} x {:.4}",
                inst.objects[i].id,
                t.orientation.label(),
                t.rect.x0,
                t.rect.y0,
                t.rect.width(),
                t.rect.depth(),
                t.height
            );
        }
    }
    Ok(EXIT_OK)
}

/// `--threads N`: 1 to 256.
fn threads_in_range(n: usize) -> Result<usize, Error> {
    if (1..=256).contains(&n) {
        Ok(n)
    } else {
        Err(Error::input(
            "<command line>",
            "--threads",
            format!("must be between 1 and 256, got {n}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_travel_phase_is_printed_in_millimetres_degrees_and_per_cent() {
        let t = pushpack::plan::TravelPhase {
            object: "b".into(),
            gap: 0.015,
            rotation: 0.6f64.to_radians(),
            drift: 0.0002,
            usage: 0.6,
        };
        assert_eq!(
            travel_line(3, &t),
            "travel     push 3: b closes 15.0 mm alone, turning 0.60° and drifting 0.20 mm (60 % of the tolerances)"
        );
    }
}

//! The `verify`, `simulate` and `bench` commands.

use super::*;

/// `pushpack verify`: the verifier's report (and the physics replay's with `--simulate`).
pub(super) fn cmd_verify(cmd: Cmd) -> Result<i32, Error> {
    let Cmd::Verify {
        instance,
        plan,
        json,
        packing_only,
        simulate,
        no_physics,
    } = cmd
    else {
        unreachable!("run dispatches only Cmd::Verify here")
    };
    let (p, inst) = load_plan_instance(&plan, Some(&instance))?;
    let mut report = pushpack::verify::verify_with(
        &inst,
        &p,
        &pushpack::verify::VerifyOptions {
            physics: !no_physics && !packing_only,
        },
    );
    report.packing_only |= packing_only;
    let sim = if simulate {
        Some(pushpack::simulate::simulate(
            &inst,
            &p,
            &SimOptions::from_instance(&inst),
        )?)
    } else {
        None
    };
    if json {
        let v = match &sim {
            None => serde_json::to_value(&report),
            Some(s) => serde_json::to_value(serde_json::json!({ "verify": &report, "simulation": s })),
        };
        println!(
            "{}",
            serde_json::to_string_pretty(&v.expect("serialisable")).expect("serialisable")
        );
    } else {
        println!("{report}");
        if let Some(s) = &sim {
            print!("{s}");
        }
    }
    let sim_ok = sim.as_ref().is_none_or(|s| s.ok);
    Ok(if report.is_valid() && sim_ok {
        EXIT_OK
    } else {
        EXIT_FAIL
    })
}

/// `pushpack simulate`: one physics replay, or `--sweep` over the settings a push must not
/// depend on.
pub(super) fn cmd_simulate(cmd: Cmd) -> Result<i32, Error> {
    let Cmd::Simulate {
        plan,
        instance,
        json,
        dt,
        push_speed,
        contact_hz,
        sweep,
        robust,
        seed,
        min_share,
    } = cmd
    else {
        unreachable!("run dispatches only Cmd::Simulate here")
    };
    if robust == Some(0) {
        return Err(Error::input("<command line>", "--robust", "must be >= 1"));
    }
    let min_share = min_share.unwrap_or(1.0);
    if !(0.0..=1.0).contains(&min_share) {
        return Err(Error::input(
            "<command line>",
            "--min-share",
            format!("must be within 0..=1, got {min_share}"),
        ));
    }
    let flags = [("--dt", dt), ("--push-speed", push_speed), ("--contact-hz", contact_hz)];
    for (flag, v) in flags {
        if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(Error::input(
                "<command line>",
                flag,
                format!("must be a finite number > 0, got {v}"),
            ));
        }
    }
    let (p, inst) = load_plan_instance(&plan, instance.as_deref())?;
    let d = SimOptions::from_instance(&inst);
    let opts = SimOptions {
        dt: dt.unwrap_or(d.dt),
        push_speed: push_speed.unwrap_or(d.push_speed),
        contact_hz: contact_hz.unwrap_or(d.contact_hz),
        ..d
    };
    if let Some(n) = robust {
        let runs = pushpack::simulate::robust::robust(&inst, &p, &opts, n, seed.unwrap_or(0))?;
        let share = pushpack::simulate::robust::share_ok(&runs);
        if json {
            let v = serde_json::json!({ "share_within_tolerance": share, "runs": runs });
            println!("{}", serde_json::to_string_pretty(&v).expect("serialisable"));
        } else {
            print!("{}", pushpack::simulate::robust::robust_table(&runs));
        }
        return Ok(if share + 1e-12 >= min_share { EXIT_OK } else { EXIT_FAIL });
    }
    if sweep {
        let runs = pushpack::simulate::sweep::sweep(&inst, &p, &opts)?;
        if json {
            println!("{}", serde_json::to_string_pretty(&runs).expect("serialisable"));
        } else {
            print!("{}", pushpack::simulate::sweep::sweep_table(&runs));
        }
        return Ok(if runs.iter().all(|r| r.report.ok) {
            EXIT_OK
        } else {
            EXIT_FAIL
        });
    }
    let report = pushpack::simulate::simulate(&inst, &p, &opts)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("serialisable"));
    } else {
        print!("{report}");
    }
    Ok(if report.ok { EXIT_OK } else { EXIT_FAIL })
}

/// `pushpack export`: verifies the plan first, because a controller runs whatever it is sent.
pub(super) fn cmd_export(cmd: Cmd) -> Result<i32, Error> {
    let Cmd::Export {
        plan,
        format,
        out,
        instance,
        packing_only,
        left_controller,
        right_controller,
        left_gripper_controller,
        right_gripper_controller,
    } = cmd
    else {
        unreachable!("run dispatches only Cmd::Export here")
    };
    let fmt: pushpack::plan::export::ExportFormat = format
        .parse()
        .map_err(|e: String| Error::input("<command line>", "--format", e))?;
    let (p, inst) = load_plan_instance(&plan, instance.as_deref())?;
    let opts = pushpack::plan::export::ExportOptions {
        left_controller,
        right_controller,
        left_gripper_controller,
        right_gripper_controller,
        ..pushpack::plan::export::ExportOptions::from_instance(&inst)
    };
    opts.check("<command line>")?;
    let report = pushpack::verify(&inst, &p);
    if !report.is_packing_valid() {
        eprintln!(
            "error: {} is not a valid packing ({} violation(s); `pushpack verify` lists them); nothing exported",
            plan.display(),
            report.violations.len()
        );
        return Ok(EXIT_FAIL);
    }
    if !report.is_executable() {
        let why = if report.packing_only {
            "it was planned as a packing-only study".to_string()
        } else {
            format!("{} robot issue(s)", report.robot_issues.len())
        };
        if !packing_only {
            eprintln!(
                "error: {} is not executable ({why}; `pushpack verify` lists them), so a controller must not run it; nothing exported. Give --packing-only to export it anyway.",
                plan.display()
            );
            return Ok(EXIT_FAIL);
        }
        eprintln!(
            "warning: {} is not executable ({why}); exported because of --packing-only: do not send it to a robot",
            plan.display()
        );
    }
    for f in pushpack::plan::export::export_with(&p, fmt, &out, &opts)? {
        println!("wrote {}", f.display());
    }
    Ok(EXIT_OK)
}

/// `pushpack bench`.
pub(super) fn cmd_bench(cmd: Cmd) -> Result<i32, Error> {
    let Cmd::Bench {
        instances,
        planners,
        time_limit,
        hard_limit,
        jobs,
        out,
        shard,
        resume,
        max_runs,
    } = cmd
    else {
        unreachable!("run dispatches only Cmd::Bench here")
    };
    let time_limit = positive_time(Some(time_limit), "--time-limit")?.unwrap_or(time_limit);
    let hard_limit = match positive_time(hard_limit, "--hard-limit")? {
        Some(h) => h,
        None => 2.0 * time_limit + 30.0,
    };
    let jobs = match jobs {
        Some(0) => return Err(Error::input("<command line>", "--jobs", "must be at least 1")),
        Some(j) => j,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let cfg = pushpack::bench::BenchConfig {
        instances,
        planners: pushpack::bench::spec::PlannerSpec::parse_list(&planners, "--planners")?,
        time_limit,
        hard_limit,
        jobs,
        out,
        shard: shard.as_deref().map(pushpack::bench::Shard::parse).transpose()?,
        resume,
        max_runs,
        exe: std::env::current_exe().map_err(|e| Error::Io {
            path: PathBuf::from("<current executable>"),
            source: e,
        })?,
    };
    let s = pushpack::bench::run_batch(&cfg)?;
    println!(
        "bench: {} runs in this shard, {} already done, {} run now ({} failed, {} stopped by a time or node limit), {} left; results in {}",
        s.total,
        s.already_done,
        s.ran,
        s.failed,
        s.stopped,
        s.left,
        s.results.display()
    );
    Ok(EXIT_OK)
}

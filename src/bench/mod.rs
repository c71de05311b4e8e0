//! The benchmark harness: expands instance sets × planner specs into runs, shards them, runs
//! each in its own child process in parallel (rayon) with a progress bar, and appends one
//! result row per run as it ends so that an interrupted batch resumes (docs/benchmarks.md).
//!
//! Why a child process per run, not `catch_unwind` in this process: the library's time limits
//! are per stage and cooperative (the joint-trajectory stage and the verifier have none), a
//! HiGHS call can overrun its limit, and a run can abort or exhaust memory. A child can be
//! killed at a hard wall-clock limit and takes its memory with it; a panic or abort costs one
//! row, not the batch. The child itself still catches panics so that their message is recorded.

pub mod row;
pub mod run;
pub mod sets;
pub mod spec;

use crate::error::{Error, Result};
use crate::instance::Instance;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use row::{read_jsonl, ResultRow, RowWriter, RunStatus};
use spec::PlannerSpec;
use std::collections::HashSet;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wait_timeout::ChildExt;

/// The part of a batch this process runs: `index` of `count` (0-based, `K/N` on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, `0..count`.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Parse `K/N` with `0 <= K < N`.
    pub fn parse(text: &str) -> Result<Shard> {
        let bad = |r: String| Error::input("<command line>", "--shard", r);
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad(format!("must be K/N (e.g. 0/4), got {text:?}")))?;
        let k: usize = k
            .trim()
            .parse()
            .map_err(|_| bad(format!("K in {text:?} is not a number")))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad(format!("N in {text:?} is not a number")))?;
        if n == 0 || k >= n {
            return Err(bad(format!("need 0 <= K < N, got {k}/{n} (K is 0-based)")));
        }
        Ok(Shard { index: k, count: n })
    }
}

/// One (instance, planner) run.
#[derive(Debug, Clone)]
pub struct Job {
    /// Instance path as given (after directory expansion).
    pub path: String,
    /// Planner.
    pub spec: PlannerSpec,
}

impl Job {
    /// Resume/merge key, the same as [`ResultRow::key`].
    pub fn key(&self) -> (String, String) {
        (self.path.clone(), self.spec.to_string())
    }
}

/// Instance files among `paths`: files as given, directories searched one level deep for
/// `*.toml` and `*.json`, sorted by name. Errors name a path that is missing or holds none.
pub fn expand_instances(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = collect_files(paths, &["toml", "json"], "instance file (*.toml or *.json)")?;
    let mut seen = HashSet::new();
    out.retain(|p| seen.insert(p.clone()));
    Ok(out)
}

/// Files among `paths`: files as given, directories searched one level deep for files ending in
/// one of `exts` (sorted by name). A missing path, or a directory without such a file (`what`),
/// is an input error naming it.
pub fn collect_files(paths: &[PathBuf], exts: &[&str], what: &str) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| Error::Io {
                    path: p.clone(),
                    source: e,
                })?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.is_file() && f.extension().is_some_and(|x| exts.iter().any(|e| x == *e)))
                .collect();
            found.sort();
            if found.is_empty() {
                return Err(Error::input(
                    p.display().to_string(),
                    "<directory>",
                    format!("holds no {what}"),
                ));
            }
            out.extend(found);
        } else if p.is_file() {
            out.push(p.clone());
        } else {
            return Err(Error::input(
                p.display().to_string(),
                "<path>",
                "no such file or directory",
            ));
        }
    }
    Ok(out)
}

/// Every (instance, planner) pair, sorted by instance path then canonical planner name, so that
/// the order (and hence the shard split) does not depend on the order of the arguments.
pub fn all_jobs(instances: &[PathBuf], planners: &[PlannerSpec]) -> Vec<Job> {
    let mut jobs: Vec<Job> = instances
        .iter()
        .flat_map(|p| {
            planners.iter().map(move |s| Job {
                path: p.display().to_string(),
                spec: *s,
            })
        })
        .collect();
    jobs.sort_by_key(|j| j.key());
    jobs
}

/// The jobs of one shard: every `count`-th job of the sorted list, starting at `index`.
pub fn shard_jobs(jobs: Vec<Job>, shard: Option<Shard>) -> Vec<Job> {
    match shard {
        None => jobs,
        Some(s) => jobs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % s.count == s.index)
            .map(|(_, j)| j)
            .collect(),
    }
}

/// Everything a batch needs.
#[derive(Debug, Clone)]
pub struct BenchConfig {
    /// Instance files or directories.
    pub instances: Vec<PathBuf>,
    /// Planners.
    pub planners: Vec<PlannerSpec>,
    /// Library time limit per stage (s).
    pub time_limit: f64,
    /// Wall-clock limit of one run's process (s); it is killed and recorded as `timeout` past it.
    pub hard_limit: f64,
    /// Parallel runs.
    pub jobs: usize,
    /// Output directory.
    pub out: PathBuf,
    /// This process's shard.
    pub shard: Option<Shard>,
    /// Continue the result file in `out` instead of refusing to touch it.
    pub resume: bool,
    /// Run at most this many of the pending runs, then stop (resume later).
    pub max_runs: Option<usize>,
    /// The pushpack binary that runs one job (`pushpack bench-run`).
    pub exe: PathBuf,
}

/// What a batch did.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchSummary {
    /// Runs in this shard.
    pub total: usize,
    /// Runs found done in the result file.
    pub already_done: usize,
    /// Runs made now.
    pub ran: usize,
    /// Of those, `failed`.
    pub failed: usize,
    /// Of those, `timeout` or `node_limit`.
    pub stopped: usize,
    /// Runs left for a later `--resume`.
    pub left: usize,
    /// The JSON Lines result file.
    pub results: PathBuf,
}

/// File stem of the results of a shard: `results` or `results.shard-K-of-N`.
pub fn results_stem(shard: Option<Shard>) -> String {
    match shard {
        None => "results".into(),
        Some(s) => format!("results.shard-{}-of-{}", s.index, s.count),
    }
}

/// Run one job in a child process `exe bench-run`, killing it past `hard_limit` seconds.
/// Every outcome, including a crash or a kill, becomes a row.
pub fn run_child(exe: &Path, job: &Job, inst: &Instance, time_limit: f64, hard_limit: f64, jobs: usize) -> ResultRow {
    let start = Instant::now();
    let mut row = run::base_row(&job.path, inst, &job.spec, time_limit);
    let finish = |mut row: ResultRow, status: RunStatus, msg: String| {
        row.status = status;
        row.error = Some(msg);
        row.wall_time_s = start.elapsed().as_secs_f64();
        row.jobs = Some(jobs);
        row
    };
    let child = Command::new(exe)
        .arg("bench-run")
        .arg(&job.path)
        .arg("--planner")
        .arg(job.spec.to_string())
        .arg("--time-limit")
        .arg(time_limit.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return finish(row, RunStatus::Error, format!("cannot start {}: {e}", exe.display())),
    };
    // Read both pipes on threads so a chatty child never blocks on a full pipe.
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let out_t = drain(Box::new(child.stdout.take().expect("piped")));
    let err_t = drain(Box::new(child.stderr.take().expect("piped")));
    let status = match child.wait_timeout(Duration::from_secs_f64(hard_limit)) {
        Ok(Some(s)) => Some(s),
        Ok(None) => {
            let _ = child.kill();
            let _ = child.wait();
            None
        }
        Err(e) => {
            let _ = child.kill();
            let _ = child.wait();
            return finish(row, RunStatus::Error, format!("waiting for the run failed: {e}"));
        }
    };
    let stdout = out_t.join().unwrap_or_default();
    let stderr = err_t.join().unwrap_or_default();
    let Some(status) = status else {
        return finish(
            row,
            RunStatus::Killed,
            format!("killed after the hard limit of {hard_limit} s"),
        );
    };
    match stdout
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .map(serde_json::from_str::<ResultRow>)
    {
        Some(Ok(r)) if status.success() => {
            row = r;
            row.jobs = Some(jobs);
            row.wall_time_s = start.elapsed().as_secs_f64();
            row
        }
        _ => {
            let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
            let tail: Vec<&str> = tail.into_iter().rev().collect();
            finish(
                row,
                RunStatus::Crashed,
                format!("run process {status}: {}", tail.join(" | ")),
            )
        }
    }
}

/// Run a batch: every pending job of this shard, `cfg.jobs` at a time, appending rows as they end.
pub fn run_batch(cfg: &BenchConfig) -> Result<BenchSummary> {
    // More concurrent runs than cores would make every time limit mean less, silently.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cfg.jobs == 0 || cfg.jobs > cores {
        return Err(Error::input(
            "<command line>",
            "--jobs",
            format!("must be between 1 and the machine's {cores} cores, got {}", cfg.jobs),
        ));
    }
    let files = expand_instances(&cfg.instances)?;
    // Load every instance first: a bad file is bad input, reported before hours of computing.
    let mut insts = std::collections::HashMap::new();
    for f in &files {
        insts.insert(f.display().to_string(), Instance::load(f)?);
    }
    let jobs = shard_jobs(all_jobs(&files, &cfg.planners), cfg.shard);
    std::fs::create_dir_all(&cfg.out).map_err(|e| Error::Io {
        path: cfg.out.clone(),
        source: e,
    })?;
    let stem = results_stem(cfg.shard);
    let jsonl = cfg.out.join(format!("{stem}.jsonl"));
    let (existing, keep) = if jsonl.exists() {
        read_jsonl(&jsonl)?
    } else {
        (Vec::new(), 0)
    };
    if !existing.is_empty() && !cfg.resume {
        return Err(Error::input(
            jsonl.display().to_string(),
            "<file>",
            format!(
                "already holds {} result rows; pass --resume to continue this batch or choose another --out",
                existing.len()
            ),
        ));
    }
    let done: HashSet<(String, String)> = existing.iter().map(ResultRow::key).collect();
    let mut pending: Vec<Job> = jobs.iter().filter(|j| !done.contains(&j.key())).cloned().collect();
    let already_done = jobs.len() - pending.len();
    let left_after = match cfg.max_runs {
        Some(m) if m < pending.len() => {
            let left = pending.len() - m;
            pending.truncate(m);
            left
        }
        _ => 0,
    };
    let writer = Mutex::new(RowWriter::open(&cfg.out, &stem, &existing, keep)?);

    let pb = ProgressBar::with_draw_target(Some(pending.len() as u64), ProgressDrawTarget::stderr());
    pb.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:30}] {pos}/{len} runs, {msg}, ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    pb.set_message("0 failed");
    let failed = Mutex::new((0usize, 0usize));
    let write_err: Mutex<Option<Error>> = Mutex::new(None);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.jobs.max(1))
        .build()
        .map_err(|e| Error::input("<command line>", "--jobs", format!("cannot start threads: {e}")))?;
    pool.install(|| {
        // par_bridge hands out runs in list order (par_iter would split the list in halves), so
        // an interrupted batch has finished the first sets rather than parts of every set.
        pending.iter().par_bridge().for_each(|job| {
            let inst = &insts[&job.path];
            let row = run_child(&cfg.exe, job, inst, cfg.time_limit, cfg.hard_limit, cfg.jobs);
            let (nf, nt) = {
                let mut f = failed.lock().expect("no panics while locked");
                if row.status.is_failure() {
                    f.0 += 1;
                } else if row.status.is_stopped() {
                    f.1 += 1;
                }
                *f
            };
            if let Err(e) = writer.lock().expect("no panics while locked").append(&row) {
                write_err.lock().expect("no panics while locked").get_or_insert(e);
            }
            pb.inc(1);
            pb.set_message(format!("{nf} failed, {nt} stopped by a limit"));
            if pb.is_hidden() {
                // No terminal (a batch job's log): one line per run instead of the bar.
                eprintln!(
                    "[{}/{}] {} {}: {} {:.1} s",
                    pb.position(),
                    pending.len(),
                    job.path,
                    job.spec,
                    row.status.as_str(),
                    row.wall_time_s
                );
            }
        })
    });
    pb.finish();
    if let Some(e) = write_err.into_inner().expect("no panics while locked") {
        return Err(e);
    }
    let (nf, nt) = failed.into_inner().expect("no panics while locked");
    Ok(BenchSummary {
        total: jobs.len(),
        already_done,
        ran: pending.len(),
        failed: nf,
        stopped: nt,
        left: left_after,
        results: jsonl,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_sorted_jobs() {
        let inst: Vec<PathBuf> = ["b.toml", "a.toml", "c.toml"].iter().map(PathBuf::from).collect();
        let pl = PlannerSpec::parse_list("milp+astar,bl+paper", "--planners").unwrap();
        let all = all_jobs(&inst, &pl);
        assert_eq!(all[0].key(), ("a.toml".to_string(), "bl+paper".to_string()));
        let mut merged: Vec<_> = (0..4)
            .flat_map(|k| shard_jobs(all.clone(), Some(Shard { index: k, count: 4 })))
            .map(|j| j.key())
            .collect();
        merged.sort();
        assert_eq!(merged, all.iter().map(Job::key).collect::<Vec<_>>());
        // Argument order does not change the split.
        let rev: Vec<PathBuf> = inst.iter().rev().cloned().collect();
        let s = |i: &[PathBuf]| {
            shard_jobs(all_jobs(i, &pl), Some(Shard { index: 1, count: 2 }))
                .iter()
                .map(Job::key)
                .collect::<Vec<_>>()
        };
        assert_eq!(s(&inst), s(&rev));
    }

    #[test]
    fn shard_syntax() {
        assert_eq!(Shard::parse("2/5").unwrap(), Shard { index: 2, count: 5 });
        for bad in ["5/5", "1", "a/2", "0/0", "-1/3"] {
            assert!(Shard::parse(bad).unwrap_err().is_input(), "{bad}");
        }
    }
}

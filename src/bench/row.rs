//! One benchmark result row per (instance, planner): its fields, CSV/JSON Lines I/O, and reading
//! result files back (tolerating a last line cut short by a kill).

use crate::error::{Error, Result};
use crate::status::Status;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// How a run ended: the planner's [`Status`], or one of the ways a run can fail without one
/// (docs/formats.md, "Benchmark results"). Written as one word, the status's own for
/// [`RunStatus::Planner`], so that result files keep a single `status` column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RunStatus {
    /// The planner ended with this status (`optimal` … `infeasible`; a proven-infeasible run
    /// is an answer, not a failure).
    Planner(Status),
    /// The run's process exceeded the hard wall-clock limit and was killed.
    Killed,
    /// The planner panicked, or its process died without a result.
    Crashed,
    /// The planner returned an error (bad input, a solver failure).
    Error,
    /// Written before format 2 of the rows; read back by [`ResultRow::upgraded`] only.
    #[doc(hidden)]
    LegacyOk,
    /// Written before format 2 of the rows; read back by [`ResultRow::upgraded`] only.
    #[doc(hidden)]
    LegacyFailed,
    /// Written before format 2 of the rows; read back by [`ResultRow::upgraded`] only.
    #[doc(hidden)]
    LegacyTimeout,
}

impl From<Status> for RunStatus {
    fn from(s: Status) -> RunStatus {
        RunStatus::Planner(s)
    }
}

impl RunStatus {
    /// The ways a run ends without a planner status, with their names in result files.
    const OTHERS: [(RunStatus, &'static str); 6] = [
        (RunStatus::Killed, "killed"),
        (RunStatus::Crashed, "crashed"),
        (RunStatus::Error, "error"),
        (RunStatus::LegacyOk, "ok"),
        (RunStatus::LegacyFailed, "failed"),
        (RunStatus::LegacyTimeout, "timeout"),
    ];

    /// The planner's status, when the run ended with one.
    pub fn status(self) -> Option<Status> {
        match self {
            RunStatus::Planner(s) => Some(s),
            _ => None,
        }
    }

    /// True for the ways a run fails: killed, crashed, or an error.
    pub fn is_failure(self) -> bool {
        matches!(
            self,
            RunStatus::Killed | RunStatus::Crashed | RunStatus::Error | RunStatus::LegacyFailed
        )
    }

    /// True when a limit (time, nodes, hard kill, cancel) ended the run before any plan.
    pub fn is_stopped(self) -> bool {
        matches!(
            self,
            RunStatus::Planner(Status::TimeLimit | Status::NodeLimit | Status::Cancelled) | RunStatus::Killed
        )
    }

    /// The name written in result files.
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Planner(s) => s.as_str(),
            other => {
                Self::OTHERS
                    .iter()
                    .find(|(r, _)| *r == other)
                    .expect("every other status is named")
                    .1
            }
        }
    }

    /// The status a result file names `name`.
    pub fn from_name(name: &str) -> Option<RunStatus> {
        Status::ALL
            .iter()
            .find(|s| s.as_str() == name)
            .map(|s| RunStatus::Planner(*s))
            .or_else(|| Self::OTHERS.iter().find(|(_, n)| *n == name).map(|(r, _)| *r))
    }
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for RunStatus {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

impl<'de> Deserialize<'de> for RunStatus {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<RunStatus, D::Error> {
        let name = String::deserialize(d)?;
        RunStatus::from_name(&name).ok_or_else(|| {
            let known: Vec<&str> = Status::ALL
                .iter()
                .map(|s| s.as_str())
                .chain(Self::OTHERS.iter().map(|(_, n)| *n))
                .collect();
            serde::de::Error::custom(format!("unknown run status {name:?}, expected one of {known:?}"))
        })
    }
}

/// One result row (docs/formats.md, "Benchmark results"). `None` fields are empty in CSV and
/// `null` in JSON: they are unknown because the run produced no plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultRow {
    /// Instance path as given on the command line.
    pub instance: String,
    /// SHA-256 of the instance file.
    pub instance_digest: String,
    /// Set name: the instance's parent folder name.
    pub set: String,
    /// Instance name.
    pub name: String,
    /// Number of objects.
    pub objects: usize,
    /// Number of kinds.
    pub kinds: usize,
    /// Canonical planner spec.
    pub planner: String,
    /// Seed given to the planner.
    pub seed: u64,
    /// The run's time limit (s): placement, sequence and joint trajectories together.
    pub time_limit_s: f64,
    /// How the run ended.
    pub status: RunStatus,
    /// Error message of a failed or timed-out run.
    pub error: Option<String>,
    /// Placement stage status ([`Status`]: `optimal`, `feasible` or `heuristic`).
    pub placement_status: Option<String>,
    /// Occupied area (m²).
    pub occupied_area: Option<f64>,
    /// Proven lower bound of the occupied area (m²).
    pub placement_bound: Option<f64>,
    /// Relative placement gap.
    pub placement_gap: Option<f64>,
    /// Contact length (m).
    pub contact_length: Option<f64>,
    /// Which alternative placement the plan used (`altN` planners): 0 for the placement
    /// stage's own, k ≥ 1 when the k placements before it were proven to have no plan.
    #[serde(default)]
    pub placement_alternative: Option<usize>,
    /// Number of actions.
    pub seq_len: Option<usize>,
    /// Direct places.
    pub n_place_direct: Option<usize>,
    /// Indirect places.
    pub n_place_indirect: Option<usize>,
    /// Pushes.
    pub n_push: Option<usize>,
    /// Pushes of two or more objects.
    pub n_multi_push: Option<usize>,
    /// Swept area (m²).
    pub swept_area: Option<f64>,
    /// TCP travel (m).
    pub travel: Option<f64>,
    /// Smallest push stability margin over the plan's pushes (m); none without pushes.
    pub min_push_margin: Option<f64>,
    /// Sequence stage status ([`Status`]: `optimal`, `feasible` or `heuristic`).
    pub sequence_status: Option<String>,
    /// Proven lower bound on the number of actions (A* only).
    pub sequence_bound_len: Option<usize>,
    /// Proven lower bound on the swept area (m², A* only).
    pub sequence_bound_area: Option<f64>,
    /// Proven lower bound on the travel (m, A* only).
    pub sequence_bound_travel: Option<f64>,
    /// Relative travel gap of the sequence (A* only; 1 when the bound is on an earlier criterion).
    pub sequence_gap: Option<f64>,
    /// Placement nodes (or Bottom-Left orders).
    pub placement_nodes: Option<u64>,
    /// Sequence search nodes.
    pub sequence_nodes: Option<u64>,
    /// Assignments evaluated by the sequencer.
    pub sequence_assignments: Option<u64>,
    /// Placement stage time (s).
    pub placement_time_s: Option<f64>,
    /// Sequence stage time (s).
    pub sequence_time_s: Option<f64>,
    /// Whole `plan::optimize` time, joint trajectories included (s).
    pub plan_time_s: Option<f64>,
    /// Verifier time (s).
    pub verify_time_s: Option<f64>,
    /// Wall-clock time of the run's process, start to exit (s).
    pub wall_time_s: f64,
    /// Verifier verdict on the packing plan: `valid` or `invalid`.
    pub verify: Option<String>,
    /// Number of packing violations the verifier found.
    pub violations: Option<usize>,
    /// Number of joint-trajectory problems the verifier found (reported apart, docs/robot.md).
    pub robot_issues: Option<usize>,
    /// Robot execution time of the plan: the end of its last joint trajectory (s).
    #[serde(default)]
    pub robot_time_s: Option<f64>,
    /// Physics replay (planner option `simulate`): every action and box within the push
    /// tolerances (`pushpack simulate`).
    #[serde(default)]
    pub sim_ok: Option<bool>,
    /// Physics replay: the largest final distance of a box from its target (mm).
    #[serde(default)]
    pub sim_position_error_mm: Option<f64>,
    /// Physics replay: the largest final rotation of a box from its target (degrees).
    #[serde(default)]
    pub sim_rotation_deg: Option<f64>,
    /// Physics replay time (s).
    #[serde(default)]
    pub sim_time_s: Option<f64>,
    /// Host name of the machine that ran it.
    #[serde(default)]
    pub host: Option<String>,
    /// CPU model of that machine (`/proc/cpuinfo`).
    #[serde(default)]
    pub cpu_model: Option<String>,
    /// Concurrent runs of the batch (`--jobs`): runs share the machine's cores.
    #[serde(default)]
    pub jobs: Option<usize>,
    /// pushpack version that ran the plan.
    pub tool_version: String,
    /// Git commit the binary was built from (`unknown` outside a repository).
    pub git_commit: String,
}

/// Column order of the CSV file (and the fields of [`ResultRow`]).
pub const COLUMNS: &[&str] = &[
    "instance",
    "instance_digest",
    "set",
    "name",
    "objects",
    "kinds",
    "planner",
    "seed",
    "time_limit_s",
    "status",
    "error",
    "placement_status",
    "occupied_area",
    "placement_bound",
    "placement_gap",
    "contact_length",
    "placement_alternative",
    "seq_len",
    "n_place_direct",
    "n_place_indirect",
    "n_push",
    "n_multi_push",
    "swept_area",
    "travel",
    "min_push_margin",
    "sequence_status",
    "sequence_bound_len",
    "sequence_bound_area",
    "sequence_bound_travel",
    "sequence_gap",
    "placement_nodes",
    "sequence_nodes",
    "sequence_assignments",
    "placement_time_s",
    "sequence_time_s",
    "plan_time_s",
    "verify_time_s",
    "wall_time_s",
    "verify",
    "violations",
    "robot_issues",
    "robot_time_s",
    "sim_ok",
    "sim_position_error_mm",
    "sim_rotation_deg",
    "sim_time_s",
    "host",
    "cpu_model",
    "jobs",
    "tool_version",
    "git_commit",
];

/// Fields that measure time and so differ between otherwise identical runs.
pub const TIMING_COLUMNS: &[&str] = &[
    "placement_time_s",
    "sequence_time_s",
    "plan_time_s",
    "verify_time_s",
    "sim_time_s",
    "wall_time_s",
];

/// This machine's host name and CPU model, when the system says (Linux: `/proc`).
pub fn machine() -> (Option<String>, Option<String>) {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty());
    let cpu = std::fs::read_to_string("/proc/cpuinfo").ok().and_then(|c| {
        c.lines()
            .find(|l| l.starts_with("model name"))
            .and_then(|l| l.split_once(':'))
            .map(|(_, m)| m.trim().to_string())
    });
    (host, cpu)
}

/// Version and commit of this binary.
pub fn tool_version() -> (String, String) {
    (
        env!("CARGO_PKG_VERSION").to_string(),
        env!("PUSHPACK_GIT_COMMIT").to_string(),
    )
}

impl ResultRow {
    /// The row as the current version writes it. Rows from before the one outcome vocabulary
    /// said `ok`, `failed` or `timeout`, and used the sequencer's own words (`complete`): they
    /// are restated in [`Status`] terms from the planner that ran, so that the paper's sequencer
    /// is never read back as a proof.
    pub fn upgraded(mut self) -> Self {
        let paper = super::spec::PlannerSpec::parse(&self.planner, "planner")
            .is_ok_and(|s| s.sequencer == crate::plan::Sequencer::Paper);
        let bl = self.planner.starts_with("bl");
        let placement = match self.placement_status.as_deref() {
            Some("optimal") => Some(Status::Optimal),
            Some("feasible") if bl => Some(Status::Heuristic),
            Some("feasible") => Some(Status::Feasible),
            Some(other) => serde_json::from_value(serde_json::Value::from(other)).ok(),
            None => None,
        };
        let sequence = match self.sequence_status.as_deref() {
            Some(_) if paper => Some(Status::Heuristic),
            Some("complete") => Some(Status::Optimal),
            Some("node_limit" | "time_limit") => Some(Status::Feasible),
            Some(other) => serde_json::from_value(serde_json::Value::from(other)).ok(),
            None => None,
        };
        self.placement_status = placement.map(|s| s.as_str().to_string());
        self.sequence_status = sequence.map(|s| s.as_str().to_string());
        let error = self.error.clone().unwrap_or_default();
        self.status = match self.status {
            RunStatus::LegacyOk => match (placement, sequence) {
                (Some(p), Some(q)) => Status::combine(&[p, q]).into(),
                _ => RunStatus::Planner(Status::Feasible),
            },
            RunStatus::LegacyFailed if error.starts_with("panic") || error.starts_with("run process") => {
                RunStatus::Crashed
            }
            RunStatus::LegacyFailed => RunStatus::Error,
            RunStatus::LegacyTimeout if error.starts_with("killed after") => RunStatus::Killed,
            RunStatus::LegacyTimeout if error.contains("stopped by its node limit") => {
                RunStatus::Planner(Status::NodeLimit)
            }
            RunStatus::LegacyTimeout => RunStatus::Planner(Status::TimeLimit),
            s => s,
        };
        self
    }

    /// The key results are merged and resumed by: (instance path, planner).
    pub fn key(&self) -> (String, String) {
        (self.instance.clone(), self.planner.clone())
    }

    /// True when the run produced a plan that the verifier accepts.
    pub fn solved(&self) -> bool {
        self.status.status().is_some_and(Status::has_solution) && self.verify.as_deref() == Some("valid")
    }

    /// True when the run's plan is verified and proven optimal: the placement proven optimal,
    /// and the sequence proven optimal for it ([`Status::combine`]). Heuristic stages (the
    /// paper's sequencer, Bottom-Left) never are.
    pub fn proven(&self) -> bool {
        self.solved() && self.status == RunStatus::Planner(Status::Optimal)
    }

    /// The row as JSON with the timing fields removed (for comparing runs).
    pub fn without_timing(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("rows serialise");
        if let Some(m) = v.as_object_mut() {
            for c in TIMING_COLUMNS {
                m.remove(*c);
            }
        }
        v
    }

    /// One JSON line (no trailing newline).
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).expect("rows serialise")
    }

    /// One CSV record in [`COLUMNS`] order (no trailing newline).
    pub fn to_csv_record(&self) -> String {
        let v = serde_json::to_value(self).expect("rows serialise");
        COLUMNS
            .iter()
            .map(|c| match &v[*c] {
                serde_json::Value::Null => String::new(),
                serde_json::Value::String(s) => csv_field(s),
                other => other.to_string(),
            })
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// The CSV header line.
pub fn csv_header() -> String {
    COLUMNS.join(",")
}

/// Quote a CSV field when it holds a comma, quote or line break (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn io_err(path: &Path, e: std::io::Error) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: e,
    }
}

/// Rows of a JSON Lines file and the byte length of its well-formed prefix.
///
/// A kill can cut the last line short; such a final line (no newline, or not parseable) is
/// ignored so the run is repeated on resume. A malformed line anywhere else is an input error.
pub fn read_jsonl(path: &Path) -> Result<(Vec<ResultRow>, u64)> {
    let text = std::fs::read_to_string(path).map_err(|e| io_err(path, e))?;
    let mut rows = Vec::new();
    let mut good = 0u64;
    let mut rest = text.as_str();
    let mut lineno = 0usize;
    while !rest.is_empty() {
        lineno += 1;
        let (line, complete, next) = match rest.find('\n') {
            Some(i) => (&rest[..i], true, &rest[i + 1..]),
            None => (rest, false, ""),
        };
        if line.trim().is_empty() {
            good += line.len() as u64 + u64::from(complete);
            rest = next;
            continue;
        }
        match serde_json::from_str::<ResultRow>(line) {
            Ok(r) if complete => {
                rows.push(r.upgraded());
                good += line.len() as u64 + 1;
            }
            Ok(_) => break, // parseable but unterminated: the writer died before the newline
            Err(e) => {
                if next.is_empty() {
                    break; // torn last line
                }
                return Err(Error::input(
                    path.display().to_string(),
                    format!("line {lineno}"),
                    format!("not a result row: {e}"),
                ));
            }
        }
        rest = next;
    }
    Ok((rows, good))
}

/// Every `*.jsonl` file among `paths` (files as given, directories searched one level deep).
pub fn result_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    super::collect_files(paths, &["jsonl"], "*.jsonl result file")
}

/// Appends rows to a JSON Lines and a CSV file, flushing after each row.
#[derive(Debug)]
pub struct RowWriter {
    jsonl: std::fs::File,
    csv: std::fs::File,
    jsonl_path: PathBuf,
    csv_path: PathBuf,
}

impl RowWriter {
    /// Open `stem.jsonl` and `stem.csv` in `dir`. The JSON Lines file is the record: it is cut
    /// back to `keep_bytes` (its well-formed prefix) and the CSV is rewritten from `existing`,
    /// so that both files hold the same rows after an interrupted run.
    pub fn open(dir: &Path, stem: &str, existing: &[ResultRow], keep_bytes: u64) -> Result<RowWriter> {
        let jsonl_path = dir.join(format!("{stem}.jsonl"));
        let csv_path = dir.join(format!("{stem}.csv"));
        let jsonl = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&jsonl_path)
            .map_err(|e| io_err(&jsonl_path, e))?;
        jsonl.set_len(keep_bytes).map_err(|e| io_err(&jsonl_path, e))?;
        let mut text = csv_header() + "\n";
        for r in existing {
            text += &r.to_csv_record();
            text.push('\n');
        }
        std::fs::write(&csv_path, text).map_err(|e| io_err(&csv_path, e))?;
        let csv = std::fs::OpenOptions::new()
            .append(true)
            .open(&csv_path)
            .map_err(|e| io_err(&csv_path, e))?;
        Ok(RowWriter {
            jsonl,
            csv,
            jsonl_path,
            csv_path,
        })
    }

    /// Append one row to both files and flush them to the OS (one `write` call per file, so a
    /// kill leaves at most one torn last line).
    pub fn append(&mut self, row: &ResultRow) -> Result<()> {
        let line = row.to_json_line() + "\n";
        self.jsonl
            .write_all(line.as_bytes())
            .and_then(|_| self.jsonl.flush())
            .map_err(|e| io_err(&self.jsonl_path, e))?;
        let rec = row.to_csv_record() + "\n";
        self.csv
            .write_all(rec.as_bytes())
            .and_then(|_| self.csv.flush())
            .map_err(|e| io_err(&self.csv_path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words result files have always used, in JSON and CSV alike: changing one would
    /// orphan every result file written before.
    #[test]
    fn run_status_names_are_the_files_words() {
        let every = [
            (RunStatus::Planner(Status::Optimal), "optimal"),
            (RunStatus::Planner(Status::Feasible), "feasible"),
            (RunStatus::Planner(Status::Heuristic), "heuristic"),
            (RunStatus::Planner(Status::TimeLimit), "time_limit"),
            (RunStatus::Planner(Status::NodeLimit), "node_limit"),
            (RunStatus::Planner(Status::Cancelled), "cancelled"),
            (RunStatus::Planner(Status::Infeasible), "infeasible"),
            (RunStatus::Killed, "killed"),
            (RunStatus::Crashed, "crashed"),
            (RunStatus::Error, "error"),
            (RunStatus::LegacyOk, "ok"),
            (RunStatus::LegacyFailed, "failed"),
            (RunStatus::LegacyTimeout, "timeout"),
        ];
        for (status, word) in every {
            assert_eq!(serde_json::to_value(status).unwrap(), serde_json::json!(word));
            assert_eq!(
                serde_json::from_value::<RunStatus>(serde_json::json!(word)).unwrap(),
                status
            );
            assert_eq!(status.to_string(), word);
            let mut row = sample("x.toml", "bl+paper");
            row.status = status;
            let csv = row.to_csv_record();
            let column = COLUMNS.iter().position(|c| *c == "status").unwrap();
            assert_eq!(csv.split(',').nth(column), Some(word), "{csv}");
        }
        assert!(serde_json::from_value::<RunStatus>(serde_json::json!("complete")).is_err());
    }

    fn sample(instance: &str, planner: &str) -> ResultRow {
        let inst = crate::instance::Instance::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/instances/examples/two_boxes.toml"
        ))
        .expect("bundled example");
        let spec = crate::bench::spec::PlannerSpec::parse(planner, "planner").expect("valid spec");
        let mut r = crate::bench::run::base_row(instance, &inst, &spec, 10.0);
        r.error = Some("boom, \"quoted\"".into());
        r
    }

    /// A solved row whose stages both report their best status.
    fn solved_and_complete(planner: &str) -> ResultRow {
        let mut r = sample("a", planner);
        r.error = None;
        r.status = RunStatus::LegacyOk;
        r.verify = Some("valid".into());
        r.placement_status = Some("optimal".into());
        r.sequence_status = Some("complete".into());
        r.upgraded()
    }

    #[test]
    fn only_a_complete_astar_search_on_an_optimal_placement_is_proven() {
        assert!(solved_and_complete("milp+astar").proven());
        assert!(solved_and_complete("milp+astar+no-direct").proven());
        // The paper's sequencer searched its whole candidate space: still a heuristic.
        assert!(!solved_and_complete("milp+paper").proven());
        assert!(!solved_and_complete("bl+paper").proven());
        assert_eq!(
            solved_and_complete("milp+paper").status,
            RunStatus::Planner(Status::Heuristic)
        );
        let mut r = sample("a", "milp+astar");
        r.status = RunStatus::LegacyOk;
        r.verify = Some("valid".into());
        r.placement_status = Some("feasible".into());
        r.sequence_status = Some("complete".into());
        let r = r.upgraded();
        assert_eq!(r.status, RunStatus::Planner(Status::Feasible));
        assert!(r.solved() && !r.proven());
        let mut k = sample("a", "milp+astar");
        k.status = RunStatus::LegacyTimeout;
        k.error = Some("killed after the hard limit of 9 s".into());
        assert_eq!(k.upgraded().status, RunStatus::Killed);
    }

    #[test]
    fn columns_match_the_struct_fields() {
        let v = serde_json::to_value(sample("a", "bl+paper")).unwrap();
        let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        let mut cols = COLUMNS.to_vec();
        keys.sort();
        cols.sort();
        assert_eq!(keys, cols);
        assert!(TIMING_COLUMNS.iter().all(|c| COLUMNS.contains(c)));
    }

    #[test]
    fn csv_quotes_and_jsonl_survives_a_torn_last_line() {
        let r = sample("a,b", "bl+paper");
        assert_eq!(r.status, RunStatus::Error);
        let rec = r.to_csv_record();
        assert!(rec.starts_with("\"a,b\","));
        assert!(rec.contains("\"boom, \"\"quoted\"\"\""));
        assert!(rec.split(',').count() >= COLUMNS.len());

        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.jsonl");
        let full = r.to_json_line() + "\n";
        std::fs::write(&p, format!("{full}{}", &full[..20])).unwrap();
        let (rows, good) = read_jsonl(&p).unwrap();
        assert_eq!(rows.len(), 1);
        assert_eq!(good as usize, full.len());
        // A complete but unterminated line is also not counted: its newline never made it.
        std::fs::write(&p, format!("{full}{}", r.to_json_line())).unwrap();
        assert_eq!(read_jsonl(&p).unwrap().0.len(), 1);
        // A broken line in the middle is bad input, not silently skipped.
        std::fs::write(&p, format!("{{oops\n{full}")).unwrap();
        assert!(read_jsonl(&p).unwrap_err().to_string().contains("line 1"));
    }
}

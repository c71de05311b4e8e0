//! One benchmark result row per (instance, planner): its fields, CSV/JSON Lines I/O, and reading
//! result files back (tolerating a last line cut short by a kill).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::{Path, PathBuf};

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// The planner returned a plan (it may still fail verification; see `verify`).
    Ok,
    /// The planner returned an error, panicked or its process died.
    Failed,
    /// The run's process exceeded the hard wall-clock limit and was killed, or the library's
    /// time limit stopped a stage before it had any plan.
    Timeout,
    /// A stage's node limit, or the paper sequencer's candidate cap (not the clock), stopped
    /// it before it had any plan: a larger limit may find one, a longer time limit would not.
    NodeLimit,
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
    /// Library time limit per stage (s).
    pub time_limit_s: f64,
    /// How the run ended.
    pub status: RunStatus,
    /// Error message of a failed or timed-out run.
    pub error: Option<String>,
    /// Placement status (`optimal` or `feasible`).
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
    /// Sequencer status (`complete`, `node_limit`, `time_limit`).
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
    "tool_version",
    "git_commit",
];

/// Fields that measure time and so differ between otherwise identical runs.
pub const TIMING_COLUMNS: &[&str] = &[
    "placement_time_s",
    "sequence_time_s",
    "plan_time_s",
    "verify_time_s",
    "wall_time_s",
];

/// Version and commit of this binary.
pub fn tool_version() -> (String, String) {
    (
        env!("CARGO_PKG_VERSION").to_string(),
        env!("PUSHPACK_GIT_COMMIT").to_string(),
    )
}

impl ResultRow {
    /// The row as the current version writes it: rows from before the `node_limit` status
    /// (commit 3ff21f3) recorded a node-limit stop as `timeout`, naming the limit in `error`.
    fn upgraded(mut self) -> Self {
        if self.status == RunStatus::Timeout
            && self
                .error
                .as_deref()
                .is_some_and(|e| e.contains(&format!("stopped by its {}", crate::error::NODE_LIMIT)))
        {
            self.status = RunStatus::NodeLimit;
        }
        self
    }

    /// The key results are merged and resumed by: (instance path, planner).
    pub fn key(&self) -> (String, String) {
        (self.instance.clone(), self.planner.clone())
    }

    /// True when the run produced a plan that the verifier accepts.
    pub fn solved(&self) -> bool {
        self.status == RunStatus::Ok && self.verify.as_deref() == Some("valid")
    }

    /// True when both stages proved their result optimal: placement `optimal`, and an A* search
    /// that ran to `complete`. The paper's sequencer also ends `complete` when it has searched
    /// its candidate space, but that space is a heuristic's, so its plans are never proven.
    pub fn proven(&self) -> bool {
        let proving_sequencer = super::spec::PlannerSpec::parse(&self.planner, "planner")
            .is_ok_and(|s| s.sequencer == crate::plan::Sequencer::Astar);
        self.solved()
            && proving_sequencer
            && self.placement_status.as_deref() == Some("optimal")
            && self.sequence_status.as_deref() == Some("complete")
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
        r.status = RunStatus::Ok;
        r.verify = Some("valid".into());
        r.placement_status = Some("optimal".into());
        r.sequence_status = Some("complete".into());
        r
    }

    #[test]
    fn only_a_complete_astar_search_on_an_optimal_placement_is_proven() {
        assert!(solved_and_complete("milp+astar").proven());
        assert!(solved_and_complete("milp+astar+no-direct").proven());
        // The paper's sequencer searched its whole candidate space: still a heuristic.
        assert!(!solved_and_complete("milp+paper").proven());
        assert!(!solved_and_complete("bl+paper").proven());
        let mut r = solved_and_complete("milp+astar");
        r.placement_status = Some("feasible".into());
        assert!(!r.proven());
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
        assert_eq!(r.status, RunStatus::Failed);
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

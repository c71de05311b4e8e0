//! Live progress of `pushpack plan` on stderr, and Ctrl+C as a clean stop.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushpack::control::{CancelFlag, Event, Listener, Stage};
use std::time::Duration;

/// A spinner naming the running stage and its budget, with the search's nodes, best plan and
/// bound while it runs; a line per finished stage. Draws only when stderr is a terminal, so
/// pipes and logs stay clean.
pub struct Progress {
    bar: ProgressBar,
    /// The running stage's own words, kept so that search figures are added to them.
    stage: String,
}

impl Progress {
    pub fn new() -> Progress {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}").expect("a valid progress template"),
        );
        bar.enable_steady_tick(Duration::from_millis(120));
        Progress {
            bar,
            stage: String::new(),
        }
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// An objective or bound as the summary prints it: placement areas (m²) in cm².
fn figure(stage: Stage, v: f64) -> String {
    match stage {
        Stage::Placement => format!("{:.1} cm²", v * 1e4),
        _ => format!("{v}"),
    }
}

impl Listener for Progress {
    fn event(&mut self, event: &Event) {
        match event {
            Event::StageStarted { stage, budget_s } => {
                self.stage = if *budget_s > 0.0 {
                    format!(
                        "{} (up to {budget_s:.1} s; Ctrl+C stops with the best plan so far)",
                        stage.name()
                    )
                } else {
                    stage.name().to_string()
                };
                self.bar.set_message(self.stage.clone());
            }
            Event::Progress {
                stage,
                nodes,
                incumbent,
                bound,
            } => {
                // Placement objectives are areas in m²: shown in cm², as the summary does.
                let show = |v: f64| figure(*stage, v);
                if *stage == Stage::Motion {
                    self.bar.set_message(format!("{}: {nodes} actions planned", self.stage));
                    return;
                }
                let plan = incumbent.map_or("no solution yet".to_string(), |o| format!("best {}", show(o)));
                let bound = bound.map_or(String::new(), |b| format!(", bound {}", show(b)));
                self.bar
                    .set_message(format!("{}: {nodes} nodes, {plan}{bound}", self.stage));
            }
            Event::StageFinished {
                stage,
                status,
                time_s,
                nodes,
                objective,
                bound,
            } => {
                let show = |v: f64| figure(*stage, v);
                let figures = match (objective, bound) {
                    (Some(o), Some(b)) => format!(", objective {}, bound {}", show(*o), show(*b)),
                    (Some(o), None) => format!(", objective {}", show(*o)),
                    _ => String::new(),
                };
                self.bar.println(format!(
                    "{:<10} {status} in {time_s:.2} s ({nodes} nodes{figures})",
                    stage.name()
                ));
            }
        }
    }
}

/// A flag the first Ctrl+C sets; the run then stops and writes its best plan. A second Ctrl+C
/// ends the process at once (exit 130), for a stage that cannot stop quickly.
pub fn cancel_on_ctrl_c() -> CancelFlag {
    let flag = CancelFlag::new();
    let f = flag.clone();
    // Without a handler (another one is installed, or the platform has none) Ctrl+C keeps its
    // default meaning: end the process.
    let _ = ctrlc::set_handler(move || {
        if f.is_cancelled() {
            std::process::exit(130);
        }
        eprintln!("\nstopping: finishing the current step and writing the best plan so far (Ctrl+C again to quit now)");
        f.cancel();
    });
    flag
}

//! Loading a plan and its instance for `verify`, `simulate`, `render` and `export`, with errors
//! that name the fix: a swapped pair of files says which is which, and an instance path
//! recorded in the plan that does not resolve from here points to `--instance FILE`.

use super::*;

/// What a file holds, judged by its top-level keys (not by validating it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Looks {
    Instance,
    Plan,
    Other,
}

impl Looks {
    fn of(path: &Path) -> Looks {
        let Ok(text) = std::fs::read_to_string(path) else {
            return Looks::Other;
        };
        if let Ok(serde_json::Value::Object(m)) = serde_json::from_str::<serde_json::Value>(&text) {
            let any = |keys: &[&str]| keys.iter().any(|k| m.contains_key(*k));
            if any(&["placement", "actions", "trajectories"]) {
                return Looks::Plan;
            }
            if m.contains_key("container") && any(&["objects", "kinds"]) {
                return Looks::Instance;
            }
            return Looks::Other;
        }
        match toml::from_str::<toml::Table>(&text) {
            Ok(t) if t.contains_key("container") => Looks::Instance,
            _ => Looks::Other,
        }
    }
}

/// The plan, or an error that says so when `plan` is an instance (and, for `verify`, when the
/// two files were given the wrong way round).
fn load_plan(plan: &Path, instance: Option<&Path>) -> Result<Plan, Error> {
    Plan::load(plan).map_err(|e| {
        if !matches!(e, Error::Input { .. }) || Looks::of(plan) != Looks::Instance {
            return e;
        }
        let reason = match instance {
            Some(i) if Looks::of(i) == Looks::Plan => format!(
                "this looks like an instance file, and {} like a plan: the two are swapped (`pushpack verify INSTANCE PLAN` takes the instance first)",
                i.display()
            ),
            _ => "this looks like an instance file, not a plan: give the plan.json that `pushpack plan` wrote, and the instance with --instance FILE".to_string(),
        };
        Error::input(plan.display().to_string(), "<file>", reason)
    })
}

/// The plan and its instance: `instance` when given, else the path the plan recorded. Warns
/// when the instance changed since the plan was made.
pub(super) fn load_plan_instance(plan: &Path, instance: Option<&Path>) -> Result<(Plan, Instance), Error> {
    let p = load_plan(plan, instance)?;
    let inst = match instance {
        Some(i) => Instance::load(i).map_err(|e| {
            if matches!(e, Error::Input { .. }) && Looks::of(i) == Looks::Plan {
                Error::input(
                    i.display().to_string(),
                    "<file>",
                    "this looks like a plan, not an instance: give the instance file (TOML or JSON) that the plan was made for",
                )
            } else {
                e
            }
        })?,
        None => {
            let src = Path::new(&p.instance.source);
            if !src.is_file() {
                let here = std::env::current_dir()
                    .map(|d| format!(" (from {})", d.display()))
                    .unwrap_or_default();
                return Err(Error::input(
                    plan.display().to_string(),
                    "instance.source",
                    format!(
                        "the instance file {:?} recorded in the plan is not found{here}; name it with --instance FILE",
                        p.instance.source
                    ),
                ));
            }
            Instance::load(src)?
        }
    };
    if inst.digest != p.instance.digest {
        eprintln!("warning: the instance file changed since the plan was made (digest differs)");
    }
    Ok((p, inst))
}

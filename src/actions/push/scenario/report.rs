//! The verdict on a scenario: per-phase reports, what failed and why, and how it is printed.

use super::*;

/// Verdict of a check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Margin above the tolerance.
    Stable,
    /// Otherwise.
    Unstable,
}

/// How a push fails.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FailureKind {
    /// A contact slides: no force inside its friction cone balances the boxes.
    Slip,
    /// A box turns: a line of action leaves its contact segment.
    Rotate,
    /// A box tips: its floor centre of pressure leaves the footprint.
    Tip,
    /// The solver failed; treated as unstable.
    NoSolution,
}

/// Why a push is not stable.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failure {
    /// Phase number (1-based, in the order they occur).
    pub phase: usize,
    /// Failure mode.
    pub kind: FailureKind,
    /// Contact (`back → front`) or box concerned.
    pub at: String,
    /// Human-readable explanation.
    pub detail: String,
}

/// A contact force in a report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactReport {
    /// `back → front`.
    pub name: String,
    /// Pusher or object contact.
    pub kind: ContactKind,
    /// The force.
    #[serde(flatten)]
    pub force: ContactForce,
}

/// A floor reaction in a report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloorReport {
    /// Box.
    pub name: String,
    /// The reaction.
    #[serde(flatten)]
    pub floor: FloorForce,
}

/// One phase in a report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseReport {
    /// Boxes moving in this phase, front to back.
    pub moving: Vec<String>,
    /// Program outcome.
    pub status: PhaseStatus,
    /// Phase margin (m).
    pub margin: Option<f64>,
    /// What limits it.
    pub limited_by: Option<String>,
    /// Contact forces (the certificate of equilibrium).
    pub contacts: Vec<ContactReport>,
    /// Floor reactions (3-D).
    pub floor: Vec<FloorReport>,
    /// A phase of finite travel whose box would turn: rotation and drift over its travel.
    pub travel: Option<TravelCheck>,
    /// 3-D: margin of the planar part (no vertical friction; the 2-D margin).
    pub planar_margin: Option<f64>,
    /// 3-D: smallest tipping margin over the moving boxes.
    pub tip_margin: Option<f64>,
}

/// Robust-mode summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobustReport {
    /// Cases solved (vertices of the uncertainty set plus the nominal point).
    pub cases: usize,
    /// Margin at the nominal parameters.
    pub nominal_margin: Option<f64>,
    /// Parameters of the worst case.
    pub worst: RobustCase,
}

/// The answer of `push-check`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PushReport {
    /// Scenario name.
    pub scenario: String,
    /// Requested mode.
    pub mode: Mode,
    /// Verdict.
    pub verdict: Verdict,
    /// Stability margin (m); `null` when no contact forces exist at any segment shrink.
    pub margin: Option<f64>,
    /// Stable iff margin > tolerance (m).
    pub tolerance: f64,
    /// Friction-cone shrink fraction used.
    pub cone_shrink: f64,
    /// Gap closed before each box (m), front to back, the pusher's last.
    pub gaps: Vec<f64>,
    /// Why it fails (when unstable).
    pub failure: Option<Failure>,
    /// The phase (1-based) that limits the push: the first that fails, else the one with the
    /// smallest margin.
    pub limiting_phase: Option<usize>,
    /// Phases in the order they occur.
    pub phases: Vec<PhaseReport>,
    /// Robust summary (robust modes).
    pub robust: Option<RobustReport>,
}

impl PushReport {
    /// Whether the push is stable.
    pub fn stable(&self) -> bool {
        self.verdict == Verdict::Stable
    }
}

/// Decide a scenario.
pub fn check_scenario(s: &Scenario) -> PushReport {
    let dim = s.mode.dim();
    let (result, robust) = if s.mode.robust() {
        let set = s
            .uncertainty
            .clone()
            .unwrap_or_else(|| UncertaintySet::nominal(&s.model));
        let r = robust::check(&s.model, &set, dim, &s.options);
        let model = robust::apply(&s.model, &r.worst);
        (
            (r.result, model),
            Some(RobustReport {
                cases: r.cases,
                nominal_margin: r.nominal_margin,
                worst: r.worst,
            }),
        )
    } else {
        ((convex::check(&s.model, dim, &s.options), s.model.clone()), None)
    };
    let (result, model) = result;
    report(s, &model, &result, robust)
}

pub(super) fn edge_name(model: &PushModel, body: usize, axis: usize, side: i8) -> &'static str {
    let a = model.bodies[body].axes[axis];
    let out = [a[0] * side as f64, a[1] * side as f64];
    let along = dot(out, model.u);
    if along > std::f64::consts::FRAC_1_SQRT_2 {
        "front"
    } else if along < -std::f64::consts::FRAC_1_SQRT_2 {
        "back"
    } else if dot(out, model.left()) > 0.0 {
        "left"
    } else {
        "right"
    }
}

/// Failure kind, place and explanation of a binding constraint; `failed` words it as a failure,
/// otherwise as what limits a positive margin.
pub(super) fn describe(
    model: &PushModel,
    b: &Binding,
    margin: Option<f64>,
    failed: bool,
) -> (FailureKind, String, String) {
    let mm = |m: Option<f64>| m.map_or("—".to_string(), |m| format!("{:.3} mm", m * 1e3));
    match b {
        Binding::Segment { contact, end } => {
            let c = &model.contacts[*contact];
            let front = &model.bodies[c.front].name;
            let name = model.contact_name(*contact);
            let end_s = if *end == 0 { "first" } else { "second" };
            let p = if *end == 0 { c.p0 } else { c.p1() };
            let at = format!("({:.4}, {:.4})", p[0], p[1]);
            let detail = if failed {
                format!(
                    "{front} rotates: the line of action through contact {name} reaches the {end_s} end {at} of the contact segment (margin {})",
                    mm(margin)
                )
            } else {
                format!(
                    "contact {name}: line of action {} from the {end_s} end {at} of the contact segment (beyond it {front} would rotate)",
                    mm(margin)
                )
            };
            (FailureKind::Rotate, name.clone(), detail)
        }
        Binding::Footprint { body, axis, side } => {
            let name = model.bodies[*body].name.clone();
            let edge = edge_name(model, *body, *axis, *side);
            let detail = if failed {
                format!(
                    "{name} tips over its {edge} edge: the floor's centre of pressure reaches the footprint edge (margin {})",
                    mm(margin)
                )
            } else {
                format!(
                    "{name}: floor centre of pressure {} from its {edge} edge (beyond it the box would tip)",
                    mm(margin)
                )
            };
            (FailureKind::Tip, name.clone(), detail)
        }
        Binding::Slip { contact, excess } => {
            let name = model.contact_name(*contact);
            let e = excess.iter().find(|(c, _)| c == contact).map_or(0.0, |x| x.1);
            (
                FailureKind::Slip,
                name.clone(),
                format!(
                    "contact {name} slips: balancing the boxes needs a tangential force {:.1}% of its reference load beyond the (shrunk) friction cone",
                    e * 100.0
                ),
            )
        }
    }
}

pub(super) fn report(
    s: &Scenario,
    model: &PushModel,
    result: &CheckResult,
    robust: Option<RobustReport>,
) -> PushReport {
    let phases: Vec<PhaseReport> = result
        .phases
        .iter()
        .map(|p| PhaseReport {
            moving: model.bodies[p.start..].iter().map(|b| b.name.clone()).collect(),
            status: p.status,
            margin: p.margin,
            limited_by: p
                .binding
                .as_ref()
                .map(|b| describe(model, b, p.margin, !p.passes(s.options.tol)).2),
            contacts: p
                .contacts
                .iter()
                .map(|c| ContactReport {
                    name: model.contact_name(c.contact),
                    kind: model.contacts[c.contact].kind,
                    force: c.clone(),
                })
                .collect(),
            floor: p
                .floor
                .iter()
                .map(|f| FloorReport {
                    name: model.bodies[f.body].name.clone(),
                    floor: f.clone(),
                })
                .collect(),
            travel: p.travel.clone(),
            planar_margin: p.planar_margin,
            tip_margin: p.tip_margin,
        })
        .collect();
    let failure = if result.stable {
        None
    } else {
        result
            .phases
            .iter()
            .enumerate()
            .find(|(_, p)| !p.passes(s.options.tol))
            .map(|(k, p)| match &p.binding {
                Some(b) if p.travel.is_some() => {
                    let t = p.travel.as_ref().expect("travel");
                    let (kind, at, _) = describe(model, b, p.margin, true);
                    Failure {
                        phase: k + 1,
                        kind,
                        at,
                        detail: format!(
                            "{} turns {:.2}° and drifts {:.3} mm while it closes its {:.3} mm gap (limits {:.2}°, {:.3} mm)",
                            model.bodies[t.body].name,
                            t.rotation.to_degrees(),
                            t.drift * 1e3,
                            t.travel * 1e3,
                            s.options.max_rotation.to_degrees(),
                            s.options.max_drift * 1e3
                        ),
                    }
                }
                Some(b) => {
                    let (kind, at, detail) = describe(model, b, p.margin, true);
                    Failure {
                        phase: k + 1,
                        kind,
                        at,
                        detail,
                    }
                }
                None => Failure {
                    phase: k + 1,
                    kind: FailureKind::NoSolution,
                    at: String::new(),
                    detail: "the solver found no solution; treated as unstable".into(),
                },
            })
    };
    PushReport {
        scenario: s.name.clone(),
        mode: s.mode,
        verdict: if result.stable {
            Verdict::Stable
        } else {
            Verdict::Unstable
        },
        margin: result.margin,
        tolerance: s.options.tol,
        cone_shrink: s.options.cone_shrink,
        gaps: s.gaps.clone(),
        failure,
        limiting_phase: result.limiting_phase.map(|k| k + 1),
        phases,
        robust,
    }
}

/// Friction use as a percentage; a frictionless contact (`μ = 0`) has none to use.
pub(super) fn fmt_use(u: Option<f64>) -> String {
    u.map_or("n/a (μ = 0)".to_string(), |u| format!("{:.0}%", u * 100.0))
}

pub(super) fn fmt_m(m: Option<f64>) -> String {
    m.map_or("none (no forces inside the friction cones)".to_string(), |m| {
        format!("{:.6} m", m)
    })
}

impl fmt::Display for PushReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "push-check {} (mode {}): {}, margin {}",
            self.scenario,
            self.mode.name(),
            match self.verdict {
                Verdict::Stable => "STABLE",
                Verdict::Unstable => "UNSTABLE",
            },
            fmt_m(self.margin)
        )?;
        writeln!(
            f,
            "  stable iff margin > {:.1e} m; friction cones shrunk by {:.0}%",
            self.tolerance,
            self.cone_shrink * 100.0
        )?;
        if let Some(fl) = &self.failure {
            writeln!(f, "  failure (phase {}): {}", fl.phase, fl.detail)?;
        } else if let Some(k) = self.limiting_phase {
            writeln!(f, "  limited by phase {k}")?;
        }
        if let Some(r) = &self.robust {
            writeln!(
                f,
                "  robust: {} cases, nominal margin {}; worst case: mu_floor {:?}, contact mu {:?}, centres of friction {}",
                r.cases,
                fmt_m(r.nominal_margin),
                r.worst.mu_floor,
                r.worst.mu_contact,
                r.worst
                    .cof
                    .iter()
                    .map(|c| format!("({:.4}, {:.4})", c[0], c[1]))
                    .collect::<Vec<_>>()
                    .join(", ")
            )?;
        }
        for (k, p) in self.phases.iter().enumerate() {
            writeln!(
                f,
                "  phase {} — moving [{}]: margin {}",
                k + 1,
                p.moving.join(", "),
                fmt_m(p.margin)
            )?;
            if let Some(l) = &p.limited_by {
                writeln!(f, "    limited by: {l}")?;
            }
            if p.planar_margin.is_some() {
                writeln!(
                    f,
                    "    planar margin {}, tipping margin {}",
                    fmt_m(p.planar_margin),
                    p.tip_margin
                        .map_or("none (solver failed)".to_string(), |m| format!("{m:.6} m"))
                )?;
            }
            if let Some(t) = &p.travel {
                writeln!(
                    f,
                    "    judged by its travel: closes {:.3} mm (finger {:.3} mm); turns {:.3}°, drifts {:.4} mm ({} at the finger); {:.0}% of the limits: {}",
                    t.travel * 1e3,
                    t.pusher_travel * 1e3,
                    t.rotation.to_degrees(),
                    t.drift * 1e3,
                    if t.sticking { "sticking" } else { "sliding" },
                    t.usage * 100.0,
                    if t.passes { "passes" } else { "fails" }
                )?;
            }
            for c in &p.contacts {
                writeln!(
                    f,
                    "    {}: force ({:.4}, {:.4}, {:.4}) N, normal {:.4} N, tangential {:.4} N, at ({:.4}, {:.4}, {:.4}) m, segment margin {:.4} m, friction use {}",
                    c.name,
                    c.force.force[0],
                    c.force.force[1],
                    c.force.force[2],
                    c.force.normal,
                    c.force.tangential[0].hypot(c.force.tangential[1]),
                    c.force.point[0],
                    c.force.point[1],
                    c.force.point[2],
                    c.force.segment_margin,
                    fmt_use(c.force.friction_use)
                )?;
            }
            for fl in &p.floor {
                writeln!(
                    f,
                    "    floor under {}: normal {:.4} N, friction {:.4} N, centre of pressure ({:.4}, {:.4}) m, footprint margin {:.4} m",
                    fl.name, fl.floor.normal, fl.floor.friction, fl.floor.cop[0], fl.floor.cop[1], fl.floor.footprint_margin
                )?;
            }
        }
        Ok(())
    }
}

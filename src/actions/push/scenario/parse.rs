//! Reading a push scenario file: field checks with the file, field and reason, and the model built from it.

use super::*;

/// Geometric tolerance of scenario geometry (m).
pub(super) const TOL: f64 = 1e-7;

pub(super) fn err(file: &str, field: impl Into<String>, reason: impl Into<String>) -> Error {
    Error::input(file, field, reason)
}

/// Parse and validate a scenario from JSON text; `source` names it in errors.
pub fn parse_scenario(text: &str, source: &str) -> Result<Scenario> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let f: ScenarioFile = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let reason = inner.to_string();
        let field = if let Some(rest) = reason.strip_prefix("missing field `") {
            let name = rest.split('`').next().unwrap_or("");
            if path == "." || path.is_empty() {
                name.to_string()
            } else {
                format!("{path}.{name}")
            }
        } else if inner.is_syntax() || inner.is_eof() {
            "<syntax>".to_string()
        } else if path == "." || path.is_empty() {
            "<root>".to_string()
        } else {
            path
        };
        err(source, field, reason)
    })?;
    build(f, source)
}

pub(super) fn finite(file: &str, field: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be a finite number, got {v}")))
    }
}

pub(super) fn positive(file: &str, field: &str, v: f64) -> Result<f64> {
    if finite(file, field, v)? > 0.0 {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be > 0, got {v}")))
    }
}

/// A length (m) that must be at least the instance files' smallest box edge, so that the
/// geometric tolerances stay negligible against it.
pub(super) fn edge(file: &str, field: &str, v: f64) -> Result<f64> {
    use crate::instance::MIN_EDGE;
    if v < MIN_EDGE {
        return Err(err(
            file,
            field,
            format!("must be at least {MIN_EDGE} m (100 x the geometric tolerance, as in instance files), got {v:e} m"),
        ));
    }
    Ok(v)
}

pub(super) fn non_negative(file: &str, field: &str, v: f64) -> Result<f64> {
    if finite(file, field, v)? >= 0.0 {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be >= 0, got {v}")))
    }
}

pub(super) fn unit(file: &str, field: &str, v: V2) -> Result<V2> {
    finite(file, &format!("{field}[0]"), v[0])?;
    finite(file, &format!("{field}[1]"), v[1])?;
    let n = v[0].hypot(v[1]);
    if n > 1e-12 {
        Ok([v[0] / n, v[1] / n])
    } else {
        Err(err(file, field, "must be a non-zero vector"))
    }
}

/// A checked scenario from its file: each step checks its own fields, in the order a reader
/// meets them, so the first bad field is the one an error names.
pub(super) fn build(f: ScenarioFile, file: &str) -> Result<Scenario> {
    let scale = units_scale(file, f.units.as_deref())?;
    let u = push_direction(file, &f.push_dir)?;
    let gravity = match f.gravity {
        Some(g) => positive(file, "gravity", g)?,
        None => crate::instance::GRAVITY,
    };
    let mu_floor = positive(file, "friction.mu_floor", f.friction.mu_floor)?;
    let mu_obj = non_negative(file, "friction.mu_obj", f.friction.mu_obj)?;
    let mu_finger = non_negative(file, "friction.mu_finger", f.friction.mu_finger)?;
    let cone_shrink = match f.cone_shrink {
        Some(c) => {
            let c = non_negative(file, "cone_shrink", c)?;
            if c >= 1.0 {
                return Err(err(file, "cone_shrink", format!("must be < 1, got {c}")));
            }
            c
        }
        None => crate::actions::push::CONE_SHRINK,
    };
    let max_rotation = match f.max_rotation {
        Some(r) => positive(file, "max_rotation", r)?,
        None => crate::actions::push::MAX_ROTATION,
    };
    let max_drift = match f.max_drift {
        Some(d) => positive(file, "max_drift", d)? * scale,
        None => crate::actions::push::MAX_DRIFT,
    };
    // The margin a push needs (a planner's `min_push_margin`): a phase short of it is judged by
    // its travel where the rule applies, so a file can reproduce a planner's verdict.
    let min_margin = match f.min_margin {
        Some(m) => non_negative(file, "min_margin", m)? * scale,
        None => crate::actions::push::MARGIN_TOL,
    };
    if f.boxes.is_empty() {
        return Err(err(file, "boxes", "needs at least one box"));
    }
    let (mut bodies, box_mu) = bodies(&f, file, scale, [mu_floor, mu_obj, mu_finger])?;
    let (mut pusher, height) = pusher_face(&f, file, scale, u, &bodies)?;
    check_overlaps(file, &bodies, &pusher)?;
    let gaps = close_gaps(&f, file, scale, u, &mut bodies, &mut pusher)?;
    let contacts = closed_contacts(file, &bodies, &pusher, height, &box_mu)?;
    let k = bodies.len();
    let gap_flags: Vec<bool> = gaps[..k - 1].iter().map(|&g| g > TOL).collect();
    let mut model = PushModel::new(u, bodies, contacts, &gap_flags);
    model.gravity = gravity;
    // Phase `s > 0` (boxes `s..k`) lasts until it closes the gap in front of box `s`.
    model.phase_travel = model
        .phase_starts
        .iter()
        .map(|&s| if s == 0 { f64::INFINITY } else { gaps[s - 1] })
        .collect();
    let uncertainty = uncertainty(&f, file, scale, &model, &box_mu)?;
    Ok(Scenario {
        source: file.to_string(),
        name: f.name.unwrap_or_else(|| file.to_string()),
        mode: f.mode,
        model,
        gaps,
        uncertainty,
        options: CheckOptions {
            cone_shrink,
            max_rotation,
            max_drift,
            tol: min_margin,
        },
    })
}

/// A box's object–object and finger friction coefficients.
type BoxFriction = (f64, f64);

/// Metres per unit of the file's lengths.
fn units_scale(file: &str, units: Option<&str>) -> Result<f64> {
    Ok(match units {
        None | Some("m") => 1.0,
        Some("cm") => 0.01,
        Some("mm") => 0.001,
        Some(other) => {
            return Err(err(
                file,
                "units",
                format!("must be \"m\", \"cm\" or \"mm\", got \"{other}\""),
            ))
        }
    })
}

/// The push direction, named or as a vector (made unit).
fn push_direction(file: &str, spec: &DirSpec) -> Result<V2> {
    Ok(match spec {
        DirSpec::Named(s) => match s.as_str() {
            "-x" => [-1.0, 0.0],
            "+x" | "x" => [1.0, 0.0],
            "-y" => [0.0, -1.0],
            "+y" | "y" => [0.0, 1.0],
            other => {
                return Err(err(
                    file,
                    "push_dir",
                    format!("must be \"-x\", \"+x\", \"-y\", \"+y\" or [ux, uy], got \"{other}\""),
                ))
            }
        },
        DirSpec::Vector(v) => unit(file, "push_dir", *v)?,
    })
}

/// The boxes, front to back, in metres, with their floor friction; and per box its
/// object–object and finger friction, each defaulting to the file's `friction`.
fn bodies(f: &ScenarioFile, file: &str, scale: f64, mu: [f64; 3]) -> Result<(Vec<Body>, Vec<BoxFriction>)> {
    let [mu_floor, mu_obj, mu_finger] = mu;
    let mut bodies = Vec::with_capacity(f.boxes.len());
    let mut box_mu = Vec::with_capacity(f.boxes.len());
    for (i, b) in f.boxes.iter().enumerate() {
        let fld = |s: &str| format!("boxes[{i}].{s}");
        if b.id.trim().is_empty() {
            return Err(err(file, fld("id"), "must not be empty"));
        }
        if f.boxes[..i].iter().any(|o| o.id == b.id) {
            return Err(err(file, fld("id"), format!("duplicate id \"{}\"", b.id)));
        }
        let mut size = [0.0; 3];
        for (k, v) in size.iter_mut().enumerate() {
            let field = format!("{}[{k}]", fld("size"));
            *v = edge(file, &field, positive(file, &field, b.size[k])? * scale)?;
        }
        let mass = positive(file, &fld("mass"), b.mass)?;
        for k in 0..3 {
            finite(file, &format!("{}[{k}]", fld("pose")), b.pose[k])?;
        }
        let mf = match b.mu_floor {
            Some(v) => positive(file, &fld("mu_floor"), v)?,
            None => mu_floor,
        };
        let mo = match b.mu_obj {
            Some(v) => non_negative(file, &fld("mu_obj"), v)?,
            None => mu_obj,
        };
        let mg = match b.mu_finger {
            Some(v) => non_negative(file, &fld("mu_finger"), v)?,
            None => mu_finger,
        };
        box_mu.push((mo, mg));
        bodies.push(Body::with_yaw(
            &b.id,
            [b.pose[0] * scale, b.pose[1] * scale],
            b.pose[2],
            [size[0] / 2.0, size[1] / 2.0],
            size[2],
            mass,
            mf,
        ));
    }
    Ok((bodies, box_mu))
}

/// The pusher's face (two end points, m, as placed in the file) and its fingertip height,
/// below the top of the back box and facing along the push direction.
fn pusher_face(f: &ScenarioFile, file: &str, scale: f64, u: V2, bodies: &[Body]) -> Result<(Vec<V2>, f64)> {
    let p = &f.pusher;
    for k in 0..2 {
        finite(file, &format!("pusher.point[{k}]"), p.point[k])?;
    }
    let width = edge(file, "pusher.width", positive(file, "pusher.width", p.width)? * scale)?;
    let height = non_negative(file, "pusher.height", p.height)? * scale;
    let pn = match p.normal {
        Some(v) => unit(file, "pusher.normal", v)?,
        None => u,
    };
    let back_h = bodies.last().expect("non-empty").height;
    if height >= back_h {
        return Err(err(
            file,
            "pusher.height",
            format!(
                "the fingertip ({height} m) must be below the top of the back box \"{}\" ({back_h} m)",
                bodies.last().expect("non-empty").name
            ),
        ));
    }
    if dot(pn, u) <= 1e-9 {
        return Err(err(
            file,
            "pusher.normal",
            "must point along the push direction (positive dot product with push_dir)",
        ));
    }
    let pc = [p.point[0] * scale, p.point[1] * scale];
    let pd = [-pn[1], pn[0]];
    let pusher = vec![
        [pc[0] - width / 2.0 * pd[0], pc[1] - width / 2.0 * pd[1]],
        [pc[0] + width / 2.0 * pd[0], pc[1] + width / 2.0 * pd[1]],
    ];
    Ok((pusher, height))
}

/// No two boxes overlap, and the pusher's face cuts into none.
fn check_overlaps(file: &str, bodies: &[Body], pusher: &[V2]) -> Result<()> {
    let k = bodies.len();
    let polys: Vec<Vec<V2>> = bodies.iter().map(|b| b.corners().to_vec()).collect();
    for i in 0..k {
        for j in i + 1..k {
            let depth = penetration(&polys[i], &polys[j]);
            if depth > TOL {
                return Err(err(
                    file,
                    format!("boxes[{j}].pose"),
                    format!(
                        "box \"{}\" overlaps box \"{}\" by {depth:.3e} m",
                        bodies[j].name, bodies[i].name
                    ),
                ));
            }
        }
        if segment_enters(&polys[i], pusher[0], pusher[1]) {
            return Err(err(
                file,
                "pusher.point",
                format!("the pusher face cuts into box \"{}\"", bodies[i].name),
            ));
        }
    }
    Ok(())
}

/// Close the gaps from the front: everything behind body `m` moves along `u` by the gaps closed
/// so far. Returns the gap in front of each box and the pusher's (the last is the pusher's).
fn close_gaps(
    f: &ScenarioFile,
    file: &str,
    scale: f64,
    u: V2,
    bodies: &mut [Body],
    pusher: &mut Vec<V2>,
) -> Result<Vec<f64>> {
    let k = bodies.len();
    let originals: Vec<Vec<V2>> = bodies.iter().map(|b| b.corners().to_vec()).collect();
    let pusher_orig = pusher.clone();
    let mut gaps = Vec::with_capacity(k);
    let mut total = 0.0;
    for m in 0..k {
        let front: Vec<V2> = bodies[m].corners().to_vec();
        let back = if m + 1 < k {
            translate(&originals[m + 1], u, total)
        } else {
            translate(&pusher_orig, u, total)
        };
        let Some(gap) = gap_along(&front, &back, u) else {
            let (field, what) = if m + 1 < k {
                (
                    format!("boxes[{}].pose", m + 1),
                    format!("box \"{}\"", bodies[m + 1].name),
                )
            } else {
                ("pusher.point".to_string(), "the pusher".to_string())
            };
            return Err(err(
                file,
                field,
                format!(
                    "{what} does not meet box \"{}\" when pushed along the push direction (list boxes front to back)",
                    bodies[m].name
                ),
            ));
        };
        let gap = gap.max(0.0);
        gaps.push(gap);
        total += gap;
        if m + 1 < k {
            let orig = f.boxes[m + 1].pose;
            let b = &mut bodies[m + 1];
            b.centre = [orig[0] * scale + total * u[0], orig[1] * scale + total * u[1]];
            b.cof = b.centre;
        } else {
            *pusher = translate(&pusher_orig, u, total);
        }
    }
    Ok(gaps)
}

/// The contacts of the closed line: each box with the one behind it, the back box with the
/// pusher (from its fingertip `height` up).
fn closed_contacts(
    file: &str,
    bodies: &[Body],
    pusher: &[V2],
    height: f64,
    box_mu: &[BoxFriction],
) -> Result<Vec<Contact>> {
    let k = bodies.len();
    let mut contacts = Vec::with_capacity(k);
    for m in 0..k {
        let front = bodies[m].corners().to_vec();
        let (back, kind, z, mu, what) = if m + 1 < k {
            (
                bodies[m + 1].corners().to_vec(),
                ContactKind::Object,
                [0.0, bodies[m].height.min(bodies[m + 1].height)],
                box_mu[m].0.min(box_mu[m + 1].0),
                format!("boxes[{}].pose", m + 1),
            )
        } else {
            (
                pusher.to_vec(),
                ContactKind::Pusher,
                [height, bodies[m].height],
                box_mu[m].1,
                "pusher.point".to_string(),
            )
        };
        let Some((p0, dir, len, normal)) = touching(&front, &back) else {
            return Err(err(
                file,
                what,
                format!("no contact with box \"{}\" after closing the gap", bodies[m].name),
            ));
        };
        contacts.push(Contact {
            front: m,
            kind,
            p0,
            dir,
            len,
            normal,
            z,
            mu,
        });
    }
    Ok(contacts)
}

/// The uncertainty set of a robust scenario: friction intervals that contain the nominal
/// values, and a centre-of-friction region within every footprint.
fn uncertainty(
    f: &ScenarioFile,
    file: &str,
    scale: f64,
    model: &PushModel,
    box_mu: &[BoxFriction],
) -> Result<Option<UncertaintySet>> {
    let k = model.bodies.len();
    Ok(match (&f.robust, f.mode.robust()) {
        (None, true) => {
            return Err(err(
                file,
                "robust",
                "mode robust needs the uncertainty: intervals mu_floor / mu_obj / mu_finger and/or cof_region",
            ))
        }
        (None, false) => None,
        (Some(r), _) => {
            let iv = |name: &str, v: Option<[f64; 2]>, nominal: &[f64]| -> Result<Option<[f64; 2]>> {
                let Some([lo, hi]) = v else { return Ok(None) };
                let fld = format!("robust.{name}");
                non_negative(file, &format!("{fld}[0]"), lo)?;
                non_negative(file, &format!("{fld}[1]"), hi)?;
                if lo > hi {
                    return Err(err(file, fld, format!("interval [{lo}, {hi}] is empty")));
                }
                if let Some(x) = nominal.iter().find(|&&x| x < lo - 1e-12 || x > hi + 1e-12) {
                    return Err(err(
                        file,
                        fld,
                        format!("interval [{lo}, {hi}] must contain the nominal value {x}"),
                    ));
                }
                Ok(Some([lo, hi]))
            };
            let floors: Vec<f64> = model.bodies.iter().map(|b| b.mu_floor).collect();
            let objs: Vec<f64> = box_mu.iter().map(|m| m.0).collect();
            let fingers = [box_mu[k - 1].1];
            let mf = iv("mu_floor", r.mu_floor, &floors)?;
            if let Some([lo, _]) = mf {
                if lo <= 0.0 {
                    return Err(err(file, "robust.mu_floor[0]", "must be > 0"));
                }
            }
            let mo = iv("mu_obj", r.mu_obj, &objs)?;
            let mg = iv("mu_finger", r.mu_finger, &fingers)?;
            let cof = match r.cof_region {
                Some([a, b]) => [
                    non_negative(file, "robust.cof_region[0]", a)? * scale,
                    non_negative(file, "robust.cof_region[1]", b)? * scale,
                ],
                None => [0.0, 0.0],
            };
            for (i, b) in model.bodies.iter().enumerate() {
                if cof[0] > b.half[0] || cof[1] > b.half[1] {
                    return Err(err(
                        file,
                        "robust.cof_region",
                        format!("region exceeds the footprint of box \"{}\"", f.boxes[i].id),
                    ));
                }
            }
            let mut set = UncertaintySet::nominal(model);
            for (i, b) in model.bodies.iter().enumerate() {
                if let Some(iv) = mf {
                    set.mu_floor[i] = iv;
                } else {
                    set.mu_floor[i] = [b.mu_floor; 2];
                }
            }
            for (j, c) in model.contacts.iter().enumerate() {
                let iv = match c.kind {
                    ContactKind::Object => mo,
                    ContactKind::Pusher => mg,
                };
                if let Some(iv) = iv {
                    set.mu_contact[j] = iv;
                }
            }
            set.cof = vec![cof; k];
            Some(set)
        }
    })
}

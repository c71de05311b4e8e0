//! `push-check` scenarios: one push described in a small JSON file, decided by the convex check,
//! reported with a verdict, a margin and a certificate.
//!
//! Format (lengths in metres unless `units` says `cm`/`mm`; angles in radians):
//!
//! ```json
//! {
//!   "name": "two boxes, lateral offset",
//!   "mode": "2d",                      // "2d" | "3d" | "robust" (2-D) | "robust3d"
//!   "push_dir": "-x",                  // "-x" | "+x" | "-y" | "+y" | [ux, uy]
//!   "friction": { "mu_floor": 0.35, "mu_obj": 0.3, "mu_finger": 0.5 },
//!   "boxes": [                         // front (nearest the destination) to back
//!     { "id": "b1", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.03, 0.02, 0.0] },
//!     { "id": "b2", "size": [0.06, 0.04, 0.03], "mass": 0.05, "pose": [0.09, 0.02, 0.0],
//!       "mu_floor": 0.4 }              // optional per-box mu_floor / mu_obj / mu_finger
//!   ],
//!   "pusher": { "point": [0.12, 0.02], "width": 0.02, "height": 0.005 },
//!   "robust": { "mu_floor": [0.3, 0.4], "mu_obj": [0.25, 0.35], "mu_finger": [0.4, 0.6],
//!               "cof_region": [0.003, 0.003] }
//! }
//! ```
//!
//! `size` is the box's extent along its own x and y (turned by the pose's yaw) and its height;
//! `pose` the footprint centre and yaw. Boxes may start apart along the push direction: the back
//! ones then move first (one phase per gap). The pusher is the flat back of the closed fingers:
//! a face `width` wide centred at `point`, perpendicular to `normal` (default: the push
//! direction), fingertip `height` above the floor; its contact patch reaches from the fingertip
//! to the top of the back box. Optional: `units`, `gravity`, `cone_shrink`, `name`.

use std::fmt;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::convex::{self, Binding, CheckOptions, CheckResult, ContactForce, Dim, FloorForce, PhaseStatus};
use super::model::{cross, dot, Body, Contact, ContactKind, PushModel, V2};
use super::robust::{self, RobustCase, UncertaintySet};
use super::travel::TravelCheck;
use crate::error::{Error, Result};

/// Which check a scenario asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Mode {
    /// Planar LP.
    #[serde(rename = "2d")]
    D2,
    /// Spatial SOCP with patches, floor pressure and toppling.
    #[serde(rename = "3d")]
    D3,
    /// 2-D over the uncertainty set.
    #[serde(rename = "robust")]
    Robust,
    /// 3-D over the uncertainty set.
    #[serde(rename = "robust3d")]
    Robust3d,
}

impl Mode {
    /// Model dimension of the mode.
    pub fn dim(self) -> Dim {
        match self {
            Mode::D2 | Mode::Robust => Dim::D2,
            Mode::D3 | Mode::Robust3d => Dim::D3,
        }
    }
    /// Whether the mode is robust.
    pub fn robust(self) -> bool {
        matches!(self, Mode::Robust | Mode::Robust3d)
    }
    /// File spelling.
    pub fn name(self) -> &'static str {
        match self {
            Mode::D2 => "2d",
            Mode::D3 => "3d",
            Mode::Robust => "robust",
            Mode::Robust3d => "robust3d",
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    units: Option<String>,
    mode: Mode,
    push_dir: DirSpec,
    #[serde(default)]
    gravity: Option<f64>,
    friction: FrictionFile,
    #[serde(default)]
    robust: Option<RobustFile>,
    boxes: Vec<BoxFile>,
    pusher: PusherFile,
    #[serde(default)]
    cone_shrink: Option<f64>,
    #[serde(default)]
    max_rotation: Option<f64>,
    #[serde(default)]
    max_drift: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum DirSpec {
    Named(String),
    Vector([f64; 2]),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FrictionFile {
    mu_floor: f64,
    mu_obj: f64,
    mu_finger: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobustFile {
    #[serde(default)]
    mu_floor: Option<[f64; 2]>,
    #[serde(default)]
    mu_obj: Option<[f64; 2]>,
    #[serde(default)]
    mu_finger: Option<[f64; 2]>,
    #[serde(default)]
    cof_region: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BoxFile {
    id: String,
    size: [f64; 3],
    mass: f64,
    pose: [f64; 3],
    #[serde(default)]
    mu_floor: Option<f64>,
    #[serde(default)]
    mu_obj: Option<f64>,
    #[serde(default)]
    mu_finger: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PusherFile {
    point: [f64; 2],
    width: f64,
    height: f64,
    #[serde(default)]
    normal: Option<[f64; 2]>,
}

/// A validated scenario: the push model plus what to check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scenario {
    /// File the scenario came from (or `<memory>`).
    pub source: String,
    /// Display name.
    pub name: String,
    /// Requested check.
    pub mode: Mode,
    /// The push model with every gap closed (boxes at the moment they touch).
    pub model: PushModel,
    /// Gap closed before each box (m), front to back, the pusher's last.
    pub gaps: Vec<f64>,
    /// Uncertainty set (robust modes).
    pub uncertainty: Option<UncertaintySet>,
    /// Cone shrink and tolerance.
    pub options: CheckOptions,
}

/// Read and validate a scenario file.
pub fn load_scenario(path: impl AsRef<Path>) -> Result<Scenario> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    parse_scenario(&text, &path.display().to_string())
}

/// Geometric tolerance of scenario geometry (m).
const TOL: f64 = 1e-7;

fn err(file: &str, field: impl Into<String>, reason: impl Into<String>) -> Error {
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

fn finite(file: &str, field: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be a finite number, got {v}")))
    }
}

fn positive(file: &str, field: &str, v: f64) -> Result<f64> {
    if finite(file, field, v)? > 0.0 {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be > 0, got {v}")))
    }
}

/// A length (m) that must be at least the instance files' smallest box edge, so that the
/// geometric tolerances stay negligible against it.
fn edge(file: &str, field: &str, v: f64) -> Result<f64> {
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

fn non_negative(file: &str, field: &str, v: f64) -> Result<f64> {
    if finite(file, field, v)? >= 0.0 {
        Ok(v)
    } else {
        Err(err(file, field, format!("must be >= 0, got {v}")))
    }
}

fn unit(file: &str, field: &str, v: V2) -> Result<V2> {
    finite(file, &format!("{field}[0]"), v[0])?;
    finite(file, &format!("{field}[1]"), v[1])?;
    let n = v[0].hypot(v[1]);
    if n > 1e-12 {
        Ok([v[0] / n, v[1] / n])
    } else {
        Err(err(file, field, "must be a non-zero vector"))
    }
}

fn build(f: ScenarioFile, file: &str) -> Result<Scenario> {
    let scale = match f.units.as_deref() {
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
    };
    let u = match &f.push_dir {
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
    };
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
        None => super::CONE_SHRINK,
    };
    let max_rotation = match f.max_rotation {
        Some(r) => positive(file, "max_rotation", r)?,
        None => super::MAX_ROTATION,
    };
    let max_drift = match f.max_drift {
        Some(d) => positive(file, "max_drift", d)? * scale,
        None => super::MAX_DRIFT,
    };
    if f.boxes.is_empty() {
        return Err(err(file, "boxes", "needs at least one box"));
    }
    // Bodies.
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
    // Pusher.
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
    let mut pusher = vec![
        [pc[0] - width / 2.0 * pd[0], pc[1] - width / 2.0 * pd[1]],
        [pc[0] + width / 2.0 * pd[0], pc[1] + width / 2.0 * pd[1]],
    ];
    // Overlaps and gaps, closing the line from the front.
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
    // Close the gaps from the front: everything behind body m moves by the gaps closed so far.
    let originals: Vec<Vec<V2>> = polys.clone();
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
            pusher = translate(&pusher_orig, u, total);
        }
    }
    // Contacts in the closed configuration.
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
                pusher.clone(),
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
    let gap_flags: Vec<bool> = gaps[..k - 1].iter().map(|&g| g > TOL).collect();
    let mut model = PushModel::new(u, bodies, contacts, &gap_flags);
    model.gravity = gravity;
    // Phase `s > 0` (boxes `s..k`) lasts until it closes the gap in front of box `s`.
    model.phase_travel = model
        .phase_starts
        .iter()
        .map(|&s| if s == 0 { f64::INFINITY } else { gaps[s - 1] })
        .collect();
    // Uncertainty.
    let uncertainty = match (&f.robust, f.mode.robust()) {
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
            let mut set = UncertaintySet::nominal(&model);
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
    };
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
            ..CheckOptions::default()
        },
    })
}

fn translate(pts: &[V2], u: V2, s: f64) -> Vec<V2> {
    pts.iter().map(|p| [p[0] + s * u[0], p[1] + s * u[1]]).collect()
}

/// Outward unit normals of a convex polygon's edges (counter-clockwise vertices; a two-point
/// "polygon" is a segment with both normals).
fn edges(poly: &[V2]) -> Vec<(V2, V2, V2)> {
    let n = poly.len();
    (0..n)
        .filter_map(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy);
            (l > 0.0).then(|| (a, b, [dy / l, -dx / l]))
        })
        .collect()
}

/// Penetration depth of two convex polygons (≤ 0 when they do not overlap), by separating axes.
fn penetration(a: &[V2], b: &[V2]) -> f64 {
    let mut depth = f64::INFINITY;
    for (_, _, n) in edges(a).into_iter().chain(edges(b)) {
        let pa = a.iter().map(|p| dot(*p, n));
        let pb = b.iter().map(|p| dot(*p, n));
        let (amin, amax) = pa.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        let (bmin, bmax) = pb.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
        depth = depth.min(amax.min(bmax) - amin.max(bmin));
    }
    depth
}

/// Whether segment `[p, q]` passes through the interior of a convex polygon (shrunk by the
/// tolerance), by Cyrus–Beck clipping.
fn segment_enters(poly: &[V2], p: V2, q: V2) -> bool {
    let d = [q[0] - p[0], q[1] - p[1]];
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (a, _, n) in edges(poly) {
        // Inside: dot(x − a, n) ≤ −TOL.
        let num = -TOL - dot([p[0] - a[0], p[1] - a[1]], n);
        let den = dot(d, n);
        if den.abs() < 1e-18 {
            if num < 0.0 {
                return false;
            }
        } else if den > 0.0 {
            hi = hi.min(num / den);
        } else {
            lo = lo.max(num / den);
        }
        if lo > hi {
            return false;
        }
    }
    true
}

/// Parameter `s` at which the ray `p + s d` crosses segment `[a, b]`.
fn ray_hit(p: V2, d: V2, a: V2, b: V2) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let den = cross(d, e);
    if den.abs() < 1e-15 {
        return None;
    }
    let ap = [a[0] - p[0], a[1] - p[1]];
    let s = cross(ap, e) / den;
    let r = cross(ap, d) / den;
    (-1e-12..=1.0 + 1e-12).contains(&r).then_some(s)
}

/// Distance `back` must travel along `u` to touch `front` (None if it never does).
fn gap_along(front: &[V2], back: &[V2], u: V2) -> Option<f64> {
    let mut best: Option<f64> = None;
    let mut consider = |s: f64| {
        if s >= -TOL {
            best = Some(best.map_or(s, |b: f64| b.min(s)));
        }
    };
    for &v in back {
        for (a, b, _) in edges(front) {
            if let Some(s) = ray_hit(v, u, a, b) {
                consider(s);
            }
        }
    }
    let mu = [-u[0], -u[1]];
    for &v in front {
        for (a, b, _) in edges(back) {
            if let Some(s) = ray_hit(v, mu, a, b) {
                consider(s);
            }
        }
    }
    best
}

/// The contact of two touching convex polygons, as `(p0, dir, len, normal)` with the normal the
/// direction of the force on `front` (out of `back`, into `front`): a shared edge segment when
/// two anti-parallel edges coincide, else a vertex on an edge (a point contact).
fn touching(front: &[V2], back: &[V2]) -> Option<(V2, V2, f64, V2)> {
    let ef = edges(front);
    let eb = edges(back);
    for &(a, b, na) in &ef {
        for &(c, d, nb) in &eb {
            if dot(na, nb) > -(1.0 - 1e-9) {
                continue;
            }
            if (dot([c[0] - a[0], c[1] - a[1]], na)).abs() > TOL {
                continue;
            }
            let t = [b[0] - a[0], b[1] - a[1]];
            let l = t[0].hypot(t[1]);
            let t = [t[0] / l, t[1] / l];
            let (s0, s1): (f64, f64) = (0.0, l);
            let (r0, r1) = {
                let x = dot([c[0] - a[0], c[1] - a[1]], t);
                let y = dot([d[0] - a[0], d[1] - a[1]], t);
                (x.min(y), x.max(y))
            };
            let lo = s0.max(r0);
            let hi = s1.min(r1);
            if hi - lo > TOL {
                return Some(([a[0] + lo * t[0], a[1] + lo * t[1]], t, hi - lo, [-na[0], -na[1]]));
            }
        }
    }
    let on_edge = |p: V2, a: V2, b: V2, n: V2| {
        let t = [b[0] - a[0], b[1] - a[1]];
        let l2 = dot(t, t);
        let r = dot([p[0] - a[0], p[1] - a[1]], t) / l2;
        (dot([p[0] - a[0], p[1] - a[1]], n)).abs() <= TOL && (-1e-9..=1.0 + 1e-9).contains(&r)
    };
    for &v in back {
        for &(a, b, na) in &ef {
            if on_edge(v, a, b, na) {
                let n = [-na[0], -na[1]];
                return Some((v, [-n[1], n[0]], 0.0, n));
            }
        }
    }
    for &v in front {
        for &(c, d, nb) in &eb {
            if on_edge(v, c, d, nb) {
                return Some((v, [-nb[1], nb[0]], 0.0, nb));
            }
        }
    }
    None
}

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

fn edge_name(model: &PushModel, body: usize, axis: usize, side: i8) -> &'static str {
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
fn describe(model: &PushModel, b: &Binding, margin: Option<f64>, failed: bool) -> (FailureKind, String, String) {
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

fn report(s: &Scenario, model: &PushModel, result: &CheckResult, robust: Option<RobustReport>) -> PushReport {
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
fn fmt_use(u: Option<f64>) -> String {
    u.map_or("n/a (μ = 0)".to_string(), |u| format!("{:.0}%", u * 100.0))
}

fn fmt_m(m: Option<f64>) -> String {
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

//! Pictures: SVG of the final placement and a storyboard with one panel per action.
//!
//! [`render`] writes three hand-written SVG files (no dependencies, inline attributes only, so
//! browsers and simple converters such as ImageMagick draw them alike):
//!
//! * `placement.svg` — the container floor and walls, every object's footprint in C coloured by
//!   kind and labelled with its id, kind and orientation, axes in cm, the occupied-area rectangle
//!   dashed, and a title with occupied area and contact length;
//! * `storyboard.svg` — one panel per action (like the paper's Figs. 11 and 13): objects
//!   already at their targets in grey, released objects waiting for a push outlined at their
//!   release pose, the acting object highlighted with its finger slabs (places) or the pusher,
//!   its sweep and the push distance (pushes); a finger that passes above a lower box is drawn
//!   lighter and dashed with both heights (`↑4.5 over 4.0`, cm), not as a collision;
//! * `swept.svg` — the swept area (bounding rectangle from C's origin of every footprint so far,
//!   releases included) after each step, as a step plot;
//! * `view.html` — the plan played in 3-D (arms, hands, objects, container), a self-contained
//!   page for any browser ([`view_html`]; plans with joint trajectories only).
//!
//! [`render_placement`] writes `placement.svg` alone, from a placement stage result, for runs
//! whose sequence stage found no plan.
//!
//! C's y axis points up on the page, x to the right, as in the paper's figures.

mod svg;

use crate::actions::{Action, PlaceMode};
use crate::error::{Error, Result};
use crate::geometry::Arm;
use crate::geometry::{Axis2, PushDir, Rect};
use crate::instance::Instance;
use crate::placement::{Placement, PlacementResult};
use crate::plan::Plan;
use std::path::{Path, PathBuf};
use svg::{text_width, tint, Anchor, Paint, Svg};

mod placement;
mod storyboard;
mod swept;
mod view;

use placement::*;
use storyboard::*;
use swept::*;
pub use view::view_html;

/// Write `placement.svg`, `storyboard.svg`, `swept.svg` and (for a plan with joint trajectories)
/// `view.html` for `plan` into `out_dir` (created if missing); returns the paths written.
pub fn render(inst: &Instance, plan: &Plan, out_dir: &Path) -> Result<Vec<PathBuf>> {
    let placement = plan.placement(inst)?;
    let actions = plan.actions(inst)?;
    std::fs::create_dir_all(out_dir).map_err(|e| Error::Io {
        path: out_dir.to_path_buf(),
        source: e,
    })?;
    let story = Story::new(inst, &placement, &actions);
    let solver_label = match plan.placement.alternative {
        0 => plan.placement.solver.clone(),
        k => format!("{}, alternative {k}", plan.placement.solver),
    };
    let files = [
        (
            "placement.svg",
            placement_svg(inst, &solver_label, plan.placement.status, &placement),
        ),
        (
            "storyboard.svg",
            storyboard_svg(inst, plan, &placement, &actions, &story),
        ),
        ("swept.svg", swept_svg(inst, plan, &placement, &actions, &story)),
    ];
    let view = if plan.trajectories.iter().any(|t| !t.points.is_empty()) {
        Some(("view.html", view_html(inst, plan)?))
    } else {
        None
    };
    let mut out = Vec::new();
    for (name, text) in files.into_iter().chain(view) {
        let path = out_dir.join(name);
        std::fs::write(&path, text).map_err(|e| Error::Io {
            path: path.clone(),
            source: e,
        })?;
        out.push(path);
    }
    Ok(out)
}

/// Write `placement.svg` alone for a placement stage result into `out_dir` (created if
/// missing); for runs that end without a sequence. Returns the path written.
pub fn render_placement(inst: &Instance, r: &PlacementResult, out_dir: &Path) -> Result<PathBuf> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::Io {
        path: out_dir.to_path_buf(),
        source: e,
    })?;
    let path = out_dir.join("placement.svg");
    std::fs::write(
        &path,
        placement_svg(inst, &r.solver, crate::plan::placement_status(r), &r.placement),
    )
    .map_err(|e| Error::Io {
        path: path.clone(),
        source: e,
    })?;
    Ok(path)
}

// ---------------------------------------------------------------------------------------------
// Shared helpers.

/// One colour per kind (Tableau 10), cycled.
const KIND_COLOURS: [&str; 10] = [
    "#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac",
];
const DONE_FILL: &str = "#c9c9c9";
const WALL_FILL: &str = "#8c8c8c";
const ACT_STROKE: &str = "#d62728";
const FINGER_FILL: &str = "#262626";
const TEXT: &str = "#1a1a1a";

fn kind_colour(inst: &Instance, i: usize) -> &'static str {
    KIND_COLOURS[inst.objects[i].kind % KIND_COLOURS.len()]
}

fn cm(v: f64) -> String {
    format!("{:.1}", v * 100.0)
}

fn dir_label(d: PushDir) -> &'static str {
    match d {
        PushDir::MinusX => "\u{2212}x",
        PushDir::MinusY => "\u{2212}y",
    }
}

fn axis_label(a: Axis2) -> &'static str {
    match a {
        Axis2::X => "x",
        Axis2::Y => "y",
    }
}

fn arm_label(a: Arm) -> &'static str {
    match a {
        Arm::Left => "left arm",
        Arm::Right => "right arm",
    }
}

/// A deferred label: page rectangle (left, top, width, height), text, bold, maximum font size.
type Label = ((f64, f64, f64, f64), String, bool, f64);

/// Maps C (metres, y up) to the page (pixels, y down).
#[derive(Clone, Copy)]
struct View {
    /// Page x of C's origin.
    ox: f64,
    /// Page y of C's origin.
    oy: f64,
    /// Pixels per metre.
    s: f64,
}

impl View {
    fn x(&self, x: f64) -> f64 {
        self.ox + x * self.s
    }
    fn y(&self, y: f64) -> f64 {
        self.oy - y * self.s
    }
    fn len(&self, l: f64) -> f64 {
        l * self.s
    }
    /// Page rectangle (left, top, width, height) of a rectangle of C.
    fn rect(&self, r: &Rect) -> (f64, f64, f64, f64) {
        (self.x(r.x0), self.y(r.y1), self.len(r.width()), self.len(r.depth()))
    }
    fn draw(&self, svg: &mut Svg, r: &Rect, p: Paint) {
        let (x, y, w, h) = self.rect(r);
        svg.rect(x, y, w, h, p);
    }
}

/// Container walls and floor.
fn draw_container(svg: &mut Svg, inst: &Instance, v: &View) {
    let c = &inst.container;
    let t = c.wall_thickness;
    let outer = Rect::new(-t, -t, c.width + 2.0 * t, c.depth + 2.0 * t);
    v.draw(svg, &outer, Paint::fill(WALL_FILL, "#555555", 1.0));
    v.draw(svg, &c.floor(), Paint::fill("#fbfbf8", "#555555", 1.0));
}

/// Label lines centred in a page rectangle, shrinking the font until the widest line fits and
/// dropping trailing lines rather than going below 10 px.
fn label_in(svg: &mut Svg, (x, y, w, h): (f64, f64, f64, f64), lines: &[(&str, bool)], max_size: f64) {
    let mut lines: Vec<(&str, bool)> = lines.to_vec();
    loop {
        let widest = lines.iter().map(|(s, _)| s.chars().count()).max().unwrap_or(1).max(1) as f64;
        let size_w = (w - 6.0) / (widest * 0.62);
        let size_h = (h - 4.0) / (lines.len() as f64 * 1.2);
        let size = max_size.min(size_w).min(size_h);
        if size >= 10.0f64.min(max_size) || lines.len() == 1 {
            let size = size.max(6.0);
            let total = lines.len() as f64 * size * 1.2;
            let mut base = y + (h - total) / 2.0 + size * 0.95;
            for (s, bold) in &lines {
                svg.text(x + w / 2.0, base, size, Anchor::Middle, *bold, TEXT, s);
                base += size * 1.2;
            }
            return;
        }
        lines.pop();
    }
}

/// Nice tick step for an axis spanning `len` with about `n` ticks.
fn nice_step(len: f64, n: f64) -> f64 {
    let raw = (len / n).max(1e-12);
    let mag = 10f64.powf(raw.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * mag >= raw {
            return m * mag;
        }
    }
    10.0 * mag
}

/// Where each object is during the plan.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pos {
    Table,
    Released(Rect),
    Done,
}

/// States before each action and the swept extent after each step, replayed from the plan.
struct Story {
    /// `before[k]` = every object's position before action `k`; one more entry for the end.
    before: Vec<Vec<Pos>>,
    /// Swept area (m²) after step k (index 0 = before the first action).
    swept: Vec<f64>,
}

fn release_rect(p: &Placement, i: usize, mode: &PlaceMode) -> Rect {
    let t = p.targets[i].rect;
    match mode {
        PlaceMode::Direct => t,
        PlaceMode::Indirect { push_dir, offset } => t.moved(*push_dir, -offset),
    }
}

impl Story {
    fn new(inst: &Instance, p: &Placement, actions: &[Action]) -> Story {
        let mut pos = vec![Pos::Table; inst.n()];
        let mut before = vec![pos.clone()];
        let (mut mx, mut my) = (0.0f64, 0.0f64);
        let mut swept = vec![0.0];
        for a in actions {
            match a {
                Action::Place { object, mode, .. } => {
                    let r = release_rect(p, *object, mode);
                    pos[*object] = match mode {
                        PlaceMode::Direct => Pos::Done,
                        PlaceMode::Indirect { .. } => Pos::Released(r),
                    };
                    mx = mx.max(r.x1);
                    my = my.max(r.y1);
                }
                Action::Push { objects, .. } => {
                    for &i in objects {
                        pos[i] = Pos::Done;
                        mx = mx.max(p.targets[i].rect.x1);
                        my = my.max(p.targets[i].rect.y1);
                    }
                }
            }
            before.push(pos.clone());
            swept.push(mx * my);
        }
        Story { before, swept }
    }
}

// ---------------------------------------------------------------------------------------------
// placement.svg

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
//!   its sweep and the push distance (pushes);
//! * `swept.svg` — the swept area (bounding rectangle from C's origin of every footprint so far,
//!   releases included) after each step, as a step plot.
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

/// Write `placement.svg`, `storyboard.svg` and `swept.svg` for `plan` into `out_dir` (created if
/// missing); returns the paths written.
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
    let mut out = Vec::new();
    for (name, text) in files {
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

fn placement_svg(inst: &Instance, solver: &str, status: crate::status::Status, p: &Placement) -> String {
    let c = &inst.container;
    let t = c.wall_thickness;
    let s = (620.0 / c.width).min(440.0 / c.depth);
    let (left, top) = (90.0, 104.0);
    let v = View {
        ox: left + t * s,
        oy: top + (c.depth + t) * s,
        s,
    };
    let legend_x = left + (c.width + 2.0 * t) * s + 34.0;
    let legend_w = 250.0;
    let n_kinds = inst.kinds.len();
    let legend_h = 40.0 + 24.0 * (n_kinds as f64 + 2.0);
    let width = legend_x + legend_w;
    let height = (v.oy + t * s + 70.0).max(top + legend_h + 20.0);
    let mut svg = Svg::new(width, height);
    svg.comment(&format!("pushpack placement of {}", inst.name));

    // Title.
    let (mx, my) = p.extent();
    let area = p.occupied_area();
    let contact = p.contact_length(inst);
    svg.text(
        20.0,
        32.0,
        19.0,
        Anchor::Start,
        true,
        TEXT,
        &format!("Placement \u{2014} {} ({} objects)", inst.name, inst.n()),
    );
    svg.text(
        20.0,
        58.0,
        14.0,
        Anchor::Start,
        false,
        TEXT,
        &format!(
            "occupied area {:.1} cm\u{b2} ({} \u{d7} {} cm) \u{b7} contact length {} cm \u{b7} solver {} ({})",
            area * 1e4,
            cm(mx),
            cm(my),
            cm(contact),
            solver,
            serde_json::to_value(status)
                .ok()
                .and_then(|x| x.as_str().map(String::from))
                .unwrap_or_default()
        ),
    );

    draw_container(&mut svg, inst, &v);
    // Objects.
    for (i, tg) in p.targets.iter().enumerate() {
        let o = &inst.objects[i];
        let fill = tint(kind_colour(inst, i), 0.45);
        v.draw(&mut svg, &tg.rect, Paint::fill(&fill, "#222222", 1.2));
        let kind = format!("kind {}", inst.kinds[o.kind].name);
        let ori = format!("{} \u{b7} h {}", tg.orientation.label(), cm(tg.height));
        label_in(
            &mut svg,
            v.rect(&tg.rect),
            &[(o.id.as_str(), true), (kind.as_str(), false), (ori.as_str(), false)],
            17.0,
        );
    }
    // Occupied area, dashed.
    v.draw(
        &mut svg,
        &Rect::new(0.0, 0.0, mx, my),
        Paint::line(ACT_STROKE, 2.0).dashed("8,5"),
    );
    // Origin marker.
    svg.circle(v.x(0.0), v.y(0.0), 3.5, Paint::fill(ACT_STROKE, "none", 0.0));

    // Axes (cm), outside the walls.
    let step = nice_step(c.width.max(c.depth), 8.0);
    let ax_y = v.y(-t) + 14.0;
    svg.line(v.x(0.0), ax_y, v.x(c.width), ax_y, Paint::line(TEXT, 1.0));
    let mut x = 0.0;
    while x <= c.width + 1e-9 {
        svg.line(v.x(x), ax_y, v.x(x), ax_y + 5.0, Paint::line(TEXT, 1.0));
        svg.text(
            v.x(x),
            ax_y + 19.0,
            12.0,
            Anchor::Middle,
            false,
            TEXT,
            &format!("{:.0}", x * 100.0),
        );
        x += step;
    }
    svg.text(
        v.x(c.width / 2.0),
        ax_y + 38.0,
        13.0,
        Anchor::Middle,
        true,
        TEXT,
        "x (cm)",
    );
    let ax_x = v.x(-t) - 14.0;
    svg.line(ax_x, v.y(0.0), ax_x, v.y(c.depth), Paint::line(TEXT, 1.0));
    let mut y = 0.0;
    while y <= c.depth + 1e-9 {
        svg.line(ax_x - 5.0, v.y(y), ax_x, v.y(y), Paint::line(TEXT, 1.0));
        svg.text(
            ax_x - 8.0,
            v.y(y) + 4.0,
            12.0,
            Anchor::End,
            false,
            TEXT,
            &format!("{:.0}", y * 100.0),
        );
        y += step;
    }
    svg.text(
        ax_x - 8.0,
        v.y(c.depth + t) - 12.0,
        13.0,
        Anchor::Middle,
        true,
        TEXT,
        "y (cm)",
    );

    // Legend.
    let mut ly = top + 6.0;
    svg.text(legend_x, ly, 14.0, Anchor::Start, true, TEXT, "Kinds");
    ly += 12.0;
    for (k, kind) in inst.kinds.iter().enumerate() {
        let count = inst.objects.iter().filter(|o| o.kind == k).count();
        let fill = tint(KIND_COLOURS[k % KIND_COLOURS.len()], 0.45);
        svg.rect(legend_x, ly, 18.0, 14.0, Paint::fill(&fill, "#222222", 1.0));
        svg.text(
            legend_x + 26.0,
            ly + 12.0,
            12.0,
            Anchor::Start,
            false,
            TEXT,
            &format!(
                "{}: {} \u{d7} {} \u{d7} {} cm, {} pc",
                kind.name,
                cm(kind.size[0]),
                cm(kind.size[1]),
                cm(kind.size[2]),
                count
            ),
        );
        ly += 24.0;
    }
    ly += 6.0;
    svg.line(
        legend_x,
        ly + 7.0,
        legend_x + 18.0,
        ly + 7.0,
        Paint::line(ACT_STROKE, 2.0).dashed("5,3"),
    );
    svg.text(
        legend_x + 26.0,
        ly + 12.0,
        12.0,
        Anchor::Start,
        false,
        TEXT,
        &format!("occupied area {} \u{d7} {} cm", cm(mx), cm(my)),
    );
    ly += 24.0;
    svg.rect(legend_x, ly, 18.0, 14.0, Paint::fill(WALL_FILL, "#555555", 1.0));
    svg.text(
        legend_x + 26.0,
        ly + 12.0,
        12.0,
        Anchor::Start,
        false,
        TEXT,
        &format!("walls {} cm thick, {} cm high", cm(t), cm(c.wall_height)),
    );
    svg.finish()
}

// ---------------------------------------------------------------------------------------------
// storyboard.svg

/// Rectangle of a finger next to footprint `r` along `axis` (the `hi` side or the low side),
/// at `gap` from the face, `thick` deep, `width` wide centred on the face.
fn finger_rect(r: &Rect, axis: Axis2, hi: bool, gap: f64, thick: f64, width: f64) -> Rect {
    let c = r.center();
    let (a0, a1) = if hi {
        (r.hi(axis) + gap, r.hi(axis) + gap + thick)
    } else {
        (r.lo(axis) - gap - thick, r.lo(axis) - gap)
    };
    match axis {
        Axis2::X => Rect {
            x0: a0,
            x1: a1,
            y0: c[1] - width / 2.0,
            y1: c[1] + width / 2.0,
        },
        Axis2::Y => Rect {
            x0: c[0] - width / 2.0,
            x1: c[0] + width / 2.0,
            y0: a0,
            y1: a1,
        },
    }
}

/// Pusher rectangle behind `back` (the +axis side), `gap` from it, centred at lateral `at`.
fn pusher_rect(back: &Rect, dir: PushDir, at: f64, gap: f64, thick: f64, width: f64) -> Rect {
    let axis = dir.axis();
    let a0 = back.hi(axis) + gap;
    match axis {
        Axis2::X => Rect {
            x0: a0,
            x1: a0 + thick,
            y0: at - width / 2.0,
            y1: at + width / 2.0,
        },
        Axis2::Y => Rect {
            x0: at - width / 2.0,
            x1: at + width / 2.0,
            y0: a0,
            y1: a0 + thick,
        },
    }
}

fn caption(inst: &Instance, plan: &Plan, k: usize, a: &Action) -> (String, String) {
    let e = &plan.actions[k];
    match a {
        Action::Place {
            object,
            mode,
            grasp_axis,
            arm,
        } => {
            let id = &inst.objects[*object].id;
            match mode {
                PlaceMode::Direct => (
                    format!("step {}: place {id} direct", k + 1),
                    format!("grasp {} \u{b7} {}", axis_label(*grasp_axis), arm_label(*arm)),
                ),
                PlaceMode::Indirect { push_dir, offset } => (
                    format!("step {}: place {id} indirect {}", k + 1, dir_label(*push_dir)),
                    format!(
                        "offset {} cm \u{b7} grasp {} \u{b7} {}",
                        cm(*offset),
                        axis_label(*grasp_axis),
                        arm_label(*arm)
                    ),
                ),
            }
        }
        Action::Push {
            objects,
            push_dir,
            distance,
            pusher_at,
            arm,
        } => {
            let ids: Vec<&str> = objects.iter().map(|&i| inst.objects[i].id.as_str()).collect();
            let lat = axis_label(push_dir.axis().other());
            let margin = e
                .margin
                .map(|m| format!("margin {} mm \u{b7} ", format_args!("{:.1}", m * 1000.0)))
                .unwrap_or_default();
            (
                format!(
                    "step {}: push {} {} {} cm",
                    k + 1,
                    ids.join("+"),
                    dir_label(*push_dir),
                    cm(*distance)
                ),
                format!(
                    "{margin}pusher at {lat} = {} cm \u{b7} {}",
                    cm(*pusher_at),
                    arm_label(*arm)
                ),
            )
        }
    }
}

fn storyboard_svg(inst: &Instance, plan: &Plan, p: &Placement, actions: &[Action], story: &Story) -> String {
    let c = &inst.container;
    let g = &inst.gripper;
    let t = c.wall_thickness;
    let n = actions.len();
    let cols = match n {
        0 => 1,
        1..=4 => n,
        5..=9 => 3,
        _ => 4,
    };
    let rows = n.div_ceil(cols).max(1);
    let draw_w = 340.0;
    let s = draw_w / (c.width + 2.0 * t);
    let draw_h = (c.depth + 2.0 * t) * s;
    let (pad, cap_h, gap) = (10.0, 42.0, 12.0);
    let panel_w = draw_w + 2.0 * pad;
    let panel_h = cap_h + draw_h + 2.0 * pad;
    let (left, top) = (16.0, 96.0);
    let width = (left * 2.0 + cols as f64 * panel_w + (cols as f64 - 1.0) * gap).max(760.0);
    let height = top + rows as f64 * panel_h + (rows as f64 - 1.0) * gap + 16.0;
    let mut svg = Svg::new(width, height);
    svg.comment(&format!("pushpack storyboard of {}", inst.name));
    let m = &plan.metrics;
    svg.text(
        left,
        30.0,
        19.0,
        Anchor::Start,
        true,
        TEXT,
        &format!("Storyboard \u{2014} {}: {} actions", inst.name, n),
    );
    svg.text(
        left,
        52.0,
        13.0,
        Anchor::Start,
        false,
        TEXT,
        &format!(
            "{} direct, {} indirect places \u{b7} {} push{} ({} multi-object) \u{b7} swept area {:.1} cm\u{b2} \u{b7} travel {:.2} m",
            m.n_place_direct,
            m.n_place_indirect,
            m.n_push,
            if m.n_push == 1 { "" } else { "es" },
            m.n_multi_push,
            m.swept_area * 1e4,
            m.travel
        ),
    );
    // Legend line.
    let mut lx = left;
    let ly = 66.0;
    let acting_fill = tint("#f28e2b", 0.25);
    let released_fill = tint("#f28e2b", 0.8);
    let items: [(Paint, &str); 5] = [
        (Paint::fill(DONE_FILL, "#777777", 1.0), "at target"),
        (
            Paint::fill(&released_fill, "#f28e2b", 1.5).dashed("4,3"),
            "released, waiting for its push",
        ),
        (Paint::fill(&acting_fill, ACT_STROKE, 2.5), "acting object"),
        (Paint::fill(FINGER_FILL, "none", 0.0), "fingers / pusher"),
        (Paint::line("#aaaaaa", 1.0).dashed("2,2"), "targets"),
    ];
    for (paint, label) in items {
        svg.rect(lx, ly, 16.0, 12.0, paint);
        svg.text(lx + 21.0, ly + 10.5, 11.5, Anchor::Start, false, TEXT, label);
        lx += 21.0 + text_width(label, 11.5) + 22.0;
    }

    for (k, a) in actions.iter().enumerate() {
        let (col, row) = (k % cols, k / cols);
        let px = left + col as f64 * (panel_w + gap);
        let py = top + row as f64 * (panel_h + gap);
        svg.rect(px, py, panel_w, panel_h, Paint::fill("#ffffff", "#bbbbbb", 1.0));
        let (cap1, cap2) = caption(inst, plan, k, a);
        let f1 = 13.5f64.min((panel_w - 12.0) / (cap1.chars().count() as f64 * 0.62));
        let f2 = 11.0f64.min((panel_w - 12.0) / (cap2.chars().count() as f64 * 0.6));
        svg.text(px + 8.0, py + 18.0, f1, Anchor::Start, true, TEXT, &cap1);
        svg.text(px + 8.0, py + 34.0, f2, Anchor::Start, false, "#444444", &cap2);
        let v = View {
            ox: px + pad + t * s,
            oy: py + cap_h + pad + (c.depth + t) * s,
            s,
        };
        draw_container(&mut svg, inst, &v);
        let before = &story.before[k];
        let acting = a.objects();
        // Labels are drawn last, on top of fingers and pusher: (page rect, text, bold, size).
        let mut labels: Vec<Label> = Vec::new();
        // The push distance, boxed on white: (x, y baseline, anchor, text).
        let mut tag: Option<(f64, f64, Anchor, String)> = None;
        // Targets, faint.
        for tg in &p.targets {
            v.draw(&mut svg, &tg.rect, Paint::line("#b5b5b5", 0.8).dashed("2,2"));
        }
        // Objects already in the container, not acting.
        for (i, pos) in before.iter().enumerate() {
            if acting.contains(&i) {
                continue;
            }
            let id = inst.objects[i].id.as_str();
            match pos {
                Pos::Done => {
                    v.draw(&mut svg, &p.targets[i].rect, Paint::fill(DONE_FILL, "#777777", 1.0));
                    labels.push((v.rect(&p.targets[i].rect), id.to_string(), false, 11.0));
                }
                Pos::Released(r) => {
                    let fill = tint(kind_colour(inst, i), 0.8);
                    v.draw(&mut svg, r, Paint::fill(&fill, kind_colour(inst, i), 1.8).dashed("5,3"));
                    labels.push((v.rect(r), id.to_string(), false, 11.0));
                }
                Pos::Table => {}
            }
        }
        match a {
            Action::Place {
                object,
                mode,
                grasp_axis,
                ..
            } => {
                let i = *object;
                let r = release_rect(p, i, mode);
                if let PlaceMode::Indirect { .. } = mode {
                    v.draw(
                        &mut svg,
                        &p.targets[i].rect,
                        Paint::line(kind_colour(inst, i), 1.2).dashed("3,2"),
                    );
                }
                let fill = tint(kind_colour(inst, i), 0.25);
                v.draw(&mut svg, &r, Paint::fill(&fill, ACT_STROKE, 2.5));
                labels.push((v.rect(&r), inst.objects[i].id.clone(), true, 13.0));
                for hi in [false, true] {
                    let f = finger_rect(
                        &r,
                        *grasp_axis,
                        hi,
                        g.release_clearance,
                        g.finger_thickness,
                        g.finger_width,
                    );
                    v.draw(&mut svg, &f, Paint::fill(FINGER_FILL, "none", 0.0));
                }
            }
            Action::Push {
                objects,
                push_dir,
                distance,
                pusher_at,
                ..
            } => {
                for &i in objects {
                    if let Pos::Released(r) = before[i] {
                        v.draw(&mut svg, &r, Paint::line(kind_colour(inst, i), 1.5).dashed("5,3"));
                    }
                    let tr = p.targets[i].rect;
                    let fill = tint(kind_colour(inst, i), 0.25);
                    v.draw(&mut svg, &tr, Paint::fill(&fill, ACT_STROKE, 2.5));
                    labels.push((v.rect(&tr), inst.objects[i].id.clone(), true, 13.0));
                }
                let back = *objects.last().expect("a push moves at least one object");
                let back_rel = match before[back] {
                    Pos::Released(r) => r,
                    _ => p.targets[back].rect.moved(*push_dir, -distance),
                };
                let start = pusher_rect(
                    &back_rel,
                    *push_dir,
                    *pusher_at,
                    g.release_clearance,
                    g.finger_thickness,
                    g.finger_width,
                );
                let end = pusher_rect(
                    &p.targets[back].rect,
                    *push_dir,
                    *pusher_at,
                    0.0,
                    g.finger_thickness,
                    g.finger_width,
                );
                v.draw(&mut svg, &end, Paint::line(FINGER_FILL, 1.2).dashed("3,2"));
                v.draw(&mut svg, &start, Paint::fill(FINGER_FILL, "none", 0.0));
                // Arrow beside the pusher's path over the push distance: from the back object's
                // release face to its target face.
                let axis = push_dir.axis();
                let (a0, a1) = (back_rel.hi(axis), p.targets[back].rect.hi(axis));
                let side = g.finger_width / 2.0 * s + 7.0;
                let label = format!("{} cm", cm(*distance));
                match axis {
                    Axis2::X => {
                        let y = v.y(*pusher_at) - side;
                        svg.arrow(v.x(a0), y, v.x(a1), y, ACT_STROKE, 2.2);
                        tag = Some(((v.x(a0) + v.x(a1)) / 2.0, y - 5.0, Anchor::Middle, label));
                    }
                    Axis2::Y => {
                        let x = v.x(*pusher_at) + side;
                        svg.arrow(x, v.y(a0), x, v.y(a1), ACT_STROKE, 2.2);
                        tag = Some((x + 5.0, (v.y(a0) + v.y(a1)) / 2.0 + 4.0, Anchor::Start, label));
                    }
                }
            }
        }
        for (rect, text, bold, size) in &labels {
            label_in(&mut svg, *rect, &[(text.as_str(), *bold)], *size);
        }
        if let Some((x, y, anchor, text)) = tag {
            let w = text_width(&text, 11.0);
            let x0 = match anchor {
                Anchor::Start => x,
                Anchor::Middle => x - w / 2.0,
                Anchor::End => x - w,
            };
            svg.rect(
                x0 - 2.0,
                y - 10.5,
                w + 4.0,
                14.0,
                Paint::fill("#ffffff", ACT_STROKE, 0.8),
            );
            svg.text(x, y, 11.0, anchor, true, ACT_STROKE, &text);
        }
    }
    svg.finish()
}

// ---------------------------------------------------------------------------------------------
// swept.svg

fn short_action(inst: &Instance, a: &Action) -> String {
    match a {
        Action::Place { object, mode, .. } => format!(
            "place {}{}",
            inst.objects[*object].id,
            match mode {
                PlaceMode::Direct => "",
                PlaceMode::Indirect { .. } => " (ind.)",
            }
        ),
        Action::Push { objects, .. } => {
            let ids: Vec<&str> = objects.iter().map(|&i| inst.objects[i].id.as_str()).collect();
            format!("push {}", ids.join("+"))
        }
    }
}

fn swept_svg(inst: &Instance, plan: &Plan, p: &Placement, actions: &[Action], story: &Story) -> String {
    let n = actions.len();
    let vals: Vec<f64> = story.swept.iter().map(|a| a * 1e4).collect(); // cm²
    let occupied = p.occupied_area() * 1e4;
    let floor = inst.container.width * inst.container.depth * 1e4;
    let (left, right, top) = (84.0, 170.0, 112.0);
    let step_px = (600.0 / n.max(1) as f64).clamp(40.0, 110.0);
    let plot_w = step_px * n.max(1) as f64;
    let plot_h = 300.0;
    let width = (left + plot_w + right).max(720.0);
    // Key to the steps below the axis, wrapped to the page width.
    let key: Vec<String> = actions
        .iter()
        .enumerate()
        .map(|(k, a)| format!("{}: {}", k + 1, short_action(inst, a)))
        .collect();
    let key_size = 12.0;
    let mut key_lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    for item in &key {
        let next = if cur.is_empty() {
            item.clone()
        } else {
            format!("{cur}   {item}")
        };
        if !cur.is_empty() && text_width(&next, key_size) > width - 40.0 {
            key_lines.push(std::mem::take(&mut cur));
            cur = item.clone();
        } else {
            cur = next;
        }
    }
    if !cur.is_empty() {
        key_lines.push(cur);
    }
    let height = top + plot_h + 60.0 + key_lines.len() as f64 * (key_size * 1.5) + 16.0;
    let mut svg = Svg::new(width, height);
    svg.comment(&format!("pushpack swept area of {}", inst.name));
    let ymax_data = vals.iter().copied().fold(occupied, f64::max).max(1e-9);
    let ystep = nice_step(ymax_data * 1.1, 6.0);
    let ymax = (ymax_data * 1.1 / ystep).ceil() * ystep;
    let px = |k: f64| left + k * step_px;
    let py = |a: f64| top + plot_h - a / ymax * plot_h;

    svg.text(
        20.0,
        30.0,
        18.0,
        Anchor::Start,
        true,
        TEXT,
        &format!("Swept area after each step \u{2014} {}", inst.name),
    );
    svg.text(
        20.0,
        52.0,
        13.0,
        Anchor::Start,
        false,
        TEXT,
        "bounding rectangle from C's origin of every footprint so far, release poses included",
    );
    svg.text(
        20.0,
        72.0,
        13.0,
        Anchor::Start,
        false,
        TEXT,
        &format!(
            "final {:.1} cm\u{b2} (plan metric {:.1} cm\u{b2}) \u{b7} occupied area {:.1} cm\u{b2} \u{b7} floor {:.0} cm\u{b2}",
            vals.last().copied().unwrap_or(0.0),
            plan.metrics.swept_area * 1e4,
            occupied,
            floor
        ),
    );
    // Grid and axes.
    let mut y = 0.0;
    while y <= ymax + 1e-9 {
        svg.line(px(0.0), py(y), px(n as f64), py(y), Paint::line("#e3e3e3", 1.0));
        svg.text(
            px(0.0) - 8.0,
            py(y) + 4.0,
            12.0,
            Anchor::End,
            false,
            TEXT,
            &format!("{y:.0}"),
        );
        y += ystep;
    }
    svg.line(px(0.0), py(0.0), px(0.0), py(ymax), Paint::line(TEXT, 1.2));
    svg.line(px(0.0), py(0.0), px(n as f64), py(0.0), Paint::line(TEXT, 1.2));
    svg.text(
        px(0.0),
        py(ymax) - 12.0,
        13.0,
        Anchor::Middle,
        true,
        TEXT,
        "swept area (cm\u{b2})",
    );
    // Occupied area of the final placement, for reference, labelled right of the plot.
    svg.line(
        px(0.0),
        py(occupied),
        px(n as f64),
        py(occupied),
        Paint::line("#59a14f", 1.5).dashed("6,4"),
    );
    svg.text(
        px(n as f64) + 10.0,
        py(occupied) - 2.0,
        11.5,
        Anchor::Start,
        true,
        "#3b7a34",
        "occupied area",
    );
    svg.text(
        px(n as f64) + 10.0,
        py(occupied) + 12.0,
        11.5,
        Anchor::Start,
        false,
        "#3b7a34",
        &format!("of the placement {occupied:.1}"),
    );
    // The step line: the value after step k holds from k to k + 1.
    let mut pts = vec![(px(0.0), py(vals[0]))];
    for k in 1..=n {
        pts.push((px(k as f64), py(vals[k - 1])));
        pts.push((px(k as f64), py(vals[k])));
    }
    svg.polyline(&pts, Paint::line("#4e79a7", 2.5));
    for k in 0..=n {
        svg.circle(px(k as f64), py(vals[k]), 3.5, Paint::fill("#4e79a7", "white", 1.0));
        if k > 0 && (vals[k] - vals[k - 1]).abs() > 1e-9 {
            svg.text(
                px(k as f64) - 6.0,
                py(vals[k]) - 7.0,
                11.0,
                Anchor::End,
                true,
                "#2b4f75",
                &format!("{:.1}", vals[k]),
            );
        }
    }
    // X ticks (step numbers) and the key to the steps.
    for k in 0..=n {
        let x = px(k as f64);
        svg.line(x, py(0.0), x, py(0.0) + 5.0, Paint::line(TEXT, 1.0));
        svg.text(x, py(0.0) + 19.0, 12.0, Anchor::Middle, false, TEXT, &k.to_string());
    }
    svg.text(
        px(n as f64) + 10.0,
        py(0.0) + 19.0,
        13.0,
        Anchor::Start,
        true,
        TEXT,
        "step",
    );
    let mut ky = py(0.0) + 46.0;
    for line in &key_lines {
        svg.text(20.0, ky, key_size, Anchor::Start, false, "#333333", line);
        ky += key_size * 1.5;
    }
    svg.finish()
}

//! The storyboard: one panel per action, with fingers, pusher and captions.

use super::*;

/// Rectangle of a finger next to footprint `r` along `axis` (the `hi` side or the low side),
/// at `gap` from the face, `thick` deep, `width` wide centred on the face.
pub(super) fn finger_rect(r: &Rect, axis: Axis2, hi: bool, gap: f64, thick: f64, width: f64) -> Rect {
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
pub(super) fn pusher_rect(back: &Rect, dir: PushDir, at: f64, gap: f64, thick: f64, width: f64) -> Rect {
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

pub(super) fn caption(inst: &Instance, plan: &Plan, k: usize, a: &Action) -> (String, String) {
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

pub(super) fn storyboard_svg(inst: &Instance, plan: &Plan, p: &Placement, actions: &[Action], story: &Story) -> String {
    let c = &inst.container;
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
    legend(&mut svg, left);

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
        let mut tag: Option<Tag> = None;
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
                draw_place(&mut svg, inst, p, &v, before, *object, mode, *grasp_axis, &mut labels);
            }
            Action::Push {
                objects,
                push_dir,
                distance,
                pusher_at,
                ..
            } => {
                tag = Some(draw_push(
                    &mut svg,
                    inst,
                    p,
                    &v,
                    before,
                    objects,
                    *push_dir,
                    *distance,
                    *pusher_at,
                    &mut labels,
                ));
            }
        }
        for (rect, text, bold, size) in &labels {
            label_in(&mut svg, *rect, &[(text.as_str(), *bold)], *size);
        }
        if let Some(tag) = tag {
            distance_tag(&mut svg, tag);
        }
    }
    svg.finish()
}

/// The line of swatches under the title that says what each fill and outline means.
fn legend(svg: &mut Svg, left: f64) {
    let mut lx = left;
    let ly = 66.0;
    let acting_fill = tint("#f28e2b", 0.25);
    let released_fill = tint("#f28e2b", 0.8);
    let above = tint(FINGER_FILL, 0.6);
    let items: [(Paint, &str); 6] = [
        (Paint::fill(DONE_FILL, "#777777", 1.0), "at target"),
        (
            Paint::fill(&released_fill, "#f28e2b", 1.5).dashed("4,3"),
            "released, waiting for its push",
        ),
        (Paint::fill(&acting_fill, ACT_STROKE, 2.5), "acting object"),
        (Paint::fill(FINGER_FILL, "none", 0.0), "fingers / pusher"),
        (
            Paint::fill(&above, FINGER_FILL, 1.0).dashed("3,2"),
            "fingers above a lower box (heights in cm)",
        ),
        (Paint::line("#aaaaaa", 1.0).dashed("2,2"), "targets"),
    ];
    for (paint, label) in items {
        svg.rect(lx, ly, 16.0, 12.0, paint);
        svg.text(lx + 21.0, ly + 10.5, 11.5, Anchor::Start, false, TEXT, label);
        lx += 21.0 + text_width(label, 11.5) + 22.0;
    }
}

/// A place: the acting object at its release (its target outlined when it is released short of
/// it) and the open fingers. A finger over a box already in the container passes above it (the
/// planner's finger slab allows no less): it is drawn lighter and dashed, with its fingertips'
/// height and the box's, so that a top view does not show it as a collision.
#[allow(clippy::too_many_arguments)]
fn draw_place(
    svg: &mut Svg,
    inst: &Instance,
    p: &Placement,
    v: &View,
    before: &[Pos],
    i: usize,
    mode: &PlaceMode,
    grasp_axis: Axis2,
    labels: &mut Vec<Label>,
) {
    let g = &inst.gripper;
    let r = release_rect(p, i, mode);
    if let PlaceMode::Indirect { .. } = mode {
        v.draw(
            svg,
            &p.targets[i].rect,
            Paint::line(kind_colour(inst, i), 1.2).dashed("3,2"),
        );
    }
    let fill = tint(kind_colour(inst, i), 0.25);
    v.draw(svg, &r, Paint::fill(&fill, ACT_STROKE, 2.5));
    labels.push((v.rect(&r), inst.objects[i].id.clone(), true, 13.0));
    for hi in [false, true] {
        let f = finger_rect(
            &r,
            grasp_axis,
            hi,
            g.release_clearance,
            g.finger_thickness,
            g.finger_width,
        );
        let below: Vec<usize> = (0..inst.n())
            .filter(|&j| j != i)
            .filter(|&j| match &before[j] {
                Pos::Done => p.targets[j].rect.overlaps(&f),
                Pos::Released(r) => r.overlaps(&f),
                Pos::Table => false,
            })
            .collect();
        if below.is_empty() {
            v.draw(svg, &f, Paint::fill(FINGER_FILL, "none", 0.0));
            continue;
        }
        let above = tint(FINGER_FILL, 0.6);
        v.draw(svg, &f, Paint::fill(&above, FINGER_FILL, 1.0).dashed("3,2"));
        let tallest = below.iter().map(|&j| p.targets[j].height).fold(0.0, f64::max);
        let tip = p.targets[i].height - g.grasp_depth;
        let text = format!("\u{2191}{} over {}", cm(tip), cm(tallest));
        let (x, y, _, h) = v.rect(&f);
        let size = 10.0;
        let tx = x.clamp(4.0, f64::MAX);
        svg.rect(
            tx - 1.0,
            y + h + 1.0,
            text_width(&text, size) + 2.0,
            size + 2.0,
            Paint::fill("#ffffff", "none", 0.0),
        );
        svg.text(tx, y + h + size, size, Anchor::Start, false, TEXT, &text);
    }
}

/// The push distance to print: page position, anchor and text.
type Tag = (f64, f64, Anchor, String);

/// A push: the objects at their targets with their releases outlined, the pusher at its start
/// and its end, and an arrow over the push distance; returns the distance's tag, drawn last.
#[allow(clippy::too_many_arguments)]
fn draw_push(
    svg: &mut Svg,
    inst: &Instance,
    p: &Placement,
    v: &View,
    before: &[Pos],
    objects: &[usize],
    push_dir: PushDir,
    distance: f64,
    pusher_at: f64,
    labels: &mut Vec<Label>,
) -> Tag {
    let g = &inst.gripper;
    for &i in objects {
        if let Pos::Released(r) = before[i] {
            v.draw(svg, &r, Paint::line(kind_colour(inst, i), 1.5).dashed("5,3"));
        }
        let tr = p.targets[i].rect;
        let fill = tint(kind_colour(inst, i), 0.25);
        v.draw(svg, &tr, Paint::fill(&fill, ACT_STROKE, 2.5));
        labels.push((v.rect(&tr), inst.objects[i].id.clone(), true, 13.0));
    }
    let back = *objects.last().expect("a push moves at least one object");
    let back_rel = match before[back] {
        Pos::Released(r) => r,
        _ => p.targets[back].rect.moved(push_dir, -distance),
    };
    let start = pusher_rect(
        &back_rel,
        push_dir,
        pusher_at,
        g.release_clearance,
        g.finger_thickness,
        g.finger_width,
    );
    let end = pusher_rect(
        &p.targets[back].rect,
        push_dir,
        pusher_at,
        0.0,
        g.finger_thickness,
        g.finger_width,
    );
    v.draw(svg, &end, Paint::line(FINGER_FILL, 1.2).dashed("3,2"));
    v.draw(svg, &start, Paint::fill(FINGER_FILL, "none", 0.0));
    // Arrow beside the pusher's path over the push distance: from the back object's
    // release face to its target face.
    let axis = push_dir.axis();
    let (a0, a1) = (back_rel.hi(axis), p.targets[back].rect.hi(axis));
    let side = g.finger_width / 2.0 * v.s + 7.0;
    let label = format!("{} cm", cm(distance));
    match axis {
        Axis2::X => {
            let y = v.y(pusher_at) - side;
            svg.arrow(v.x(a0), y, v.x(a1), y, ACT_STROKE, 2.2);
            ((v.x(a0) + v.x(a1)) / 2.0, y - 5.0, Anchor::Middle, label)
        }
        Axis2::Y => {
            let x = v.x(pusher_at) + side;
            svg.arrow(x, v.y(a0), x, v.y(a1), ACT_STROKE, 2.2);
            (x + 5.0, (v.y(a0) + v.y(a1)) / 2.0 + 4.0, Anchor::Start, label)
        }
    }
}

/// The push distance, boxed on white so that it reads over fingers and objects.
fn distance_tag(svg: &mut Svg, (x, y, anchor, text): Tag) {
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

// ---------------------------------------------------------------------------------------------
// swept.svg

pub(super) fn short_action(inst: &Instance, a: &Action) -> String {
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

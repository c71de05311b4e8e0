//! The placement picture: targets in the container, with sizes, orientations and the objective.

use super::*;

pub(super) fn placement_svg(inst: &Instance, solver: &str, status: crate::status::Status, p: &Placement) -> String {
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
    axes(&mut svg, inst, &v);
    legend(&mut svg, inst, legend_x, top, (mx, my));
    svg.finish()
}

/// Centimetre scales along x below the front wall and along y left of the left wall.
fn axes(svg: &mut Svg, inst: &Instance, v: &View) {
    let c = &inst.container;
    let t = c.wall_thickness;
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
}

/// The kinds with their sizes and counts, the occupied area `mx × my` and the walls, from
/// `(legend_x, top)` down.
fn legend(svg: &mut Svg, inst: &Instance, legend_x: f64, top: f64, (mx, my): (f64, f64)) {
    let c = &inst.container;
    let t = c.wall_thickness;
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
}

// ---------------------------------------------------------------------------------------------
// storyboard.svg

//! The swept-area picture: every footprint at every moment, and the bounding rectangle.

use super::*;

pub(super) fn swept_svg(inst: &Instance, plan: &Plan, p: &Placement, actions: &[Action], story: &Story) -> String {
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
    let key_lines = wrap(&key, key_size, width - 40.0);
    let height = top + plot_h + 60.0 + key_lines.len() as f64 * (key_size * 1.5) + 16.0;
    let mut svg = Svg::new(width, height);
    svg.comment(&format!("pushpack swept area of {}", inst.name));
    let ymax_data = vals.iter().copied().fold(occupied, f64::max).max(1e-9);
    let ystep = nice_step(ymax_data * 1.1, 6.0);
    let ymax = (ymax_data * 1.1 / ystep).ceil() * ystep;
    let px = |k: f64| left + k * step_px;
    let py = |a: f64| top + plot_h - a / ymax * plot_h;

    titles(&mut svg, inst, plan, &vals, occupied, floor);
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

/// Items joined by three spaces into lines no wider than `max_width` at font `size`; an item
/// wider than that gets a line of its own.
fn wrap(items: &[String], size: f64, max_width: f64) -> Vec<String> {
    let mut key_lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    for item in items {
        let next = if cur.is_empty() {
            item.clone()
        } else {
            format!("{cur}   {item}")
        };
        if !cur.is_empty() && text_width(&next, size) > max_width {
            key_lines.push(std::mem::take(&mut cur));
            cur = item.clone();
        } else {
            cur = next;
        }
    }
    if !cur.is_empty() {
        key_lines.push(cur);
    }
    key_lines
}

/// The title, what the curve measures, and the final swept, occupied and floor areas (cm²).
fn titles(svg: &mut Svg, inst: &Instance, plan: &Plan, vals: &[f64], occupied: f64, floor: f64) {
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
}

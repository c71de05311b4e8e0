//! SVG plots of benchmark rows (plotters): time vs objects, cactus, ratio distributions to the
//! reference planner, and the paper's Table II as bars.

use super::{ablation_groups, ablation_means, best_per_instance, median, performance_profile, planners};
use crate::bench::row::ResultRow;
use crate::error::{Error, Result};
use plotters::chart::MeshStyle;
use plotters::prelude::*;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

const SIZE: (u32, u32) = (960, 600);
const FONT: &str = "sans-serif";
/// Tableau 10: distinguishable, and readable in grey print.
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn color(k: usize) -> RGBColor {
    COLORS[k % COLORS.len()]
}

/// Line width of series `k` of `n`: earlier series are drawn wider, so a later series lying on
/// top of an earlier one (e.g. two planners with the same placement) leaves it visible.
fn width(k: usize, n: usize) -> u32 {
    2 + 2 * (n.saturating_sub(k + 1).min(3)) as u32
}

fn draw_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    }
}

/// Write every plot the rows support; returns the files written.
pub fn write_plots(rows: &[ResultRow], out: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let all = planners(rows);
    // More series than colours cannot be told apart; the ablation variants then have their
    // own plots (table2_*.svg), and the comparison plots keep the base planners.
    let names: Vec<String> = if all.len() > COLORS.len() {
        all.into_iter().filter(|p| !p.contains("+no-")).collect()
    } else {
        all
    };
    let p = out.join("time_vs_objects.svg");
    time_vs_objects(rows, &names, &p).map_err(|e| draw_err(&p, e))?;
    files.push(p);
    let p = out.join("cactus.svg");
    cactus(rows, &names, &p).map_err(|e| draw_err(&p, e))?;
    files.push(p);
    // A profile needs instances every planner ran; merged batches of different planners may
    // have none, and an empty plot says nothing.
    if names.len() > 1 && names.len() <= 63 && super::performance_profile(rows, &names).instances > 0 {
        let p = out.join("performance_profile.svg");
        profile_plot(rows, &names, &p).map_err(|e| draw_err(&p, e))?;
        files.push(p);
    }
    let p = out.join("ratios.svg");
    ratios(rows, &names, &p).map_err(|e| draw_err(&p, e))?;
    files.push(p);
    if let Some(reference) = optimal_reference(rows, &names) {
        let p = out.join("scatter.svg");
        scatter(rows, &names, &reference, &p).map_err(|e| draw_err(&p, e))?;
        files.push(p);
    }
    for (base, variants) in ablation_groups(rows) {
        let p = out.join(format!("table2_{}.svg", base.replace('+', "_")));
        table2(rows, &base, &variants, &p).map_err(|e| draw_err(&p, e))?;
        files.push(p);
    }
    Ok(files)
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// The look shared by every plot: label sizes and light grid lines.
fn house_style<'m, 'a, 'b, X, Y, DB>(m: &'m mut MeshStyle<'a, 'b, X, Y, DB>) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
    DB: DrawingBackend,
{
    m.label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .light_line_style(RGBColor(242, 242, 242))
        .bold_line_style(RGBColor(205, 205, 205))
}

/// Log-axis range covering `v` with some room, never touching zero.
fn log_range(v: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for x in v.filter(|x| x.is_finite() && *x > 0.0) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return 0.1..10.0;
    }
    // Whole decades: plotters labels a log axis well only from one power of ten to another.
    let lo = 10f64.powf((lo * 0.9).max(1e-3).log10().floor());
    let hi = 10f64.powf((hi * 1.1).log10().ceil()).max(lo * 10.0);
    lo..hi
}

/// Labelled ticks of a log axis over `r` (whole decades): 1, 2 and 5 of every decade. The
/// default key points of plotters' log axis skipped every label below 1 s.
fn log_ticks(r: &std::ops::Range<f64>) -> Vec<f64> {
    let mut out = Vec::new();
    let mut e = r.start.log10().round() as i32;
    while 10f64.powi(e) <= r.end * 1.0001 {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(e);
            if v >= r.start * 0.9999 && v <= r.end * 1.0001 {
                out.push(v);
            }
        }
        e += 1;
    }
    out
}

/// A tick value without float noise: `0.2`, `0.05`, `20`.
fn tick_label(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn draw_legend<
    'a,
    DB: DrawingBackend + 'a,
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    pos: SeriesLabelPosition,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.5))
        .label_font((FONT, 17))
        .draw()?;
    Ok(())
}

fn time_vs_objects(rows: &[ResultRow], names: &[String], path: &Path) -> DrawResult {
    // Median wall time of solved runs per (planner, object count).
    // Object counts are whole: an integer axis ticks whole numbers only (a real axis once
    // printed ticks between them without decimals, "5 6 6 6 7 8 8 8 9").
    let mut pts: Vec<(usize, Vec<(i32, f64)>)> = Vec::new();
    for (k, p) in names.iter().enumerate() {
        let mut by_n: BTreeMap<usize, Vec<f64>> = BTreeMap::new();
        for r in rows.iter().filter(|r| &r.planner == p && r.solved()) {
            by_n.entry(r.objects).or_default().push(r.wall_time_s);
        }
        let v: Vec<(i32, f64)> = by_n
            .into_iter()
            .filter_map(|(n, t)| median(&t).map(|m| (n as i32, m)))
            .collect();
        pts.push((k, v));
    }
    let nmax = rows.iter().map(|r| r.objects).max().unwrap_or(1) as i32;
    let nmin = rows.iter().map(|r| r.objects).min().unwrap_or(0) as i32;
    let yr = log_range(pts.iter().flat_map(|(_, v)| v.iter().map(|p| p.1)));
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Median wall time of solved runs vs number of objects", (FONT, 24))
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(
            (nmin - 1)..(nmax + 1),
            yr.clone().log_scale().with_key_points(log_ticks(&yr)),
        )?;
    house_style(&mut chart.configure_mesh())
        .x_desc("objects")
        .y_desc("median wall time (s, log scale)")
        .y_labels(30)
        .x_labels(12)
        .x_label_formatter(&|x| x.to_string())
        .y_label_formatter(&|y| tick_label(*y))
        .draw()?;
    for (k, v) in pts {
        let (c, w) = (color(k), width(k, names.len()));
        chart
            .draw_series(LineSeries::new(v.clone(), c.stroke_width(w)))?
            .label(names[k].clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(w)));
        chart.draw_series(v.into_iter().map(|p| Circle::new(p, 5, c.filled())))?;
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    root.present()?;
    Ok(())
}

fn cactus(rows: &[ResultRow], names: &[String], path: &Path) -> DrawResult {
    let mut series = Vec::new();
    for p in names {
        let mut t: Vec<f64> = rows
            .iter()
            .filter(|r| &r.planner == p && r.solved())
            .map(|r| r.wall_time_s)
            .collect();
        t.sort_by(f64::total_cmp);
        series.push(t);
    }
    // Ablation variants often run on fewer sets than the base planners, so each legend entry
    // carries its own run count and the axis names one only when they all agree.
    let runs: Vec<usize> = names
        .iter()
        .map(|p| rows.iter().filter(|r| &r.planner == p).count())
        .collect();
    let per_planner = runs.iter().copied().max().unwrap_or(1);
    let same_runs = runs.iter().all(|&n| n == per_planner);
    let yr = log_range(series.iter().flatten().copied());
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("Cactus plot: instances solved within a time per run", (FONT, 24))
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(
            0i32..(per_planner as i32 + 1),
            yr.clone().log_scale().with_key_points(log_ticks(&yr)),
        )?;
    house_style(&mut chart.configure_mesh())
        .x_desc(if same_runs {
            format!("instances solved (of {per_planner} per planner)")
        } else {
            "instances solved (runs per planner in the legend)".to_string()
        })
        .y_desc("wall time per run (s, log scale)")
        .y_labels(30)
        .x_labels(12)
        .x_label_formatter(&|x| x.to_string())
        .y_label_formatter(&|y| tick_label(*y))
        .draw()?;
    for (k, t) in series.into_iter().enumerate() {
        let (c, w) = (color(k), width(k, names.len()));
        let pts: Vec<(i32, f64)> = t.iter().enumerate().map(|(i, &y)| ((i + 1) as i32, y)).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(w)))?
            .label(format!("{} ({} of {} solved)", names[k], pts.len(), runs[k]))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(w)));
        if pts.len() <= 60 {
            chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, c.filled())))?;
        }
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    root.present()?;
    Ok(())
}

/// Dolan–Moré performance profile of wall time ([`super::Profile`]): a step line per planner.
fn profile_plot(rows: &[ResultRow], names: &[String], path: &Path) -> DrawResult {
    let prof = performance_profile(rows, names);
    let top = prof.ratios.iter().flatten().copied().fold(1.0, f64::max);
    let xr = 1.0..10f64.powf((top * 1.5).log10().ceil()).max(10.0);
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "Performance profile: wall time, {} instances every planner ran",
                prof.instances
            ),
            (FONT, 24),
        )
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(xr.clone().log_scale().with_key_points(log_ticks(&xr)), 0f64..1.02)?;
    house_style(&mut chart.configure_mesh())
        .x_desc("τ: time within τ × the fastest planner on the instance (log scale)")
        .y_desc("share of instances")
        .x_label_formatter(&|x| tick_label(*x))
        .y_label_formatter(&|y| format!("{:.0} %", 100.0 * y))
        .draw()?;
    for (k, r) in prof.ratios.iter().enumerate() {
        let (c, w) = (color(k), width(k, names.len()));
        let n = prof.instances.max(1) as f64;
        let mut pts = vec![(1.0, 0.0)];
        for (i, &x) in r.iter().enumerate() {
            pts.push((x, i as f64 / n));
            pts.push((x, (i + 1) as f64 / n));
        }
        pts.push((xr.end, r.len() as f64 / n));
        chart
            .draw_series(LineSeries::new(pts, c.stroke_width(w)))?
            .label(format!("{} ({} of {} solved)", names[k], r.len(), prof.instances))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(w)));
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    root.present()?;
    Ok(())
}

/// The reference for ratios: `milp+astar` (the exact pipeline) when present, else the best
/// solved planner per instance.
fn reference(rows: &[ResultRow], names: &[String]) -> (String, HashMap<String, (f64, f64)>) {
    if names.iter().any(|n| n == "milp+astar") {
        let m = rows
            .iter()
            .filter(|r| r.planner == "milp+astar" && r.solved())
            .filter_map(|r| Some((r.instance.clone(), (r.occupied_area?, r.seq_len? as f64))))
            .collect();
        ("milp+astar".into(), m)
    } else {
        ("the best planner per instance".into(), best_per_instance(rows))
    }
}

fn ratios(rows: &[ResultRow], names: &[String], path: &Path) -> DrawResult {
    let (refname, refv) = reference(rows, names);
    // Per planner (other than the reference): sorted ratios of area and of actions.
    let mut data: Vec<(usize, Vec<f64>, Vec<f64>)> = Vec::new();
    for (k, p) in names.iter().enumerate().filter(|(_, p)| **p != refname) {
        let (mut a, mut l) = (Vec::new(), Vec::new());
        for r in rows.iter().filter(|r| &r.planner == p && r.solved()) {
            if let (Some(&(ra, rl)), Some(x), Some(n)) = (refv.get(&r.instance), r.occupied_area, r.seq_len) {
                a.push(x / ra);
                l.push(n as f64 / rl);
            }
        }
        a.sort_by(f64::total_cmp);
        l.sort_by(f64::total_cmp);
        data.push((k, a, l));
    }
    let root = SVGBackend::new(path, (SIZE.0 * 3 / 2, SIZE.1)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!("Distribution of the ratio to {refname} on the instances both solved"),
        (FONT, 24),
    )?;
    let panels = root.split_evenly((1, 2));
    for (pi, (panel, what)) in panels.iter().zip(["occupied area", "number of actions"]).enumerate() {
        let all: Vec<f64> = data
            .iter()
            .flat_map(|d| if pi == 0 { d.1.clone() } else { d.2.clone() })
            .collect();
        let lo = all.iter().copied().fold(1.0f64, f64::min);
        let hi = all.iter().copied().fold(1.0f64, f64::max);
        let pad = ((hi - lo) * 0.05).max(0.02);
        let mut chart = ChartBuilder::on(panel)
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d((lo - pad)..(hi + pad), 0f64..1.02)?;
        house_style(&mut chart.configure_mesh())
            .x_desc(format!("{what} / {what} of {refname}"))
            .y_desc("share of instances with ratio ≤ x")
            .x_label_formatter(&|x| format!("{x:.2}"))
            .y_label_formatter(&|y| format!("{:.0} %", 100.0 * y))
            .draw()?;
        for (k, a, l) in &data {
            let v = if pi == 0 { a } else { l };
            if v.is_empty() {
                continue;
            }
            // Empirical CDF as a step line.
            let n = v.len() as f64;
            let mut pts = vec![(lo - pad, 0.0)];
            for (i, &x) in v.iter().enumerate() {
                pts.push((x, i as f64 / n));
                pts.push((x, (i + 1) as f64 / n));
            }
            pts.push((hi + pad, 1.0));
            let (c, w) = (color(*k), width(*k, names.len()));
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(w)))?
                .label(format!("{} (n = {})", names[*k], v.len()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(w)));
        }
        if !data.iter().all(|d| d.1.is_empty()) {
            // Area ratios of a heuristic sit far right; above the curves on the left only the
            // best planner's line at 100 % runs.
            let pos = if pi == 0 {
                SeriesLabelPosition::UpperLeft
            } else {
                SeriesLabelPosition::LowerRight
            };
            draw_legend(&mut chart, pos)?;
        }
    }
    root.present()?;
    Ok(())
}

fn table2(rows: &[ResultRow], base: &str, variants: &[String], path: &Path) -> DrawResult {
    // Only sets where some instance was solved by every variant: the others have no bars.
    let means: Vec<_> = ablation_means(rows, variants).into_iter().filter(|m| m.1 > 0).collect();
    let set_names: Vec<String> = means.iter().map(|m| format!("{} ({})", m.0, m.1)).collect();
    let ymax = means
        .iter()
        .flat_map(|(_, _, m)| m.iter().flatten().copied())
        .fold(1.0f64, f64::max);
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("Table II: mean number of actions with ablations of {base}"),
            (FONT, 24),
        )
        .margin(20)
        .x_label_area_size(55)
        .y_label_area_size(70)
        .build_cartesian_2d(0.4f64..(set_names.len() as f64 + 0.6), 0f64..(ymax * 1.25))?;
    let labels = set_names.clone();
    house_style(&mut chart.configure_mesh())
        .disable_x_mesh()
        .x_labels(set_names.len() + 2)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 1.0 && (i as usize) <= labels.len() {
                labels[i as usize - 1].clone()
            } else {
                String::new()
            }
        })
        .x_desc("instance set (number of instances every variant solved)")
        .y_desc("mean number of actions")
        .draw()?;
    let w = 0.8 / variants.len() as f64;
    for (j, v) in variants.iter().enumerate() {
        let c = color(j);
        let bars: Vec<Rectangle<(f64, f64)>> = means
            .iter()
            .enumerate()
            .filter_map(|(i, (_, _, m))| {
                let y = m[j]?;
                let x0 = i as f64 + 1.0 - 0.4 + j as f64 * w;
                Some(Rectangle::new([(x0 + 0.05 * w, 0.0), (x0 + 0.95 * w, y)], c.filled()))
            })
            .collect();
        chart
            .draw_series(bars)?
            .label(v.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 18, y + 6)], c.filled()));
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present()?;
    Ok(())
}

/// The planner with the most proven-optimal runs, when some other planner ran too: the
/// scatter's reference.
fn optimal_reference(rows: &[ResultRow], names: &[String]) -> Option<String> {
    if names.len() < 2 {
        return None;
    }
    names
        .iter()
        .map(|p| (rows.iter().filter(|r| &r.planner == p && r.proven()).count(), p))
        .filter(|(n, _)| *n > 0)
        .max_by_key(|(n, _)| *n)
        .map(|(_, p)| p.clone())
}

/// A planner's index and its (reference, planner) points of area and of actions.
type ScatterSeries = (usize, Vec<(f64, f64)>, Vec<(f64, f64)>);

/// Each planner against the reference, instance by instance, on the instances where the
/// reference's plan is proven optimal and the planner has a verified plan: occupied area and
/// number of actions, with the diagonal (equal) drawn. Points above it are worse.
fn scatter(rows: &[ResultRow], names: &[String], reference: &str, path: &Path) -> DrawResult {
    let refv: HashMap<&str, (f64, f64)> = rows
        .iter()
        .filter(|r| r.planner == reference && r.proven())
        .filter_map(|r| Some((r.instance.as_str(), (r.occupied_area? * 1e4, r.seq_len? as f64))))
        .collect();
    let mut data: Vec<ScatterSeries> = Vec::new();
    for (k, p) in names.iter().enumerate().filter(|(_, p)| p.as_str() != reference) {
        let (mut a, mut l) = (Vec::new(), Vec::new());
        for r in rows.iter().filter(|r| &r.planner == p && r.solved()) {
            if let (Some(&(ra, rl)), Some(x), Some(n)) = (refv.get(r.instance.as_str()), r.occupied_area, r.seq_len) {
                a.push((ra, x * 1e4));
                l.push((rl, n as f64));
            }
        }
        data.push((k, a, l));
    }
    let root = SVGBackend::new(path, (SIZE.0 * 3 / 2, SIZE.1)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "Each planner against the proven-optimal plan of {reference} (area first, then actions), per instance"
        ),
        (FONT, 24),
    )?;
    let panels = root.split_evenly((1, 2));
    for (pi, (panel, what)) in panels
        .iter()
        .zip(["occupied area (cm²)", "number of actions"])
        .enumerate()
    {
        let pts = |d: &ScatterSeries| if pi == 0 { d.1.clone() } else { d.2.clone() };
        let all: Vec<f64> = data
            .iter()
            .flat_map(|d| pts(d).into_iter().flat_map(|(x, y)| [x, y]))
            .collect();
        let lo = all.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = all.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        let pad = ((hi - lo) * 0.06).max(if pi == 0 { 1.0 } else { 0.5 });
        let range = (lo - pad)..(hi + pad);
        let mut chart = ChartBuilder::on(panel)
            .margin(20)
            .x_label_area_size(55)
            .y_label_area_size(70)
            .build_cartesian_2d(range.clone(), range.clone())?;
        house_style(&mut chart.configure_mesh())
            .x_desc(format!("{what}: {reference} (proven optimal)"))
            .y_desc(format!("{what}: other planner"))
            .x_label_formatter(&|x| tick_label(*x))
            .y_label_formatter(&|y| tick_label(*y))
            .draw()?;
        chart.draw_series(LineSeries::new(
            vec![(range.start, range.start), (range.end, range.end)],
            BLACK.mix(0.4).stroke_width(1),
        ))?;
        for d in &data {
            let v = pts(d);
            if v.is_empty() {
                continue;
            }
            let (k, n) = (d.0, v.len());
            let c = color(k);
            // Later planners drawn smaller, so that points on top of each other stay visible.
            let size = 4 + 2 * (names.len().saturating_sub(k + 1).min(3)) as i32;
            chart
                .draw_series(v.into_iter().map(move |p| Circle::new(p, size, c.stroke_width(2))))?
                .label(format!("{} (n = {n})", names[k]))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.stroke_width(2)));
        }
        if data.iter().any(|d| !pts(d).is_empty()) {
            draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        }
    }
    root.present()?;
    Ok(())
}

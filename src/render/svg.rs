//! A tiny SVG writer: shapes with inline attributes only (no style sheets, markers or filters),
//! so that simple renderers such as ImageMagick's internal one draw it like a browser does.

use std::fmt::Write;

/// Escape text for XML content and attribute values.
pub(super) fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// `#rrggbb` blended toward white by `amount` (0 = unchanged, 1 = white). Pre-blended colours
/// instead of `fill-opacity`, which some renderers ignore.
pub(super) fn tint(hex: &str, amount: f64) -> String {
    let h = hex.trim_start_matches('#');
    if h.len() != 6 {
        return hex.to_string();
    }
    let ch = |k: usize| u8::from_str_radix(&h[k..k + 2], 16).unwrap_or(0) as f64;
    let mix = |c: f64| (c + (255.0 - c) * amount.clamp(0.0, 1.0)).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(ch(0)), mix(ch(2)), mix(ch(4)))
}

/// Rough width of a text run in pixels (DejaVu Sans averages ~0.6 em per character).
pub(super) fn text_width(s: &str, size: f64) -> f64 {
    s.chars().count() as f64 * size * 0.6
}

/// Text alignment relative to the anchor point.
#[derive(Clone, Copy)]
pub(super) enum Anchor {
    Start,
    Middle,
    End,
}

/// Fill and stroke of a shape.
#[derive(Clone, Copy)]
pub(super) struct Paint<'a> {
    pub fill: &'a str,
    pub stroke: &'a str,
    pub width: f64,
    /// `stroke-dasharray`, empty for a solid line.
    pub dash: &'a str,
}

impl<'a> Paint<'a> {
    /// Filled, with a thin outline.
    pub fn fill(fill: &'a str, stroke: &'a str, width: f64) -> Paint<'a> {
        Paint {
            fill,
            stroke,
            width,
            dash: "",
        }
    }
    /// Outline only.
    pub fn line(stroke: &'a str, width: f64) -> Paint<'a> {
        Paint {
            fill: "none",
            stroke,
            width,
            dash: "",
        }
    }
    /// Same paint, dashed.
    pub fn dashed(self, dash: &'a str) -> Paint<'a> {
        Paint { dash, ..self }
    }
    fn attrs(&self) -> String {
        let mut s = format!("fill=\"{}\"", self.fill);
        if self.stroke == "none" || self.width <= 0.0 {
            s.push_str(" stroke=\"none\"");
        } else {
            let _ = write!(s, " stroke=\"{}\" stroke-width=\"{:.2}\"", self.stroke, self.width);
            if !self.dash.is_empty() {
                let _ = write!(s, " stroke-dasharray=\"{}\"", self.dash);
            }
        }
        s
    }
}

/// An SVG document being written.
pub(super) struct Svg {
    width: f64,
    height: f64,
    body: String,
}

/// Font used for every text.
const FONT: &str = "DejaVu Sans, Verdana, Arial, sans-serif";

impl Svg {
    /// An empty white page.
    pub fn new(width: f64, height: f64) -> Svg {
        let mut s = Svg {
            width: width.ceil(),
            height: height.ceil(),
            body: String::new(),
        };
        s.rect(0.0, 0.0, s.width, s.height, Paint::fill("white", "none", 0.0));
        s
    }

    /// A comment (kept short; `--` is not allowed inside).
    pub fn comment(&mut self, text: &str) {
        let _ = writeln!(self.body, "<!-- {} -->", esc(text).replace("--", "- -"));
    }

    /// Axis-aligned rectangle with its top-left corner at (x, y).
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, p: Paint) {
        let _ = writeln!(
            self.body,
            "<rect x=\"{x:.2}\" y=\"{y:.2}\" width=\"{:.2}\" height=\"{:.2}\" {}/>",
            w.max(0.0),
            h.max(0.0),
            p.attrs()
        );
    }

    /// Straight line.
    pub fn line(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, p: Paint) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{x1:.2}\" y1=\"{y1:.2}\" x2=\"{x2:.2}\" y2=\"{y2:.2}\" {}/>",
            Paint { fill: "none", ..p }.attrs()
        );
    }

    /// Closed polygon.
    pub fn polygon(&mut self, pts: &[(f64, f64)], p: Paint) {
        let list: Vec<String> = pts.iter().map(|(x, y)| format!("{x:.2},{y:.2}")).collect();
        let _ = writeln!(self.body, "<polygon points=\"{}\" {}/>", list.join(" "), p.attrs());
    }

    /// Open polyline, written as separate segments (some renderers close `<polyline>`).
    pub fn polyline(&mut self, pts: &[(f64, f64)], p: Paint) {
        for w in pts.windows(2) {
            self.line(w[0].0, w[0].1, w[1].0, w[1].1, p);
        }
    }

    /// Circle.
    pub fn circle(&mut self, cx: f64, cy: f64, r: f64, p: Paint) {
        let _ = writeln!(
            self.body,
            "<circle cx=\"{cx:.2}\" cy=\"{cy:.2}\" r=\"{r:.2}\" {}/>",
            p.attrs()
        );
    }

    /// Arrow from (x1, y1) to (x2, y2) with a filled head.
    pub fn arrow(&mut self, x1: f64, y1: f64, x2: f64, y2: f64, colour: &str, width: f64) {
        let (dx, dy) = (x2 - x1, y2 - y1);
        let len = (dx * dx + dy * dy).sqrt();
        if len <= 0.0 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        let head = (4.0 * width + 4.0).min(len * 0.6);
        let (bx, by) = (x2 - ux * head, y2 - uy * head);
        let half = head * 0.45;
        self.line(x1, y1, bx, by, Paint::line(colour, width));
        self.polygon(
            &[
                (x2, y2),
                (bx - uy * half, by + ux * half),
                (bx + uy * half, by - ux * half),
            ],
            Paint::fill(colour, "none", 0.0),
        );
    }

    /// Text with its baseline at `y` (never rotated: some renderers ignore text transforms).
    #[allow(clippy::too_many_arguments)]
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, bold: bool, colour: &str, s: &str) {
        let a = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let _ = writeln!(
            self.body,
            "<text x=\"{x:.2}\" y=\"{y:.2}\" font-family=\"{FONT}\" font-size=\"{size:.1}\" text-anchor=\"{a}\"{} fill=\"{colour}\">{}</text>",
            if bold { " font-weight=\"bold\"" } else { "" },
            esc(s)
        );
    }

    /// The finished document.
    pub fn finish(self) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}

//! PNG and PDF copies of the report's SVG plots (resvg, svg2pdf): one SVG parse, the system's
//! fonts for the text.

use crate::error::{Error, Result};
use resvg::{tiny_skia, usvg};
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// Pixels per SVG unit in the PNG: plots are drawn 960 units wide, so 2 gives 1920 pixels,
/// sharp enough for a slide or a paper figure.
pub const PNG_SCALE: f32 = 2.0;

fn io_err(path: &Path, message: String) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(message),
    }
}

/// The system's fonts, loaded once. An empty database is an error rather than plots without
/// their labels.
fn fonts(path: &Path) -> Result<Arc<usvg::fontdb::Database>> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    let db = FONTS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_system_fonts();
        sans_serif(&mut db);
        Arc::new(db)
    });
    if db.is_empty() {
        return Err(io_err(
            path,
            "no fonts on this system for the plots' text: install one (Debian: fonts-dejavu-core)".into(),
        ));
    }
    Ok(db.clone())
}

/// Point the generic `sans-serif` family (the plots' font) at a sans face this system has:
/// fontdb's default is Arial, which a Linux machine rarely has, and usvg then drops the text
/// without a word.
fn sans_serif(db: &mut usvg::fontdb::Database) {
    use usvg::fontdb::{Family, Query};
    let has = |db: &usvg::fontdb::Database, f: Family| {
        db.query(&Query {
            families: &[f],
            ..Query::default()
        })
        .is_some()
    };
    if has(db, Family::SansSerif) {
        return;
    }
    let preferred = [
        "DejaVu Sans",
        "Liberation Sans",
        "Noto Sans",
        "FreeSans",
        "Helvetica",
        "Arial",
    ];
    let name = preferred
        .iter()
        .find(|n| has(db, Family::Name(n)))
        .map(|n| n.to_string())
        .or_else(|| db.faces().find_map(|f| f.families.first().map(|(n, _)| n.clone())));
    if let Some(n) = name {
        db.set_sans_serif_family(n);
    }
}

/// Write `name.png` and `name.pdf` beside `svg`; returns both paths.
pub fn png_and_pdf(svg: &Path) -> Result<[PathBuf; 2]> {
    let data = std::fs::read(svg).map_err(|e| Error::Io {
        path: svg.to_path_buf(),
        source: e,
    })?;
    let opts = usvg::Options {
        fontdb: fonts(svg)?,
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_data(&data, &opts).map_err(|e| io_err(svg, format!("not a readable SVG: {e}")))?;

    let png = svg.with_extension("png");
    let size = tree
        .size()
        .to_int_size()
        .scale_by(PNG_SCALE)
        .ok_or_else(|| io_err(svg, "empty picture".into()))?;
    let mut pixmap =
        tiny_skia::Pixmap::new(size.width(), size.height()).ok_or_else(|| io_err(svg, "picture too large".into()))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(PNG_SCALE, PNG_SCALE),
        &mut pixmap.as_mut(),
    );
    pixmap.save_png(&png).map_err(|e| io_err(&png, e.to_string()))?;

    let pdf = svg.with_extension("pdf");
    let bytes = svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions::default(),
    )
    .map_err(|e| io_err(&pdf, format!("PDF conversion failed: {e}")))?;
    std::fs::write(&pdf, bytes).map_err(|e| Error::Io {
        path: pdf.clone(),
        source: e,
    })?;
    Ok([png, pdf])
}

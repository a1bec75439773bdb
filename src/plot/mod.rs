//! Small scientific figures (PNG and SVG) on [`plotters`].
//!
//! A [`Figure`] is a grid of [`Panel`]s; a panel has axes (linear or logarithmic), a title, and
//! [`Series`] drawn as lines, dashed lines or points (optionally with vertical error bars), plus
//! shaded x-intervals ([`Panel::band`], e.g. a fit window). Each series with a non-empty label
//! appears in the panel's legend. Colours come from a fixed colour-blind-safe palette (Okabe–Ito)
//! in series order unless set with [`Series::color`].
//!
//! ```no_run
//! use dpdnl::plot::{Figure, Panel, Series};
//! let dt = vec![0.01, 0.02, 0.05];
//! let panel = Panel::new("T(δt)", "δt", "T / T0")
//!     .with(Series::points("measured", dt.clone(), vec![1.01, 1.02, 1.05]).errors(vec![0.004; 3]))
//!     .with(Series::line("eq. 22", dt, vec![1.0102, 1.0204, 1.0526]));
//! Figure::single(panel).save(std::path::Path::new("out/t_vs_dt")).unwrap();
//! // writes out/t_vs_dt.png and out/t_vs_dt.svg
//! ```
//!
//! Text in PNG files is drawn with DejaVu Sans, embedded in the library
//! (`assets/fonts/DejaVuSans.ttf`, licence beside it), so no system font is looked up; SVG files
//! name the font family and leave the text to the viewer. Non-finite points (and, on a log axis,
//! non-positive ones) are skipped. Nothing here panics on data: errors come back as `Err(String)`.

mod axes;
mod draw;
mod legend;
mod model;

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

use draw::draw_panel;
pub use model::{Band, Legend, Mark, Panel, Series};

static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Registers the embedded font once per process as plotters' `sans-serif` family.
fn ensure_font() -> Result<(), String> {
    let mut result = Ok(());
    REGISTER.call_once(|| {
        result = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .map_err(|_| "plot: the embedded font could not be loaded".to_string());
    });
    result
}

/// A grid of panels, filled row by row.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub panels: Vec<Panel>,
    /// Panels per row (at least 1).
    pub columns: usize,
    /// Size of one panel in pixels (PNG) or user units (SVG).
    pub panel_size: (u32, u32),
}

impl Figure {
    /// A figure of one panel.
    pub fn single(panel: Panel) -> Self {
        Self::grid(vec![panel], 1)
    }
    /// A grid of panels with `columns` panels per row.
    pub fn grid(panels: Vec<Panel>, columns: usize) -> Self {
        Figure {
            panels,
            columns: columns.max(1),
            panel_size: (800, 560),
        }
    }

    fn size(&self) -> (u32, u32) {
        let cols = self.columns.min(self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(self.columns).max(1);
        (
            self.panel_size.0 * cols as u32,
            self.panel_size.1 * rows as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let rows = self.panels.len().div_ceil(self.columns).max(1);
        let cols = self.columns.min(self.panels.len().max(1));
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            draw_panel(panel, area)?;
        }
        root.present().map_err(err)
    }

    /// The figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, String> {
        ensure_font()?;
        let mut s = String::new();
        {
            let root = SVGBackend::with_string(&mut s, self.size()).into_drawing_area();
            self.draw(root)?;
        }
        Ok(s)
    }

    /// The figure as PNG bytes (8-bit RGB).
    pub fn to_png(&self) -> Result<Vec<u8>, String> {
        ensure_font()?;
        let (w, h) = self.size();
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
            self.draw(root)?;
        }
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, w, h);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let mut writer = enc.write_header().map_err(|e| format!("plot: PNG: {e}"))?;
            writer
                .write_image_data(&rgb)
                .map_err(|e| format!("plot: PNG: {e}"))?;
        }
        Ok(out)
    }

    /// Writes `PREFIX.png` and `PREFIX.svg` (the parent folder must exist) and returns their
    /// paths.
    pub fn save(&self, prefix: &Path) -> Result<[PathBuf; 2], String> {
        let png_path = with_suffix(prefix, "png");
        let svg_path = with_suffix(prefix, "svg");
        let png = self.to_png()?;
        std::fs::write(&png_path, png)
            .map_err(|e| format!("cannot write {}: {e}", png_path.display()))?;
        let svg = self.to_svg()?;
        std::fs::write(&svg_path, svg)
            .map_err(|e| format!("cannot write {}: {e}", svg_path.display()))?;
        Ok([png_path, svg_path])
    }
}

/// `prefix` with `.ext` appended (not replacing a dot already in the name).
pub fn with_suffix(prefix: &Path, ext: &str) -> PathBuf {
    let mut s = prefix.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("plot: {e:?}")
}

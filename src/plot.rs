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

use plotters::coord::Shift;
use plotters::coord::ranged1d::{
    KeyPointHint, KeyPointWeight, NoDefaultFormatting, Ranged, ValueFormatter,
};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// `x > 0`, false for NaN.
fn is_pos(x: f64) -> bool {
    x > 0.0
}

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");
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

/// Okabe–Ito palette (colour-blind safe), in the order series get them.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(230, 159, 0),   // orange
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(0, 0, 0),       // black
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line through the points in order.
    Line,
    /// A dashed line (e.g. a theory curve or a fit).
    Dashed,
    /// Filled circles.
    Points,
    /// Filled circles joined by a thin line.
    PointsLine,
}

/// One data series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text; an empty label keeps the series out of the legend.
    pub label: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Symmetric vertical error bars (one standard error per point), if any.
    pub y_err: Option<Vec<f64>>,
    pub mark: Mark,
    /// Index into the palette (wraps around); `None` takes the next colour.
    pub color: Option<usize>,
}

impl Series {
    fn new(label: &str, x: Vec<f64>, y: Vec<f64>, mark: Mark) -> Self {
        Series {
            label: label.to_string(),
            x,
            y,
            y_err: None,
            mark,
            color: None,
        }
    }
    /// A solid line.
    pub fn line(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(label, x, y, Mark::Line)
    }
    /// A dashed line.
    pub fn dashed(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(label, x, y, Mark::Dashed)
    }
    /// Points.
    pub fn points(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(label, x, y, Mark::Points)
    }
    /// Points joined by a line.
    pub fn points_line(label: &str, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self::new(label, x, y, Mark::PointsLine)
    }
    /// Adds symmetric vertical error bars.
    pub fn errors(mut self, y_err: Vec<f64>) -> Self {
        self.y_err = Some(y_err);
        self
    }
    /// Fixes the palette colour (index, wraps around).
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }

    /// The drawable points `(x, y, err)`: finite, and positive where the axis is logarithmic.
    fn visible(&self, x_log: bool, y_log: bool) -> Vec<(f64, f64, f64)> {
        let n = self.x.len().min(self.y.len());
        (0..n)
            .filter_map(|i| {
                let (x, y) = (self.x[i], self.y[i]);
                let e = self
                    .y_err
                    .as_ref()
                    .and_then(|e| e.get(i).copied())
                    .filter(|e| e.is_finite())
                    .map_or(0.0, f64::abs);
                let ok =
                    x.is_finite() && y.is_finite() && (!x_log || x > 0.0) && (!y_log || y > 0.0);
                ok.then_some((x, y, e))
            })
            .collect()
    }
}

/// A shaded vertical band over `[lo, hi]` on the x axis (e.g. a fit window).
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    pub lo: f64,
    pub hi: f64,
    /// Legend text; empty for none.
    pub label: String,
}

/// One set of axes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_log: bool,
    pub y_log: bool,
    pub series: Vec<Series>,
    pub bands: Vec<Band>,
    /// Fixed axis ranges; `None` fits the data (with a 5 % margin, in log space on log axes).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// Where the legend goes.
    pub legend: Legend,
}

/// Legend corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    #[default]
    UpperRight,
    UpperLeft,
    LowerLeft,
    LowerRight,
    /// The first of upper right, upper left, lower right and lower left where the legend box
    /// covers no point and no error-bar end; when every corner covers some, the y range is
    /// raised until the points lie below the box, which then goes upper right. For panels of a
    /// few points (a flow curve), where a fixed corner can hide one.
    Auto,
}

/// The corners [`Legend::Auto`] tries, in order.
const AUTO_CORNERS: [Legend; 4] = [
    Legend::UpperRight,
    Legend::UpperLeft,
    Legend::LowerRight,
    Legend::LowerLeft,
];

/// Legend text size, and plotters' defaults for the legend box around it (margin, and the
/// width of the sample mark before the text), which [`legend_box`] must reproduce.
const LEGEND_FONT: u32 = 18;
const LEGEND_MARGIN: i32 = 10;
const LEGEND_MARK: i32 = 30;
/// Clearance between the legend box and a point's centre: the marker radius and a little more.
const LEGEND_CLEAR: i32 = 7;

impl Panel {
    /// An empty panel with a title and axis labels.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Panel {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            ..Panel::default()
        }
    }
    /// Logarithmic x axis.
    pub fn log_x(mut self) -> Self {
        self.x_log = true;
        self
    }
    /// Logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.y_log = true;
        self
    }
    /// Adds a series.
    pub fn with(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    /// Adds a shaded x-interval.
    pub fn band(mut self, lo: f64, hi: f64, label: &str) -> Self {
        self.bands.push(Band {
            lo,
            hi,
            label: label.to_string(),
        });
        self
    }
    /// Puts the legend in another corner.
    pub fn legend(mut self, at: Legend) -> Self {
        self.legend = at;
        self
    }
    /// Fixes the x range.
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    /// Fixes the y range.
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }

    /// Axis ranges from the data, error bars and bands.
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for s in &self.series {
            for (x, y, e) in s.visible(self.x_log, self.y_log) {
                xs.push(x);
                ys.push(y);
                if e > 0.0 {
                    ys.push(y + e);
                    if !self.y_log || y - e > 0.0 {
                        ys.push(y - e);
                    }
                }
            }
        }
        for b in &self.bands {
            for v in [b.lo, b.hi] {
                if v.is_finite() && (!self.x_log || v > 0.0) {
                    xs.push(v);
                }
            }
        }
        let x = self.x_range.unwrap_or_else(|| padded(&xs, self.x_log));
        let y = self.y_range.unwrap_or_else(|| padded(&ys, self.y_log));
        (x, y)
    }
}

/// `[min, max]` of `v` widened by 5 % (multiplicatively on a log axis); a degenerate range is
/// opened around its value.
fn padded(v: &[f64], log: bool) -> (f64, f64) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10(), hi.log10());
        let pad = if b > a { 0.05 * (b - a) } else { 0.5 };
        (10f64.powf(a - pad), 10f64.powf(b + pad))
    } else {
        let span = hi - lo;
        let pad = if span > 0.0 {
            0.05 * span
        } else if lo != 0.0 {
            0.1 * lo.abs()
        } else {
            1.0
        };
        (lo - pad, hi + pad)
    }
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

/// Tick positions of one axis, in drawing coordinates (log10 of the value on a log axis).
struct Ticks {
    major: Vec<f64>,
    minor: Vec<f64>,
}

/// A "nice" step (1, 2, 2.5 or 5 × 10^k) close to `raw`.
fn nice_step(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    let f = raw / p;
    let m = if f < 1.5 {
        1.0
    } else if f < 2.25 {
        2.0
    } else if f < 3.5 {
        2.5
    } else if f < 7.5 {
        5.0
    } else {
        10.0
    };
    m * p
}

/// Multiples of `step` in `[lo, hi]`.
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if !is_pos(step) || !lo.is_finite() || !hi.is_finite() {
        return Vec::new();
    }
    let start = (lo / step).ceil() as i64;
    let end = (hi / step).floor() as i64;
    (start..=end.min(start + 200))
        .map(|k| k as f64 * step)
        .collect()
}

/// Linear ticks over `[lo, hi]`: about six labelled ones, five minor steps between.
fn linear_ticks(lo: f64, hi: f64) -> Ticks {
    let step = nice_step((hi - lo) / 6.0);
    Ticks {
        major: multiples(lo, hi, step),
        minor: multiples(lo, hi, step / 5.0),
    }
}

/// Ticks of a log axis spanning `[10^a, 10^b]`, returned as log10 values: decades (thinned
/// beyond ~8), 1-2-5 within one to three decades, plain linear ticks below half a decade.
fn log_ticks(a: f64, b: f64) -> Ticks {
    let span = b - a;
    let decades: Vec<f64> = multiples(a, b, 1.0);
    let within = |mults: &[f64]| -> Vec<f64> {
        let mut v = Vec::new();
        for k in (a.floor() as i64)..=(b.ceil() as i64) {
            for m in mults {
                let t = k as f64 + m.log10();
                if t >= a - 1e-12 && t <= b + 1e-12 {
                    v.push(t);
                }
            }
        }
        v
    };
    let all = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    if span > 8.0 {
        let step = (span / 8.0).ceil();
        Ticks {
            major: multiples(a, b, step),
            minor: decades,
        }
    } else if span > 3.0 {
        Ticks {
            major: decades,
            minor: within(&all),
        }
    } else if span > 0.5 {
        Ticks {
            major: within(&[1.0, 2.0, 5.0]),
            minor: within(&all),
        }
    } else {
        let (lo, hi) = (10f64.powf(a), 10f64.powf(b));
        let t = linear_ticks(lo, hi);
        let lg = |v: Vec<f64>| v.into_iter().filter(|x| *x > 0.0).map(f64::log10).collect();
        Ticks {
            major: lg(t.major),
            minor: lg(t.minor),
        }
    }
}

/// A tick label: four significant digits at most, trailing zeros removed, exponent form
/// outside [1e-3, 1e5).
fn tick_label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.3e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        return format!("{m}e{e}");
    }
    let digits = (3 - a.log10().floor() as i32).clamp(0, 8) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// One axis in drawing coordinates (log10 of the value on a log axis), with its own ticks.
struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    ticks: Ticks,
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let f = (value - self.lo) / (self.hi - self.lo);
        let p = limit.0 as f64 + f * (limit.1 - limit.0) as f64;
        p.round().clamp(-1e7, 1e7) as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        match hint.weight() {
            KeyPointWeight::Bold => self.ticks.major.clone(),
            KeyPointWeight::Any => self.ticks.minor.clone(),
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, v: &f64) -> String {
        tick_label(if self.log { 10f64.powf(*v) } else { *v })
    }
}

/// An axis value in drawing coordinates: `log10(v)` on a log axis, `v` otherwise.
fn axis_value(log: bool, v: f64) -> f64 {
    if log { v.log10() } else { v }
}

/// The panel's two axes in drawing coordinates, with their ticks; `Err` for an empty or
/// non-finite range.
fn panel_axes(panel: &Panel) -> Result<(Axis, Axis), String> {
    let ((x0, x1), (y0, y1)) = panel.ranges();
    let tx = |v: f64| axis_value(panel.x_log, v);
    let ty = |v: f64| axis_value(panel.y_log, v);
    let (a0, a1) = (tx(x0), tx(x1));
    let (b0, b1) = (ty(y0), ty(y1));
    if !(a0.is_finite() && a1.is_finite() && b0.is_finite() && b1.is_finite())
        || a1 <= a0
        || b1 <= b0
    {
        return Err(format!(
            "plot '{}': empty or invalid axis range x [{x0}, {x1}], y [{y0}, {y1}]",
            panel.title
        ));
    }
    let xt = if panel.x_log {
        log_ticks(a0, a1)
    } else {
        linear_ticks(a0, a1)
    };
    let yt = if panel.y_log {
        log_ticks(b0, b1)
    } else {
        linear_ticks(b0, b1)
    };
    let x_coord = Axis {
        lo: a0,
        hi: a1,
        log: panel.x_log,
        ticks: xt,
    };
    let y_coord = Axis {
        lo: b0,
        hi: b1,
        log: panel.y_log,
        ticks: yt,
    };
    Ok((x_coord, y_coord))
}

/// The chart a panel is drawn on.
type PanelChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// Shade the panel's x-intervals over the full height `[ylo, yhi]`.
fn draw_bands<'a, DB: DrawingBackend + 'a>(
    chart: &mut PanelChart<'a, DB>,
    panel: &Panel,
    ylo: f64,
    yhi: f64,
) -> Result<(), String> {
    let tx = |v: f64| axis_value(panel.x_log, v);
    for b in &panel.bands {
        if !(b.lo.is_finite() && b.hi.is_finite()) || (panel.x_log && (b.lo <= 0.0 || b.hi <= 0.0))
        {
            continue;
        }
        let fill = RGBColor(120, 120, 120).mix(0.15).filled();
        let ann = chart
            .draw_series(std::iter::once(Rectangle::new(
                [(tx(b.lo), ylo), (tx(b.hi), yhi)],
                fill,
            )))
            .map_err(err)?;
        if !b.label.is_empty() {
            ann.label(b.label.as_str())
                .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], fill));
        }
    }
    Ok(())
}

/// Draw series number `k` of `panel` (error bars, then its line or points, then its legend
/// entry); `ylo` is the bottom of the plot, where a log-axis error bar reaching below zero is cut.
fn draw_one_series<'a, DB: DrawingBackend + 'a>(
    chart: &mut PanelChart<'a, DB>,
    panel: &Panel,
    k: usize,
    s: &Series,
    ylo: f64,
) -> Result<(), String> {
    let tx = |v: f64| axis_value(panel.x_log, v);
    let ty = |v: f64| axis_value(panel.y_log, v);
    let color = PALETTE[s.color.unwrap_or(k) % PALETTE.len()];
    let pts: Vec<(f64, f64, f64, f64)> = s
        .visible(panel.x_log, panel.y_log)
        .into_iter()
        .map(|(x, y, e)| {
            // Error bar ends in drawing coordinates; on a log axis a bar reaching below
            // zero is cut at the bottom of the plot.
            let lo = if panel.y_log && y - e <= 0.0 {
                ylo
            } else {
                ty(y - e)
            };
            (tx(x), ty(y), lo, ty(y + e))
        })
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    if s.y_err.is_some() {
        chart
            .draw_series(pts.iter().filter(|p| p.3 > p.2).map(|&(x, y, lo, hi)| {
                ErrorBar::new_vertical(x, lo, y, hi, color.stroke_width(1), 8)
            }))
            .map_err(err)?;
    }
    let line_style = color.stroke_width(2);
    let xy = || pts.iter().map(|p| (p.0, p.1));
    let ann = match s.mark {
        Mark::Line => chart
            .draw_series(LineSeries::new(xy(), line_style))
            .map_err(err)?,
        Mark::Dashed => chart
            .draw_series(DashedLineSeries::new(xy(), 8, 6, line_style))
            .map_err(err)?,
        Mark::Points | Mark::PointsLine => {
            if s.mark == Mark::PointsLine {
                chart
                    .draw_series(LineSeries::new(xy(), color.stroke_width(1)))
                    .map_err(err)?;
            }
            chart
                .draw_series(xy().map(|p| Circle::new(p, 4, color.filled())))
                .map_err(err)?
        }
    };
    if !s.label.is_empty() {
        let mark = s.mark;
        ann.label(s.label.as_str())
            .legend(move |(x, y)| -> DynElement<'static, _, _> {
                match mark {
                    Mark::Points | Mark::PointsLine => {
                        Circle::new((x + 10, y), 4, color.filled()).into_dyn()
                    }
                    _ => PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                        .into_dyn(),
                }
            });
    }
    Ok(())
}

/// Draw the legend box when any series or band has a label.
fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut PanelChart<'a, DB>,
    panel: &Panel,
) -> Result<(), String> {
    let labelled = panel.series.iter().any(|s| !s.label.is_empty())
        || panel.bands.iter().any(|b| !b.label.is_empty());
    if labelled {
        chart
            .configure_series_labels()
            .label_font(("sans-serif", LEGEND_FONT))
            .margin(LEGEND_MARGIN as u32)
            .legend_area_size(LEGEND_MARK as u32)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .position(match panel.legend {
                Legend::UpperRight | Legend::Auto => SeriesLabelPosition::UpperRight,
                Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
                Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
                Legend::LowerRight => SeriesLabelPosition::LowerRight,
            })
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// The legend's lines (bands first, then series: the order plotters lists them in).
fn legend_lines(panel: &Panel) -> Vec<&str> {
    let bands = panel.bands.iter().map(|b| b.label.as_str());
    let series = panel.series.iter().map(|s| s.label.as_str());
    bands.chain(series).filter(|l| !l.is_empty()).collect()
}

/// The legend box at `corner` in pixels of a plotting area of `dim`, `[x0, y0, x1, y1]`, laid out
/// as plotters lays it out (`SeriesLabelStyle::draw`: 5 px from the corner's two edges).
fn legend_box(panel: &Panel, corner: Legend, dim: (u32, u32)) -> Result<[i32; 4], String> {
    let font: TextStyle = ("sans-serif", LEGEND_FONT).into_font().into();
    let mut text = MultiLineText::<_, &str>::new((0, 0), &font);
    for l in legend_lines(panel) {
        text.push_line(l);
    }
    let (w, h) = text.estimate_dimension().map_err(err)?;
    let (w, h) = (w + LEGEND_MARK + 2 * LEGEND_MARGIN, h + 2 * LEGEND_MARGIN);
    let (aw, ah) = (dim.0 as i32, dim.1 as i32);
    let x0 = match corner {
        Legend::UpperLeft | Legend::LowerLeft => 5,
        _ => aw - w - 5,
    };
    let y0 = match corner {
        Legend::LowerLeft | Legend::LowerRight => ah - h - 5,
        _ => 5,
    };
    Ok([x0, y0, x0 + w, y0 + h])
}

/// Every point and error-bar end of the panel in pixels of its plotting area.
fn point_pixels<DB: DrawingBackend>(panel: &Panel, chart: &PanelChart<'_, DB>) -> Vec<(i32, i32)> {
    let (bx, by) = chart.plotting_area().get_base_pixel();
    let tx = |v: f64| axis_value(panel.x_log, v);
    let ty = |v: f64| axis_value(panel.y_log, v);
    let mut out = Vec::new();
    for s in &panel.series {
        for (x, y, e) in s.visible(panel.x_log, panel.y_log) {
            let mut ys = vec![y];
            if e > 0.0 {
                ys.push(y + e);
                if !panel.y_log || y - e > 0.0 {
                    ys.push(y - e);
                }
            }
            for v in ys {
                let (px, py) = chart.backend_coord(&(tx(x), ty(v)));
                out.push((px - bx, py - by));
            }
        }
    }
    out
}

/// How many of `points` the box `[x0, y0, x1, y1]` (widened by [`LEGEND_CLEAR`]) covers.
fn covered(points: &[(i32, i32)], b: [i32; 4]) -> usize {
    let c = LEGEND_CLEAR;
    points
        .iter()
        .filter(|&&(x, y)| x >= b[0] - c && x <= b[2] + c && y >= b[1] - c && y <= b[3] + c)
        .count()
}

/// The chart of a panel on `area` (already inside its margin and title), nothing drawn yet.
fn panel_chart<'a, DB: DrawingBackend>(
    panel: &Panel,
    area: &'a DrawingArea<DB, Shift>,
) -> Result<PanelChart<'a, DB>, String> {
    let (x_coord, y_coord) = panel_axes(panel)?;
    ChartBuilder::on(area)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x_coord, y_coord)
        .map_err(err)
}

/// Resolves [`Legend::Auto`]: the panel to draw (its y range raised if no corner is free) with
/// a fixed corner. Other panels come back unchanged.
fn place_legend<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, Shift>,
) -> Result<Panel, String> {
    let mut p = panel.clone();
    if p.legend != Legend::Auto || legend_lines(&p).is_empty() {
        return Ok(p);
    }
    let chart = panel_chart(&p, area)?;
    let dim = chart.plotting_area().dim_in_pixel();
    let pts = point_pixels(&p, &chart);
    for corner in AUTO_CORNERS {
        if covered(&pts, legend_box(&p, corner, dim)?) == 0 {
            p.legend = corner;
            return Ok(p);
        }
    }
    // No free corner: raise the top of the y range so that the highest point lies
    // LEGEND_CLEAR + 2 px below the box's lower edge (the axis is linear in drawing
    // coordinates, log10 on a log axis, so one proportion does it).
    let b = legend_box(&p, Legend::UpperRight, dim)?;
    let ((_, _), (ylo, yhi)) = p.ranges();
    let (b0, b1) = (axis_value(p.y_log, ylo), axis_value(p.y_log, yhi));
    let top_px = pts.iter().map(|q| q.1).min().unwrap_or(dim.1 as i32);
    let h = dim.1 as f64;
    let room = h - f64::from(b[3] + LEGEND_CLEAR + 2);
    // Fraction of the height the data span now, and the one they may span.
    let now = (h - f64::from(top_px)) / h;
    p.legend = Legend::UpperRight;
    if room > h / 3.0 && now > 0.0 {
        let top = b0 + (b1 - b0) * now; // the highest point, in drawing coordinates
        let new_b1 = b0 + (top - b0) * h / room;
        let new_hi = if p.y_log { 10f64.powf(new_b1) } else { new_b1 };
        if new_hi.is_finite() && new_hi > yhi {
            p.y_range = Some((ylo, new_hi));
        }
    }
    Ok(p)
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), String> {
    // The margin and title as ChartBuilder's `margin(12)` and `caption` would draw them, done
    // here so that the chart can be built twice (for `Legend::Auto`) with one title drawn.
    let area = area
        .margin(12, 12, 12, 12)
        .titled(&panel.title, ("sans-serif", 24))
        .map_err(err)?;
    let placed = place_legend(panel, &area)?;
    let panel = &placed;
    let (nx, ny) = {
        let (x, y) = panel_axes(panel)?;
        (x.ticks.major.len(), y.ticks.major.len())
    };
    let mut chart = panel_chart(panel, &area)?;
    let font = ("sans-serif", 20).into_font();
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .label_style(font.clone())
        .axis_desc_style(font.clone())
        .x_labels(nx.max(2))
        .y_labels(ny.max(2))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()
        .map_err(err)?;

    let (ylo, yhi) = {
        let r = chart.y_range();
        (r.start, r.end)
    };
    draw_bands(&mut chart, panel, ylo, yhi)?;
    for (k, s) in panel.series.iter().enumerate() {
        draw_one_series(&mut chart, panel, k, s, ylo)?;
    }
    draw_legend(&mut chart, panel)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.30000000000000004), "0.3");
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(1000.0), "1000");
        assert_eq!(tick_label(1e-5), "1e-5");
        assert_eq!(tick_label(-0.05), "-0.05");
    }

    /// The legend box `Legend::Auto` settles on, and the points it covers there, for a panel
    /// drawn in a figure's first 800 x 560 panel (the same margin, title and axes as `draw_panel`).
    fn auto_legend(panel: &Panel) -> (Panel, usize) {
        ensure_font().unwrap();
        let mut rgb = vec![0u8; 800 * 560 * 3];
        let root = BitMapBackend::with_buffer(&mut rgb, (800, 560)).into_drawing_area();
        let area = root
            .margin(12, 12, 12, 12)
            .titled(&panel.title, ("sans-serif", 24))
            .unwrap();
        let placed = place_legend(panel, &area).unwrap();
        let chart = panel_chart(&placed, &area).unwrap();
        let dim = chart.plotting_area().dim_in_pixel();
        let pts = point_pixels(&placed, &chart);
        let b = legend_box(&placed, placed.legend, dim).unwrap();
        (placed.clone(), covered(&pts, b))
    }

    fn flow_panel(cross: Vec<f64>) -> Panel {
        let rates = vec![0.3, 1.0, 3.0];
        Panel::new("Viscosity against shear rate", "shear rate", "viscosity")
            .log_x()
            .log_y()
            .legend(Legend::Auto)
            .with(
                Series::points_line("none", rates.clone(), vec![2.16, 2.21, 2.63])
                    .errors(vec![0.04, 0.01, 0.01]),
            )
            .with(Series::points_line("cross", rates, cross).errors(vec![0.03, 0.01, 0.01]))
    }

    #[test]
    fn auto_legend_covers_no_point() {
        // The tutorial's flow curve: the lowest point is lower left, where the fixed corner of
        // `analyze flowcurve` used to put the legend over it.
        let (p, n) = auto_legend(&flow_panel(vec![1.91, 1.94, 2.10]));
        assert_eq!(n, 0, "{:?}", p.legend);
        assert_ne!(p.legend, Legend::LowerLeft);
        assert_eq!(p.y_range, None, "a free corner needs no extra room");
        // Points in all four corners: the range is raised and the box goes above them all.
        let corners = Panel::new("corners", "x", "y")
            .legend(Legend::Auto)
            .with(Series::points(
                "a long legend label",
                vec![0.0, 0.0, 1.0, 1.0, 0.5],
                vec![0.0, 1.0, 0.0, 1.0, 0.5],
            ))
            .with(Series::line("another", vec![0.0, 1.0], vec![0.5, 0.5]));
        let (p, n) = auto_legend(&corners);
        assert_eq!(n, 0);
        assert_eq!(p.legend, Legend::UpperRight);
        let (lo, hi) = p.y_range.expect("raised range");
        assert!(hi > 1.05 && lo < 0.0, "{lo} {hi}");
        // A panel that asks for a corner keeps it: the corner `analyze flowcurve` had, which
        // covers the lowest point of this curve.
        let fixed = flow_panel(vec![1.91, 1.94, 2.10]).legend(Legend::LowerLeft);
        let (p, n) = auto_legend(&fixed);
        assert_eq!(p.legend, Legend::LowerLeft);
        assert!(
            n > 0,
            "the lower-left legend should cover the point at rate 0.3"
        );
        // And every figure still renders.
        assert!(
            Figure::single(corners)
                .to_svg()
                .unwrap()
                .contains("a long legend label")
        );
    }

    #[test]
    fn log_ticks_within_a_decade_are_linear_values() {
        let t = log_ticks(2f64.log10(), 4.6f64.log10());
        let v: Vec<f64> = t.major.iter().map(|x| 10f64.powf(*x)).collect();
        assert!(v.len() >= 3, "{v:?}");
        assert!(v.iter().all(|x| (2.0..=4.6).contains(x)));
    }
}

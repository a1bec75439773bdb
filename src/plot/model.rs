//! The figure model: series, bands, panels and their legend corner, and the axis ranges fitted
//! to the data.

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
    pub(super) fn visible(&self, x_log: bool, y_log: bool) -> Vec<(f64, f64, f64)> {
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
    pub(super) fn ranges(&self) -> ((f64, f64), (f64, f64)) {
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

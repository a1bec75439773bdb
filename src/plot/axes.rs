//! Axes in drawing coordinates (log10 on a log axis): tick positions, tick labels, and the
//! plotters coordinate type built from a panel's ranges, and the chart built on them.

use plotters::coord::ranged1d::{
    KeyPointHint, KeyPointWeight, NoDefaultFormatting, Ranged, ValueFormatter,
};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{Panel, err};

/// `x > 0`, false for NaN.
fn is_pos(x: f64) -> bool {
    x > 0.0
}

/// Tick positions of one axis, in drawing coordinates (log10 of the value on a log axis).
pub(super) struct Ticks {
    pub(super) major: Vec<f64>,
    pub(super) minor: Vec<f64>,
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
pub(super) struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    pub(super) ticks: Ticks,
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
pub(super) fn axis_value(log: bool, v: f64) -> f64 {
    if log { v.log10() } else { v }
}

/// The panel's two axes in drawing coordinates, with their ticks; `Err` for an empty or
/// non-finite range.
pub(super) fn panel_axes(panel: &Panel) -> Result<(Axis, Axis), String> {
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
pub(super) type PanelChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// The chart of a panel on `area` (already inside its margin and title), nothing drawn yet.
pub(super) fn panel_chart<'a, DB: DrawingBackend>(
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

    #[test]
    fn log_ticks_within_a_decade_are_linear_values() {
        let t = log_ticks(2f64.log10(), 4.6f64.log10());
        let v: Vec<f64> = t.major.iter().map(|x| 10f64.powf(*x)).collect();
        assert!(v.len() >= 3, "{v:?}");
        assert!(v.iter().all(|x| (2.0..=4.6).contains(x)));
    }
}

//! Where the legend goes: the box plotters draws at each corner, the points it would cover, and
//! the choice of [`Legend::Auto`].

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axes::{PanelChart, axis_value, panel_chart};
use super::{Legend, Panel, err};

/// The corners [`Legend::Auto`] tries, in order.
const AUTO_CORNERS: [Legend; 4] = [
    Legend::UpperRight,
    Legend::UpperLeft,
    Legend::LowerRight,
    Legend::LowerLeft,
];

/// Legend text size, and plotters' defaults for the legend box around it (margin, and the
/// width of the sample mark before the text), which [`legend_box`] must reproduce.
pub(super) const LEGEND_FONT: u32 = 18;
pub(super) const LEGEND_MARGIN: i32 = 10;
pub(super) const LEGEND_MARK: i32 = 30;
/// Clearance between the legend box and a point's centre: the marker radius and a little more.
const LEGEND_CLEAR: i32 = 7;

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

/// Resolves [`Legend::Auto`]: the panel to draw (its y range raised if no corner is free) with
/// a fixed corner. Other panels come back unchanged.
pub(super) fn place_legend<DB: DrawingBackend>(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::{Figure, Series, ensure_font};

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
}

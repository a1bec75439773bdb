//! Drawing one panel on a plotters area: its mesh, shaded bands, series and legend.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axes::{PanelChart, axis_value, panel_axes, panel_chart};
use super::legend::{LEGEND_FONT, LEGEND_MARGIN, LEGEND_MARK, place_legend};
use super::{Legend, Mark, Panel, Series, err};

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

/// Draw `panel` on `area`: margin, title, mesh, bands, series and legend.
pub(super) fn draw_panel<DB: DrawingBackend>(
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

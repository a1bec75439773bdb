//! How the difference between two runs of one script grows from the first step: round-off
//! amplified by the chaos of the dynamics, or a difference of the models.
//!
//! Two engines that compute the same forces in different summation orders start at round-off
//! (≈ 1e-13 relative) and, like any molecular dynamics, the trajectories separate
//! exponentially at the largest Lyapunov exponent: the difference grows by a constant factor per
//! step until it saturates at the size of the fluctuations. A difference of the models is
//! already there at the first step (different forces), or appears after it faster than that
//! growth can explain (a different integrator, thermostat or boundary).
//!
//! [`timeline`] puts the per-step maxima of a thermo comparison and of dump comparisons
//! ([`StepMax`]) on one axis of elapsed steps, each point tagged with its source; [`merged`]
//! keeps the largest difference per step (the table a user reads). [`classify`] decides
//! ([`Growth`]):
//!
//! - [`Growth::AtStart`]: the first compared step differs by more than [`ROUNDOFF`] (or the
//!   printed resolution, if coarser): a model difference.
//! - [`Growth::Chaotic`]: at most round-off at the first step; then, fitted on one source (the
//!   one with most points: thermo averages and per-atom dump values grow at the same rate but
//!   sit a decade or so apart), from its first point above the round-off floor to the first
//!   step of [`SATURATION`], a line ln(difference) = a + λ t with λ > 0 through at least two
//!   points, which taken back to the first step lies within [`START_SLACK`] of the floor and
//!   (with three or more points) passes within a factor [`LINE_SLACK`] of every point, at a rate
//!   no faster than [`MAX_RATE`]: round-off growing at a roughly constant Lyapunov rate λ.
//! - [`Growth::NotRoundoff`]: round-off at the first step, but no such line, or a growth faster
//!   than [`MAX_RATE`] from round-off to the first point above it: a model difference that acts
//!   after the first step.
//! - [`Growth::Unresolved`]: fewer than two resolvable points before saturation, so the rate
//!   cannot be measured, and the rate that growth from round-off would need is not beyond
//!   [`MAX_RATE`].
//! - [`Growth::RoundoffOnly`]: no difference above the round-off floor, but some above the
//!   tolerance.

use crate::io::lammps_log::StepMax;
use crate::stats::linear_fit;

/// A relative difference at or below this at the first compared step is round-off: the two
/// engines add the same pair forces in different orders (measured ≈ 1e-13 for the forces of
/// the cross-engine golden cases, whose test requires ≤ 1e-12).
pub const ROUNDOFF: f64 = 1e-12;

/// Differences above this have left the exponential regime (they saturate at the size of the
/// fluctuations, O(1e-2–1)); the growth is fitted only below it.
pub const SATURATION: f64 = 1e-3;

/// The fitted growth line, taken back to the first step, may lie up to this factor above the
/// round-off floor: the first steps of a divergence are not yet exponential (a force difference
/// moves the positions by t² before the instability takes over).
pub const START_SLACK: f64 = 100.0;

/// With three or more fitted points, each must lie within this factor of the fitted line: the
/// largest difference over a step's values scatters by about half a decade around the growth
/// (measured on the sheared golden case `in.shear_dot_twostep_2d` run to 1500 steps).
pub const LINE_SLACK: f64 = 30.0;

/// The largest growth rate (of ln(difference), per step) accepted as chaos: ×10 in 4.6 steps.
/// A trajectory that separates that fast is not resolved by its time step; the rates measured
/// for DPD are 0.03–0.05 per step (the sheared golden case `in.shear_dot_twostep_2d` at
/// δt = 0.01, and issue 41's sheared polymer), more than ten times below.
pub const MAX_RATE: f64 = 0.5;

/// One output step of the comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Steps since the first compared step (runs after a `reset_timestep` continue the count).
    pub elapsed: i64,
    /// The step as printed.
    pub step: i64,
    /// The thermo block (run, 0-based) the step is in.
    pub block: usize,
    /// The largest scaled difference there ([`StepMax::max_scaled`]).
    pub diff: f64,
    /// Where it is: the column, with the atom id and the dump for a dump value.
    pub what: String,
    /// 0 for the thermo log, k for the k-th dump.
    pub source: usize,
}

/// The verdict on the growth of the differences. `start` is always the first compared step,
/// `floor` the round-off floor, [`ROUNDOFF`] or the printed resolution if coarser.
#[derive(Debug, Clone, PartialEq)]
pub enum Growth {
    /// No difference above the tolerance.
    Agree,
    /// Already above round-off at the first compared step: a model difference.
    AtStart {
        /// The first compared step.
        start: Point,
        /// The round-off floor.
        floor: f64,
    },
    /// Round-off at the first step, growing exponentially at a roughly constant rate.
    Chaotic {
        /// The first compared step.
        start: Point,
        /// Growth rate of ln(difference) per step (a Lyapunov exponent per step).
        rate: f64,
        /// The fitted points (indices into the timeline).
        fitted: Vec<usize>,
        /// The elapsed step at which the fitted line reaches the tolerance.
        reaches_rtol: Option<f64>,
    },
    /// Round-off at the first step, but not a constant exponential growth from it, or one too
    /// fast to be chaos ([`MAX_RATE`]).
    NotRoundoff {
        /// The first compared step.
        start: Point,
        /// The first point above the floor after it.
        at: Point,
        /// The rate per step that growth from the floor at the first step to `at` needs.
        needed_rate: f64,
        /// The fitted line taken back to the first step (`None` when the difference does not
        /// grow).
        line_start: Option<f64>,
        /// The round-off floor.
        floor: f64,
    },
    /// Too few resolvable points before saturation to fit a growth.
    Unresolved {
        /// The first compared step.
        start: Point,
        /// The first point above the floor.
        at: Point,
        /// The rate per step that growth from the floor at the first step to `at` needs.
        needed_rate: f64,
        /// The round-off floor.
        floor: f64,
    },
    /// Every difference is at round-off or below the printed resolution, yet above the
    /// tolerance: the tolerance is tighter than the comparison can resolve.
    RoundoffOnly {
        /// The point with the largest difference.
        largest: Point,
        /// The round-off floor.
        floor: f64,
    },
}

/// The per-step maxima of a thermo comparison (`thermo`) and of dump comparisons (each with
/// its name) on one axis, sorted by elapsed step (thermo first at a common step).
///
/// Elapsed steps count from the first thermo step; a thermo block whose first step is below
/// the last step of the previous one (`reset_timestep` between runs) continues from where that
/// one ended. A dump frame is placed in the last thermo block whose steps include it (or, past
/// all of them, the last block).
pub fn timeline(thermo: &[StepMax], dumps: &[(String, Vec<StepMax>)]) -> Vec<Point> {
    // (block, first step, last step, offset from step to elapsed), in order.
    let mut blocks: Vec<(usize, i64, i64, i64)> = Vec::new();
    for m in thermo {
        match blocks.last_mut() {
            Some(b) if b.0 == m.block => b.2 = m.step,
            _ => {
                let offset = match blocks.last() {
                    None => -m.step,
                    Some(&(_, _, last, off)) if m.step < last => last + off - m.step,
                    Some(&(_, _, _, off)) => off,
                };
                blocks.push((m.block, m.step, m.step, offset));
            }
        }
    }
    let mut points: Vec<Point> = thermo
        .iter()
        .map(|m| {
            let off = blocks.iter().find(|b| b.0 == m.block).map_or(0, |b| b.3);
            Point {
                elapsed: m.step + off,
                step: m.step,
                block: m.block,
                diff: m.max_scaled,
                what: m.column.clone(),
                source: 0,
            }
        })
        .collect();
    let dump_base = dumps
        .iter()
        .flat_map(|(_, v)| v.first().map(|m| m.step))
        .min()
        .unwrap_or(0);
    for (k, (name, frames)) in dumps.iter().enumerate() {
        for m in frames {
            let (block, off) = blocks
                .iter()
                .rev()
                .find(|b| b.1 <= m.step && m.step <= b.2)
                .or(blocks.last())
                .map_or((0, -dump_base), |b| (b.0, b.3));
            let what = match m.id {
                Some(id) if !m.column.is_empty() => format!("{} (id {id}, {name})", m.column),
                _ => format!("{} ({name})", m.column),
            };
            points.push(Point {
                elapsed: m.step + off,
                step: m.step,
                block,
                diff: m.max_scaled,
                what,
                source: k + 1,
            });
        }
    }
    points.sort_by_key(|p| (p.elapsed, p.source));
    points
}

/// The largest difference per elapsed step of a [`timeline`] (the first source's point where
/// several are equal).
pub fn merged(points: &[Point]) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::new();
    for p in points {
        match out.last_mut() {
            Some(q) if q.elapsed == p.elapsed => {
                if p.diff > q.diff {
                    *q = p.clone();
                }
            }
            _ => out.push(p.clone()),
        }
    }
    out
}

/// Significant digits printed in `text`: the most over the tokens of lines that are all
/// numbers and hold a decimal point or exponent (thermo rows, dump rows); `None` if there are
/// none. `%20.15g` gives 15, LAMMPS's default thermo format 8, a dump's default `%g` 6.
pub fn printed_digits(text: &str) -> Option<usize> {
    let mut best: Option<usize> = None;
    for line in text.lines() {
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.is_empty() || toks.iter().any(|t| t.parse::<f64>().is_err()) {
            continue;
        }
        for t in toks.iter().filter(|t| t.contains(['.', 'e', 'E'])) {
            let mantissa = t
                .trim_start_matches(['-', '+'])
                .split(['e', 'E'])
                .next()
                .unwrap_or("");
            let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
            let n = digits.trim_start_matches('0').len();
            if n > 0 {
                best = Some(best.map_or(n, |b| b.max(n)));
            }
        }
    }
    best
}

/// The relative resolution of numbers printed with `digits` significant digits: one unit in
/// the last place of a number whose first digit is 1, `10^(1 − digits)`.
pub fn resolution(digits: usize) -> f64 {
    10f64.powi(1 - digits as i32)
}

/// Classifies the growth of a [`timeline`] against the tolerance `rtol` (of the merged
/// differences), with the values printed to relative `resolution` (the coarsest of the
/// compared files).
pub fn classify(points: &[Point], rtol: f64, resolution: f64) -> Growth {
    let m = merged(points);
    let Some(start) = m.first() else {
        return Growth::Agree;
    };
    if m.iter().all(|p| p.diff <= rtol) {
        return Growth::Agree;
    }
    let floor = ROUNDOFF.max(resolution);
    if start.diff > floor {
        return Growth::AtStart {
            start: start.clone(),
            floor,
        };
    }
    let t0 = start.elapsed;
    // Up to (not including) the first step of saturation, over every source.
    let end = m
        .iter()
        .find(|p| p.diff > SATURATION)
        .map_or(i64::MAX, |p| p.elapsed);
    // Per source: its points from its first one above the floor, resolvable, before `end`.
    let n_sources = points.iter().map(|p| p.source + 1).max().unwrap_or(0);
    let fit_points = |src: usize| -> Vec<usize> {
        let mine: Vec<usize> = (0..points.len())
            .filter(|&i| {
                let p = &points[i];
                p.source == src && p.elapsed > t0 && p.elapsed < end
            })
            .collect();
        let from = mine
            .iter()
            .position(|&i| points[i].diff > floor)
            .unwrap_or(mine.len());
        mine[from..]
            .iter()
            .copied()
            .filter(|&i| points[i].diff > resolution && points[i].diff.is_finite())
            .collect()
    };
    let fitted = (0..n_sources)
        .map(fit_points)
        .max_by_key(|v| v.len())
        .unwrap_or_default();
    let first_above = m.iter().skip(1).find(|p| p.diff > floor);
    let needed = |at: &Point| (at.diff / floor).ln() / (at.elapsed - t0).max(1) as f64;
    if fitted.len() < 2 {
        return match first_above {
            Some(at) if needed(at) > MAX_RATE => Growth::NotRoundoff {
                start: start.clone(),
                at: at.clone(),
                needed_rate: needed(at),
                line_start: None,
                floor,
            },
            Some(at) => Growth::Unresolved {
                start: start.clone(),
                at: at.clone(),
                needed_rate: needed(at),
                floor,
            },
            None => Growth::RoundoffOnly {
                largest: m
                    .iter()
                    .max_by(|a, b| a.diff.total_cmp(&b.diff))
                    .unwrap_or(start)
                    .clone(),
                floor,
            },
        };
    }
    let x: Vec<f64> = fitted
        .iter()
        .map(|&i| (points[i].elapsed - t0) as f64)
        .collect();
    let y: Vec<f64> = fitted.iter().map(|&i| points[i].diff.ln()).collect();
    let at = first_above.unwrap_or(&points[fitted[0]]).clone();
    let needed_rate = needed(&at);
    let Ok(fit) = linear_fit(&x, &y) else {
        return Growth::NotRoundoff {
            start: start.clone(),
            at,
            needed_rate,
            line_start: None,
            floor,
        };
    };
    let rate = fit.slope;
    let line_start = fit.intercept.exp();
    let on_line = x
        .iter()
        .zip(&y)
        .all(|(xi, yi)| (yi - (fit.intercept + rate * xi)).abs() <= LINE_SLACK.ln());
    if rate > 0.0
        && rate <= MAX_RATE
        && needed_rate <= MAX_RATE
        && line_start <= START_SLACK * floor
        && (fitted.len() < 3 || on_line)
    {
        let reaches = (rtol.ln() - fit.intercept) / rate + t0 as f64;
        Growth::Chaotic {
            start: start.clone(),
            rate,
            fitted,
            reaches_rtol: reaches.is_finite().then_some(reaches),
        }
    } else {
        Growth::NotRoundoff {
            start: start.clone(),
            at,
            needed_rate,
            line_start: (rate > 0.0).then_some(line_start),
            floor,
        }
    }
}

/// Up to `max` of the points for a short table: the first and the last, the first above
/// `rtol`, the fitted ones where they fit, the rest evenly spread.
pub fn table_rows(points: &[Point], rtol: f64, max: usize) -> Vec<usize> {
    let n = points.len();
    if n <= max {
        return (0..n).collect();
    }
    let mut keep: Vec<usize> = vec![0, n - 1];
    if let Some(i) = points.iter().position(|p| p.diff > rtol) {
        keep.push(i);
    }
    let slots = max.saturating_sub(keep.len()).max(1);
    for k in 1..=slots {
        keep.push(k * (n - 1) / (slots + 1));
    }
    keep.sort_unstable();
    keep.dedup();
    keep
}

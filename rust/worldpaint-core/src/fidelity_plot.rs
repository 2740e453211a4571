//! The fidelity plot: a small picture that shows whether what a color paints has the statistics of its example.
//!
//! Left (the whole picture when the color has no slope map): the pair-correlation function of every category
//! with itself — the rdf of eq. (2), 1 everywhere for a Poisson arrangement — as two curves over distance from 0
//! to the color's `max_radius`: the example's (solid) and a candidate's learned with the same bins (dashed, lighter),
//! one hue per category in the order of the palette preview's dots, over a grey line at pcf = 1. Right, when both
//! colors have a slope map: the slope histograms `h_m` of the same categories, example solid and candidate dashed,
//! from 0° to the largest slope either of them reached.
//!
//! The picture holds no text (the wheel links no font library); [`PlotExtent`] gives the ranges of its axes so the
//! interface can label them. Drawn with `plotters` into an RGB buffer, returned as RGBA rows from the top; the same
//! colors give the same pixels.

use crate::error::{Error, Result};
use crate::palette::{Color, Histogram, Interaction, MapSource};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Smallest side of a plot (px).
pub(crate) const MIN_PLOT_SIDE: u32 = 32;
/// Largest side of a plot (px).
pub(crate) const MAX_PLOT_SIDE: u32 = 2048;

const BACKGROUND: RGBColor = RGBColor(20, 23, 20);
const AXIS: RGBColor = RGBColor(150, 150, 150);
const UNIT_LINE: RGBColor = RGBColor(90, 90, 90);
/// The hues of the palette preview's dots (its `HUES`), one per category in priority order.
const HUES: [RGBColor; 6] = [
    RGBColor(38, 140, 38),
    RGBColor(153, 148, 140),
    RGBColor(191, 217, 64),
    RGBColor(204, 115, 51),
    RGBColor(77, 128, 217),
    RGBColor(191, 77, 153),
];

/// A drawn plot: `rgba` holds `height` rows of `width` pixels, the top row first, 4 bytes each.
#[derive(Clone, Debug, PartialEq)]
pub struct FidelityPlot {
    /// Width (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    /// RGBA bytes, rows from the top.
    pub rgba: Vec<u8>,
    /// What the axes span.
    pub extent: PlotExtent,
}

/// The ranges the plot's axes span, for the labels the interface draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotExtent {
    /// The pcf panel's distance axis runs from 0 to this (m).
    pub max_distance: f64,
    /// The pcf panel's value axis runs from 0 to this.
    pub max_pcf: f64,
    /// The slope panel's axis runs from 0 to this (degrees); None when there is no slope panel.
    pub max_slope_degrees: Option<f64>,
}

/// A curve of one category: its points (x, y) and its hue.
struct Curve {
    points: Vec<(f64, f64)>,
    hue: RGBColor,
}

/// Points (bin centre, value) of a histogram, read at `at`'s bin centres (so two histograms share their x).
fn curve_points(hist: &Histogram, at: &Histogram, scale_x: f64) -> Vec<(f64, f64)> {
    (0..at.values.len())
        .map(|k| {
            let x = at.start + (k as f64 + 0.5) * at.bin_width;
            (x * scale_x, hist.value_at(x))
        })
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect()
}

fn self_rdf<'a>(color: &'a Color, category: &str) -> Option<&'a Histogram> {
    color.pairs.iter().find_map(|p| match &p.interaction {
        Interaction::Rdf { hist } if p.category == category && p.other == category => Some(hist),
        _ => None,
    })
}

fn slope_hist<'a>(color: &'a Color, category: &str) -> Option<&'a Histogram> {
    color
        .maps
        .iter()
        .find(|m| m.source == MapSource::Terrain && m.map == "slope" && m.category == category)
        .map(|m| &m.hist)
}

/// The (example, candidate) curves of every category of `reference` that `get` finds a histogram of, with x
/// scaled by `scale_x`; a category the candidate lacks reads 0.
fn curve_pairs(
    reference: &Color,
    candidate: &Color,
    get: impl for<'c> Fn(&'c Color, &str) -> Option<&'c Histogram>,
    scale_x: f64,
) -> Vec<(Curve, Curve)> {
    reference
        .categories
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let name = &c.category.name;
            let ex = get(reference, name)?;
            let empty = Histogram::zeros(ex.start, ex.bin_width, 0);
            let cand = get(candidate, name).unwrap_or(&empty);
            let hue = HUES[i % HUES.len()];
            Some((
                Curve {
                    points: curve_points(ex, ex, scale_x),
                    hue,
                },
                Curve {
                    points: curve_points(cand, ex, scale_x),
                    hue: lighter(hue),
                },
            ))
        })
        .collect()
}

fn lighter(c: RGBColor) -> RGBColor {
    let mix = |v: u8| ((v as u16 + 2 * 235) / 3) as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

/// The largest y of the curves (at least `floor`), rounded up a little so the tops show.
fn top(pairs: &[(Curve, Curve)], floor: f64) -> f64 {
    let max = pairs
        .iter()
        .flat_map(|(a, b)| a.points.iter().chain(&b.points))
        .map(|p| p.1)
        .fold(floor, f64::max);
    max * 1.08
}

/// The largest x where any curve is above zero, plus a bin (at least two bins).
fn right_end(pairs: &[(Curve, Curve)], bin: f64) -> f64 {
    let last = pairs
        .iter()
        .flat_map(|(a, b)| a.points.iter().chain(&b.points))
        .filter(|p| p.1 > 0.0)
        .map(|p| p.0)
        .fold(0.0, f64::max);
    (last + bin).max(2.0 * bin)
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::invalid("the fidelity plot", format!("could not be drawn: {e}"))
}

/// Draws one panel: axes, an optional horizontal line at `unit`, and the curve pairs over `[0, x_max] × [0, y_max]`.
fn panel(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    pairs: &[(Curve, Curve)],
    x_max: f64,
    y_max: f64,
    unit: Option<f64>,
) -> Result<()> {
    let (w, h) = area.dim_in_pixel();
    let margin = (w.min(h) / 14).max(3);
    let mut chart = ChartBuilder::on(area)
        .margin(margin)
        .build_cartesian_2d(0.0..x_max, 0.0..y_max)
        .map_err(plot_error)?;
    let thin = ((w.min(h) / 150).max(1)) as i32;
    let line =
        |color: RGBColor, width: i32| ShapeStyle::from(color).stroke_width(width.max(1) as u32);
    if let Some(u) = unit {
        chart
            .draw_series(LineSeries::new(
                [(0.0, u), (x_max, u)],
                line(UNIT_LINE, thin),
            ))
            .map_err(plot_error)?;
    }
    // axes with five ticks each (the interface writes their ranges)
    let plotting = chart.plotting_area();
    let axes = PathElement::new(
        vec![(0.0, y_max), (0.0, 0.0), (x_max, 0.0)],
        line(AXIS, thin),
    );
    plotting.draw(&axes).map_err(plot_error)?;
    let tick = |x: f64, y: f64, dx: f64, dy: f64| {
        PathElement::new(vec![(x, y), (x + dx, y + dy)], line(AXIS, thin))
    };
    for k in 1..=4 {
        let f = k as f64 / 4.0;
        plotting
            .draw(&tick(f * x_max, 0.0, 0.0, 0.03 * y_max))
            .map_err(plot_error)?;
        plotting
            .draw(&tick(0.0, f * y_max, 0.03 * x_max, 0.0))
            .map_err(plot_error)?;
    }
    let width = 2 * thin;
    let dash = (w.min(h) / 30).max(3);
    for (example, candidate) in pairs {
        chart
            .draw_series(DashedLineSeries::new(
                candidate.points.iter().copied(),
                dash,
                dash * 2 / 3,
                line(candidate.hue, width),
            ))
            .map_err(plot_error)?;
        chart
            .draw_series(LineSeries::new(
                example.points.iter().copied(),
                line(example.hue, width),
            ))
            .map_err(plot_error)?;
    }
    Ok(())
}

/// Draws the fidelity plot of `candidate` against `reference` (see the module documentation), `width` × `height`
/// pixels, each between `MIN_PLOT_SIDE` and `MAX_PLOT_SIDE`. The candidate should be learned with the
/// reference's bins.
pub fn draw_fidelity(
    reference: &Color,
    candidate: &Color,
    width: u32,
    height: u32,
) -> Result<FidelityPlot> {
    for (what, side) in [("width", width), ("height", height)] {
        if !(MIN_PLOT_SIDE..=MAX_PLOT_SIDE).contains(&side) {
            return Err(Error::invalid(
                format!("the plot's {what}"),
                format!("is {side} px; it must lie in {MIN_PLOT_SIDE}..={MAX_PLOT_SIDE}"),
            ));
        }
    }
    let pcf = curve_pairs(reference, candidate, self_rdf, 1.0);
    let max_distance = if reference.max_radius.is_finite() && reference.max_radius > 0.0 {
        reference.max_radius
    } else {
        1.0
    };
    let max_pcf = top(&pcf, 2.0);
    // a candidate painted without the terrain has no slope histogram to show beside the example's
    let has_slope = |c: &Color| {
        c.maps
            .iter()
            .any(|m| m.source == MapSource::Terrain && m.map == "slope")
    };
    let slopes = if has_slope(candidate) {
        curve_pairs(reference, candidate, slope_hist, 1.0f64.to_degrees())
    } else {
        Vec::new()
    };
    let slope_bin = reference
        .maps
        .iter()
        .find(|m| m.map == "slope")
        .map_or(1.0, |m| m.hist.bin_width.to_degrees());
    let slope_extent =
        (!slopes.is_empty()).then(|| (right_end(&slopes, slope_bin), top(&slopes, 0.0)));

    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let backend =
            BitMapBackend::with_buffer_and_format(&mut rgb, (width, height)).map_err(plot_error)?;
        let root = backend.into_drawing_area();
        root.fill(&BACKGROUND).map_err(plot_error)?;
        match slope_extent {
            Some((slope_max, slope_top)) => {
                let split = width * 3 / 5;
                let (left, right) = root.split_horizontally(split);
                panel(&left, &pcf, max_distance, max_pcf, Some(1.0))?;
                panel(&right, &slopes, slope_max, slope_top.max(1e-9), None)?;
            }
            None => panel(&root, &pcf, max_distance, max_pcf, Some(1.0))?,
        }
        root.present().map_err(plot_error)?;
    }
    let rgba = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    Ok(FidelityPlot {
        width,
        height,
        rgba,
        extent: PlotExtent {
            max_distance,
            max_pcf,
            max_slope_degrees: slope_extent.map(|(x, _)| x),
        },
    })
}

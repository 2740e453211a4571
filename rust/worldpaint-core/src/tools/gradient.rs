//! Gradients (Section 5.2 "Gradients"; thesis 6.4.4): "generates object distributions with a distribution
//! interpolated at different levels within the active region". The coefficient `t` of a point is "the projection
//! of `x_i` on the box axis, normalized by its width" (linear) or "the normalized distance to the center"
//! (radial). "To speed up calculation we precompute `N` interpolated distributions": the region is cut into `N`
//! bands of `t` (slabs across the axis, or rings), and band `k` is synthesized with
//! `c_k = interpolate(k / (N − 1), c_start, c_end)` while "taking into account the surrounding objects in `X`
//! and the newly created objects in `{φ_i, i < k}`" (thesis Fig. 6.16). `N` is given, or adapted to the region:
//! one band per interaction radius of the two colors along the gradient, between 2 and `MAX_BANDS`.
//!
//! A *bilinear* gradient ([`bilinear_gradient`]) spreads four colors over the corners of the region's box: `t`
//! becomes `(u, v)`, the box is cut into `N × N` cells, and cell `(i, j)` is painted, in row order and conditioned
//! on the cells before it, with `interpolate(v, interpolate(u, c_sw, c_se), interpolate(u, c_nw, c_ne))` at its
//! centre's `(u, v) = (i, j) / (N − 1)`. `N` is given, or one cell per interaction radius of the four colors
//! across the box's longer side, between 2 and `MAX_BILINEAR_CELLS`.

use super::{Clearing, ToolEdit, Working};
use crate::error::{Error, Result};
use crate::geom::{DVec2, Region};
use crate::interpolate::interpolate_colors;
use crate::palette::Color;
use crate::scene::Scene;
use crate::synthesis::{mix_seed, SynthesisOptions};

/// Largest number of bands of an adaptive gradient.
pub(crate) const MAX_BANDS: usize = 32;
/// Largest number of cells along each side of an adaptive bilinear gradient (each cell interpolates three colors).
pub(crate) const MAX_BILINEAR_CELLS: usize = 8;

/// Where `t` runs from 0 to 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GradientShape {
    /// `t` is the projection on the segment `from → to`, clamped to [0, 1].
    Linear {
        /// Where `t` = 0, world XY (m).
        from: DVec2,
        /// Where `t` = 1, world XY (m).
        to: DVec2,
    },
    /// `t` is the distance to `center` over `radius`, clamped to [0, 1].
    Radial {
        /// Where `t` = 0, world XY (m).
        center: DVec2,
        /// Distance from `center` at which `t` reaches 1 (m).
        radius: f64,
    },
}

impl GradientShape {
    /// The gradient's extent along `t` (m).
    fn length(&self) -> f64 {
        match self {
            GradientShape::Linear { from, to } => from.distance(*to),
            GradientShape::Radial { radius, .. } => *radius,
        }
    }

    /// `t` of a point.
    pub fn t_at(&self, p: DVec2) -> f64 {
        match self {
            GradientShape::Linear { from, to } => {
                let d = *to - *from;
                ((p - *from).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            }
            GradientShape::Radial { center, radius } => (p.distance(*center) / radius).min(1.0),
        }
    }

    /// The part of the plane where `t` lies in band `k` of `n` (the first and last bands extend past 0 and 1).
    fn band(&self, k: usize, n: usize, reach: f64) -> Region {
        let (t0, t1) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
        match *self {
            GradientShape::Linear { from, to } => {
                let d = to - from;
                let len = d.length();
                let (u, v) = (d / len, d.perp() / len);
                let lo = if k == 0 { -reach } else { t0 * len };
                let hi = if k + 1 == n { len + reach } else { t1 * len };
                let at = |s: f64, w: f64| from + u * s + v * w;
                Region::Polygon {
                    points: vec![at(lo, -reach), at(hi, -reach), at(hi, reach), at(lo, reach)],
                }
            }
            GradientShape::Radial { center, radius } => {
                let outer = if k + 1 == n { reach } else { t1 * radius };
                let disc = Region::Circle {
                    center,
                    radius: outer,
                };
                if k == 0 {
                    disc
                } else {
                    Region::Clipped {
                        within: vec![disc],
                        without: vec![Region::Circle {
                            center,
                            radius: t0 * radius,
                        }],
                    }
                }
            }
        }
    }
}

/// Gradient settings.
#[derive(Clone, Debug, Default)]
pub struct GradientOptions {
    /// Number of bands `N` (≥ 2); `None` adapts it to the region.
    pub bands: Option<usize>,
    /// Seed (band `k` uses a seed derived from it and `k`), region of influence, proposals.
    pub synthesis: SynthesisOptions,
}

/// The number of bands a gradient uses (see the module documentation).
pub(crate) fn band_count(
    start: &Color,
    end: &Color,
    shape: &GradientShape,
    bands: Option<usize>,
) -> usize {
    match bands {
        Some(n) => n.clamp(2, 1000),
        None => {
            let w = start.max_radius.max(end.max_radius);
            ((shape.length() / w).round() as usize).clamp(2, MAX_BANDS)
        }
    }
}

/// Paints a gradient from `start` to `end` over `region` (see the module documentation): the region's unlocked
/// content is replaced.
pub fn gradient(
    scene: &Scene,
    start: &Color,
    end: &Color,
    region: &Region,
    shape: GradientShape,
    opts: &GradientOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<ToolEdit> {
    region.validate()?;
    let valid = match shape {
        GradientShape::Linear { from, to } => {
            from.is_finite() && to.is_finite() && from.distance(to) > 0.0
        }
        GradientShape::Radial { center, radius } => {
            center.is_finite() && radius.is_finite() && radius > 0.0
        }
    };
    if !valid {
        return Err(Error::invalid(
            format!("gradient {shape:?}"),
            "has no extent",
        ));
    }
    let n = band_count(start, end, &shape, opts.bands);
    let (lo, hi) = region.bbox();
    let reach = 2.0 * (hi - lo).length() + shape.length();
    let mut work = Working::new(scene);
    work.remove_inside(region);
    for k in 0..n {
        let band = Region::Clipped {
            within: vec![region.clone(), shape.band(k, n, reach)],
            without: Vec::new(),
        };
        if band.validate().is_err() || band.area() <= 0.0 {
            continue;
        }
        let t = k as f64 / (n - 1) as f64;
        let color = interpolate_colors(
            start,
            end,
            t,
            &format!("{} → {} ({t:.2})", start.name, end.name),
        )?;
        let mut band_opts = opts.synthesis.clone();
        band_opts.seed = mix_seed(opts.synthesis.seed, k as u64 + 1);
        work.fill(Clearing::All, &color, &band, &band_opts, &|f| {
            progress((k as f64 + f) / n as f64)
        })?;
    }
    Ok(work.edit())
}

/// Paints a bilinear gradient over `region` (see the module documentation): `corners` are the colors at the
/// corners of its box, south-west, south-east, north-west, north-east (min x min y first); `opts.bands` is the
/// number of cells along each side. The region's unlocked content is replaced.
pub fn bilinear_gradient(
    scene: &Scene,
    corners: [&Color; 4],
    region: &Region,
    opts: &GradientOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<ToolEdit> {
    region.validate()?;
    let (lo, hi) = region.bbox();
    let size = hi - lo;
    let n = match opts.bands {
        Some(n) => n.clamp(2, MAX_BANDS),
        None => {
            let w = corners.iter().map(|c| c.max_radius).fold(0.0, f64::max);
            ((size.max_element() / w).round() as usize).clamp(2, MAX_BILINEAR_CELLS)
        }
    };
    let [sw, se, nw, ne] = corners;
    let mut work = Working::new(scene);
    work.remove_inside(region);
    // cell edges; the outer cells reach past the box, so that nothing of the region is left between them
    let edges = |lo: f64, side: f64| -> Vec<f64> {
        (0..=n)
            .map(|k| match k {
                0 => lo - side,
                k if k == n => lo + 2.0 * side,
                k => lo + side * k as f64 / n as f64,
            })
            .collect()
    };
    let (xs, ys) = (edges(lo.x, size.x), edges(lo.y, size.y));
    for j in 0..n {
        let v = j as f64 / (n - 1) as f64;
        for i in 0..n {
            let cell_index = j * n + i;
            let (min, max) = (DVec2::new(xs[i], ys[j]), DVec2::new(xs[i + 1], ys[j + 1]));
            let cell = Region::Clipped {
                within: vec![region.clone(), Region::Rect { min, max }],
                without: Vec::new(),
            };
            if cell.validate().is_err() || cell.area() <= 0.0 {
                continue;
            }
            let u = i as f64 / (n - 1) as f64;
            let south = interpolate_colors(sw, se, u, "south")?;
            let north = interpolate_colors(nw, ne, u, "north")?;
            let name = format!(
                "{}·{}·{}·{} ({u:.2}, {v:.2})",
                sw.name, se.name, nw.name, ne.name
            );
            let color = interpolate_colors(&south, &north, v, &name)?;
            let mut cell_opts = opts.synthesis.clone();
            cell_opts.seed = mix_seed(opts.synthesis.seed, cell_index as u64 + 1);
            work.fill(Clearing::All, &color, &cell, &cell_opts, &|f| {
                progress((cell_index as f64 + f) / (n * n) as f64)
            })?;
        }
    }
    Ok(work.edit())
}

//! Blur (thesis 6.5.2, Fig. 6.19): "applying a blur to a scene means to smoothly blend point distributions ...
//! first, we perform several analyses in the brush surrounding, then we synthesize new objects within the brush
//! region, and use different colors computed from various interpolations of the analyzed regions".
//!
//! * **Analyses around the region.** `windows` discs (default 8) are placed just outside the region, one per
//!   direction from its centre, each of radius half the region's equivalent radius; each gives the color of the
//!   content it covers (an empty window gives an empty color).
//! * **Interpolated colors inside.** The region is cut into cells (a `cells × cells` grid over its bounding box,
//!   clipped to it). A cell's color is the barycentre of the window colors with weights `1 / d²` (`d` from the
//!   cell's centre to the window's): for the displacement interpolation of [`crate::interpolate`] the barycentre
//!   of several histograms is the weighted mean of their quantile functions, which successive pairwise
//!   interpolations with the running weights give exactly.
//! * **Synthesis.** The region's unlocked content is removed and the cells are painted from the outside in,
//!   each conditioned on the content around the region and on the cells painted before it.

use super::{color_of_region, empty_color, holding_arrangements, Clearing, ToolEdit, Working};
use crate::error::{Error, Result};
use crate::geom::{DVec2, PreparedRegion, Region, RegionQueries};
use crate::interpolate::interpolate_colors;
use crate::palette::Color;
use crate::scene::Scene;
use crate::synthesis::{mix_seed, SynthesisOptions};
use std::f64::consts::TAU;

/// Blur settings.
#[derive(Clone, Debug)]
pub struct BlurOptions {
    /// Analysis windows around the region.
    pub windows: usize,
    /// Cells across the region's bounding box.
    pub cells: usize,
    /// Seed (cell `k` uses a seed derived from it and `k`), region of influence, proposals.
    pub synthesis: SynthesisOptions,
}

impl Default for BlurOptions {
    fn default() -> Self {
        BlurOptions {
            windows: 8,
            cells: 4,
            synthesis: SynthesisOptions::default(),
        }
    }
}

/// One analysis window: where it is and the color it saw (`None`: nothing there).
struct Window {
    center: DVec2,
    color: Option<Color>,
}

/// The analysis windows around `region` (see the module documentation).
fn windows(scene: &Scene, region: &Region, count: usize) -> Result<Vec<Window>> {
    let (lo, hi) = region.bbox();
    let centre = 0.5 * (lo + hi);
    let reach = (hi - lo).length();
    let radius = 0.5 * (region.area() / std::f64::consts::PI).sqrt();
    let outline = PreparedRegion::new(region);
    let mut out = Vec::with_capacity(count);
    for k in 0..count {
        let a = TAU * k as f64 / count as f64;
        let dir = DVec2::new(a.cos(), a.sin());
        // where the ray from the centre leaves the region (bisection between inside and far outside)
        let (mut inside, mut outside) = (0.0, reach);
        for _ in 0..40 {
            let mid = 0.5 * (inside + outside);
            if outline.contains(centre + dir * mid) {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        let center = centre + dir * (outside + radius);
        let disc = Region::Circle { center, radius };
        let color = color_of_region(scene, &disc, &format!("around {k}"))?;
        out.push(Window { center, color });
    }
    Ok(out)
}

/// The barycentre of the windows' colors seen from `p` (weights `1 / d²`).
fn blended_color(windows: &[Window], p: DVec2, like: &Color, cell: &Region) -> Result<Color> {
    let mut acc: Option<Color> = None;
    let mut total = 0.0;
    for w in windows {
        let weight = 1.0 / w.center.distance_squared(p).max(1e-9);
        let color = w.color.clone().unwrap_or_else(|| empty_color(like, cell));
        total += weight;
        acc = Some(match acc {
            None => color,
            Some(a) => interpolate_colors(&a, &color, weight / total, "blur")?,
        });
    }
    acc.ok_or_else(|| Error::invalid("blur", "needs at least one analysis window"))
}

/// Blurs the content of `region` into the colors around it (see the module documentation).
pub fn blur(
    scene: &Scene,
    region: &Region,
    opts: &BlurOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<ToolEdit> {
    region.validate()?;
    if opts.windows == 0 || opts.cells == 0 {
        return Err(Error::invalid(
            "blur",
            format!(
                "needs windows ({}) and cells ({}) above zero",
                opts.windows, opts.cells
            ),
        ));
    }
    let scene = &*holding_arrangements(scene);
    let windows = windows(scene, region, opts.windows)?;
    let mut work = Working::new(scene);
    work.remove_inside(region);
    let Some(like) = windows.iter().find_map(|w| w.color.clone()) else {
        // nothing around: the blurred region is as empty as its surroundings
        return Ok(work.edit());
    };
    let (lo, hi) = region.bbox();
    let n = opts.cells.min(64);
    let size = (hi - lo) / n as f64;
    let centre = 0.5 * (lo + hi);
    let mut cells: Vec<(f64, Region, DVec2)> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = lo + DVec2::new(i as f64, j as f64) * size;
            let rect = Region::Rect {
                min: a,
                max: a + size,
            };
            let cell = Region::Clipped {
                within: vec![region.clone(), rect],
                without: Vec::new(),
            };
            if cell.validate().is_err() || cell.area() <= 0.0 {
                continue;
            }
            let mid = a + 0.5 * size;
            // outside in: the cells farthest from the centre first
            cells.push((-(mid - centre).length(), cell, mid));
        }
    }
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let count = cells.len();
    for (k, (_, cell, mid)) in cells.iter().enumerate() {
        let color = blended_color(&windows, *mid, &like, cell)?;
        let mut cell_opts = opts.synthesis.clone();
        cell_opts.seed = mix_seed(opts.synthesis.seed, k as u64 + 1);
        work.fill(Clearing::All, &color, cell, &cell_opts, &|f| {
            progress((k as f64 + f) / count as f64)
        })?;
    }
    Ok(work.edit())
}

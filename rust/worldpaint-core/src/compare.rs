//! Fidelity metrics between two colors (e.g. an exemplar and a color learned back from a synthesized result):
//! how well synthesis reproduced the statistics of Section 4.1 — density per category, the rdf of eq. (2) per
//! pair, and the map-sampling histograms `h_m` per category and map.
//!
//! * density ratio: candidate density / reference density;
//! * rdf L2: `sqrt(Σ_k (h_ref(k) − h_cand(k))² d_r)`, the L2 norm of the difference of the two rdfs as functions
//!   of distance, read at the reference's bin centres (so both colors should be learned with the same bins:
//!   pass the reference's `max_radius` and `bin_width` in `AnalysisOptions` when learning the candidate);
//! * map TV: total variation distance of the normalized map histograms.
//!
//! The worst of each (the figures a paste and the palette report) leave out the categories the reference holds
//! fewer than `MEASURED_COUNT` of (a village's one church): counting noise alone moves their density by a third
//! and their rdf by more, so they would hide how the rest is reproduced. They are named in `too_few`.
//!
//! The candidate is a color learned back from what a color painted ([`learned_back`]): after a paste, from the
//! pasted region; for the palette's fidelity view, from the color's *self-synthesis* ([`self_synthesis`]), the
//! color painted into its own example region on the same terrain with nothing else around, which says how well
//! the color reproduces its example where the example is.

use crate::analysis::{learn_color, AnalysisOptions};
use crate::error::{Error, Result};
use crate::geom::Region;
use crate::paint::synthesize_with_progress;
use crate::palette::{Color, Histogram, Interaction, MapInteraction, MapSource};
use crate::scene::Scene;
use crate::synthesis::SynthesisOptions;
use crate::terrain::Heightfield;
use serde::Serialize;
use std::sync::Arc;

/// Categories with fewer instances in the reference are left out of the worst figures (see the module documentation).
const MEASURED_COUNT: usize = 10;

/// How close a candidate color is to a reference color.
#[derive(Clone, Debug, Serialize)]
pub struct Fidelity {
    /// Per category: candidate / reference density.
    pub density_ratio: Vec<(String, f64)>,
    /// Per pair: L2 distance between rdf histograms.
    pub rdf_l2: Vec<(String, String, f64)>,
    /// Per category and map: total variation of map histograms.
    pub map_tv: Vec<(String, String, f64)>,
    /// The reference's categories with too few instances to measure, left out of the worst figures.
    pub too_few: Vec<String>,
}

/// L2 distance between two rdfs as functions of distance, at the reference's bin centres.
pub(crate) fn rdf_l2(reference: &Histogram, candidate: &Histogram) -> f64 {
    let w = reference.bin_width;
    (reference
        .values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let x = reference.start + (k as f64 + 0.5) * w;
            (v - candidate.value_at(x)).powi(2)
        })
        .sum::<f64>()
        * w)
        .sqrt()
}

/// The options that learn a color comparable with `color` bin by bin: its bins, its terrain maps and its oriented
/// pairs.
pub(crate) fn same_options(color: &Color) -> AnalysisOptions {
    let mut maps: Vec<String> = terrain_maps(color).map(|m| m.map.clone()).collect();
    maps.sort();
    maps.dedup();
    let oriented = color
        .pairs
        .iter()
        .filter(|p| matches!(p.interaction, Interaction::OrientedRdf { .. }))
        .map(|p| (p.category.clone(), p.other.clone()))
        .collect();
    AnalysisOptions {
        bin_width: Some(color.bin_width),
        max_radius: Some(color.max_radius),
        oriented,
        maps,
        local: false,
    }
}

fn terrain_maps(color: &Color) -> impl Iterator<Item = &MapInteraction> {
    color.maps.iter().filter(|m| m.source == MapSource::Terrain)
}

/// What `color` painted into `region` of `scene`, learned back with the options of `color` (`same_options`) under
/// its name. A region with nothing in it gives a color without categories (compared, its densities read 0).
pub fn learned_back(scene: &Scene, region: &Region, color: &Color) -> Result<Color> {
    match learn_color(scene, region, &color.name, &same_options(color)) {
        Err(Error::EmptyExemplar { .. }) => Ok(color.emptied()),
        other => other,
    }
}

/// The color's self-synthesis, learned back: `color` synthesized with `seed` into its own example region of an
/// otherwise empty scene, on `terrain` when the color has terrain maps and a terrain is given (it should be the one
/// the color was learned on), else without terrain and without the color's terrain maps; then learned back there
/// ([`learned_back`]). The same color, terrain and seed give the same color. `progress` is called with the fraction
/// of the synthesis done; returning false cancels ([`Error::Cancelled`]).
pub fn self_synthesis(
    color: &Color,
    terrain: Option<Arc<Heightfield>>,
    seed: u64,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Color> {
    let terrain = terrain.filter(|_| terrain_maps(color).next().is_some());
    let painted_color = if terrain.is_some() {
        color.clone()
    } else {
        let off: Vec<(String, String)> = terrain_maps(color)
            .map(|m| (m.category.clone(), m.map.clone()))
            .collect();
        color.without_interactions(&off)
    };
    let scene = Scene {
        terrain,
        ..color.blank_scene()
    };
    let opts = SynthesisOptions {
        seed,
        ..Default::default()
    };
    let out = synthesize_with_progress(&scene, &painted_color, &color.region, &opts, progress)?;
    let painted = Scene {
        categories: out.categories,
        instances: out.instances,
        paths: out.paths,
        contours: out.contours,
        terrain: scene.terrain,
    };
    learned_back(&painted, &color.region, &painted_color)
}

/// Compares a candidate color against a reference color (categories and pairs matched by name).
pub fn compare(reference: &Color, candidate: &Color) -> Fidelity {
    let density_ratio = reference
        .categories
        .iter()
        .map(|r| {
            let cand = candidate
                .category(&r.category.name)
                .map_or(0.0, |c| c.density);
            let ratio = if r.density > 0.0 {
                cand / r.density
            } else if cand > 0.0 {
                f64::INFINITY
            } else {
                1.0
            };
            (r.category.name.clone(), ratio)
        })
        .collect();
    let find_rdf = |c: &Color, a: &str, b: &str| {
        c.pairs.iter().find_map(|p| match &p.interaction {
            Interaction::Rdf { hist }
                if (p.category == a && p.other == b) || (p.category == b && p.other == a) =>
            {
                Some(hist.clone())
            }
            _ => None,
        })
    };
    let rdf_l2s = reference
        .pairs
        .iter()
        .filter_map(|p| match &p.interaction {
            Interaction::Rdf { hist } => {
                let cand = find_rdf(candidate, &p.category, &p.other)
                    .unwrap_or_else(|| Histogram::zeros(hist.start, hist.bin_width, 0));
                Some((p.category.clone(), p.other.clone(), rdf_l2(hist, &cand)))
            }
            _ => None,
        })
        .collect();
    let map_tv = reference
        .maps
        .iter()
        .map(|m| {
            let tv = candidate
                .maps
                .iter()
                .find(|c| c.category == m.category && c.map == m.map)
                .map_or(1.0, |c| m.hist.total_variation(&c.hist));
            (m.category.clone(), m.map.clone(), tv)
        })
        .collect();
    let too_few = reference
        .categories
        .iter()
        .filter(|c| c.count < MEASURED_COUNT)
        .map(|c| c.category.name.clone())
        .collect();
    Fidelity {
        density_ratio,
        rdf_l2: rdf_l2s,
        map_tv,
        too_few,
    }
}

impl Fidelity {
    /// Whether `category` has enough instances in the reference to be measured.
    pub fn measured(&self, category: &str) -> bool {
        !self.too_few.iter().any(|c| c == category)
    }

    /// Largest |density ratio − 1| over the measured categories.
    pub fn worst_density_error(&self) -> f64 {
        self.density_ratio
            .iter()
            .filter(|(c, _)| self.measured(c))
            .map(|(_, r)| (r - 1.0).abs())
            .fold(0.0, f64::max)
    }

    /// Largest rdf L2 over the pairs of measured categories (0 when there is none).
    pub fn max_rdf_l2(&self) -> f64 {
        self.rdf_l2
            .iter()
            .filter(|(a, b, _)| self.measured(a) && self.measured(b))
            .map(|(_, _, v)| *v)
            .fold(0.0, f64::max)
    }

    /// Largest map total variation over the measured categories and maps (0 when there is none).
    pub fn max_map_tv(&self) -> f64 {
        self.map_tv
            .iter()
            .filter(|(c, _, _)| self.measured(c))
            .map(|(_, _, v)| *v)
            .fold(0.0, f64::max)
    }

    /// The rdf L2 of one pair (either order), if present.
    pub fn rdf_l2_of(&self, a: &str, b: &str) -> Option<f64> {
        self.rdf_l2
            .iter()
            .find(|(x, y, _)| (x == a && y == b) || (x == b && y == a))
            .map(|(_, _, v)| *v)
    }
}

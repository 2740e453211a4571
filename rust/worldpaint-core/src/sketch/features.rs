//! Terrain features: silhouettes from the camera and ridge lines (thesis §5.3.1). The matching of §5.3.2 picks
//! among them the curve each stroke deforms, and §5.4 reuses the silhouettes to find the ones that protrude.
//!
//! > "When we deform a terrain, we consider two types of features: terrain silhouettes (viewed from the
//! > first-person viewpoint) and terrain ridges."
//!
//! **Silhouettes** ([`silhouettes`]): "a common and naive algorithm for computing the exact silhouettes of a 3D
//! mesh. Silhouette edges are detected by finding all visible edges shared by a front face and a back face in the
//! current perspective view. Neighboring silhouette edges are then linked to form long silhouette curves." The
//! mesh is the heightfield's grid with every cell split along its rising diagonal, from sample `(i, j)` to
//! `(i + 1, j + 1)` (Blender's grids are quads; one consistent split is as good as another). A face is in front
//! when the eye lies above its plane (the vector from the face to the eye, not the view direction: the view is a
//! perspective). Of the edges between a front and a back face, the ones whose back face lies on the eye's side
//! (the far end of a hidden slope, a concave fold) can never be seen and are dropped before any ray is cast; the
//! others are kept if their midpoint lies in the camera frame (with a margin) and the eye sees both their ends
//! (the segment from the eye to a point a hair above each does not pass under the terrain), so that every point of
//! a curve is visible, also where a far ridge comes out from behind a near one. That test is
//! [`Sight::blocked_within`], the march of [`Sight::hit`] (half a cell at a time, leaping over the blocks of 8 × 8
//! cells whose highest sample the ray passes above: a tenfold saving on a rough 512² terrain), but it stops at the
//! sample (a ray cast on to the end of the terrain would pay for the ground behind it; each sample is tested once,
//! whatever the number of its edges) and leaves out the last cell before the sample, where the bilinear surface the march
//! samples and the triangles the edge belongs to differ by up to a quarter of a cell's relief. Edges are linked
//! at shared samples into polylines split where more than two meet; curves shorter than a few cells are dropped.
//!
//! **Ridges** ([`ridges`]), after the profile-recognition and polygon-breaking algorithm (PPA) of Chang, Song
//! and Hsu (1998) as programmed by Chang and Sinha (2007): "The PPA algorithm marks each terrain point that is
//! likely to be on a ridge-line, based on the point height profile. Segments forming a cyclic graph, connect
//! adjacent candidate points. Polygon-breaking repeatedly deletes the lowest segment in a cycle until the graph is
//! acyclic. Finally, the branches on the produced tree structure are reduced and smoothed. [...] we simply connect
//! candidate points as in the original PPA algorithm and replace the polygon-breaking with a minimum spanning
//! forest algorithm." The readings chosen here:
//!
//! * *profile recognition*: a sample's profile in one of the four grid directions (the axes and the diagonals)
//!   runs `ridge_window` samples to each side (7 samples by default, the PPA's usual profile); the direction
//!   counts if each side holds at least one sample lower than the centre (the PPA's deliberately loose test, which
//!   takes a belt a few samples wide around the crest). PPA accepts a sample on one direction; a cone's flank is
//!   then a target everywhere (every flank is higher than its neighbours across the slope), so a sample is a
//!   candidate here when at least `ridge_directions` directions count, two by default;
//! * *target connection*: candidates are joined to their 8 neighbours that are candidates; of two diagonals
//!   crossing in one cell only the higher is kept (the rising one on a tie), so the graph stays planar;
//! * *polygon breaking* by the thesis's spanning forest, taken on the segments' height (the sum of their ends'
//!   heights) so that it keeps the highest segments (a minimum spanning forest of the negated heights):
//!   Kruskal's algorithm on the segments sorted from the highest down (ties in grid order), with a union-find. A
//!   segment is left out exactly when it is the lowest of some cycle, which is where deleting the lowest segment
//!   of a cycle until none is left ends;
//! * *branch reduction*: a branch from a leaf to a branching point shorter than `ridge_prune_length` cells is
//!   removed, shortest first, while its branching point keeps two others, until none is left; the trees that
//!   remain shorter than `min_ridge_length` cells are dropped;
//! * *smoothing*: the polylines between endpoints and branching points get `ridge_smoothing` passes of the
//!   (¼, ½, ¼) Laplacian with their ends fixed (so the network stays connected), then are draped back on the
//!   terrain (bilinear height).
//!
//! Both detectors are parallel over grid rows with rayon and gather the rows in order, so their output does not
//! depend on the number of threads.

mod chains;
mod ridges;
mod silhouettes;

pub use ridges::ridges;
pub use silhouettes::silhouettes;

use super::{Camera, Feature, Sight};
use crate::error::{check, Error, Result};
use crate::terrain::Heightfield;

/// The settings of feature detection. Lengths are in terrain cells, so the defaults suit any terrain scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureOptions {
    /// How far outside the camera frame (in frame widths and heights) silhouette edges are still detected, so that
    /// a curve leaving the frame is not cut at its border. Default 0.05.
    pub frustum_margin: f64,
    /// Silhouette curves shorter than this (cells) are dropped. Default 3.
    pub min_silhouette_length: f64,
    /// Samples on each side of a ridge candidate's profiles (the PPA profile has `2 × window + 1` samples).
    /// Default 3 (7-sample profiles).
    pub ridge_window: usize,
    /// Of the four profile directions, how many must show a lower sample on both sides for a ridge candidate
    /// (1 to 4). Default 2.
    pub ridge_directions: usize,
    /// Branches from a leaf to a branching point shorter than this (cells) are pruned. Default 5.
    pub ridge_prune_length: f64,
    /// Ridge trees shorter than this in all (cells) are dropped. Default 8.
    pub min_ridge_length: f64,
    /// Laplacian smoothing passes on the ridge polylines. Default 3.
    pub ridge_smoothing: usize,
}

impl Default for FeatureOptions {
    fn default() -> Self {
        FeatureOptions {
            frustum_margin: 0.05,
            min_silhouette_length: 3.0,
            ridge_window: 3,
            ridge_directions: 2,
            ridge_prune_length: 5.0,
            min_ridge_length: 8.0,
            ridge_smoothing: 3,
        }
    }
}

impl FeatureOptions {
    /// Checks every setting; the detectors call it first.
    pub fn check(&self) -> Result<()> {
        check::non_negative("feature frustum margin", self.frustum_margin)?;
        check::non_negative("minimum silhouette length", self.min_silhouette_length)?;
        check::non_negative("ridge prune length", self.ridge_prune_length)?;
        check::non_negative("minimum ridge length", self.min_ridge_length)?;
        if self.ridge_window == 0 || self.ridge_window > 64 {
            return Err(Error::invalid(
                "ridge window",
                format!("{} samples is not within 1 to 64", self.ridge_window),
            ));
        }
        if !(1..=4).contains(&self.ridge_directions) {
            return Err(Error::invalid(
                "ridge directions",
                format!("{} is not within 1 to 4", self.ridge_directions),
            ));
        }
        if self.ridge_smoothing > 100 {
            return Err(Error::invalid(
                "ridge smoothing",
                format!("{} passes is more than 100", self.ridge_smoothing),
            ));
        }
        Ok(())
    }
}

/// Checks that a terrain (whose fields are public) is a grid the detectors can walk: at least 2 × 2 samples, as
/// many heights, all finite, a positive cell, and sample ids that fit in 32 bits.
fn check_terrain(t: &Heightfield) -> Result<()> {
    check::positive("terrain cell size", t.cell)?;
    if t.nx < 2 || t.ny < 2 {
        return Err(Error::invalid(
            format!("terrain grid {}x{}", t.nx, t.ny),
            "needs at least 2x2 samples",
        ));
    }
    let samples = t.nx.checked_mul(t.ny).filter(|&n| n < u32::MAX as usize);
    let Some(samples) = samples else {
        return Err(Error::invalid(
            format!("terrain grid {}x{}", t.nx, t.ny),
            "has too many samples",
        ));
    };
    check::same_len("terrain heights", t.heights.len(), samples)?;
    if let Some(k) = t.heights.iter().position(|h| !h.is_finite()) {
        return Err(Error::invalid(
            format!("terrain height {k}"),
            "is not finite",
        ));
    }
    Ok(())
}

/// All the terrain's features for the matching of §5.3.2: its visible silhouettes from `camera`, then its ridges.
pub fn detect_features(
    sight: &Sight,
    camera: &Camera,
    options: &FeatureOptions,
) -> Result<Vec<Feature>> {
    options.check()?;
    let (seen, ridges) = rayon::join(
        || silhouettes(sight, camera, options),
        || ridges(sight.terrain, options),
    );
    let mut all = seen?;
    all.extend(ridges?);
    Ok(all)
}

/// The length of a polyline (m).
fn polyline_length(points: &[glam::DVec3]) -> f64 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sketch::FeatureKind;
    use glam::{DVec2, DVec3};

    #[test]
    fn a_flat_terrain_has_no_features() {
        let terrain =
            Heightfield::new(DVec2::ZERO, 2.0, 64, 48, vec![5.0; 64 * 48]).expect("a grid");
        let sight = Sight::new(&terrain);
        let cam = Camera::looking_at(
            DVec3::new(64.0, -20.0, 12.0),
            DVec3::new(64.0, 48.0, 5.0),
            60.0,
            1.5,
        )
        .expect("a camera");
        let features = detect_features(&sight, &cam, &FeatureOptions::default()).expect("valid");
        assert!(features.is_empty(), "{features:?}");
        // a 2×2 terrain, and a camera looking away
        let tiny =
            Heightfield::new(DVec2::ZERO, 1.0, 2, 2, vec![0.0, 1.0, 2.0, 0.5]).expect("grid");
        let away = Camera::looking_at(
            DVec3::new(0.5, -5.0, 3.0),
            DVec3::new(0.5, -20.0, 3.0),
            60.0,
            1.0,
        )
        .expect("a camera");
        let features =
            detect_features(&Sight::new(&tiny), &away, &FeatureOptions::default()).expect("ok");
        assert!(features.iter().all(|f| f.kind == FeatureKind::Ridge));
    }

    #[test]
    fn a_malformed_terrain_is_refused() {
        let mut terrain = Heightfield::new(DVec2::ZERO, 1.0, 8, 8, vec![0.0; 64]).expect("grid");
        terrain.heights.pop();
        let options = FeatureOptions::default();
        assert!(ridges(&terrain, &options).is_err());
        terrain.heights.push(f32::NAN);
        assert!(ridges(&terrain, &options).is_err());
        terrain.heights[63] = 0.0;
        terrain.ny = 1;
        let cam = Camera::looking_at(DVec3::new(4.0, -5.0, 3.0), DVec3::splat(4.0), 60.0, 1.0)
            .expect("a camera");
        assert!(silhouettes(&Sight::new(&terrain), &cam, &options).is_err());
    }

    #[test]
    fn bad_options_are_refused() {
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, 8, 8, vec![0.0; 64]).expect("grid");
        let cam = Camera::looking_at(DVec3::new(4.0, -5.0, 3.0), DVec3::splat(4.0), 60.0, 1.0)
            .expect("a camera");
        for options in [
            FeatureOptions {
                ridge_window: 0,
                ..Default::default()
            },
            FeatureOptions {
                ridge_directions: 5,
                ..Default::default()
            },
            FeatureOptions {
                ridge_prune_length: f64::NAN,
                ..Default::default()
            },
            FeatureOptions {
                frustum_margin: -1.0,
                ..Default::default()
            },
        ] {
            assert!(detect_features(&Sight::new(&terrain), &cam, &options).is_err());
        }
    }
}

//! Random draws of the synthesis: Gaussian steps of the moves, and a new instance's attributes (rotation, scale,
//! prototype) from its category's learned histograms, its rotation turned to the nearest road where the category
//! faces the roads (see `analysis::facing` for what is learned).
//!
//! Attributes are drawn once the chain has placed the category's points: neither rotation nor scale enters the
//! density the chain samples, so drawing them for the final points alone gives the same result as drawing them at
//! every birth and move, with one nearest-road query per instance instead of one per proposal.

use super::structures::StructuredContent;
use crate::analysis::facing::toward_road;
use crate::graph::SegmentIndex;
use crate::palette::{CategoryColor, Histogram, RoadFacing};
use crate::scene::Instance;
use glam::DVec2;
use rand::Rng;
use std::f64::consts::TAU;
use std::sync::Arc;

/// A standard normal 2D step (Box–Muller).
pub(crate) fn gaussian<R: Rng>(rng: &mut R) -> DVec2 {
    let u1: f64 = rng.random::<f64>().max(1e-300);
    let u2: f64 = rng.random();
    let r = (-2.0 * u1.ln()).sqrt();
    let a = std::f64::consts::TAU * u2;
    DVec2::new(r * a.cos(), r * a.sin())
}

fn draw_from_histogram<R: Rng>(h: &Histogram, rng: &mut R, fallback: f64) -> f64 {
    let total = h.total();
    if !(total > 0.0) || !(h.bin_width > 0.0) {
        return fallback;
    }
    let mut u = rng.random::<f64>() * total;
    for (k, v) in h.values.iter().enumerate() {
        if u < *v {
            return h.start + (k as f64 + rng.random::<f64>()) * h.bin_width;
        }
        u -= v;
    }
    h.start + (h.values.len() as f64 - 0.5) * h.bin_width
}

fn draw_index<R: Rng>(weights: &[f64], rng: &mut R) -> u32 {
    let total: f64 = weights.iter().sum();
    if !(total > 0.0) {
        return 0;
    }
    let mut u = rng.random::<f64>() * total;
    for (k, w) in weights.iter().enumerate() {
        if u < *w {
            return k as u32;
        }
        u -= w;
    }
    (weights.len().saturating_sub(1)) as u32
}

/// A new instance at `p`: rotation, scale and prototype drawn from the category's learned distributions. Near a
/// road (`facing`, for a category that faces the roads) its rotation is the direction towards the nearest point of
/// the roads turned by an angle drawn from the learned angles of its band of distance to them; farther, it is drawn
/// from the world rotation histogram. Its scale is drawn from the size histogram (the log of the
/// scale) when the color has one, else from the scale histogram.
pub(crate) fn attributes<R: Rng>(
    cat: &CategoryColor,
    p: DVec2,
    category: usize,
    facing: Option<&Facing>,
    rng: &mut R,
) -> Instance {
    let rotation = match facing.and_then(|f| f.nearest_road(p)) {
        Some((angles, toward)) => toward.y.atan2(toward.x) + draw_from_histogram(angles, rng, 0.0),
        None => draw_from_histogram(&cat.rotation, rng, 0.0),
    };
    let scale = if cat.size.values.is_empty() {
        draw_from_histogram(&cat.scale, rng, 1.0)
    } else {
        draw_from_histogram(&cat.size, rng, 0.0).exp()
    };
    Instance {
        position: p,
        rotation: rotation.rem_euclid(TAU),
        scale,
        category,
        prototype: draw_index(&cat.prototype_weights, rng),
        locked: false,
        tint: 0.0,
    }
}

/// The roads a category faces, as the synthesis sees them when it paints the category (kept around the region and
/// painted in it), with the learned facing.
pub(crate) struct Facing<'c> {
    learned: &'c RoadFacing,
    roads: Vec<Arc<SegmentIndex>>,
}

impl<'c> Facing<'c> {
    /// The roads category `cat` faces among the graphs the synthesis sees, when it faces roads.
    pub(crate) fn of(cat: &'c CategoryColor, structured: &StructuredContent) -> Option<Self> {
        let learned = cat.facing.as_ref()?;
        Some(Facing {
            learned,
            roads: learned.roads.iter().map(|r| structured.graph(r)).collect(),
        })
    }

    /// The direction from `p` towards the nearest point of the roads within the learned reach, with the learned
    /// angles of its distance band, if there is one.
    fn nearest_road(&self, p: DVec2) -> Option<(&'c Histogram, DVec2)> {
        let mut best: Option<(f64, (DVec2, DVec2))> = None;
        for index in &self.roads {
            let max = best.map_or(self.learned.reach(), |(d, _)| d);
            if let Some(found) = index.nearest(p, max) {
                best = Some(found);
            }
        }
        let (d, segment) = best?;
        Some((self.learned.angles_at(d)?, toward_road(p, segment)))
    }
}

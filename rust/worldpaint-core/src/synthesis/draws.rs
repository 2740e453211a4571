//! Random draws of the synthesis: Gaussian steps of the moves, and a new instance's attributes (rotation, scale,
//! prototype) from its category's learned histograms.

use crate::palette::{CategoryColor, Histogram};
use crate::scene::Instance;
use glam::DVec2;
use rand::Rng;

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

/// A new instance at `p`: rotation, scale and prototype drawn from the category's learned distributions.
pub(crate) fn attributes<R: Rng>(
    cat: &CategoryColor,
    p: DVec2,
    category: usize,
    rng: &mut R,
) -> Instance {
    Instance {
        position: p,
        rotation: draw_from_histogram(&cat.rotation, rng, 0.0).rem_euclid(std::f64::consts::TAU),
        scale: draw_from_histogram(&cat.scale, rng, 1.0),
        category,
        prototype: draw_index(&cat.prototype_weights, rng),
        locked: false,
        tint: 0.0,
    }
}

//! The flow field of the flow-field mode (seed §3 and §5.3): "The flow field tool allows the user to design flow
//! fields by drawing a set of strokes. The system uses the directions of the input strokes as constraints and
//! interpolates 2D space by radial basis functions [EWMZ07]."
//!
//! Readings chosen:
//! - each stroke is sampled at even arc-length steps, `h` = the strokes' total length / 256 (so at most 256
//!   samples, one more per stroke at most), and the direction at a sample is that of the chord from `s − h/2` to
//!   `s + h/2` along the stroke (the stroke's direction as drawn: a stroke drawn the other way turns the field);
//! - the two components of the unit direction are interpolated separately by a thin-plate spline
//!   `φ(r) = r² ln r` with a linear polynomial (the constant alone when every sample lies on one line, where the
//!   linear part is not determined), in coordinates centred on the samples and divided by their extent, so the
//!   fit does not depend on the unit of length. The thin-plate spline has no width to choose, is the smoothest
//!   interpolant (least bending energy) and goes on linearly away from the strokes instead of falling to zero as
//!   a Gaussian does, so the field is defined over the whole region;
//! - a ridge of 1e-6 on the kernel's diagonal keeps the system solvable when two strokes cross with different
//!   directions (the spline then smooths instead of interpolating exactly there);
//! - the interpolant is normalised; where it vanishes (between opposite strokes) the nearest sample's direction is
//!   taken.
//!
//! The system has at most 256 + (number of strokes) + 3 unknowns: a dense LU with full pivoting (`faer`, already
//! the relaxation's solver) solves it in well under a millisecond and is robust to the indefinite saddle-point form
//! of the spline's system.

use faer::prelude::Solve;
use faer::Mat;
use glam::DVec2;

use crate::error::{Error, Result};

/// The samples of all strokes together, at most.
const SAMPLES: usize = 256;
/// The most strokes one flow field takes.
pub(super) const MAX_FLOW_CURVES: usize = 256;
/// The ridge on the kernel's diagonal.
const RIDGE: f64 = 1e-6;

/// A direction field interpolated from drawn strokes by a thin-plate spline.
#[derive(Clone, Debug, PartialEq)]
pub struct FlowField {
    center: DVec2,
    scale: f64,
    /// Sample positions, normalised.
    points: Vec<DVec2>,
    /// Unit directions at the samples (world).
    directions: Vec<DVec2>,
    /// Kernel weights per sample, per component.
    weights: Vec<DVec2>,
    /// The polynomial part: constant, x, y (normalised coordinates), per component.
    polynomial: [DVec2; 3],
}

impl FlowField {
    /// Fits the field to the directions of `curves` (polylines, world XY). Errors when there is no curve of
    /// positive length, a point is not finite, or there are more than `MAX_FLOW_CURVES` curves.
    pub fn from_curves(curves: &[Vec<DVec2>]) -> Result<FlowField> {
        crate::error::check::at_most_items("flow curves", curves.len(), MAX_FLOW_CURVES)?;
        let mut polylines: Vec<Vec<DVec2>> = Vec::new();
        for (k, curve) in curves.iter().enumerate() {
            crate::error::check::at_most_items(
                "a flow curve's points",
                curve.len(),
                crate::limits::MAX_REGION_VERTICES as usize,
            )?;
            if curve.iter().any(|p| !p.is_finite()) {
                return Err(Error::invalid(
                    "flow curves",
                    format!("curve {k} has a point that is not finite"),
                ));
            }
            let mut line: Vec<DVec2> = Vec::with_capacity(curve.len());
            for &p in curve {
                if line.last() != Some(&p) {
                    line.push(p);
                }
            }
            if line.len() >= 2 {
                polylines.push(line);
            }
        }
        let cumulative: Vec<Vec<f64>> = polylines.iter().map(|l| cumulative_lengths(l)).collect();
        let total: f64 = cumulative.iter().filter_map(|c| c.last()).sum();
        if polylines.is_empty() || !(total > 0.0) || !total.is_finite() {
            return Err(Error::invalid(
                "flow curves",
                format!(
                    "none of the {} curves has two distinct points: draw at least one stroke",
                    curves.len()
                ),
            ));
        }
        let h = total / SAMPLES as f64;
        let (mut samples, mut directions) = (Vec::new(), Vec::new());
        for (line, cumulative) in polylines.iter().zip(&cumulative) {
            let length = cumulative.last().copied().unwrap_or(0.0);
            let count = ((length / h).round() as usize).max(1);
            for i in 0..count {
                let s = length * (i as f64 + 0.5) / count as f64;
                let chord = point_at(line, cumulative, (s + 0.5 * h).min(length))
                    - point_at(line, cumulative, (s - 0.5 * h).max(0.0));
                let direction = match chord.try_normalize() {
                    Some(d) => d,
                    None => {
                        let (k, _) = segment_at(cumulative, s);
                        (line[k + 1] - line[k]).try_normalize().unwrap_or(DVec2::X)
                    }
                };
                samples.push(point_at(line, cumulative, s));
                directions.push(direction);
            }
        }
        Self::fit(samples, directions)
    }

    fn fit(samples: Vec<DVec2>, directions: Vec<DVec2>) -> Result<FlowField> {
        let n = samples.len();
        let center = samples.iter().copied().sum::<DVec2>() / n as f64;
        let (lo, hi) = samples.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let scale = (hi - lo).length().max(f64::MIN_POSITIVE);
        let points: Vec<DVec2> = samples.iter().map(|p| (*p - center) / scale).collect();
        // the linear part is determined only when the samples do not lie on one line
        let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
        for p in &points {
            sxx += p.x * p.x;
            sxy += p.x * p.y;
            syy += p.y * p.y;
        }
        let (trace, det) = (
            (sxx + syy) / n as f64,
            (sxx * syy - sxy * sxy) / (n * n) as f64,
        );
        let smallest = 0.5 * trace - (0.25 * trace * trace - det).max(0.0).sqrt();
        let terms = if smallest > 1e-10 { 3 } else { 1 };
        let size = n + terms;
        let poly = |p: DVec2, k: usize| match k {
            0 => 1.0,
            1 => p.x,
            _ => p.y,
        };
        let a = Mat::from_fn(size, size, |r, c| match (r < n, c < n) {
            (true, true) => {
                kernel(points[r].distance(points[c])) + if r == c { RIDGE } else { 0.0 }
            }
            (true, false) => poly(points[r], c - n),
            (false, true) => poly(points[c], r - n),
            (false, false) => 0.0,
        });
        let b = Mat::from_fn(size, 2, |r, c| match (r < n, c) {
            (true, 0) => directions[r].x,
            (true, _) => directions[r].y,
            _ => 0.0,
        });
        let x = a.full_piv_lu().solve(&b);
        let value = |r: usize| DVec2::new(x[(r, 0)], x[(r, 1)]);
        let weights: Vec<DVec2> = (0..n).map(value).collect();
        let mut polynomial = [DVec2::ZERO; 3];
        for (k, term) in polynomial.iter_mut().enumerate().take(terms) {
            *term = value(n + k);
        }
        if weights.iter().chain(&polynomial).any(|w| !w.is_finite()) {
            return Err(Error::invalid(
                "flow curves",
                "their directions cannot be interpolated (the spline's system is singular)",
            ));
        }
        Ok(FlowField {
            center,
            scale,
            points,
            directions,
            weights,
            polynomial,
        })
    }

    /// The unit flow direction at `p` (the nearest stroke sample's where the interpolant vanishes; +x at a point
    /// that is not finite).
    pub fn direction_at(&self, p: DVec2) -> DVec2 {
        if !p.is_finite() {
            return DVec2::X;
        }
        let q = (p - self.center) / self.scale;
        let mut v = self.polynomial[0] + self.polynomial[1] * q.x + self.polynomial[2] * q.y;
        for (point, w) in self.points.iter().zip(&self.weights) {
            v += *w * kernel(q.distance(*point));
        }
        if let Some(d) = v.try_normalize().filter(|_| v.length() > 1e-9) {
            return d;
        }
        self.points
            .iter()
            .zip(&self.directions)
            .min_by(|a, b| q.distance(*a.0).total_cmp(&q.distance(*b.0)))
            .map_or(DVec2::X, |(_, d)| *d)
    }

    /// The flow direction at `p` as an angle from +x (radians, counter-clockwise, in (−π, π]).
    pub fn angle_at(&self, p: DVec2) -> f64 {
        self.direction_at(p).to_angle()
    }
}

/// The thin-plate kernel `r² ln r` (0 at 0).
fn kernel(r: f64) -> f64 {
    if r > 0.0 {
        r * r * r.ln()
    } else {
        0.0
    }
}

/// Arc length at each vertex of `line`.
fn cumulative_lengths(line: &[DVec2]) -> Vec<f64> {
    let mut cumulative = Vec::with_capacity(line.len());
    let mut total = 0.0;
    cumulative.push(0.0);
    for w in line.windows(2) {
        total += w[0].distance(w[1]);
        cumulative.push(total);
    }
    cumulative
}

/// The segment of `line` (consecutive points distinct) at arc length `s`: its index and the fraction along it.
fn segment_at(cumulative: &[f64], s: f64) -> (usize, f64) {
    let last = cumulative.len().saturating_sub(2);
    let k = cumulative
        .partition_point(|&c| c <= s)
        .saturating_sub(1)
        .min(last);
    let l = cumulative[k + 1] - cumulative[k];
    (k, ((s - cumulative[k]) / l).clamp(0.0, 1.0))
}

/// The point at arc length `s` along `line`.
fn point_at(line: &[DVec2], cumulative: &[f64], s: f64) -> DVec2 {
    let (k, t) = segment_at(cumulative, s);
    line[k].lerp(line[k + 1], t)
}

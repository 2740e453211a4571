//! Subdivision and adaptation to the terrain (thesis 4.3.1): a "fractal-like subdivision based on midpoint
//! displacement, which takes the underlying terrain model into account".
//!
//! Each segment `p_i p_{i+1}` of a contact arc longer (in plan) than the detail length `l = γ/σ` is cut at its
//! midpoint `m`, moved to `x = m + λu` with `u` the horizontal normal of the segment and `λ ∈ [-τ, τ]`,
//! `τ = ‖p_{i+1} − p_i‖/2` (the thesis's `‖u‖/2`, read with `u` the segment vector), where `x` minimizes
//! `C(x) = w_g C_g(x) + w_a C_a(x) + w_r C_r(x)`:
//!
//! * gradient cost `C_g(x) = (∫_V ‖g‖ f_p(v, g) dt + ∫_W ‖g‖ f_p(w, g) dt) / ‖p_{i+1} − p_i‖` with
//!   `f_p(v, g) = −2 v · g/‖g‖ + 1`. The thesis wants the cost "low when v and w are aligned in the same direction
//!   as the slope of the terrain", isolines penalized and "climbing a slope [...] penalized even more severely",
//!   which holds when `g` points down the slope: `g = −∇h`. The integrals are midpoint sums at about one sample per
//!   terrain cell (2 to 32 per half);
//! * angle cost `C_a(x) = (a/π)² + (b/π)² + (c/π)²` with `a`, `b`, `c` the turns (radians, in plan) at `p_i`,
//!   `x` and `p_{i+1}`; the turn at an end of the arc counts 0;
//! * random cost `C_r(x)`, one uniform draw in `[0, 1)` per candidate from the arc's seeded generator.
//!
//! The search tries `2 · search_steps + 1` evenly spaced `λ`. The new point is put on the terrain, unless that
//! breaks the minimum slope towards `p_i` or `p_{i+1}`: then it goes to the nearest height that keeps it, and
//! displacements for which no height keeps it (the detour is too long for the drop) are not tried. Every level
//! cuts all the segments still longer than `l`; `l` is at least one terrain cell (the terrain has no finer
//! detail to follow) and at most [`WaterfallParams::max_levels`] levels are made.
//!
//! Distance to the controller: a cut displaces by at most half the segment and leaves halves at most `1/√2` as
//! long, so no point strays more than `L/2 · 1/(1 − 1/√2) ≈ 1.71 L` from a control segment of plan length `L`.

use super::model::WaterfallParams;
use crate::geom::DVec2;
use crate::terrain::Heightfield;
use glam::DVec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// The bound on the distance of a subdivided curve from its control segment, as a multiple of its plan length.
pub const MAX_DEVIATION_FACTOR: f64 = 0.5 / (1.0 - std::f64::consts::FRAC_1_SQRT_2);

/// Slack on the minimum-slope window (scene units), for rounding.
const SLACK: f64 = 1e-9;

/// The subdivided path of a contact arc with flow `flow`, from its corrected control points.
pub(crate) fn subdivide_arc(
    terrain: &Heightfield,
    points: &[DVec3],
    flow: f64,
    params: &WaterfallParams,
    seed: u64,
) -> Vec<DVec3> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let detail = detail_length(flow, params, terrain.cell);
    let t = params.min_slope.tan();
    let mut path = points.to_vec();
    for _ in 0..params.max_levels {
        if path
            .windows(2)
            .all(|s| s[0].truncate().distance(s[1].truncate()) < detail)
        {
            break;
        }
        let mut next = Vec::with_capacity(2 * path.len());
        next.push(path[0]);
        for i in 0..path.len() - 1 {
            let (a, b) = (path[i], path[i + 1]);
            if a.truncate().distance(b.truncate()) >= detail {
                let before = i.checked_sub(1).map(|k| path[k].truncate());
                let after = path.get(i + 2).map(|p| p.truncate());
                next.push(best_midpoint(
                    terrain, before, a, b, after, t, params, &mut rng,
                ));
            }
            next.push(b);
        }
        path = next;
    }
    path
}

/// `l = γ/σ`, not below one terrain cell.
pub fn detail_length(flow: f64, params: &WaterfallParams, cell: f64) -> f64 {
    let l = flow / params.sigma;
    if l.is_finite() {
        l.max(cell)
    } else {
        cell
    }
}

/// The downhill vector `−∇h` by central differences one cell wide (one-sided at the border).
pub fn downhill(terrain: &Heightfield, p: DVec2) -> DVec2 {
    let (lo, hi) = terrain.bbox();
    let c = terrain.cell;
    let h = |q: DVec2| terrain.height_at(q.clamp(lo, hi)).unwrap_or(0.0);
    let dx = DVec2::new(c, 0.0);
    let dy = DVec2::new(0.0, c);
    let (x0, x1) = ((p - dx).clamp(lo, hi), (p + dx).clamp(lo, hi));
    let (y0, y1) = ((p - dy).clamp(lo, hi), (p + dy).clamp(lo, hi));
    let gx = if x1.x > x0.x {
        (h(x1) - h(x0)) / (x1.x - x0.x)
    } else {
        0.0
    };
    let gy = if y1.y > y0.y {
        (h(y1) - h(y0)) / (y1.y - y0.y)
    } else {
        0.0
    };
    -DVec2::new(gx, gy)
}

/// `∫ ‖g‖ f_p(v, g) dt` along `a → b` with `g = −∇h`: `‖g‖ f_p = ‖g‖ − 2 v · g`, which needs no division.
fn gradient_integral(terrain: &Heightfield, a: DVec2, b: DVec2) -> f64 {
    let len = a.distance(b);
    if !(len > 0.0) {
        return 0.0;
    }
    let v = (b - a) / len;
    let n = ((len / terrain.cell).ceil() as usize).clamp(2, 32);
    let dt = len / n as f64;
    (0..n)
        .map(|s| {
            let g = downhill(terrain, a + v * ((s as f64 + 0.5) * dt));
            g.length() - 2.0 * v.dot(g)
        })
        .sum::<f64>()
        * dt
}

/// The turn (radians) between two directions; 0 when one is missing or degenerate.
fn turn(d0: Option<DVec2>, d1: DVec2) -> f64 {
    match d0 {
        Some(d0) if d0.length_squared() > 0.0 && d1.length_squared() > 0.0 => {
            d0.normalize().dot(d1.normalize()).clamp(-1.0, 1.0).acos()
        }
        _ => 0.0,
    }
}

#[allow(clippy::too_many_arguments)]
fn best_midpoint(
    terrain: &Heightfield,
    before: Option<DVec2>,
    a: DVec3,
    b: DVec3,
    after: Option<DVec2>,
    t: f64,
    params: &WaterfallParams,
    rng: &mut ChaCha8Rng,
) -> DVec3 {
    let (a2, b2) = (a.truncate(), b.truncate());
    let len = a2.distance(b2);
    let m = 0.5 * (a2 + b2);
    let u = (b2 - a2).perp() / len;
    let tau = params.amplitude * len;
    let steps = params.search_steps as i64;
    let mut best: Option<(f64, DVec3)> = None;
    for j in -steps..=steps {
        // one draw per candidate whether it is tried or not, so the stream does not depend on the terrain
        let random: f64 = rng.random();
        let lambda = if steps > 0 {
            tau * j as f64 / steps as f64
        } else {
            0.0
        };
        let x = m + u * lambda;
        let Some(h) = terrain.height_at(x) else {
            continue;
        };
        let (d1, d2) = (a2.distance(x), x.distance(b2));
        let highest = a.z - t * d1;
        let lowest = b.z + t * d2;
        if lowest > highest + SLACK {
            continue;
        }
        let z = h.clamp(lowest.min(highest), highest);
        let gradient =
            (gradient_integral(terrain, a2, x) + gradient_integral(terrain, x, b2)) / len;
        let angle = (turn(before.map(|p| a2 - p), x - a2) / PI).powi(2)
            + (turn(Some(x - a2), b2 - x) / PI).powi(2)
            + (turn(Some(b2 - x), after.map(|p| p - b2).unwrap_or(DVec2::ZERO)) / PI).powi(2);
        let cost = params.w_gradient * gradient + params.w_angle * angle + params.w_random * random;
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, x.extend(z)));
        }
    }
    // the straight midpoint always keeps the slope of a corrected segment; this is for rounding only
    best.map(|(_, x)| x).unwrap_or(0.5 * (a + b))
}

/// The free-fall parabola from `points[0]` to `points[last]` with its apex at the start (the water leaves the
/// lip horizontally): `z(s) = z_0 − (z_0 − z_1) s²` for the fraction `s` of the horizontal run, `samples` points.
pub(crate) fn free_fall_path(points: &[DVec3], samples: usize) -> Vec<DVec3> {
    let (s, e) = (points[0], points[points.len() - 1]);
    let n = samples.max(2);
    (0..n)
        .map(|k| {
            let f = k as f64 / (n - 1) as f64;
            let p = s.truncate().lerp(e.truncate(), f);
            p.extend(s.z - (s.z - e.z) * f * f)
        })
        .collect()
}

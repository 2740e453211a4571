//! Roads embedded in the terrain (issue "Terrain that adapts", with the deformation of thesis 4.4.2): the
//! carriageway follows a profile `z(s)` along the centreline — the terrain smoothed along the road, or heights the
//! user gives — level across its width; cut and fill banks blend it into the natural slope over the bank width,
//! by diffusing the height differences between the carriageway (fixed) and the natural terrain beyond the banks
//! (fixed at 0).
//!
//! Where carriageways overlap (crossings, T-junctions), the road given first keeps its heights and a later road's
//! profile meets them, blending back to its own on either side.

use super::diffusion::{diffuse, Constraints, Diffusion, DiffusionOptions};
use super::junctions::meet_earlier_roads;
use super::rasterize::near_curve;
use crate::error::{check, Error, Result};
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};

/// A road to embed.
#[derive(Clone, Debug)]
pub struct EmbeddedRoad {
    /// Centreline in plan (m), at least two points.
    pub centreline: Vec<DVec2>,
    /// Heights of the carriageway at the centreline points; `None`: the terrain's, smoothed along the road.
    pub heights: Option<Vec<f64>>,
    /// Carriageway width (m).
    pub width: f64,
    /// Width (m) of the cut and fill banks on each side, beyond which the terrain stays natural.
    pub bank_width: f64,
}

/// How roads are embedded.
#[derive(Clone, Debug, Default)]
pub struct RoadEmbeddingOptions {
    /// Standard deviation (m) of the Gaussian smoothing the terrain's heights along the road into the profile;
    /// `None`: twice the carriageway width.
    pub smoothing: Option<f64>,
    /// The diffusion's tolerance and cycle limit (its falloff is not used: the banks bound the change).
    pub diffusion: DiffusionOptions,
}

/// The carriageway profile of one road: samples of the smoothed centreline about half a cell apart with their
/// heights (met by the earlier roads' carriageways where it reaches them).
#[derive(Clone, Debug)]
pub struct RoadProfile {
    /// Plan position and carriageway height of each sample.
    pub points: Vec<DVec3>,
    /// Distance along the road of each sample (m).
    pub s: Vec<f64>,
}

/// The terrain with its roads embedded.
#[derive(Clone, Debug)]
pub struct RoadEmbedding {
    /// `H + D`.
    pub terrain: Heightfield,
    /// `D` and the solver's statistics.
    pub diffusion: Diffusion,
    /// One profile per road, in the order given.
    pub profiles: Vec<RoadProfile>,
}

fn check_road(terrain: &Heightfield, r: usize, road: &EmbeddedRoad) -> Result<()> {
    if road.centreline.len() < 2 {
        return Err(Error::invalid(
            format!("road {r}"),
            format!(
                "needs at least two centreline points, it has {}",
                road.centreline.len()
            ),
        ));
    }
    check::positive(&format!("road {r} width"), road.width)?;
    check::non_negative(&format!("road {r} bank width"), road.bank_width)?;
    for (k, p) in road.centreline.iter().enumerate() {
        if !p.is_finite() {
            return Err(Error::invalid(
                format!("road {r}"),
                format!("centreline point {k} is not finite"),
            ));
        }
        if !terrain.contains(*p) {
            return Err(Error::invalid(
                format!("road {r}"),
                format!(
                    "centreline point {k} ({}, {}) lies off the terrain",
                    p.x, p.y
                ),
            ));
        }
    }
    if let Some(h) = &road.heights {
        check::same_len(&format!("road {r} heights"), h.len(), road.centreline.len())?;
        if let Some(k) = h.iter().position(|z| !z.is_finite()) {
            return Err(Error::invalid(
                format!("road {r}"),
                format!("height {k} is not finite"),
            ));
        }
    }
    let length: f64 = road
        .centreline
        .windows(2)
        .map(|w| w[0].distance(w[1]))
        .sum();
    if !(length > 0.0) {
        return Err(Error::invalid(format!("road {r}"), "has no length"));
    }
    Ok(())
}

/// The centreline as a smooth curve through its points (centripetal Catmull-Rom, which neither overshoots into
/// loops nor cusps), sampled about `spacing` apart, with the distance along it and the user's heights interpolated
/// linearly between their points, if any. A polyline's corners would fan the level carriageway out around each
/// vertex and put steps in its grade.
fn resample(road: &EmbeddedRoad, spacing: f64) -> (Vec<DVec2>, Vec<f64>, Option<Vec<f64>>) {
    // consecutive duplicates carry no direction
    let mut c: Vec<DVec2> = Vec::with_capacity(road.centreline.len());
    let mut hs: Vec<f64> = Vec::with_capacity(road.centreline.len());
    for (k, p) in road.centreline.iter().enumerate() {
        if c.last().is_some_and(|q| q.distance(*p) <= 1e-9) {
            continue;
        }
        c.push(*p);
        hs.push(road.heights.as_ref().map_or(0.0, |h| h[k]));
    }
    let n = c.len();
    let mut points = vec![c[0]];
    let mut s = vec![0.0];
    let mut heights = road.heights.as_ref().map(|_| vec![hs[0]]);
    for k in 0..n.saturating_sub(1) {
        let (p1, p2) = (c[k], c[k + 1]);
        let p0 = if k > 0 { c[k - 1] } else { 2.0 * p1 - p2 };
        let p3 = if k + 2 < n { c[k + 2] } else { 2.0 * p2 - p1 };
        let len = p1.distance(p2);
        let steps = ((1.5 * len / spacing).ceil() as usize).clamp(1, 10_000_000);
        for step in 1..=steps {
            let t = step as f64 / steps as f64;
            let p = if step == steps {
                p2
            } else {
                catmull_rom([p0, p1, p2, p3], t)
            };
            let prev = points.last().copied().unwrap_or(p);
            let s_prev = s.last().copied().unwrap_or(0.0);
            points.push(p);
            s.push(s_prev + prev.distance(p));
            if let Some(out) = heights.as_mut() {
                out.push(hs[k] + t * (hs[k + 1] - hs[k]));
            }
        }
    }
    (points, s, heights)
}

/// The centripetal Catmull-Rom segment between `p[1]` and `p[2]` at `t ∈ [0, 1]` (Barry and Goldman's pyramid).
fn catmull_rom(p: [DVec2; 4], t: f64) -> DVec2 {
    let knot = |a: DVec2, b: DVec2| a.distance(b).sqrt().max(1e-12);
    let t0 = 0.0;
    let t1 = t0 + knot(p[0], p[1]);
    let t2 = t1 + knot(p[1], p[2]);
    let t3 = t2 + knot(p[2], p[3]);
    let u = t1 + t * (t2 - t1);
    let lerp = |a: DVec2, b: DVec2, ta: f64, tb: f64| {
        a * ((tb - u) / (tb - ta)) + b * ((u - ta) / (tb - ta))
    };
    let a1 = lerp(p[0], p[1], t0, t1);
    let a2 = lerp(p[1], p[2], t1, t2);
    let a3 = lerp(p[2], p[3], t2, t3);
    let b1 = lerp(a1, a2, t0, t2);
    let b2 = lerp(a2, a3, t1, t3);
    lerp(b1, b2, t1, t2)
}

/// Gaussian smoothing of `z` sampled at positions `s` (standard deviation `sigma`, truncated at 3σ and
/// renormalized at the ends).
fn smooth(s: &[f64], z: &[f64], sigma: f64) -> Vec<f64> {
    let n = z.len();
    let mut out = Vec::with_capacity(n);
    let mut lo = 0;
    let mut hi = 0;
    for k in 0..n {
        while s[lo] < s[k] - 3.0 * sigma {
            lo += 1;
        }
        while hi + 1 < n && s[hi + 1] <= s[k] + 3.0 * sigma {
            hi += 1;
        }
        let (mut sum, mut wsum) = (0.0, 0.0);
        for q in lo..=hi {
            let x = (s[q] - s[k]) / sigma;
            let w = (-0.5 * x * x).exp();
            sum += w * z[q];
            wsum += w;
        }
        out.push(sum / wsum);
    }
    out
}

/// The carriageway profile of a road.
fn profile(
    terrain: &Heightfield,
    r: usize,
    road: &EmbeddedRoad,
    options: &RoadEmbeddingOptions,
) -> Result<RoadProfile> {
    let (points, s, heights) = resample(road, 0.5 * terrain.cell);
    // the smooth curve through points on the terrain can bulge past its border by a fraction of a cell (a road
    // along the border of a village that fills the terrain): it is held on the terrain
    let (lo, hi) = terrain.bbox();
    let points: Vec<DVec2> = points.into_iter().map(|p| p.clamp(lo, hi)).collect();
    let z = match heights {
        Some(h) => h,
        None => {
            let sigma = options.smoothing.unwrap_or(2.0 * road.width);
            check::positive("profile smoothing", sigma)?;
            let raw: Vec<f64> = points
                .iter()
                .map(|p| {
                    terrain.height_at(*p).ok_or_else(|| {
                        Error::invalid(
                            format!("road {r}"),
                            format!("leaves the terrain at ({}, {})", p.x, p.y),
                        )
                    })
                })
                .collect::<Result<_>>()?;
            smooth(&s, &raw, sigma)
        }
    };
    Ok(RoadProfile {
        points: points.iter().zip(&z).map(|(p, z)| p.extend(*z)).collect(),
        s,
    })
}

/// Embeds the roads into the terrain: every node within half a carriageway width of a centreline is fixed at the
/// profile height of its nearest centreline point (the first road wins where carriageways overlap, and the later
/// road's profile meets it there), every node farther than half the width plus the bank width from all centrelines
/// keeps its height, and the nodes between (the banks) take the diffused height differences.
pub fn embed_roads(
    terrain: &Heightfield,
    roads: &[EmbeddedRoad],
    options: &RoadEmbeddingOptions,
) -> Result<RoadEmbedding> {
    for (r, road) in roads.iter().enumerate() {
        check_road(terrain, r, road)?;
    }
    let mut profiles: Vec<RoadProfile> = roads
        .iter()
        .enumerate()
        .map(|(r, road)| profile(terrain, r, road, options))
        .collect::<Result<_>>()?;
    let widths: Vec<f64> = roads.iter().map(|road| road.width).collect();
    meet_earlier_roads(&mut profiles, &widths);
    let mut constraints = Constraints::for_terrain(terrain);
    let nx = terrain.nx;
    for (road, prof) in roads.iter().zip(&profiles) {
        for n in near_curve(terrain, &prof.points, 0.5 * road.width)? {
            constraints.set_if_free(
                n.node % nx,
                n.node / nx,
                n.z - terrain.heights[n.node] as f64,
            )?;
        }
    }
    // beyond the banks of every road the terrain stays natural
    let mut near = vec![false; nx * terrain.ny];
    for (road, prof) in roads.iter().zip(&profiles) {
        for n in near_curve(terrain, &prof.points, 0.5 * road.width + road.bank_width)? {
            near[n.node] = true;
        }
    }
    for (k, near) in near.iter().enumerate() {
        if !near {
            constraints.set_if_free(k % nx, k / nx, 0.0)?;
        }
    }
    let diffusion = diffuse(
        &constraints,
        &DiffusionOptions {
            falloff: None,
            ..options.diffusion.clone()
        },
    )?;
    Ok(RoadEmbedding {
        terrain: diffusion.apply(terrain)?,
        diffusion,
        profiles,
    })
}

/// Embeds one road; see [`embed_roads`].
pub fn embed_road(
    terrain: &Heightfield,
    road: &EmbeddedRoad,
    options: &RoadEmbeddingOptions,
) -> Result<RoadEmbedding> {
    embed_roads(terrain, std::slice::from_ref(road), options)
}

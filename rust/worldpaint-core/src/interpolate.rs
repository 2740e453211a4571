//! Interpolation of two colors (Section 5.2, "Distribution Interpolation and Gradients"): "*Distribution*
//! interpolation means an interpolation of corresponding histograms", done "by using optimal mass transport
//! within the analyzed interaction histograms [Read 1999], which is based on the inverse cumulative density
//! function", so that two Gaussian shapes interpolate into a Gaussian with interpolated parameters rather than
//! a fade-in-fade-out of the two.
//!
//! ## Displacement interpolation of one histogram
//! Each histogram is read as a piecewise-constant density (mass spread uniformly within a bin). Its CDF `F` is
//! piecewise linear and so is its quantile function `Q = F⁻¹`. The interpolated quantile function is
//! `Q_t(u) = (1 − t) Q_a(u) + t Q_b(u)`: between consecutive knots of the union of both CDFs' values at bin
//! edges both quantiles are linear in `u`, so `Q_t` is piecewise linear and each of its pieces carries its
//! mass `Δu` uniformly over `[Q_t(u_k), Q_t(u_{k+1})]`. That mass is deposited exactly into a common bin grid:
//! from the smaller start to the larger end of the two histograms, at the finer of the two bin widths. The
//! shape is transported; the total mass is interpolated linearly, `(1 − t) M_a + t M_b`. When one histogram is
//! empty there is no shape to transport and the two are blended linearly on the common grid.
//!
//! ## What is interpolated how
//! * **rdf** (`Interaction::Rdf`): an rdf is not a probability density — it tends to 1 at large `r`. The paper
//!   nevertheless applies mass transport to it; our reading: the rdf is normalized into a distribution of
//!   distance (its integral `∫ h(r) dr`, i.e. `Σ h_k d_r`, so bin widths may differ), the shape is transported,
//!   and the scale is restored by interpolating the integral linearly. The value of a bin is mass / width,
//!   again an rdf. Two rdfs learned with different `max_radius` are first extended to the common range with
//!   1 — the neutral value synthesis uses beyond an rdf's range — so both span the same distances; otherwise
//!   the shorter one would drag mass of the longer one inwards and leave zeros (read as hard cores) at its end.
//!   The hard core of a pair thereby moves continuously, e.g. from 2 m to 6 m through 4 m at `t = ½`.
//! * **scale, rotation, size, map sampling** histograms, the map's region histogram and the angles to the nearest
//!   road: masses per bin, transported as above (a size only one color has is kept; the angles are transported band
//!   by band, the bands' edges blended, when both colors have as many bands, else the nearer color's facing is
//!   kept).
//! * **oriented rdf**: linear blend of the values (the angular dimension has no single order to transport
//!   along). Values past the shorter one's distance range are taken as 1; grids that differ in distance bin or
//!   angle bins are not blended, the nearer color's (`t < ½`: `a`) is kept.
//! * **density, count, `min_distance`, prototype weights, `region_area`**: linear (`min_distance` of a color
//!   with fewer than two instances is `+∞`, no information: the other color's is kept; a count is rounded).
//! * **categories present in only one color** are kept with their density (and count) scaled by `1 − t` (only
//!   in `a`) or `t` (only in `b`); they are dropped where that weight is 0. Their pairs and maps are kept as
//!   they are. A pair or map present in only one color of a category both share is kept as it is.
//! * `region`, `preview` and the category records themselves (layer, priority) come from the nearer color.
//! * `max_radius` is the larger and `bin_width` the smaller of the two.
//!
//! `t = 0` gives `a` and `t = 1` gives `b` exactly (under the new name); `t` outside [0, 1] or NaN is an
//! [`crate::Error::OutOfRange`].

use crate::error::{check, Error, Result};
use crate::palette::{
    CategoryColor, Color, ColorKind, GraphColor, Histogram, Interaction, MapInteraction,
    PairInteraction, PolygonColor, RoadFacing,
};

/// Interpolates two colors at `t` ∈ [0, 1] by displacement interpolation of their histograms (see the module
/// documentation). The result is named `name`.
pub fn interpolate_colors(a: &Color, b: &Color, t: f64, name: &str) -> Result<Color> {
    check::within("interpolation parameter t", t, 0.0, 1.0)?;
    if t == 0.0 || t == 1.0 {
        let mut c = if t == 0.0 { a.clone() } else { b.clone() };
        c.name = name.to_string();
        return Ok(c);
    }
    // a pattern's topology has no halfway point with another's or with statistics
    if let Some(c) = [a, b].into_iter().find(|c| !c.kind.is_statistics()) {
        return Err(Error::invalid(
            format!("color '{}'", c.name),
            "is an arrangement: arrangements cannot be blended with other colors",
        ));
    }
    let near = if t < 0.5 { a } else { b };
    let lerp = |x: f64, y: f64| (1.0 - t) * x + t * y;

    let categories = merged_categories(a, b, t);
    let mut pairs = merged_pairs(a, b, t);
    let mut maps = merged_maps(a, b, t);
    // drop what belongs to a category that was dropped (weight 0 cannot happen for 0 < t < 1, but stay safe)
    let known = |n: &str| categories.iter().any(|c| c.category.name == n);
    pairs.retain(|p| known(&p.category) && known(&p.other));
    maps.retain(|m| known(&m.category));

    let graphs = merge_by(
        &a.graphs,
        &b.graphs,
        |g, h| g.category == h.category,
        |ga, gb| interpolate_graph(ga, gb, t),
    );
    let polygons = merge_by(
        &a.polygons,
        &b.polygons,
        |p, q| p.category == q.category,
        |pa, pb| PolygonColor {
            category: pa.category.clone(),
            spacing: lerp(pa.spacing, pb.spacing),
            islands_per_area: lerp(pa.islands_per_area, pb.islands_per_area),
            island_areas: quantile_blend(&pa.island_areas, &pb.island_areas, t),
            lakes_per_area: pa
                .lakes_per_area
                .zip(pb.lakes_per_area)
                .map(|(a, b)| lerp(a, b)),
        },
    );
    let color = Color {
        name: name.to_string(),
        region: near.region.clone(),
        region_area: lerp(a.region_area, b.region_area),
        max_radius: a.max_radius.max(b.max_radius),
        bin_width: a.bin_width.min(b.bin_width),
        categories,
        pairs,
        maps,
        graphs,
        polygons,
        preview: near.preview.clone(),
        kind: ColorKind::Statistics,
    };
    color.validate()?;
    Ok(color)
}

/// The categories of both colors: those of both interpolated, the others scaled by their color's weight, in
/// priority order (stable).
fn merged_categories(a: &Color, b: &Color, t: f64) -> Vec<CategoryColor> {
    let mut categories: Vec<CategoryColor> = Vec::new();
    for ca in &a.categories {
        match b.category(&ca.category.name) {
            Some(cb) => categories.push(interpolate_category(ca, cb, t)),
            None => categories.push(scaled_category(ca, 1.0 - t)),
        }
    }
    for cb in &b.categories {
        if a.category(&cb.category.name).is_none() {
            categories.push(scaled_category(cb, t));
        }
    }
    categories.sort_by_key(|c| c.category.priority);
    categories
}

/// The pair interactions of both colors: those of both interpolated, the others kept.
fn merged_pairs(a: &Color, b: &Color, t: f64) -> Vec<PairInteraction> {
    merge_by(
        &a.pairs,
        &b.pairs,
        |p, q| p.category == q.category && p.other == q.other,
        |pa, pb| PairInteraction {
            category: pa.category.clone(),
            other: pa.other.clone(),
            interaction: interpolate_interaction(&pa.interaction, &pb.interaction, t),
        },
    )
}

/// The map interactions of both colors: those of both transported, the others kept.
fn merged_maps(a: &Color, b: &Color, t: f64) -> Vec<MapInteraction> {
    merge_by(
        &a.maps,
        &b.maps,
        |m, q| m.category == q.category && m.map == q.map,
        |ma, mb| MapInteraction {
            category: ma.category.clone(),
            map: ma.map.clone(),
            hist: displacement_interpolate(&ma.hist, &mb.hist, t),
            region_hist: displacement_interpolate(&ma.region_hist, &mb.region_hist, t),
            source: ma.source,
        },
    )
}

/// Entries of `a` and `b` matched by `same`: blended where both have one, kept where one has; those of `a`
/// first, in order.
fn merge_by<T: Clone>(
    a: &[T],
    b: &[T],
    same: impl Fn(&T, &T) -> bool,
    blend: impl Fn(&T, &T) -> T,
) -> Vec<T> {
    let mut out: Vec<T> = a
        .iter()
        .map(|x| match b.iter().find(|y| same(y, x)) {
            Some(y) => blend(x, y),
            None => x.clone(),
        })
        .collect();
    out.extend(b.iter().filter(|y| !a.iter().any(|x| same(x, y))).cloned());
    out
}

/// Two ascending samples blended by their quantiles (displacement interpolation of their distributions), as
/// many values as the larger holds; an empty one gives way to the other.
fn quantile_blend(a: &[f64], b: &[f64], t: f64) -> Vec<f64> {
    if a.is_empty() || b.is_empty() {
        return if a.is_empty() { b.to_vec() } else { a.to_vec() };
    }
    let n = a.len().max(b.len());
    let at = |s: &[f64], u: f64| s[((u * s.len() as f64) as usize).min(s.len() - 1)];
    (0..n)
        .map(|k| {
            let u = (k as f64 + 0.5) / n as f64;
            (1.0 - t) * at(a, u) + t * at(b, u)
        })
        .collect()
}

/// Graph statistics: the histograms transported, the numbers blended, the constraints of the nearer color.
fn interpolate_graph(ga: &GraphColor, gb: &GraphColor, t: f64) -> GraphColor {
    let lerp = |x: f64, y: f64| (1.0 - t) * x + t * y;
    let near = if t < 0.5 { ga } else { gb };
    GraphColor {
        category: ga.category.clone(),
        edge_length: displacement_interpolate(&ga.edge_length, &gb.edge_length, t),
        angle: displacement_interpolate(&ga.angle, &gb.angle, t),
        turn: match (ga.turn.values.is_empty(), gb.turn.values.is_empty()) {
            (false, false) => displacement_interpolate(&ga.turn, &gb.turn, t),
            // a color learned before turns were has none to blend
            (true, _) => gb.turn.clone(),
            (false, true) => ga.turn.clone(),
        },
        degree: (0..ga.degree.len().max(gb.degree.len()))
            .map(|k| {
                lerp(
                    ga.degree.get(k).copied().unwrap_or(0.0),
                    gb.degree.get(k).copied().unwrap_or(0.0),
                )
            })
            .collect(),
        min_angle: lerp(ga.min_angle, gb.min_angle),
        edges_per_node: lerp(ga.edges_per_node, gb.edges_per_node),
        components_per_area: lerp(ga.components_per_area, gb.components_per_area),
        clearance: near.clearance.clone(),
        avoids: near.avoids.clone(),
    }
}

fn scaled_category(c: &CategoryColor, w: f64) -> CategoryColor {
    let mut c = c.clone();
    c.density *= w;
    c.count = (c.count as f64 * w).round() as usize;
    c
}

fn interpolate_category(ca: &CategoryColor, cb: &CategoryColor, t: f64) -> CategoryColor {
    let lerp = |x: f64, y: f64| (1.0 - t) * x + t * y;
    let min_distance = match (ca.min_distance.is_finite(), cb.min_distance.is_finite()) {
        (true, true) => lerp(ca.min_distance, cb.min_distance),
        (true, false) => ca.min_distance,
        (false, true) => cb.min_distance,
        (false, false) => f64::INFINITY,
    };
    let n = ca.prototype_weights.len().max(cb.prototype_weights.len());
    let at = |v: &[f64], k: usize| v.get(k).copied().unwrap_or(0.0);
    let prototype_weights = (0..n)
        .map(|k| lerp(at(&ca.prototype_weights, k), at(&cb.prototype_weights, k)))
        .collect();
    CategoryColor {
        category: if t < 0.5 {
            ca.category.clone()
        } else {
            cb.category.clone()
        },
        count: lerp(ca.count as f64, cb.count as f64).round().max(0.0) as usize,
        density: lerp(ca.density, cb.density),
        min_distance,
        scale: displacement_interpolate(&ca.scale, &cb.scale, t),
        rotation: displacement_interpolate(&ca.rotation, &cb.rotation, t),
        prototype_weights,
        size: match (ca.size.values.is_empty(), cb.size.values.is_empty()) {
            (false, false) => displacement_interpolate(&ca.size, &cb.size, t),
            // a color learned before sizes were has none to blend
            (true, _) => cb.size.clone(),
            (false, true) => ca.size.clone(),
        },
        facing: interpolate_facing(ca.facing.as_ref(), cb.facing.as_ref(), t),
    }
}

/// Facing the roads: with as many distance bands, each band's edge blended and its angles transported, the share
/// near roads blended, the roads of the nearer color; otherwise (bands that do not correspond, or a color that does
/// not face its roads) the nearer color's facing.
fn interpolate_facing(
    fa: Option<&RoadFacing>,
    fb: Option<&RoadFacing>,
    t: f64,
) -> Option<RoadFacing> {
    let lerp = |x: f64, y: f64| (1.0 - t) * x + t * y;
    match (fa, fb) {
        (Some(a), Some(b)) if a.bands.len() == b.bands.len() => Some(RoadFacing {
            roads: if t < 0.5 { &a.roads } else { &b.roads }.clone(),
            bands: a
                .bands
                .iter()
                .zip(&b.bands)
                .map(|(x, y)| lerp(*x, *y))
                .collect(),
            angles: a
                .angles
                .iter()
                .zip(&b.angles)
                .map(|(x, y)| displacement_interpolate(x, y, t))
                .collect(),
            near_share: lerp(a.near_share, b.near_share),
        }),
        _ => if t < 0.5 { fa } else { fb }.cloned(),
    }
}

fn interpolate_interaction(ia: &Interaction, ib: &Interaction, t: f64) -> Interaction {
    match (ia, ib) {
        (Interaction::Rdf { hist: ha }, Interaction::Rdf { hist: hb }) => Interaction::Rdf {
            hist: interpolate_rdf(ha, hb, t),
        },
        (
            Interaction::OrientedRdf {
                distance_bin: da,
                angle_bins: na,
                values: va,
            },
            Interaction::OrientedRdf {
                distance_bin: db,
                angle_bins: nb,
                values: vb,
            },
        ) if da == db && na == nb => {
            let n = va.len().max(vb.len());
            let at = |v: &[f64], k: usize| v.get(k).copied().unwrap_or(1.0);
            Interaction::OrientedRdf {
                distance_bin: *da,
                angle_bins: *na,
                values: (0..n)
                    .map(|k| (1.0 - t) * at(va, k) + t * at(vb, k))
                    .collect(),
            }
        }
        _ => {
            if t < 0.5 {
                ia.clone()
            } else {
                ib.clone()
            }
        }
    }
}

/// `h` extended with the value 1 up to (at least) `end`.
fn extend_rdf(h: &Histogram, end: f64) -> Histogram {
    let mut h = h.clone();
    if h.bin_width > 0.0 && h.bin_width.is_finite() {
        let missing = ((end - h.end()) / h.bin_width - 1e-9).ceil();
        if missing > 0.0 && missing.is_finite() {
            h.values.extend(std::iter::repeat_n(1.0, missing as usize));
        }
    }
    h
}

/// Displacement interpolation of two rdfs (values are densities over distance; see the module documentation).
pub(crate) fn interpolate_rdf(a: &Histogram, b: &Histogram, t: f64) -> Histogram {
    let end = a.end().max(b.end());
    let (a, b) = (extend_rdf(a, end), extend_rdf(b, end));
    let to_mass = |h: &Histogram| Histogram {
        start: h.start,
        bin_width: h.bin_width,
        values: h.values.iter().map(|v| v * h.bin_width).collect(),
    };
    let mut out = displacement_interpolate(&to_mass(&a), &to_mass(&b), t);
    let w = out.bin_width;
    if w > 0.0 {
        out.values.iter_mut().for_each(|v| *v /= w);
    }
    out
}

/// A usable histogram: finite positive bin width, finite start, finite non-negative values, positive total.
fn has_shape(h: &Histogram) -> bool {
    h.bin_width.is_finite()
        && h.bin_width > 0.0
        && h.start.is_finite()
        && !h.values.is_empty()
        && h.values.iter().all(|v| v.is_finite() && *v >= 0.0)
        && h.total() > 0.0
}

/// The common grid of two histograms: from the smaller start to the larger end, at the finer bin width.
fn common_grid(a: &Histogram, b: &Histogram) -> Histogram {
    let usable =
        |h: &Histogram| h.bin_width.is_finite() && h.bin_width > 0.0 && h.start.is_finite();
    match (usable(a), usable(b)) {
        (true, true) => {
            let start = a.start.min(b.start);
            let end = a.end().max(b.end());
            let w = a.bin_width.min(b.bin_width);
            let n = ((end - start) / w - 1e-9).ceil().max(0.0);
            Histogram::zeros(start, w, if n.is_finite() { n as usize } else { 0 })
        }
        (true, false) => Histogram::zeros(a.start, a.bin_width, a.values.len()),
        (false, true) => Histogram::zeros(b.start, b.bin_width, b.values.len()),
        (false, false) => Histogram::zeros(0.0, 1.0, 0),
    }
}

/// Deposits `mass` spread uniformly over `[lo, hi]` into the bins of `g` (clamped to its range).
fn deposit(g: &mut Histogram, lo: f64, hi: f64, mass: f64) {
    let n = g.values.len();
    if n == 0 || mass <= 0.0 {
        return;
    }
    let w = g.bin_width;
    let index = |x: f64| (((x - g.start) / w).floor().max(0.0) as usize).min(n - 1);
    if !(hi - lo > 1e-12 * w) {
        let k = index(0.5 * (lo + hi));
        g.values[k] += mass;
        return;
    }
    let (k0, k1) = (index(lo), index(hi));
    for k in k0..=k1 {
        let b0 = g.start + k as f64 * w;
        let b1 = b0 + w;
        let overlap = (hi.min(b1) - lo.max(b0)).max(0.0);
        // mass left of the grid goes to the first bin, right of it to the last
        let extra = if k == 0 { (b0 - lo).max(0.0) } else { 0.0 }
            + if k == n - 1 { (hi - b1).max(0.0) } else { 0.0 };
        g.values[k] += mass * (overlap + extra) / (hi - lo);
    }
}

/// The piecewise-linear CDF of a histogram: cumulative fractions at its bin edges (last exactly 1).
fn cdf(h: &Histogram) -> Vec<f64> {
    let total = h.total();
    let mut acc = 0.0;
    let mut c = Vec::with_capacity(h.values.len() + 1);
    c.push(0.0);
    for v in &h.values {
        acc += v / total;
        c.push(acc.min(1.0));
    }
    if let Some(last) = c.last_mut() {
        *last = 1.0;
    }
    c
}

/// The quantile function of `h` (with CDF `c`) on the piece of `u` containing `mid`, evaluated at `u`:
/// the bin `k` with `c[k] ≤ mid < c[k+1]` is found by advancing `k` (calls come with increasing `mid`).
fn quantile_on_piece(h: &Histogram, c: &[f64], k: &mut usize, mid: f64, u: f64) -> f64 {
    let n = h.values.len();
    while *k + 1 < n && c[*k + 1] <= mid {
        *k += 1;
    }
    let m = c[*k + 1] - c[*k];
    let x0 = h.start + *k as f64 * h.bin_width;
    if m > 0.0 {
        x0 + (u - c[*k]) / m * h.bin_width
    } else {
        x0
    }
}

/// Displacement (optimal-transport) interpolation of two histograms of masses per bin: quantile functions
/// blended at `t`, rebuilt on the common grid (smaller start to larger end, finer bin width), total mass
/// interpolated linearly. When either histogram holds no mass the two are blended linearly on that grid.
pub fn displacement_interpolate(a: &Histogram, b: &Histogram, t: f64) -> Histogram {
    let mut g = common_grid(a, b);
    let total = (1.0 - t) * a.total() + t * b.total();
    if !(has_shape(a) && has_shape(b)) {
        // no shape to transport: linear blend of the masses, spread uniformly within each source bin
        for (h, w) in [(a, 1.0 - t), (b, t)] {
            if !(h.bin_width.is_finite() && h.bin_width > 0.0 && h.start.is_finite()) {
                continue;
            }
            for (k, v) in h.values.iter().enumerate() {
                if v.is_finite() && *v > 0.0 {
                    let lo = h.start + k as f64 * h.bin_width;
                    deposit(&mut g, lo, lo + h.bin_width, w * v);
                }
            }
        }
        return g;
    }
    let (ca, cb) = (cdf(a), cdf(b));
    let mut knots: Vec<f64> = ca.iter().chain(cb.iter()).copied().collect();
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    let (mut ka, mut kb) = (0usize, 0usize);
    for w in knots.windows(2) {
        let (u0, u1) = (w[0], w[1]);
        let du = u1 - u0;
        if !(du > 0.0) {
            continue;
        }
        let mid = 0.5 * (u0 + u1);
        let qa0 = quantile_on_piece(a, &ca, &mut ka, mid, u0);
        let qa1 = quantile_on_piece(a, &ca, &mut ka, mid, u1);
        let qb0 = quantile_on_piece(b, &cb, &mut kb, mid, u0);
        let qb1 = quantile_on_piece(b, &cb, &mut kb, mid, u1);
        let lo = (1.0 - t) * qa0 + t * qb0;
        let hi = (1.0 - t) * qa1 + t * qb1;
        deposit(&mut g, lo.min(hi), lo.max(hi), du * total);
    }
    g
}

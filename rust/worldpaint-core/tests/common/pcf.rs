//! The pair-correlation function as a user measures it (spatstat's `pcf` with the translation correction), independent
//! of the engine's own rdf estimator, for the tests that check clustering at every scale.
//!
//! Over a rectangular window `W` of sides `a × b`, a pair at offset `(dx, dy)` weighs `1 / |W ∩ (W + (dx, dy))|
//! = 1 / ((a − |dx|)(b − |dy|))`; `g(r) = Σ_{i≠j, d ∈ ring} w_ij / (λ² |ring|)` with `λ = n / |W|`. Rings are
//! `dr` wide out to `r_max` (pairs beyond either side of the window are left out).

use worldpaint_core::DVec2;

/// The translation-corrected pcf of `points` in the window `[lo, hi]`, one value per ring of width `dr`.
pub fn pcf(points: &[DVec2], lo: DVec2, hi: DVec2, r_max: f64, dr: f64) -> Vec<f64> {
    let (a, b) = (hi.x - lo.x, hi.y - lo.y);
    let rings = (r_max / dr).round() as usize;
    let mut sums = vec![0.0; rings];
    let inside: Vec<DVec2> = points
        .iter()
        .copied()
        .filter(|p| p.x >= lo.x && p.x < hi.x && p.y >= lo.y && p.y < hi.y)
        .collect();
    for (i, p) in inside.iter().enumerate() {
        for q in &inside[i + 1..] {
            let (dx, dy) = ((q.x - p.x).abs(), (q.y - p.y).abs());
            let k = ((dx * dx + dy * dy).sqrt() / dr) as usize;
            if k < rings && dx < a && dy < b {
                // both orders of the pair
                sums[k] += 2.0 / ((a - dx) * (b - dy));
            }
        }
    }
    let lambda = inside.len() as f64 / (a * b);
    sums.iter()
        .enumerate()
        .map(|(k, s)| {
            let ring = std::f64::consts::PI * dr * dr * ((k + 1).pow(2) - k.pow(2)) as f64;
            s / (lambda * lambda * ring)
        })
        .collect()
}

/// Root-mean-square difference of two pcfs over their common rings.
pub fn l2(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return f64::NAN;
    }
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n as f64).sqrt()
}

/// Pearson correlation of the counts of two point sets in square cells of side `cell` tiling `[lo, hi]`.
pub fn count_correlation(a: &[DVec2], b: &[DVec2], lo: DVec2, hi: DVec2, cell: f64) -> f64 {
    let (nx, ny) = (
        ((hi.x - lo.x) / cell).floor() as usize,
        ((hi.y - lo.y) / cell).floor() as usize,
    );
    let counts = |points: &[DVec2]| {
        let mut c = vec![0.0; nx * ny];
        for p in points {
            let (i, j) = ((p.x - lo.x) / cell, (p.y - lo.y) / cell);
            if i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny {
                c[j as usize * nx + i as usize] += 1.0;
            }
        }
        c
    };
    pearson(&counts(a), &counts(b))
}

/// Pearson correlation of the counts of two point sets in every square window of side `side` that fits in
/// `[lo, hi]`, its corners `step` apart: the cell counts of [`count_correlation`] at every offset of the cells,
/// which stays a figure where cells as large as the window would be too few to correlate (two 50 m cells in a
/// 50 × 100 m window give ±1).
pub fn window_count_correlation(
    a: &[DVec2],
    b: &[DVec2],
    lo: DVec2,
    hi: DVec2,
    side: f64,
    step: f64,
) -> f64 {
    let fits = |extent: f64| ((extent - side) / step + 1e-9).floor() as usize + 1;
    let (nx, ny) = (fits(hi.x - lo.x), fits(hi.y - lo.y));
    let counts = |points: &[DVec2]| -> Vec<f64> {
        (0..nx * ny)
            .map(|k| {
                let min = lo + DVec2::new((k % nx) as f64, (k / nx) as f64) * step;
                let max = min + DVec2::splat(side);
                points
                    .iter()
                    .filter(|p| p.x >= min.x && p.x < max.x && p.y >= min.y && p.y < max.y)
                    .count() as f64
            })
            .collect()
    };
    pearson(&counts(a), &counts(b))
}

/// Pearson correlation of two equally long series.
pub fn pearson(a: &[f64], b: &[f64]) -> f64 {
    let mean = |c: &[f64]| c.iter().sum::<f64>() / c.len() as f64;
    let (ma, mb) = (mean(a), mean(b));
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma).powi(2);
        sbb += (y - mb).powi(2);
    }
    sab / (saa * sbb).sqrt()
}

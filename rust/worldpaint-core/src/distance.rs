//! Exact Euclidean distance transforms on regular grids (Felzenszwalb and Huttenlocher, *Distance Transforms of
//! Sampled Functions*, 2012): the squared distance separates into one pass along the rows and one along the
//! columns, each the lower envelope of parabolas rooted at the samples. Used by the village interest maps, the
//! seam-carving stretch and the terrain edit's falloff.

use rayon::prelude::*;

/// Squared distance transform of one line: `out[q] = min_p (q − p)² + f[p]`, `f` and `out` in squared samples.
pub(crate) fn squared_distance_1d(f: &[f64], out: &mut [f64]) {
    let n = f.len().min(out.len());
    if n == 0 {
        return;
    }
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    let mut k = 0usize;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let parabola = |q: usize, p: usize| {
        ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64)
    };
    for q in 1..n {
        // z[0] = −∞ ends the loop at k = 0
        let mut s = parabola(q, v[k]);
        while s <= z[k] {
            k -= 1;
            s = parabola(q, v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, o) in out.iter_mut().enumerate().take(n) {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let d = q as f64 - v[k] as f64;
        *o = d * d + f[v[k]];
    }
}

/// Exact Euclidean distance (in units of `cell`) from every node of a row-major `nx × ny` grid to the nearest node
/// where `mask` is true; infinite everywhere when the mask is empty (or does not match the grid).
pub fn distance_transform(nx: usize, ny: usize, cell: f64, mask: &[bool]) -> Vec<f32> {
    if mask.len() != nx * ny || !mask.iter().any(|m| *m) {
        return vec![f32::INFINITY; nx * ny];
    }
    let big = 1e20;
    let mut d: Vec<f64> = mask.iter().map(|m| if *m { 0.0 } else { big }).collect();
    d.par_chunks_mut(nx).for_each(|row| {
        let mut out = vec![0.0; row.len()];
        squared_distance_1d(row, &mut out);
        row.copy_from_slice(&out);
    });
    let columns: Vec<Vec<f64>> = (0..nx)
        .into_par_iter()
        .map(|i| {
            let col: Vec<f64> = (0..ny).map(|j| d[j * nx + i]).collect();
            let mut out = vec![0.0; ny];
            squared_distance_1d(&col, &mut out);
            out
        })
        .collect();
    let mut out = vec![0.0f32; nx * ny];
    for (i, col) in columns.iter().enumerate() {
        for (j, v) in col.iter().enumerate() {
            out[j * nx + i] = if *v >= big {
                f32::INFINITY
            } else {
                (v.sqrt() * cell) as f32
            };
        }
    }
    out
}

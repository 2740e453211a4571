//! The discrete Laplace equation on a row-major grid, recomputed independently of the solvers that are checked
//! against it (included with `#[path]`, by the terrain edit tests and the multigrid's own tests).

/// Largest `|mean of the 4 neighbours − value|` over the nodes of the row-major `nx` × `ny` grid `values` that
/// `free` accepts (by index).
pub fn residual(values: &[f64], nx: usize, ny: usize, free: impl Fn(usize) -> bool) -> f64 {
    let mut worst = 0.0f64;
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if !free(k) {
                continue;
            }
            let mut n = Vec::with_capacity(4);
            if i > 0 {
                n.push(values[k - 1]);
            }
            if i + 1 < nx {
                n.push(values[k + 1]);
            }
            if j > 0 {
                n.push(values[k - nx]);
            }
            if j + 1 < ny {
                n.push(values[k + nx]);
            }
            worst = worst.max((n.iter().sum::<f64>() / n.len() as f64 - values[k]).abs());
        }
    }
    worst
}

//! Tests of the multigrid solver against Jacobi iteration and an independent residual.

use super::*;
use crate::terrain_edit::laplace_residual;

/// Max residual of a row-major solution, recomputed independently of the solver; the fixed nodes keep their value.
fn check(nx: usize, ny: usize, fixed: &[f64], u: &[f64]) -> f64 {
    for (k, f) in fixed.iter().enumerate() {
        if !f.is_nan() {
            assert_eq!(u[k], *f);
        }
    }
    laplace_residual(u, nx, ny, |k| fixed[k].is_nan())
}

#[test]
fn multigrid_and_jacobi_agree_on_odd_and_even_grids() {
    for (nx, ny) in [(33, 33), (40, 27), (5, 61), (2, 2), (100, 3)] {
        let mut fixed = vec![f64::NAN; nx * ny];
        fixed[(ny / 2) * nx + nx / 3] = 2.0;
        fixed[nx - 1] = -1.0;
        let mg = solve(nx, ny, &fixed, 1e-10, 200);
        assert!(mg.residual <= 1e-10, "{nx}x{ny}: residual {}", mg.residual);
        assert!(check(nx, ny, &fixed, &mg.u) <= 1e-9);
        let jac = jacobi(nx, ny, &fixed, 1e-12, 2_000_000);
        let diff =
            mg.u.iter()
                .zip(&jac.u)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
        assert!(
            diff < 1e-6,
            "{nx}x{ny}: multigrid and Jacobi differ by {diff}"
        );
    }
}

#[test]
fn multigrid_converges_in_few_cycles() {
    let n = 257;
    let mut fixed = vec![f64::NAN; n * n];
    for i in 20..230 {
        fixed[(i / 2 + 40) * n + i] = (i as f64 * 0.05).sin() * 5.0;
    }
    let mg = solve(n, n, &fixed, 1e-8, 100);
    assert!(mg.cycles <= 20, "{} cycles", mg.cycles);
    assert!(check(n, n, &fixed, &mg.u) <= 1e-8);
}

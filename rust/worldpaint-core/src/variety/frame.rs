//! The frame of a connecting region (seed §4.2.2): the affine map that moved a region's vertices as one solid,
//! fitted by least squares.
//!
//! The seed allows "a translation, rotation or scaling" of the whole region; the reading here is a similarity
//! (uniform scale, rotation, translation), fitted in closed form by Horn's quaternion method (the rotation is the
//! eigenvector of the largest eigenvalue of a symmetric 4×4 matrix, found by Jacobi sweeps; the scale is Horn's
//! symmetric one). The fit is accepted as a solid transform when every vertex lies within the tolerance of where the
//! map puts it. Two or fewer distinct points, or collinear ones, leave the rotation about their line free: the fit
//! then takes the smallest rotation that matches them, which is enough to place the subtree beyond them.

use glam::{DAffine3, DMat3, DQuat, DVec3};

/// The similarity that best maps `from` onto `to` (same length) in the least-squares sense, and the largest
/// distance between a mapped point and its target.
pub(super) fn fit_similarity(from: &[DVec3], to: &[DVec3]) -> (DAffine3, f64) {
    let n = from.len().min(to.len());
    if n == 0 {
        return (DAffine3::IDENTITY, 0.0);
    }
    let ca = from[..n].iter().copied().sum::<DVec3>() / n as f64;
    let cb = to[..n].iter().copied().sum::<DVec3>() / n as f64;
    let mut m = [[0.0f64; 3]; 3];
    let (mut sa, mut sb) = (0.0, 0.0);
    for (a, b) in from[..n].iter().zip(&to[..n]) {
        let (a, b) = (*a - ca, *b - cb);
        sa += a.length_squared();
        sb += b.length_squared();
        let (av, bv) = (a.to_array(), b.to_array());
        for (i, row) in m.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                *cell += av[i] * bv[j];
            }
        }
    }
    let rotation = if sa > 0.0 && sb > 0.0 {
        horn_rotation(&m)
    } else {
        DQuat::IDENTITY
    };
    let scale = if sa > 1e-300 && sb > 0.0 {
        (sb / sa).sqrt()
    } else {
        1.0
    };
    let linear = DMat3::from_quat(rotation) * scale;
    let frame = DAffine3::from_mat3_translation(linear, cb - linear * ca);
    let residual = from[..n]
        .iter()
        .zip(&to[..n])
        .map(|(a, b)| frame.transform_point3(*a).distance(*b))
        .fold(0.0, f64::max);
    (frame, residual)
}

/// The rotation maximising Σ b·R a from the cross-covariance `m[i][j] = Σ a_i b_j` (Horn 1987).
fn horn_rotation(m: &[[f64; 3]; 3]) -> DQuat {
    let [[sxx, sxy, sxz], [syx, syy, syz], [szx, szy, szz]] = *m;
    let mut n = [
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ];
    let (values, vectors) = jacobi4(&mut n);
    let mut best = 0;
    for k in 1..4 {
        if values[k] > values[best] {
            best = k;
        }
    }
    let q = DQuat::from_xyzw(
        vectors[1][best],
        vectors[2][best],
        vectors[3][best],
        vectors[0][best],
    );
    if q.length_squared() > 0.0 && q.is_finite() {
        q.normalize()
    } else {
        DQuat::IDENTITY
    }
}

/// Eigen-decomposition of a symmetric 4×4 matrix by cyclic Jacobi rotations: eigenvalues and eigenvectors (columns).
fn jacobi4(a: &mut [[f64; 4]; 4]) -> ([f64; 4], [[f64; 4]; 4]) {
    let mut v = [[0.0; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _sweep in 0..64 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let scale: f64 = (0..4).map(|i| a[i][i] * a[i][i]).sum::<f64>() + off;
        if off <= 1e-30 * scale.max(1e-300) {
            break;
        }
        for p in 0..4 {
            for q in p + 1..4 {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (row_p, row_q) = (a[p], a[q]);
                for k in 0..4 {
                    a[p][k] = c * row_p[k] - s * row_q[k];
                    a[q][k] = s * row_p[k] + c * row_q[k];
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2], a[3][3]], v)
}

/// Whether `frame` is the identity within `tol` over points whose distance from the origin is at most `reach`.
pub(super) fn is_identity(frame: &DAffine3, reach: f64, tol: f64) -> bool {
    let d = frame.matrix3 - DMat3::IDENTITY;
    let linear = d.x_axis.length() + d.y_axis.length() + d.z_axis.length();
    linear * reach + frame.translation.length() <= tol
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotated_scaled_moved_ring_is_found_again() {
        let ring: Vec<DVec3> = (0..8)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                DVec3::new(a.cos(), a.sin(), 0.3 * (k % 2) as f64)
            })
            .collect();
        let truth = DAffine3::from_scale_rotation_translation(
            DVec3::splat(1.3),
            DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7),
            DVec3::new(0.5, -2.0, 3.0),
        );
        let moved: Vec<DVec3> = ring.iter().map(|&p| truth.transform_point3(p)).collect();
        let (fit, residual) = fit_similarity(&ring, &moved);
        assert!(residual < 1e-9, "{residual}");
        assert!((fit.matrix3 - truth.matrix3)
            .abs()
            .to_cols_array()
            .iter()
            .all(|&x| x < 1e-9));
        let (same, r0) = fit_similarity(&ring, &ring);
        assert!(r0 < 1e-12 && is_identity(&same, 1.0, 1e-9));
        let mut bent = moved.clone();
        bent[3].z += 0.1;
        assert!(fit_similarity(&ring, &bent).1 > 0.01);
    }
}

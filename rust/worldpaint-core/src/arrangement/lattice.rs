//! The lattice under a near-regular reference placed by hand. The seed copies each reference ring as it was placed
//! (§5.4) and relaxes toward those rings (§5.5); a reference placed by hand is never exact, so every copy adds the
//! error of its ring, and where two growth fronts meet their elements miss each other by more than r_short: they
//! are neither merged nor far enough apart for an element between them, and the pattern loses its lattice there
//! (a hexagonal reference turned 17° with 3 % noise lost it for 10–14 % of the interior; a checkerboard for half).
//!
//! The seed's own observation, "when regular or near regular arrangements are input … these connections often break
//! the regular pattern" (§4), is answered here by estimating the lattice the user meant: two basis vectors `b1`,
//! `b2` such that every offset of the reference's interior rings is close to an integer combination `i b1 + j b2`.
//! Rings are then copied with those exact offsets, so every grown element lands on a site of one lattice through the
//! first element, fronts meet on the same sites, and the relaxation's targets agree with one another.
//!
//! Readings chosen:
//! - the offsets are clustered (each joins the nearest cluster mean within a quarter of the shortest ring edge, two
//!   passes); `b1` is the shortest mean of a cluster holding at least a tenth of the largest one's offsets, `b2` the
//!   shortest such mean at least 20° off `b1`'s line, and the pair is reduced (Lagrange–Gauss) to the shortest basis;
//! - the reference is a lattice when every offset lies within [`MAX_RESIDUAL`] of `b1`'s length from its integer
//!   combination and their root mean square within [`MAX_RMS_RESIDUAL`] (placing by hand with 5 % noise leaves
//!   about 0.1; a Poisson-disk reference 0.4 or more), with `|i|, |j| ≤` [`MAX_INDEX`];
//! - the basis is then refitted to the offsets by least squares, which averages the hand's noise away, leaving out
//!   the diagonals of cells whose two diagonals are equally long (a square lattice's, bricks' rows and columns): the
//!   triangulation kept the shorter of each pair, 1–2 % short on average with 3 % noise;
//! - a basis within 5 % in length and 3° in angle of a hexagonal or square one is made exactly so;
//! - a reference that is not a lattice (an irregular, uniform one) is grown as the seed grows it.

use glam::DVec2;

/// Largest distance of an offset from its lattice vector, in lengths of `b1`.
pub(crate) const MAX_RESIDUAL: f64 = 0.4;
/// Largest root mean square of the offsets' distances from their lattice vectors, in lengths of `b1`. Measured on
/// lattices of 49 elements placed with a normal noise of σ per coordinate: 0.06–0.07 at σ = 3 % of the spacing,
/// 0.09–0.12 at 5 %, 0.13–0.42 at 7 % (the triangulation starts to fall the other way); Poisson-disk references of
/// 40–90 elements 0.39–0.53.
pub(crate) const MAX_RMS_RESIDUAL: f64 = 0.15;
/// Largest integer coordinate of a ring offset in the basis (a ring reaches its nearest few sites).
pub(crate) const MAX_INDEX: i64 = 3;
/// A point farther than this many lengths of `b1` from a site is not on it.
pub(crate) const OFF_SITE: f64 = 0.25;
/// Least angle between the basis vectors' lines (radians): 20°.
const MIN_BASIS_ANGLE: f64 = 0.349;
/// A basis whose vectors' lengths differ by less than this share, at an angle within [`REGULAR_ANGLE`] of 60°
/// (120°) or 90°, is taken as the hexagonal or square lattice the hand meant.
const REGULAR_LENGTH: f64 = 0.05;
/// See [`REGULAR_LENGTH`] (radians): 3°.
const REGULAR_ANGLE: f64 = 0.0524;
const HEXAGONAL: f64 = std::f64::consts::FRAC_PI_3;

/// A lattice: the sites `origin + i b1 + j b2` for integers `i`, `j`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// The basis, `b1` the shorter.
    pub basis: [DVec2; 2],
    /// The root mean square distance of the reference's ring offsets from their lattice vectors (m): how far the
    /// hand placed its elements from the lattice.
    pub spread: f64,
}

impl Lattice {
    /// The lattice under a reference's interior rings, given as every `offset` from an interior element to one of its
    /// ring's (both ways along each edge), with the shortest edge; None when the reference is not near-regular.
    pub(crate) fn estimate(offsets: &[DVec2], shortest_edge: f64) -> Option<Lattice> {
        if offsets.len() < 4 {
            return None;
        }
        let means = cluster_means(offsets, 0.25 * shortest_edge);
        let basis = reduced(initial_basis(&means)?);
        let coordinates: Vec<(i64, i64)> = offsets
            .iter()
            .map(|&o| integer_coordinates(basis, o))
            .collect();
        if coordinates
            .iter()
            .any(|&(i, j)| i.abs() > MAX_INDEX || j.abs() > MAX_INDEX || (i, j) == (0, 0))
        {
            return None;
        }
        // where a cell's diagonals are equally long, the triangulation kept the shorter of each pair: biased short
        let either = ((basis[0] + basis[1]).length() - (basis[0] - basis[1]).length()).abs()
            <= REGULAR_LENGTH * (basis[0] + basis[1]).length();
        let unbiased: Vec<(DVec2, (i64, i64))> = offsets
            .iter()
            .copied()
            .zip(coordinates.iter().copied())
            .filter(|&(_, (i, j))| !(either && i.abs() == 1 && j.abs() == 1))
            .collect();
        let (fit_offsets, fit_coordinates): (Vec<DVec2>, Vec<(i64, i64)>) =
            unbiased.into_iter().unzip();
        let basis = regularised(least_squares_basis(&fit_offsets, &fit_coordinates)?);
        let residuals: Vec<f64> = offsets
            .iter()
            .zip(&coordinates)
            .map(|(&o, &(i, j))| o.distance(i as f64 * basis[0] + j as f64 * basis[1]))
            .collect();
        let unit = basis[0].length();
        let rms = (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt();
        let worst = residuals.iter().copied().fold(0.0, f64::max);
        (worst <= MAX_RESIDUAL * unit && rms <= MAX_RMS_RESIDUAL * unit)
            .then_some(Lattice { basis, spread: rms })
    }

    /// The turns (radians, in [0, 2π)) that map the lattice onto itself: every 60° for a hexagonal one, 90° for a
    /// square one, else a half turn.
    pub(crate) fn symmetries(&self) -> Vec<f64> {
        let [a, b] = self.basis;
        let step = if is_regular(a, b, HEXAGONAL) {
            std::f64::consts::FRAC_PI_3
        } else if is_regular(a, b, std::f64::consts::FRAC_PI_2) {
            std::f64::consts::FRAC_PI_2
        } else {
            std::f64::consts::PI
        };
        let count = (std::f64::consts::TAU / step).round() as usize;
        (0..count).map(|k| k as f64 * step).collect()
    }

    /// The symmetry turn nearest to `theta` (radians).
    pub(crate) fn nearest_symmetry(&self, theta: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        self.symmetries()
            .into_iter()
            .min_by(|&x, &y| {
                let dx = (theta - x).rem_euclid(tau);
                let dy = (theta - y).rem_euclid(tau);
                dx.min(tau - dx).total_cmp(&dy.min(tau - dy))
            })
            .unwrap_or(0.0)
    }

    /// What a user calls the lattice: hexagonal, square, rhombic (bricks in a running bond), rectangular or oblique.
    pub fn name(&self) -> &'static str {
        let [a, b] = self.basis;
        if is_regular(a, b, HEXAGONAL) {
            "hexagonal"
        } else if is_regular(a, b, std::f64::consts::FRAC_PI_2) {
            "square"
        } else if (a.length() - b.length()).abs() <= REGULAR_LENGTH * b.length() {
            "rhombic"
        } else if a.angle_to(b).cos().abs() <= REGULAR_ANGLE.sin() {
            "rectangular"
        } else {
            "oblique"
        }
    }

    /// Whether `offsets` (counter-clockwise) are a whole ring of the lattice's Delaunay triangulation: each one and
    /// each step between neighbouring ones no longer than the shorter diagonal of the reduced cell (either diagonal
    /// when they are equal, as on a square lattice or bricks). A reference placed by hand has, along its outline,
    /// elements whose fan closes with a triangle of just under 2π/3 or reaches a second neighbour (√3 away on a
    /// hexagonal lattice): copied, their rings connect sites no other ring connects.
    pub(crate) fn is_ring(&self, offsets: &[DVec2]) -> bool {
        let [a, b] = self.basis;
        let longest =
            (1.0 + REGULAR_LENGTH) * (a + b).length().min((a - b).length()).max(b.length());
        let n = offsets.len();
        n >= 3
            && (0..n).all(|k| {
                offsets[k].length() <= longest
                    && offsets[k].distance(offsets[(k + 1) % n]) <= longest
            })
    }

    /// Whether `v` is a diagonal of a cell whose two diagonals are equally long (a square lattice's, or bricks'
    /// rows and columns): four sites on a circle, whose Delaunay triangulation takes either diagonal, so that
    /// elements of one pattern have it in some cells and not in others.
    pub(crate) fn is_either_diagonal(&self, v: DVec2) -> bool {
        let [a, b] = self.basis;
        let (plus, minus) = (a + b, a - b);
        let tolerance = 0.5 * OFF_SITE * a.length();
        (plus.length() - minus.length()).abs() <= REGULAR_LENGTH * plus.length()
            && [plus, -plus, minus, -minus]
                .iter()
                .any(|d| d.distance(v) <= tolerance)
    }

    /// The lattice vector nearest to `offset`.
    pub(crate) fn vector_near(&self, offset: DVec2) -> DVec2 {
        let (i, j) = integer_coordinates(self.basis, offset);
        i as f64 * self.basis[0] + j as f64 * self.basis[1]
    }
}

/// The means of the offsets' clusters, with their sizes: each offset joins the nearest mean within `radius` (the
/// mean following it), else starts a cluster; a second pass reassigns every offset to its nearest first-pass mean.
fn cluster_means(offsets: &[DVec2], radius: f64) -> Vec<(DVec2, usize)> {
    let nearest = |means: &[(DVec2, usize)], o: DVec2| {
        means
            .iter()
            .enumerate()
            .map(|(k, m)| (k, m.0.distance(o)))
            .filter(|&(_, d)| d <= radius)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    };
    let mut means: Vec<(DVec2, usize)> = Vec::new();
    for &o in offsets {
        match nearest(&means, o) {
            Some(k) => {
                let (mean, n) = means[k];
                means[k] = ((mean * n as f64 + o) / (n + 1) as f64, n + 1);
            }
            None => means.push((o, 1)),
        }
    }
    let mut sums = vec![(DVec2::ZERO, 0usize); means.len()];
    for &o in offsets {
        if let Some(k) = nearest(&means, o) {
            sums[k].0 += o;
            sums[k].1 += 1;
        }
    }
    sums.into_iter()
        .filter(|s| s.1 > 0)
        .map(|(sum, n)| (sum / n as f64, n))
        .collect()
}

/// `b1` the shortest well-populated cluster mean, `b2` the shortest one well off `b1`'s line.
fn initial_basis(means: &[(DVec2, usize)]) -> Option<[DVec2; 2]> {
    let largest = means.iter().map(|m| m.1).max()?;
    let mut candidates: Vec<DVec2> = means
        .iter()
        .filter(|m| m.1 * 10 >= largest && m.1 >= 2)
        .map(|m| m.0)
        .collect();
    candidates.sort_by(|a, b| a.length_squared().total_cmp(&b.length_squared()));
    let b1 = *candidates.first()?;
    let b2 = candidates
        .iter()
        .copied()
        .find(|c| b1.angle_to(*c).sin().abs() >= MIN_BASIS_ANGLE.sin())?;
    Some([b1, b2])
}

/// The Lagrange–Gauss reduction of a basis: the shortest basis of the same lattice, `b1` the shorter.
fn reduced([mut a, mut b]: [DVec2; 2]) -> [DVec2; 2] {
    if a.length_squared() > b.length_squared() {
        std::mem::swap(&mut a, &mut b);
    }
    for _ in 0..64 {
        let mu = (a.dot(b) / a.length_squared()).round();
        b -= mu * a;
        if b.length_squared() >= a.length_squared() {
            break;
        }
        std::mem::swap(&mut a, &mut b);
    }
    [a, b]
}

/// Whether `a` and `b` are as long as each other and `angle` (or its supplement) apart, within what a hand places.
fn is_regular(a: DVec2, b: DVec2, angle: f64) -> bool {
    let (la, lb) = (a.length(), b.length());
    let between = a.angle_to(b).abs();
    (la - lb).abs() <= REGULAR_LENGTH * la.max(lb)
        && ((between - angle).abs() <= REGULAR_ANGLE
            || (between - (std::f64::consts::PI - angle)).abs() <= REGULAR_ANGLE)
}

/// A nearly hexagonal or square basis made exactly so (same lengths, the mean of the two; the angle exact, `b2`
/// turned from `b1` the way it was), so that its symmetry turns map its sites exactly onto sites; else as it is.
fn regularised([a, b]: [DVec2; 2]) -> [DVec2; 2] {
    let length = 0.5 * (a.length() + b.length());
    let between = a.angle_to(b);
    for angle in [HEXAGONAL, std::f64::consts::FRAC_PI_2] {
        if is_regular(a, b, angle) {
            let exact = if (between.abs() - angle).abs() <= REGULAR_ANGLE {
                angle
            } else {
                std::f64::consts::PI - angle
            };
            let unit = a.normalize();
            return [
                unit * length,
                DVec2::from_angle(exact.copysign(between)).rotate(unit) * length,
            ];
        }
    }
    [a, b]
}

/// The integer coordinates of the lattice vector nearest to `offset` (the real coordinates rounded: exact for a
/// reduced basis within half a site of a vector).
fn integer_coordinates(basis: [DVec2; 2], offset: DVec2) -> (i64, i64) {
    let det = basis[0].perp_dot(basis[1]);
    let i = offset.perp_dot(basis[1]) / det;
    let j = basis[0].perp_dot(offset) / det;
    (i.round() as i64, j.round() as i64)
}

/// The basis that minimises Σ ‖o − (i b1 + j b2)‖² over the offsets with their integer coordinates.
fn least_squares_basis(offsets: &[DVec2], coordinates: &[(i64, i64)]) -> Option<[DVec2; 2]> {
    let (mut sii, mut sij, mut sjj) = (0.0, 0.0, 0.0);
    let (mut si, mut sj) = (DVec2::ZERO, DVec2::ZERO);
    for (&o, &(i, j)) in offsets.iter().zip(coordinates) {
        let (i, j) = (i as f64, j as f64);
        sii += i * i;
        sij += i * j;
        sjj += j * j;
        si += i * o;
        sj += j * o;
    }
    let det = sii * sjj - sij * sij;
    if det.abs() < 1e-9 {
        return None;
    }
    Some([(sjj * si - sij * sj) / det, (sii * sj - sij * si) / det])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arrangement::Element;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn reference(points: impl Iterator<Item = DVec2>) -> Option<Lattice> {
        crate::arrangement::ReferenceArrangement::new(
            points
                .map(|position| Element {
                    position,
                    symbol: 0,
                    rotation: 0.0,
                    scale: 1.0,
                })
                .collect(),
        )
        .expect("a reference")
        .lattice()
        .copied()
    }

    #[test]
    fn a_turned_noisy_hexagonal_lattice_is_found_and_an_irregular_reference_is_not() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let turn = DVec2::from_angle(0.3);
        let lattice = reference((0..49).map(|k| {
            let (r, c) = ((k / 7) as f64, (k % 7) as f64);
            let jitter = DVec2::new(rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05));
            turn.rotate(DVec2::new(c + 0.5 * (r % 2.0), r * 0.866)) + jitter
        }));
        let lattice = lattice.expect("a lattice");
        assert_eq!(lattice.name(), "hexagonal");
        assert!((lattice.basis[0].length() - 1.0).abs() < 0.02);
        assert!((lattice.basis[1].length() - 1.0).abs() < 0.02);
        let angle = lattice.basis[0]
            .angle_to(turn.rotate(DVec2::X))
            .rem_euclid(std::f64::consts::FRAC_PI_3);
        assert!(
            angle.min(std::f64::consts::FRAC_PI_3 - angle) < 0.02,
            "turned as placed: {angle}"
        );
        assert!(lattice.spread < 0.06);

        // a hard-core (dart-throwing) scatter is no lattice
        let mut points: Vec<DVec2> = Vec::new();
        while points.len() < 60 {
            let p = DVec2::new(rng.random_range(0.0..8.0), rng.random_range(0.0..8.0));
            if points.iter().all(|q| q.distance(p) > 0.8) {
                points.push(p);
            }
        }
        assert_eq!(reference(points.into_iter()), None);
    }

    #[test]
    fn reduction_gives_the_shortest_basis() {
        let [a, b] = reduced([DVec2::new(1.0, 0.0), DVec2::new(3.2, 1.0)]);
        assert!((a - DVec2::new(1.0, 0.0)).length() < 1e-12);
        assert!((b - DVec2::new(0.2, 1.0)).length() < 1e-12);
    }
}

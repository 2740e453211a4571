//! Relaxation (seed §5.5): "For each synthesized element, we adjust its ring shape to that of the corresponding
//! reference element", minimising eq. (5) `Σ_i Σ_{j ∈ w(x_i)} ‖x_j − (x_i + r_j^i)‖²` with eq. (6) `x_k = x_k^0`
//! for the constrained elements: "we simply hold the initial element at the initial position. If there are
//! user-specified boundaries, we constrain elements at their generated positions."
//!
//! Readings: the constrained elements are the initial one and those flagged [`super::Arrangement::at_region_boundary`]
//! (stopped by the region or a boundary curve, or existing elements that [`super::grow_arrangement_around`] grew next
//! to); a neighbour an element was not placed with (an edge built later, or a topology change) keeps its current offset
//! as its target, as the seed does for elements that "lose an edge or get an extra edge". Instead of Lagrange
//! multipliers the constraints are substituted, leaving a sparse symmetric positive definite normal system `A x = b` (A
//! a graph Laplacian of the free elements plus the pull of the fixed ones), one per coordinate with the same A. A
//! vanishing Tikhonov term 1e-9 ‖x − x^0‖² keeps A definite on a part of the pattern that no constraint reaches.
//!
//! The solver is `faer`'s sparse Cholesky (LLᵀ, fill-reducing ordering, supernodal for large systems): the problem
//! is symmetric positive definite, which is what a Cholesky is made for (half the work of an LU, no pivoting), and
//! `faer` is pure Rust, actively maintained, MIT-licensed and fast on the 10⁵-unknown systems a paved town makes;
//! `sprs-ldl` is LGPL and slower, `nalgebra-sparse`'s Cholesky has no fill-reducing ordering.

use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use glam::DVec2;

use super::Arrangement;
use crate::error::{Error, Result};

/// The weight of the term that keeps the normal system definite.
const TIKHONOV: f64 = 1e-9;

/// What a relaxation did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// The summed eq. (5) error before (m²).
    pub error_before: f64,
    /// The summed eq. (5) error after (m²).
    pub error_after: f64,
    /// How many elements were held fixed (eq. (6)).
    pub fixed: usize,
}

/// One term of eq. (5): element `i`'s neighbour `j` wanted at `x_i + offset`.
pub(crate) struct Term {
    pub(crate) i: usize,
    pub(crate) j: usize,
    pub(crate) offset: DVec2,
}

fn terms(arrangement: &Arrangement) -> Result<Vec<Term>> {
    let n = arrangement.elements.len();
    let consistent = arrangement.sub_ids.len() == n
        && arrangement.ring_targets.len() == n
        && arrangement.at_region_boundary.len() == n;
    if !consistent {
        return Err(Error::invalid(
            "arrangement",
            "its per-element lists (sub-ids, ring targets, boundary flags) do not match its elements",
        ));
    }
    let mut terms = Vec::new();
    let mut targeted = std::collections::BTreeSet::new();
    for (i, ring) in arrangement.ring_targets.iter().enumerate() {
        for t in ring {
            if t.neighbour >= n || !t.offset.is_finite() {
                return Err(Error::invalid(
                    "arrangement",
                    format!("element {i} has a ring target that is not an element or not finite"),
                ));
            }
            targeted.insert((i, t.neighbour));
            terms.push(Term {
                i,
                j: t.neighbour,
                offset: t.offset,
            });
        }
    }
    for &(a, b) in &arrangement.edges {
        if a >= n || b >= n {
            return Err(Error::invalid(
                "arrangement",
                format!("edge {a}–{b} names an element past its {n} elements"),
            ));
        }
        for (i, j) in [(a, b), (b, a)] {
            if !targeted.contains(&(i, j)) {
                let offset = arrangement.elements[j].position - arrangement.elements[i].position;
                terms.push(Term { i, j, offset });
            }
        }
    }
    Ok(terms)
}

pub(crate) fn error_of(terms: &[Term], x: &[DVec2]) -> f64 {
    terms
        .iter()
        .map(|t| (x[t.j] - x[t.i] - t.offset).length_squared())
        .sum()
}

/// Moves the arrangement's free elements to the least-squares solution of eq. (5)–(6).
pub fn relax_arrangement(arrangement: &mut Arrangement) -> Result<Relaxation> {
    let terms = terms(arrangement)?;
    let n = arrangement.elements.len();
    let x0: Vec<DVec2> = arrangement.elements.iter().map(|e| e.position).collect();
    if x0.iter().any(|p| !p.is_finite()) {
        return Err(Error::invalid(
            "arrangement",
            "an element position is not finite",
        ));
    }
    let error_before = error_of(&terms, &x0);
    let fixed: Vec<bool> = (0..n)
        .map(|i| i == 0 || arrangement.at_region_boundary[i])
        .collect();
    let fixed_count = fixed.iter().filter(|&&f| f).count();
    let x = solve(&x0, &terms, &fixed)?;
    let error_after = error_of(&terms, &x);
    for (e, p) in arrangement.elements.iter_mut().zip(&x) {
        e.position = *p;
    }
    Ok(Relaxation {
        error_before,
        error_after,
        fixed: fixed_count,
    })
}

/// The least-squares positions of eq. (5) with the `fixed` elements held (eq. (6)).
pub(crate) fn solve(x0: &[DVec2], terms: &[Term], fixed: &[bool]) -> Result<Vec<DVec2>> {
    let n = x0.len();
    let mut unknown = vec![usize::MAX; n];
    let mut free = 0;
    for i in 0..n {
        if !fixed[i] {
            unknown[i] = free;
            free += 1;
        }
    }
    if free == 0 {
        return Ok(x0.to_vec());
    }
    // the lower triangle only (the Cholesky reads that side); repeated entries are summed when the matrix is built
    let mut triplets: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(free + 3 * terms.len());
    let mut rhs = vec![DVec2::ZERO; free];
    for i in 0..n {
        if !fixed[i] {
            triplets.push(Triplet::new(unknown[i], unknown[i], TIKHONOV));
            rhs[unknown[i]] += TIKHONOV * x0[i];
        }
    }
    for t in terms {
        // residual x_j − x_i − r
        match (fixed[t.i], fixed[t.j]) {
            (false, false) => {
                let (i, j) = (unknown[t.i], unknown[t.j]);
                triplets.push(Triplet::new(i, i, 1.0));
                triplets.push(Triplet::new(j, j, 1.0));
                triplets.push(Triplet::new(i.max(j), i.min(j), -1.0));
                rhs[j] += t.offset;
                rhs[i] -= t.offset;
            }
            (true, false) => {
                let j = unknown[t.j];
                triplets.push(Triplet::new(j, j, 1.0));
                rhs[j] += x0[t.i] + t.offset;
            }
            (false, true) => {
                let i = unknown[t.i];
                triplets.push(Triplet::new(i, i, 1.0));
                rhs[i] += x0[t.j] - t.offset;
            }
            (true, true) => {}
        }
    }
    let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(free, free, &triplets)
        .map_err(|e| Error::invalid("relaxation", format!("cannot build the system: {e:?}")))?;
    let llt = matrix.sp_cholesky(Side::Lower).map_err(|e| {
        Error::invalid(
            "relaxation",
            format!("the normal system is not positive definite: {e:?}"),
        )
    })?;
    let mut b = Mat::from_fn(free, 2, |r, c| if c == 0 { rhs[r].x } else { rhs[r].y });
    llt.solve_in_place(b.as_mut());
    let mut x = x0.to_vec();
    for i in 0..n {
        if !fixed[i] {
            let p = DVec2::new(b[(unknown[i], 0)], b[(unknown[i], 1)]);
            if !p.is_finite() {
                return Err(Error::invalid(
                    "relaxation",
                    "the solve gave a non-finite position",
                ));
            }
            x[i] = p;
        }
    }
    Ok(x)
}

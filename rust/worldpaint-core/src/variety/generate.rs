//! Generating many variants (seed §4.3, §6.1's "create random instance"): seeded random choices, assembled and
//! checked for new self-intersections in parallel.
//!
//! The choices are drawn one after the other from one `ChaCha8Rng` seeded by the caller, in batches whose size
//! depends only on how many are still wanted; each batch is assembled and checked with rayon and gathered in draw
//! order. So the same atlas, labels and seed give the same variants in the same order at any thread count.
//! Repeated choices are skipped, so the variants are distinct assemblies.

use super::assemble::{Assembled, Choice};
use super::atlas::{Atlas, TOLERANCE};
use super::intersect::{new_intersection, IntersectionLabels};
use crate::error::{Error, Result};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::HashSet;

/// Why an assembly was rejected.
#[derive(Clone, Debug, PartialEq)]
pub enum Rejection {
    /// Two faces intersect that did not in the original (output face indices, lower first).
    SelfIntersection(u32, u32),
    /// A connecting region did not close: its two placements were this far apart (m).
    Crack(f64),
}

/// What [`generate`] asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct GenerateOptions {
    /// Variants wanted.
    pub count: usize,
    /// The seed of every random choice.
    pub seed: u64,
    /// Most assemblies drawn in all (kept or rejected); 0 takes four times `count`.
    pub max_attempts: usize,
}

/// What [`generate`] made.
#[derive(Clone, Debug)]
pub struct Generation {
    /// The kept variants with their choices, in draw order.
    pub accepted: Vec<(Choice, Assembled)>,
    /// The rejected choices and why, in draw order.
    pub rejected: Vec<(Choice, Rejection)>,
}

/// Assembles `choice` and checks it: a crack past the tolerance or a new self-intersection rejects it.
pub fn check_assembly(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    choice: &Choice,
) -> Result<std::result::Result<Assembled, Rejection>> {
    let a = atlas.assemble(choice)?;
    let reach = a
        .model
        .vertices
        .iter()
        .map(|p| p.length())
        .fold(1.0, f64::max);
    if !(a.max_gap <= TOLERANCE * reach) {
        return Ok(Err(Rejection::Crack(a.max_gap)));
    }
    Ok(match new_intersection(&a.model, &a.face_origin, labels) {
        Some((f, g)) => Err(Rejection::SelfIntersection(f, g)),
        None => Ok(a),
    })
}

/// [`check_assembly`] of many choices in parallel, in their order.
pub fn check_assemblies(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    choices: &[Choice],
) -> Result<Vec<std::result::Result<Assembled, Rejection>>> {
    choices
        .par_iter()
        .map(|c| check_assembly(atlas, labels, c))
        .collect()
}

/// Draws, assembles and checks random variants until `count` are kept or `max_attempts` are drawn.
pub fn generate(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    options: &GenerateOptions,
) -> Result<Generation> {
    crate::limits::check(
        "variants to generate",
        options.count as f64,
        crate::limits::MAX_INSTANCES,
        "variants",
    )?;
    let attempts = if options.max_attempts == 0 {
        options.count.saturating_mul(4)
    } else {
        options.max_attempts
    };
    let total = atlas.count();
    if total == 0 {
        return Err(Error::invalid("atlas", "it makes no assembly"));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut seen: HashSet<Choice> = HashSet::new();
    let mut drawn = 0usize;
    let mut out = Generation {
        accepted: Vec::new(),
        rejected: Vec::new(),
    };
    while out.accepted.len() < options.count && drawn < attempts && (seen.len() as u128) < total {
        let want = (options.count - out.accepted.len()).min(attempts - drawn);
        let mut batch = Vec::with_capacity(want);
        while batch.len() < want && drawn < attempts && (seen.len() as u128) < total {
            let c = atlas.random_choice(&mut rng);
            drawn += 1;
            if seen.insert(c.clone()) {
                batch.push(c);
            }
        }
        let results = check_assemblies(atlas, labels, &batch)?;
        for (choice, r) in batch.into_iter().zip(results) {
            match r {
                Ok(a) if out.accepted.len() < options.count => out.accepted.push((choice, a)),
                Ok(_) => {}
                Err(why) => out.rejected.push((choice, why)),
            }
        }
    }
    Ok(out)
}

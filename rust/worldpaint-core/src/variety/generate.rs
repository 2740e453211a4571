//! Generating many variants (seed §4.3, §6.1's "create random instance"): seeded random choices, assembled and
//! checked for new self-intersections in parallel.
//!
//! The choices are drawn one after the other from one `ChaCha8Rng` seeded by the caller, in batches whose size
//! depends only on how many are still wanted; each batch is assembled and checked with rayon and gathered in draw
//! order. So the same atlas, labels and seed give the same variants in the same order at any thread count.
//! Repeated choices are skipped, so the variants are distinct assemblies, and so different models (the atlas holds
//! no variant that would repeat one).
//!
//! Random draws find fewer and fewer new assemblies as they use up #V (asking 1,000 of 1,000 by draws alone gives
//! about 983 within four times as many draws). So when the count asked reaches #V, or when the draws stall (their
//! attempts spent with fewer variants kept than asked), every assembly not yet drawn is enumerated instead, in an
//! order shuffled by the same seed: the generation then gives min(count, #V) distinct variants less the rejected
//! ones. Enumeration is done only for an atlas of at most [`ENUMERATION_LIMIT`] assemblies (a larger one does not
//! stall on repeats).

use super::assemble::{Assembled, Choice};
use super::atlas::{Atlas, TOLERANCE};
use super::intersect::{between_parts, intersecting_faces, IntersectionLabels};
use super::model::Model;
use crate::error::{Error, Result};
use rand::seq::SliceRandom;
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

/// Most assemblies an atlas may make for [`generate`] to enumerate them all when random draws cannot finish.
pub(super) const ENUMERATION_LIMIT: u128 = 1 << 22;

/// What [`generate`] made.
#[derive(Clone, Debug)]
pub struct Generation {
    /// The kept variants with their choices, in draw order.
    pub accepted: Vec<(Choice, Assembled)>,
    /// The rejected choices and why, in draw order.
    pub rejected: Vec<(Choice, Rejection)>,
    /// Whether every assembly of the atlas was tried (kept or rejected): no other variant can be made.
    pub exhausted: bool,
}

/// The first new intersecting pair of faces of a mesh, if any.
type FacePair = Option<(u32, u32)>;

/// Checks the assemblies of one atlas against the original's intersection labels. The intersections inside one
/// placed variant do not depend on the assembly (the variant moves as a solid), so each node variant is checked alone
/// once, here; an assembly then only tests pairs of faces from different placed variants.
pub(super) struct AssemblyChecker<'a> {
    atlas: &'a Atlas,
    labels: &'a IntersectionLabels,
    /// `own[g][c][e]`: the first new intersecting pair of faces inside entry `e` of node `c` of graph `g`, in the
    /// variant's own face numbering.
    own: Vec<Vec<Vec<FacePair>>>,
}

impl<'a> AssemblyChecker<'a> {
    /// Checks every node variant of `atlas` alone (in parallel).
    pub(super) fn new(atlas: &'a Atlas, labels: &'a IntersectionLabels) -> AssemblyChecker<'a> {
        let own = atlas
            .graphs()
            .iter()
            .map(|g| {
                g.nodes
                    .iter()
                    .enumerate()
                    .map(|(c, entries)| {
                        entries
                            .par_iter()
                            .map(|node| {
                                let v = &atlas.variants(c)[node.variant];
                                let alone = Model {
                                    vertices: node
                                        .positions
                                        .clone()
                                        .unwrap_or_else(|| v.model.vertices.clone()),
                                    faces: v.model.faces.clone(),
                                    uvs: None,
                                    materials: None,
                                };
                                let allowed = |a: u32, b: u32| match (
                                    v.face_origin.get(a as usize).copied().flatten(),
                                    v.face_origin.get(b as usize).copied().flatten(),
                                ) {
                                    (Some(oa), Some(ob)) => labels.allows(oa, ob),
                                    _ => false,
                                };
                                intersecting_faces(&alone, allowed, 1).first().copied()
                            })
                            .collect()
                    })
                    .collect()
            })
            .collect();
        AssemblyChecker { atlas, labels, own }
    }

    /// Assembles `choice` and checks it: a crack past the tolerance or a new self-intersection rejects it.
    pub(super) fn check(
        &self,
        choice: &Choice,
    ) -> Result<std::result::Result<Assembled, Rejection>> {
        let a = self.atlas.assemble(choice)?;
        let reach = a
            .model
            .vertices
            .iter()
            .map(|p| p.length())
            .fold(1.0, f64::max);
        if !(a.max_gap <= TOLERANCE * reach) {
            return Ok(Err(Rejection::Crack(a.max_gap)));
        }
        for (i, placed) in a.instances.iter().enumerate() {
            let own = self
                .own
                .get(choice.graph)
                .and_then(|g| g.get(placed.component))
                .and_then(|n| n.get(placed.entry))
                .copied()
                .flatten();
            if let Some((fa, fb)) = own {
                let output = |f: u32| {
                    a.face_source
                        .iter()
                        .position(|&s| s == (i as u32, f))
                        .map_or(u32::MAX, |k| k as u32)
                };
                let (x, y) = (output(fa), output(fb));
                return Ok(Err(Rejection::SelfIntersection(x.min(y), x.max(y))));
            }
        }
        let parts: Vec<u32> = a.face_source.iter().map(|s| s.0).collect();
        Ok(
            match between_parts(&a.model, &a.face_origin, &parts, self.labels) {
                Some((f, g)) => Err(Rejection::SelfIntersection(f, g)),
                None => Ok(a),
            },
        )
    }
}

/// Assembles `choice` and checks it (see `AssemblyChecker`; for many choices, make one checker).
pub fn check_assembly(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    choice: &Choice,
) -> Result<std::result::Result<Assembled, Rejection>> {
    AssemblyChecker::new(atlas, labels).check(choice)
}

/// [`check_assembly`] of many choices in parallel, in their order.
pub fn check_assemblies(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    choices: &[Choice],
) -> Result<Vec<std::result::Result<Assembled, Rejection>>> {
    let checker = AssemblyChecker::new(atlas, labels);
    choices.par_iter().map(|c| checker.check(c)).collect()
}

/// Draws, assembles and checks random variants until `count` are kept or `max_attempts` are drawn; then, when
/// fewer are kept than asked and the assemblies never drawn are no more than the attempts (the draws stalled on
/// repeats), checks those in a seeded order until `count` are kept or none is left. A count of #V or more enumerates
/// every assembly from the start (a count past #V asks for #V). Enumeration needs #V ≤ `ENUMERATION_LIMIT`; a count
/// past [`crate::limits::MAX_INSTANCES`] that #V does not bring down is refused.
pub fn generate(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    options: &GenerateOptions,
) -> Result<Generation> {
    let total = atlas.count();
    if total == 0 {
        return Err(Error::invalid("atlas", "it makes no assembly"));
    }
    // a count of #V or more asks for every model once: #V is what is made
    let options = &GenerateOptions {
        count: usize::try_from(total).map_or(options.count, |all| options.count.min(all)),
        ..options.clone()
    };
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
    let checker = AssemblyChecker::new(atlas, labels);
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut seen: HashSet<Choice> = HashSet::new();
    let mut out = Generation {
        accepted: Vec::new(),
        rejected: Vec::new(),
        exhausted: false,
    };
    let enumerable = total <= ENUMERATION_LIMIT;
    let enumerate_all = enumerable && options.count as u128 >= total;
    let mut drawn = 0usize;
    while !enumerate_all
        && out.accepted.len() < options.count
        && drawn < attempts
        && (seen.len() as u128) < total
    {
        let want = (options.count - out.accepted.len()).min(attempts - drawn);
        let mut batch = Vec::with_capacity(want);
        while batch.len() < want && drawn < attempts && (seen.len() as u128) < total {
            let c = atlas.random_choice(&mut rng);
            drawn += 1;
            if seen.insert(c.clone()) {
                batch.push(c);
            }
        }
        check_batch(&checker, batch, options.count, &mut out)?;
    }
    let mut tried = seen.len() as u128;
    let stalled = total - tried <= attempts as u128;
    if out.accepted.len() < options.count && enumerable && (enumerate_all || stalled) {
        // the assemblies not drawn yet, in an order shuffled by the seed (Fisher–Yates on their numbers)
        let mut order: Vec<u64> = (0..total as u64).collect();
        order.shuffle(&mut rng);
        let mut rest = order.into_iter();
        while out.accepted.len() < options.count {
            let want = (options.count - out.accepted.len()).min(4096);
            let mut batch = Vec::with_capacity(want);
            for k in rest.by_ref() {
                let c = atlas.choice(u128::from(k))?;
                if !seen.contains(&c) {
                    batch.push(c);
                    if batch.len() == want {
                        break;
                    }
                }
            }
            if batch.is_empty() {
                break;
            }
            tried += batch.len() as u128;
            check_batch(&checker, batch, options.count, &mut out)?;
        }
    }
    out.exhausted = tried == total;
    Ok(out)
}

/// Checks a batch of new choices in parallel and keeps them in their order, up to `count` accepted in all.
fn check_batch(
    checker: &AssemblyChecker<'_>,
    batch: Vec<Choice>,
    count: usize,
    out: &mut Generation,
) -> Result<()> {
    let results: Vec<_> = batch
        .par_iter()
        .map(|c| checker.check(c))
        .collect::<Result<_>>()?;
    for (choice, r) in batch.into_iter().zip(results) {
        match r {
            Ok(a) if out.accepted.len() < count => out.accepted.push((choice, a)),
            Ok(_) => {}
            Err(why) => out.rejected.push((choice, why)),
        }
    }
    Ok(())
}

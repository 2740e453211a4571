//! An arrangement color painted into a scene: every tool's synthesis of such a color comes here. The region is grown
//! from the elements of the color's categories already around it ([`crate::arrangement::grow_arrangement_around`]), so
//! a paste next to a pattern, or a spray dab at its edge, continues it without a seam; with none around, growth starts
//! at the guides' start point or the region's centre. The guides (start, boundary curves, flow curves) come with the
//! synthesis options; other colors ignore them.

use glam::DVec2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::arrangement::{
    gaussian, grow_arrangement_around, pattern_fidelity, ArrangementColor, Element, FlowField,
    GrowthNoise, GrowthOptions, PatternFidelity, PatternRotation,
};
use crate::error::{Error, Result};
use crate::geom::Region;
use crate::limits;
use crate::palette::Color;
use crate::scene::{Instance, Scene};
use crate::synthesis::{scene_categories, PaintRequest, SynthesisResult};

/// The elements already around `region` count within this many of the reference's longest edges: enough to
/// rebuild the rings of those at its edge.
const CONTEXT_EDGES: f64 = 3.0;

/// The random stream the colour noise draws from.
const TINT_STREAM: u64 = 1;

/// The part of `region` a pattern is painted in: on the terrain when the scene has one.
fn painted_region(scene: &Scene, region: &Region) -> Result<Region> {
    match scene.terrain.as_deref() {
        Some(t) => t.clip(region).ok_or_else(|| Error::RegionOffTerrain {
            reason: "the region and the terrain do not overlap".into(),
        }),
        None => Ok(region.clone()),
    }
}

/// What `region` of `scene` holds of the arrangement color `color`, against its reference
/// ([`crate::arrangement::pattern_fidelity`]): the figures a paste reports. None when `color` is not an arrangement.
pub fn painted_fidelity(
    scene: &Scene,
    region: &Region,
    color: &Color,
) -> Result<Option<PatternFidelity>> {
    let Some(pattern) = color.arrangement() else {
        return Ok(None);
    };
    let reference = pattern.reference()?;
    let region = painted_region(scene, region)?;
    let (_, scene_index) = scene_categories(scene, color);
    let elements: Vec<Element> = scene
        .instances
        .iter()
        .filter_map(|i| {
            let symbol = scene_index.iter().position(|&c| c == i.category)?;
            Some(Element {
                position: i.position,
                symbol: symbol as u32,
                rotation: i.rotation,
                scale: i.scale,
            })
        })
        .collect();
    Ok(Some(pattern_fidelity(&reference, &elements, &region)))
}

/// Paints the arrangement `pattern` of `color` into `region` of `scene` (the scene's unlocked content there
/// already cleared by the tool); `keep` says which of the scene's instances stay to continue from.
pub(crate) fn paint(
    request: PaintRequest<'_>,
    pattern: &ArrangementColor,
) -> Result<SynthesisResult> {
    let (scene, color, opts) = (request.scene, request.color, request.opts);
    let reference = pattern.reference()?;
    let region = painted_region(scene, request.region)?;
    let (categories, scene_index) = scene_categories(scene, color);
    let symbol_of = |category: usize| scene_index.iter().position(|&c| c == category);
    let reach = CONTEXT_EDGES * reference.longest_edge();
    let (lo, hi) = region.bbox();
    let (lo, hi) = (lo - DVec2::splat(reach), hi + DVec2::splat(reach));
    let existing: Vec<Element> = scene
        .instances
        .iter()
        .filter(|i| i.position.cmpge(lo).all() && i.position.cmple(hi).all() && (request.keep)(i))
        .filter_map(|i| {
            symbol_of(i.category).map(|s| Element {
                position: i.position,
                symbol: s as u32,
                rotation: i.rotation,
                scale: 1.0,
            })
        })
        .collect();
    let flow = match (&pattern.rotation, opts.guides.flow.is_empty()) {
        (PatternRotation::Flow, true) => {
            return Err(Error::invalid(
                format!("color '{}'", color.name),
                "follows a flow field: draw curves for it and pick them as the flow",
            ))
        }
        (_, true) => None,
        (_, false) => Some(FlowField::from_curves(&opts.guides.flow)?),
    };
    let growth = GrowthOptions {
        rotation: pattern.rotation.mode(),
        max_elements: limits::MAX_INSTANCES as usize,
        seed: opts.seed,
        priorities: color
            .categories
            .iter()
            .enumerate()
            // a lower category priority value is painted first, a higher growth priority grows first
            .map(|(k, c)| (k as u32, -c.category.priority))
            .collect(),
        relax_every: pattern.relax_every,
        flow,
        boundaries: opts.guides.boundaries.clone(),
        noise: GrowthNoise {
            scale: pattern.scale_noise,
            rotation: pattern.rotation_noise,
        },
        ..Default::default()
    };
    let grown = grow_arrangement_around(
        &reference,
        &region,
        &existing,
        opts.guides.start,
        &growth,
        request.progress,
    )?;
    // the colour noise draws from its own stream of the run's seed, so that it leaves the growth as it was
    let mut tints = ChaCha8Rng::seed_from_u64(opts.seed);
    tints.set_stream(TINT_STREAM);
    let instances = grown.elements[existing.len()..]
        .iter()
        .zip(&grown.sub_ids[existing.len()..])
        .map(|(e, &sub)| {
            let tint = pattern.color_noise * gaussian(&mut tints);
            (e, sub, tint.clamp(-1.0, 1.0) as f32)
        })
        // relaxation may nudge an element by a few millimetres across the region's edge: the region is the user's
        .filter(|(e, _, _)| region.contains(e.position))
        .map(|(e, sub, tint)| {
            let r = &pattern.elements[sub];
            Instance {
                position: e.position,
                rotation: e.rotation,
                scale: r.scale * e.scale,
                category: scene_index[e.symbol as usize],
                prototype: r.prototype,
                locked: false,
                tint,
            }
        })
        .collect();
    Ok(SynthesisResult {
        categories,
        instances,
        ..Default::default()
    })
}

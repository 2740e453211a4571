//! The one door through which a color is painted into a scene, above the two painters: a color of statistics is
//! synthesized from its histograms ([`crate::synthesis`]), an arrangement color is grown from its reference
//! (`pattern`, with [`crate::arrangement`]'s growth). The tools, the world's tiles and the bindings call this module,
//! so that neither painter knows of the other and a new kind of color is added here alone.

mod pattern;

pub use pattern::painted_fidelity;

use crate::error::Result;
use crate::geom::{PreparedRegion, Region, RegionQueries};
use crate::palette::{Color, ColorKind};
use crate::scene::{Instance, Scene};
use crate::synthesis::{PaintRequest, SynthesisOptions, SynthesisResult};

/// Synthesize the color in `region`. The scene's unlocked instances *inside* the region are treated as removed
/// (paste replaces); locked ones inside it and all within the influence radius outside it condition the result.
/// Paths and contours are all kept as they are (the paste tool cuts them at the region first).
pub fn synthesize(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
) -> Result<SynthesisResult> {
    synthesize_with_progress(scene, color, region, opts, &|_| true)
}

/// As [`synthesize`], calling `progress` with the fraction done; returning false cancels
/// ([`crate::Error::Cancelled`]).
pub fn synthesize_with_progress(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<SynthesisResult> {
    // the scene's instances around a drawn outline can be many: its polygons are indexed once, when one is asked
    let inside = std::sync::OnceLock::new();
    synthesize_keeping(PaintRequest {
        scene,
        color,
        region,
        opts,
        progress,
        keep: &|i: &Instance| {
            i.locked
                || !inside
                    .get_or_init(|| PreparedRegion::new(region))
                    .contains(i.position)
        },
    })
}

/// Paints the request's color in its region, conditioned on the scene's instances for which `keep` holds (those the
/// caller does not remove): the color and the region are checked, then the color's painter runs.
pub(crate) fn synthesize_keeping(request: PaintRequest<'_>) -> Result<SynthesisResult> {
    request.region.validate()?;
    request.color.validate()?;
    match &request.color.kind {
        ColorKind::Arrangement(pattern) => pattern::paint(request, pattern),
        ColorKind::Statistics => crate::synthesis::synthesize_keeping(request),
    }
}

//! Adapting moved content to its new place (Section 5.4 "Move"; thesis 6.4.2): "Starting with the objects within
//! the region, we randomly choose an existing point `p` and apply to it small displacement perturbations, instead
//! of births, to find a new location `p'`. We favor local displacements to preserve the visual appearance of the
//! original object arrangement ... By also performing death steps, objects with very small probability values are
//! removed ... we allow the equivalent number of births to preserve the total number of objects".
//!
//! Per category of the color, in priority order, with the density `f` of eq. (1) in its product form (the pair
//! factors `h` with the content around and with the moved content of equal or higher priority, and the map
//! factors `ψ`):
//!
//! 1. Every moved instance starts at its *anchor*, where the move put it. It is *settled* when its local
//!    probability `ψ(x) Π h(d(x, y))` (saturated as in synthesis) is at least `HISTOGRAM_FLOOR`, the probability
//!    of one pair at a distance the exemplar never showed. Settled instances do not move at all: the arrangement
//!    travels rigidly wherever it fits, which is what keeps a drag free of flicker.
//! 2. The others take displacement steps `x' = x + N(0, σ_step)` accepted with the Metropolis ratio of
//!    `f(X) · Π K(x_i − a_i)`, where `K` is a Gaussian kernel of width `reach` around the anchor ("the probability
//!    function `f` can be multiplied by a Gaussian kernel depending on the distance", thesis 6.4.2). A forbidden
//!    place (`ψ = 0`, a hard core, off the terrain) counts as probability `e^-1e6`, so steps between forbidden
//!    places follow the kernel alone and any allowed place is taken at once.
//! 3. Instances still below the floor after their steps die; as many are born, each at an allowed place drawn
//!    uniformly in the region and then relocated by Metropolis steps on `f`.
//!
//! `σ_step` is a quarter of the category's mean spacing `1/√λ`; `reach` defaults to two mean spacings.

use super::structures::StructuredContent;
use super::target::{build_target, Conditioning, Target, FIXED_ID};
use super::{
    attributes, conditioning_content, gaussian, mix_seed, priority_order, scene_categories, Facing,
    HISTOGRAM_FLOOR,
};
use crate::error::{check, Result};
use crate::geom::{DVec2, PreparedRegion, Region, RegionQueries};
use crate::palette::Color;
use crate::scene::{Category, Instance, Scene};
use crate::spatial::GridEntry;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Log-probability standing for "forbidden" in the displacement steps.
const FORBIDDEN: f64 = -1e6;
/// Uniform draws tried per birth before giving up.
const BIRTH_TRIES: usize = 500;
/// Relocation steps per newborn instance.
const BIRTH_STEPS: usize = 20;

/// How to adapt moved content.
#[derive(Clone, Debug)]
pub struct AdaptOptions {
    /// Seed of the adaptation's random choices (displacements, births).
    pub seed: u64,
    /// Width of the band around the region whose content conditions the result (None: the color's radius).
    pub influence_radius: Option<f64>,
    /// Displacement steps per unsettled instance.
    pub steps: usize,
    /// Width of the kernel that keeps an instance near its anchor (None: two mean spacings of its category).
    pub reach: Option<f64>,
}

impl Default for AdaptOptions {
    fn default() -> Self {
        AdaptOptions {
            seed: 0,
            influence_radius: None,
            steps: 60,
            reach: None,
        }
    }
}

/// Where the moved instances ended.
#[derive(Clone, Debug, Default)]
pub(crate) struct Adapted {
    /// Per moved instance (in the given order): its final position, or `None` when it died.
    pub positions: Vec<Option<DVec2>>,
    /// Instances born to keep each category's count; their categories index the scene's list extended by the
    /// color's categories (as [`crate::synthesis::SynthesisResult`]).
    pub births: Vec<Instance>,
    /// Moved instances that were not settled at their anchor.
    pub displaced: usize,
    /// The scene's categories, then the color's new ones.
    pub categories: Vec<Category>,
}

/// Adapts `moving` (instances at their anchors, categories indexing `fixed.categories`) to `region` of the scene
/// `fixed` (the content that stays). Instances of categories the color does not know stay at their anchors.
pub(crate) fn adapt(
    fixed: &Scene,
    color: &Color,
    region: &Region,
    moving: &[Instance],
    opts: &AdaptOptions,
) -> Result<Adapted> {
    region.validate()?;
    color.validate()?;
    let influence = opts.influence_radius.unwrap_or(color.max_radius);
    check::non_negative("influence radius", influence)?;
    if let Some(r) = opts.reach {
        check::positive("reach", r)?;
    }
    let order = priority_order(color, None)?;
    let (categories, scene_index) = scene_categories(fixed, color);
    let terrain = fixed.terrain.as_deref();
    let outline = region;
    // every proposal asks the region: its large polygons are indexed once for the whole call
    let region = &PreparedRegion::new(outline);
    let context = conditioning_content(fixed, &scene_index, region, influence, &|_| true);
    let inside: Vec<Option<Vec<DVec2>>> = vec![None; color.categories.len()];
    let (rlo, rhi) = region.bbox();
    let pad = DVec2::splat(color.max_radius);
    let area = outline.area();
    let mut out = Adapted {
        positions: moving.iter().map(|i| Some(i.position)).collect(),
        ..Default::default()
    };
    // the moved content of each color category, conditioning the categories of lower priority once adapted
    let mut adapted: Vec<Vec<DVec2>> = vec![Vec::new(); color.categories.len()];
    // distances to the graphs and polygons around the destination
    let structured = StructuredContent::near(fixed, outline, influence + color.max_radius);
    for &ci in &order {
        let members: Vec<usize> = (0..moving.len())
            .filter(|&k| moving[k].category == scene_index[ci])
            .collect();
        let mut cond_context = context.clone();
        for (oi, pts) in adapted.iter().enumerate() {
            cond_context[oi].extend_from_slice(pts);
        }
        let cond = Conditioning {
            inside: &inside,
            context: &cond_context,
        };
        let (mut target, self_tag) = build_target(
            color,
            ci,
            &cond,
            &structured,
            terrain,
            (rlo - pad, rhi + pad),
            area,
        );
        let cat = &color.categories[ci];
        let spacing = if cat.density > 0.0 {
            1.0 / cat.density.sqrt()
        } else {
            color.max_radius / 3.0
        };
        let chain = Chain {
            step: 0.25 * spacing,
            reach: opts.reach.unwrap_or(2.0 * spacing),
            floor: HISTOGRAM_FLOOR.ln(),
            self_tag,
            region,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(opts.seed, ci as u64 + 1));
        let anchors: Vec<DVec2> = members.iter().map(|&k| moving[k].position).collect();
        let (positions, displaced) = chain.displace(&mut target, &anchors, opts.steps, &mut rng);
        out.displaced += displaced;
        let deaths = positions.iter().filter(|p| p.is_none()).count();
        let born = chain.births(&mut target, positions.len(), deaths, &mut rng);
        for (&k, p) in members.iter().zip(&positions) {
            out.positions[k] = *p;
        }
        adapted[ci] = positions.iter().flatten().copied().collect();
        adapted[ci].extend_from_slice(&born);
        let facing = Facing::of(cat, &structured);
        for p in born {
            out.births.push(attributes(
                cat,
                p,
                scene_index[ci],
                facing.as_ref(),
                &mut rng,
            ));
        }
    }
    out.categories = categories;
    Ok(out)
}

/// The displacement chain of one category.
struct Chain<'r> {
    step: f64,
    reach: f64,
    /// `ln` of the death threshold.
    floor: f64,
    self_tag: u32,
    region: &'r PreparedRegion<'r>,
}

impl Chain<'_> {
    fn log_f(target: &Target, p: DVec2, id: u32) -> f64 {
        target.energy(p, id).max(FORBIDDEN)
    }

    /// Displacement steps for the instances not settled at their anchors; returns the final positions (`None`:
    /// died) and how many were displaced.
    fn displace<R: Rng>(
        &self,
        target: &mut Target,
        anchors: &[DVec2],
        steps: usize,
        rng: &mut R,
    ) -> (Vec<Option<DVec2>>, usize) {
        for (k, a) in anchors.iter().enumerate() {
            target.grid.insert(GridEntry {
                position: *a,
                tag: self.tag(),
                id: k as u32,
            });
        }
        let mut pos: Vec<DVec2> = anchors.to_vec();
        let unsettled: Vec<usize> = (0..anchors.len())
            .filter(|&k| Self::log_f(target, pos[k], k as u32) < self.floor)
            .collect();
        let kernel = |x: DVec2, a: DVec2| -x.distance_squared(a) / (2.0 * self.reach * self.reach);
        for _ in 0..steps * unsettled.len() {
            let k = unsettled[rng.random_range(0..unsettled.len())];
            let (x, a) = (pos[k], anchors[k]);
            let q = x + gaussian(rng) * self.step;
            if !self.region.contains(q) {
                continue;
            }
            let id = k as u32;
            let log_ratio = Self::log_f(target, q, id) - Self::log_f(target, x, id) + kernel(q, a)
                - kernel(x, a);
            if rng.random::<f64>().ln() < log_ratio {
                target.grid.remove(x, id);
                target.grid.insert(GridEntry {
                    position: q,
                    tag: self.tag(),
                    id,
                });
                pos[k] = q;
            }
        }
        let mut out: Vec<Option<DVec2>> = pos.iter().map(|p| Some(*p)).collect();
        for &k in &unsettled {
            if Self::log_f(target, pos[k], k as u32) < self.floor {
                target.grid.remove(pos[k], k as u32);
                out[k] = None;
            }
        }
        (out, unsettled.len())
    }

    /// `count` births at allowed places in the region, relocated by Metropolis steps on `f`.
    fn births<R: Rng>(
        &self,
        target: &mut Target,
        first_id: usize,
        count: usize,
        rng: &mut R,
    ) -> Vec<DVec2> {
        let mut born: Vec<DVec2> = Vec::new();
        for b in 0..count {
            let id = (first_id + b) as u32;
            let place = (0..BIRTH_TRIES).find_map(|_| {
                let p = self.region.sample_uniform(rng)?;
                (Self::log_f(target, p, FIXED_ID) >= self.floor).then_some(p)
            });
            let Some(mut x) = place else { continue };
            target.grid.insert(GridEntry {
                position: x,
                tag: self.tag(),
                id,
            });
            for _ in 0..BIRTH_STEPS {
                let Some(q) = self.region.sample_uniform(rng) else {
                    break;
                };
                let e_q = Self::log_f(target, q, id);
                if e_q < self.floor {
                    continue;
                }
                if rng.random::<f64>().ln() < e_q - Self::log_f(target, x, id) {
                    target.grid.remove(x, id);
                    target.grid.insert(GridEntry {
                        position: q,
                        tag: self.tag(),
                        id,
                    });
                    x = q;
                }
            }
            born.push(x);
        }
        born
    }

    fn tag(&self) -> u32 {
        self.self_tag
    }
}

//! One synthesis call, category by category in priority order: each category's conditioning on what is already
//! painted, its target, its expected count, its chain (the product model or the rdf-matching chain), and its
//! content (instances, arcs of a graph, contours traced from dense points) added to the result. See the module
//! documentation of [`super`] for the method.

use super::births::BirthIntensity;
use super::structures::StructuredContent;
use super::target::{
    build_target, concentration, lattice_bins, lattice_log, learned_concentration, rake_maps,
    unseen_shares, Conditioning, StructureValues, Target,
};
use super::{
    add_unseen, arcs, attributes, islands, mix_seed, product, rdf, Facing, SynthesisOptions,
    SynthesisResult,
};
use crate::analysis::region_lattice;
use crate::contour::{fill_polygons, fill_polygons_within, trace_contours};
use crate::error::Result;
use crate::geom::{DVec2, PreparedRegion, Region, RegionQueries};
use crate::limits;
use crate::palette::Color;
use crate::scene::{CategoryKind, Contour, Path, Scene};
use crate::terrain::Heightfield;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::OnceLock;

/// Expected count from which synthesis matches the rdf directly (below it, the exemplar's `h` is used as the
/// pair factor, as in the paper).
const MIN_COUNT_FOR_RDF_MATCHING: f64 = 100.0;

/// What one synthesis call paints with and where, the same for every category.
pub(super) struct Painting<'s> {
    scene: &'s Scene,
    color: &'s Color,
    region: &'s PreparedRegion<'s>,
    opts: &'s SynthesisOptions,
    influence: f64,
    terrain: Option<&'s Heightfield>,
    /// Per color category: its index in the result's categories.
    scene_index: Vec<usize>,
    area: f64,
    /// Sample points of the region (on the terrain's lattice when there is one), built when maps first read them:
    /// a square kilometre on a terrain of 2 m cells holds a million.
    lattice: OnceLock<Vec<DVec2>>,
    /// The exemplar region's points on the terrain, when the color was learned on it.
    exemplar_lattice: Option<Vec<DVec2>>,
    /// The region's box grown by the color's largest radius: the extent of the chains' grids.
    bounds: (DVec2, DVec2),
}

/// What the categories synthesized so far leave to the next ones.
pub(super) struct Painted {
    /// Per color category: its points synthesized inside the region in this call.
    pub(super) synthesized: Vec<Option<Vec<DVec2>>>,
    /// Per color category: the fixed content that conditions by product factors.
    pub(super) context: Vec<Vec<DVec2>>,
    pub(super) structured: StructuredContent,
    /// The structures' distance maps read over the lattice so far.
    pub(super) structure_values: StructureValues,
    pub(super) out: SynthesisResult,
}

impl<'s> Painting<'s> {
    pub(super) fn new(
        scene: &'s Scene,
        color: &'s Color,
        region: &'s PreparedRegion<'s>,
        opts: &'s SynthesisOptions,
        influence: f64,
        scene_index: Vec<usize>,
    ) -> Self {
        let terrain = scene.terrain.as_deref();
        let exemplar_lattice = terrain
            .filter(|_| opts.exemplar_on_terrain)
            .map(|t| region_lattice(&color.region, t))
            .filter(|l| !l.is_empty());
        let (rlo, rhi) = region.bbox();
        let pad = DVec2::splat(color.max_radius);
        Painting {
            scene,
            color,
            region,
            opts,
            influence,
            terrain,
            scene_index,
            area: region.region().area(),
            lattice: OnceLock::new(),
            exemplar_lattice,
            bounds: (rlo - pad, rhi + pad),
        }
    }

    /// The region's sample points, built by the first call (see the field `lattice`).
    fn lattice(&self) -> &[DVec2] {
        self.lattice.get_or_init(|| match self.terrain {
            Some(t) => region_lattice(self.region.region(), t),
            None => crate::analysis::region_samples(self.region.region()),
        })
    }

    /// One category in priority order: its conditioning, its target, its expected count, its chain, and its
    /// content added to the result.
    pub(super) fn synthesize_category(
        &self,
        ci: usize,
        state: &mut Painted,
        report: &dyn Fn(f64) -> bool,
    ) -> Result<()> {
        let cat = &self.color.categories[ci];
        let merged = self.condition_on_structures(ci, state);
        let (mut target, self_tag) = self.category_target(ci, state);
        let bins = if target.maps.is_empty() {
            Vec::new()
        } else {
            lattice_bins(&target, self.lattice(), &mut state.structure_values)
        };
        let expected = self.expected_count(ci, &target, &bins, &state.context[ci]);
        // the terrain's maps can raise the count above the density's (a map bin preferred a million-fold)
        limits::check(
            &format!(
                "category '{}' of color '{}'",
                cat.category.name, self.color.name
            ),
            expected,
            limits::MAX_INSTANCES,
            "instances",
        )?;
        // the learned rdf counted the pairs the example's maps concentrated into part of its region; the painted
        // region's maps concentrate them by another factor (see "Maps")
        let learned = match self.exemplar_lattice.as_deref() {
            Some(l) => concentration(&target, l.iter().map(|p| target.maps_log(*p, true))),
            None => learned_concentration(&target),
        };
        if !target.maps.is_empty() && !self.lattice().is_empty() {
            for (name, share) in unseen_shares(&target, &bins) {
                add_unseen(&mut state.out.unseen_maps, name, share);
            }
            rake_maps(&mut target, &bins);
        }
        // read from the bins: a million terrain samples fewer
        let pair_scale = learned
            / concentration(
                &target,
                (0..bins.first().map_or(0, Vec::len)).map(|i| lattice_log(&target, &bins, i, true)),
            );
        // births where the (raked) map factors put the intensity
        let births = if target.maps.is_empty() {
            None
        } else {
            // ψ per bin of each map, once: the lattice is read a million times
            let factors: Vec<Vec<f64>> = target
                .maps
                .iter()
                .map(|m| m.hist.values.iter().map(|v| v.exp()).collect())
                .collect();
            BirthIntensity::new(
                self.lattice(),
                |i| {
                    factors
                        .iter()
                        .zip(&bins)
                        .map(|(f, b)| b[i].map_or(0.0, |k| f[k]))
                        .product()
                },
                self.region.bbox(),
            )
        };
        let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(self.opts.seed, ci as u64 + 1));
        let points = if !(expected > 0.0) || !expected.is_finite() {
            Vec::new()
        } else if expected >= MIN_COUNT_FOR_RDF_MATCHING && !self.opts.product_model {
            let chain = rdf::RdfChain {
                target: &target,
                region: self.region,
                area: self.area,
                expected,
                self_tag,
                self_pair_scale: pair_scale,
                iterations_per_instance: self.opts.iterations_per_instance,
                exemplar_count: cat.count as f64,
                births: births.as_ref(),
                quartered: cat.category.kind == CategoryKind::Polygon,
            };
            chain.run(&mut rng, report)?
        } else {
            product::run_chain(
                target,
                self.region,
                expected,
                self_tag,
                self.color.max_radius,
                self.opts.iterations_per_instance,
                births.as_ref(),
                &mut rng,
                report,
            )?
        };
        match cat.category.kind {
            CategoryKind::Graph => self.add_paths(ci, &points, state),
            CategoryKind::Polygon => self.add_contours(ci, &points, merged, state),
            _ => {
                let facing = Facing::of(cat, &state.structured);
                for p in &points {
                    state.out.instances.push(attributes(
                        cat,
                        *p,
                        self.scene_index[ci],
                        facing.as_ref(),
                        &mut rng,
                    ));
                }
            }
        }
        state.synthesized[ci] = Some(points);
        Ok(())
    }

    /// Structured content conditions its category's own points: the nodes of the kept graph, the dense points
    /// of the kept contours that are not merged with the new ones. Returns the scene's contours to merge.
    fn condition_on_structures(&self, ci: usize, state: &mut Painted) -> Vec<usize> {
        let (region, influence) = (self.region, self.influence);
        let name = &self.color.categories[ci].category.name;
        match self.color.categories[ci].category.kind {
            CategoryKind::Graph => {
                if let Some(g) = state.structured.graph_state(name) {
                    let degree = g.graph.adjacency();
                    state.context[ci].extend(g.graph.nodes.iter().zip(&degree).filter_map(
                        |(p, d)| {
                            (!d.is_empty() && region.distance_outside(*p) <= influence)
                                .then_some(*p)
                        },
                    ));
                }
                Vec::new()
            }
            CategoryKind::Polygon => {
                let spacing = self.polygon_spacing(name);
                let merged = mergeable_contours(
                    self.scene,
                    self.scene_index[ci],
                    region.region(),
                    3.0 * spacing,
                );
                let kept = state.structured.polygons(name);
                let (lo, hi) = region.bbox();
                let near = (lo - DVec2::splat(influence), hi + DVec2::splat(influence));
                let kept_points = fill_polygons_within(&kept, spacing, ci as u64, near);
                let merged_polygons = self.contour_polygons(&merged);
                state.context[ci].extend(kept_points.into_iter().filter(|p| {
                    region.distance_outside(*p) <= influence
                        && !(region.contains(*p) && merged_polygons.contains(*p))
                }));
                merged
            }
            _ => Vec::new(),
        }
    }

    /// The target of category `ci` given what is painted so far, with the free-border term (and its self tag).
    pub(super) fn category_target(&self, ci: usize, state: &Painted) -> (Target<'s>, u32) {
        let conditioning = Conditioning {
            inside: &state.synthesized,
            context: &state.context,
        };
        let (mut target, self_tag) = build_target(
            self.color,
            ci,
            &conditioning,
            &state.structured,
            self.terrain,
            self.bounds,
            self.area,
        );
        if self.color.categories[ci].category.kind == CategoryKind::Polygon {
            target.bin_width = target.tables[self_tag as usize].bin_width;
        }
        target.add_ghosts(self.region, self.bounds);
        (target, self_tag)
    }

    /// The expected count: exemplar density times the map preference integrated over the region, less the kept
    /// (locked) instances already inside it (`kept`: the category's fixed content).
    /// `bins`: the maps' bins over the region's lattice (see [`lattice_bins`]).
    fn expected_count(
        &self,
        ci: usize,
        target: &Target,
        bins: &[Vec<Option<usize>>],
        kept: &[DVec2],
    ) -> f64 {
        let preference = if target.maps.is_empty() || self.lattice().is_empty() {
            1.0
        } else {
            // relative to the exemplar region's own preference when it lies on this terrain: several maps
            // (elevation and slope) are correlated, and the product of their marginal ratios averages to more
            // than 1 over the exemplar itself (distance maps average to 1 over their own region histogram)
            let own = self
                .exemplar_lattice
                .as_deref()
                .map(|l| {
                    l.iter()
                        .map(|p| target.maps_log(*p, true).exp())
                        .sum::<f64>()
                        / l.len() as f64
                })
                .filter(|v| v.is_finite() && *v > 0.0)
                .unwrap_or(1.0);
            let n = self.lattice().len();
            (0..n)
                .map(|i| lattice_log(target, bins, i, false).exp())
                .sum::<f64>()
                / n as f64
                / own
        };
        let kept_inside = kept.iter().filter(|p| self.region.contains(**p)).count() as f64;
        (self.color.categories[ci].density * self.area * preference - kept_inside).max(0.0)
    }

    /// The arcs of graph category `ci` over its new nodes `points`, added to the result and to the structures.
    fn add_paths(&self, ci: usize, points: &[DVec2], state: &mut Painted) {
        let name = &self.color.categories[ci].category.name;
        let new_paths = graph_paths(
            self.color,
            self.region,
            ci,
            points,
            &state.structured,
            &Conditioning {
                inside: &state.synthesized,
                context: &state.context,
            },
            self.opts.seed,
        );
        state.structured.add_paths(name, &new_paths);
        state
            .out
            .paths
            .extend(new_paths.into_iter().map(|points| Path {
                category: self.scene_index[ci],
                points,
                locked: false,
            }));
    }

    /// The contours of polygon category `ci` traced from its new dense `points` and the `merged` contours
    /// (outside the region), added to the result (replacing the merged ones) and to the structures.
    fn add_contours(&self, ci: usize, points: &[DVec2], merged: Vec<usize>, state: &mut Painted) {
        let name = &self.color.categories[ci].category.name;
        let spacing = self.polygon_spacing(name);
        let merged_polygons = self.contour_polygons(&merged);
        let mut dense = points.to_vec();
        dense.extend(
            fill_polygons(&merged_polygons, spacing, ci as u64)
                .into_iter()
                .filter(|p| !self.region.contains(*p)),
        );
        let mut all: Vec<Vec<DVec2>> = self
            .scene
            .contours
            .iter()
            .enumerate()
            .filter(|(k, c)| c.category == self.scene_index[ci] && !merged.contains(k))
            .map(|(_, c)| c.points.clone())
            .collect();
        let traced = islands::match_sizes(
            trace_contours(&dense, spacing),
            dense.len() as f64 * spacing * spacing,
            self.color.polygon(name),
            &crate::contour::Polygons::new(&all),
            self.region,
            self.area,
        );
        all.extend(traced.iter().cloned());
        state.structured.set_contours(name, &all);
        state
            .out
            .contours
            .extend(traced.into_iter().map(|points| Contour {
                category: self.scene_index[ci],
                points,
                locked: false,
            }));
        state.out.replaced_contours.extend(merged);
    }

    /// The spacing of the dense points of polygon category `name`.
    fn polygon_spacing(&self, name: &str) -> f64 {
        self.color
            .polygon(name)
            .map_or(self.color.bin_width, |p| p.spacing)
    }

    /// The scene's contours `indices` as polygons.
    fn contour_polygons(&self, indices: &[usize]) -> crate::contour::Polygons {
        crate::contour::Polygons::new(
            &indices
                .iter()
                .map(|&k| self.scene.contours[k].points.clone())
                .collect::<Vec<_>>(),
        )
    }
}

/// The unlocked contours of scene category `category` whose boxes come within `margin` of the region's: the
/// synthesis merges them with the contours it traces.
fn mergeable_contours(scene: &Scene, category: usize, region: &Region, margin: f64) -> Vec<usize> {
    let (lo, hi) = region.bbox();
    let (lo, hi) = (lo - DVec2::splat(margin), hi + DVec2::splat(margin));
    scene
        .contours
        .iter()
        .enumerate()
        .filter(|(_, c)| c.category == category && !c.locked)
        .filter(|(_, c)| {
            c.points
                .iter()
                .any(|p| p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y)
        })
        .map(|(k, _)| k)
        .collect()
}

/// The arcs of graph category `ci` over its new `nodes` (module `arcs`), as paths.
fn graph_paths(
    color: &Color,
    region: &PreparedRegion,
    ci: usize,
    nodes: &[DVec2],
    structured: &StructuredContent,
    content: &Conditioning,
    seed: u64,
) -> Vec<Vec<DVec2>> {
    let name = &color.categories[ci].category.name;
    let Some(gc) = color.graph(name) else {
        return Vec::new();
    };
    let kept = structured
        .graph_state(name)
        .map(|g| g.graph.clone())
        .unwrap_or_default();
    // what arcs keep clear of: higher-priority instances (inside the region and around it), avoided polygons
    let mut clear: Vec<(Vec<DVec2>, f64)> = Vec::new();
    for (other, clearance) in &gc.clearance {
        if let Some(oi) = color
            .categories
            .iter()
            .position(|c| &c.category.name == other)
        {
            let mut points: Vec<DVec2> = content.inside[oi].clone().unwrap_or_default();
            points.extend_from_slice(&content.context[oi]);
            clear.push((points, *clearance));
        }
    }
    let borders: Vec<std::sync::Arc<crate::contour::Polygons>> =
        gc.avoids.iter().map(|p| structured.polygons(p)).collect();
    let obstacles = arcs::Obstacles::new(
        &clear
            .iter()
            .map(|(p, c)| (p.as_slice(), *c))
            .collect::<Vec<_>>(),
        borders.iter().map(|p| p.border()).collect(),
    );
    arcs::synthesize_arcs(
        gc,
        nodes,
        &kept,
        &obstacles,
        region,
        mix_seed(seed, ci as u64 + 101),
    )
    .to_paths()
}

//! Learning a color from an exemplar region (Section 4.1, "Distributions and Their Interactions").
//!
//! For every distribution category `C_X` (in priority order) and every category `C_Y` of equal or higher
//! priority (including `C_X` itself) we compute the radial distribution function of eq. (2),
//!
//! ```text
//! h_rdf(k) = Σ_{x_i ∈ X} Σ_{y_j ∈ Y, k d_r ≤ d(x_i, y_j) < (k+1) d_r}  A / (dA' n_X n_Y)
//! ```
//!
//! with the window-edge correction `dA' = α_{x_i,r} dA` ("the proportion α of the outer circle's circumference
//! that intersects the active region"). Two details differ from the letter of the paper, both so that a Poisson
//! arrangement gives exactly `h ≡ 1` in expectation (the neutral factor of the synthesis product):
//! * α is taken on the shell's middle circle `r = (k + ½) d_r`, a better estimate of `|dA ∩ φ| / |dA|` than
//!   the outer circle;
//! * for `Y = X` the normalization uses `n_X (n_X − 1)` pairs (a point is not its own neighbour).
//!
//! α is floored at 0.05 so a point in a sharp polygon corner cannot blow a bin up.
//!
//! Pairs listed in `AnalysisOptions::oriented` also get the oriented rdf `h_ordf` (distance × angle of the vector
//! `y − x` relative to world X, folded to [0, π)), normalized the same way per angular sector.
//!
//! Map sampling `h_m` (Section 4.1): the histogram of a map's value at the instances, divided by `n_X`; we also
//! store the histogram of the same map over the whole exemplar region, used by synthesis to turn `h_m` into a
//! *preference* (see `synthesis`).
//!
//! Per instance, besides the paper's statistics: the histogram of the log of the scale (the instances' sizes) and,
//! for a distribution near roads of higher priority, the histogram of its angle to the nearest road (module
//! `facing`).
//!
//! ## Bin width and maximum radius (when not given)
//! See module `radius`.

use crate::error::{Error, Result};
use crate::geom::{describe_box, DVec2, PreparedRegion, Region};
use crate::limits;
use crate::palette::{
    CategoryColor, Color, ColorKind, GraphColor, Histogram, Interaction, MapInteraction, MapSource,
    PairInteraction, PolygonColor,
};
use crate::scene::{Category, CategoryKind, Instance, Scene};

mod arrangement;
mod estimators;
pub(crate) mod facing;
pub(crate) mod intensity;
mod radius;
mod sampling;
pub(crate) mod structure;
use crate::spatial::{GridEntry, SpatialGrid};
pub use arrangement::learn_arrangement;
pub(crate) use estimators::{alphas_into, folded_angle_bin, rdf};
use estimators::{distance_bins, map_bins};
use radius::radius_and_bin_width;
pub(crate) use radius::CLUSTER_EXCESS;
use rayon::prelude::*;
pub(crate) use sampling::{region_lattice, region_samples};
use std::f64::consts::TAU;
pub use structure::HeldGraph;

/// Number of distance bins when the bin width is chosen automatically.
pub(crate) const DEFAULT_RDF_BINS: usize = 24;
/// Angular bins of an oriented rdf over [0, π).
pub(crate) const ORIENTED_ANGLE_BINS: usize = 12;
/// Slope histograms use fixed bins of 2.5° from 0 (so any two are comparable bin by bin).
pub const SLOPE_BIN_DEGREES: f64 = 2.5;
/// Bins of the histogram of any other map, spread over the map's range in the exemplar region.
pub(crate) const MAP_BINS: usize = 24;
/// How to learn a color.
#[derive(Clone, Debug, Default)]
pub struct AnalysisOptions {
    /// None = `max_radius / 24`.
    pub bin_width: Option<f64>,
    /// None = the rule in the module documentation.
    pub max_radius: Option<f64>,
    /// Category pairs (category, other) that also get an oriented rdf.
    pub oriented: Vec<(String, String)>,
    /// Map names to sample; empty = ["elevation", "slope"] when a terrain is present.
    pub maps: Vec<String>,
    /// The default radius stays at three mean spacings, however far the content stays clustered: for the small
    /// windows a tool reads around itself, where a change of density across the window is not clustering.
    pub local: bool,
}

/// The points of one category inside the exemplar region: its instances, the nodes of its graph, or the dense
/// points of its contours.
struct Group<'a> {
    category: &'a Category,
    instances: Vec<Instance>,
    positions: Vec<DVec2>,
}

impl<'a> Group<'a> {
    fn new(category: &'a Category, instances: Vec<Instance>) -> Self {
        let positions = instances.iter().map(|i| i.position).collect();
        Group {
            category,
            instances,
            positions,
        }
    }

    fn kind(&self) -> CategoryKind {
        self.category.kind
    }
}

/// Learn a color from the scene's content inside `region`: the instances of distribution categories, the graphs
/// of graph categories (their nodes as a distribution, plus the statistics of `structure`) and the contours of
/// polygon categories (as dense points).
pub fn learn_color(
    scene: &Scene,
    region: &Region,
    name: &str,
    opts: &AnalysisOptions,
) -> Result<Color> {
    region.validate()?;
    let region = &*region.with_bounded_detail();
    let area = region.area();
    let content = structure::Structures::of(scene, region);
    for name in opts.oriented.iter().flat_map(|(a, b)| [a, b]) {
        if scene.category_index(name).is_none() {
            return Err(Error::invalid(
                "an oriented pair",
                format!("names '{name}', which is not a category of the scene"),
            ));
        }
    }
    let groups = exemplar_groups(scene, region, &content)?;
    let terrain_maps = terrain_map_interactions(scene, region, &groups, &opts.maps)?;
    let (max_radius, bin_width) =
        radius_and_bin_width(opts, region, &groups, scene, &terrain_maps)?;
    limits::check(
        "max_radius / bin_width",
        max_radius / bin_width,
        limits::MAX_HISTOGRAM_BINS,
        "histogram bins",
    )?;
    let n_bins = ((max_radius / bin_width).round() as usize).max(1);
    let grids = groups
        .iter()
        .map(|g| point_grid(region, &g.positions, max_radius))
        .collect();
    let exemplar = Exemplar {
        region,
        prepared: PreparedRegion::new(region),
        area,
        content: &content,
        groups,
        grids,
        max_radius,
        bin_width,
        n_bins,
    };

    let categories = exemplar.category_colors();
    let pairs = exemplar.pair_interactions(&opts.oriented);
    let mut maps = terrain_maps;
    maps.extend(exemplar.distance_map_interactions());
    let graphs = exemplar.graph_colors();
    let polygons = exemplar.polygon_colors();
    let preview = exemplar.preview();

    Ok(Color {
        name: name.to_string(),
        region: region.clone(),
        region_area: area,
        max_radius,
        bin_width,
        categories,
        pairs,
        maps,
        graphs,
        polygons,
        preview,
        kind: ColorKind::Statistics,
    })
}

/// The histograms of terrain maps at every group (`maps`, or elevation and slope when none is named and the
/// scene has a terrain), each with the map's histogram over the region.
fn terrain_map_interactions(
    scene: &Scene,
    region: &Region,
    groups: &[Group],
    maps: &[String],
) -> Result<Vec<MapInteraction>> {
    let map_names: Vec<String> = if !maps.is_empty() {
        maps.to_vec()
    } else if scene.terrain.is_some() {
        vec!["elevation".into(), "slope".into()]
    } else {
        Vec::new()
    };
    let mut out = Vec::new();
    if map_names.is_empty() {
        return Ok(out);
    }
    let terrain = scene.terrain.as_deref().ok_or_else(|| {
        Error::invalid(
            format!("maps {map_names:?}"),
            "asked for but the scene has no terrain",
        )
    })?;
    let samples = region_lattice(region, terrain);
    if samples.is_empty() {
        return Err(Error::RegionOffTerrain {
            reason: format!(
                "the exemplar region ({}) does not overlap the terrain ({})",
                describe_box(region.bbox()),
                describe_box(terrain.bbox())
            ),
        });
    }
    for map in &map_names {
        if !terrain.maps.contains_key(map) {
            return Err(Error::invalid("the terrain", format!("has no map '{map}'")));
        }
        let values: Vec<f64> = samples
            .iter()
            .filter_map(|p| terrain.map_at(map, *p))
            .collect();
        let bins = map_bins(map, &values);
        for g in groups {
            let at = g.positions.iter().filter_map(|p| terrain.map_at(map, *p));
            out.push(map_interaction(
                g,
                map,
                MapSource::Terrain,
                &bins,
                &values,
                at,
            ));
        }
    }
    Ok(out)
}

/// The groups of the exemplar: one per category with content inside the region, in priority order (ties: order
/// in the scene).
fn exemplar_groups<'s>(
    scene: &'s Scene,
    region: &Region,
    content: &structure::Structures,
) -> Result<Vec<Group<'s>>> {
    let mut order: Vec<usize> = (0..scene.categories.len())
        .filter(|&c| {
            // external content is context only; an arrangement's elements are learned by learn_arrangement
            !matches!(
                scene.categories[c].kind,
                CategoryKind::External | CategoryKind::Arrangement
            )
        })
        .collect();
    order.sort_by_key(|&c| (scene.categories[c].priority, c));
    let mut groups: Vec<Group> = Vec::new();
    for &c in &order {
        let category = &scene.categories[c];
        let instances = category_points(scene, region, content, c);
        if instances.is_empty() {
            continue;
        }
        if instances.iter().any(|i| !i.position.is_finite()) {
            return Err(Error::invalid(
                format!("category '{}'", category.name),
                "has instances at non-finite positions",
            ));
        }
        // a mirrored instance (negative scale) or a vanished one would be learned as a size that cannot be painted
        if let Some(i) = instances
            .iter()
            .find(|i| !(i.scale.is_finite() && i.scale > 0.0))
        {
            return Err(Error::invalid(
                format!("category '{}'", category.name),
                format!(
                    "has an instance at ({:.2}, {:.2}) of scale {}: scales must be positive",
                    i.position.x, i.position.y, i.scale
                ),
            ));
        }
        groups.push(Group::new(category, instances));
    }
    if groups.is_empty() {
        return Err(Error::EmptyExemplar {
            reason: format!(
                "no instances, paths or contours inside the region (bbox {:?})",
                region.bbox()
            ),
        });
    }
    Ok(groups)
}

/// The points of category `c` inside the region: its instances, the nodes of its graph or the dense points of
/// its contours.
fn category_points(
    scene: &Scene,
    region: &Region,
    content: &structure::Structures,
    c: usize,
) -> Vec<Instance> {
    let category = &scene.categories[c];
    match category.kind {
        CategoryKind::Graph => content.graph_nodes_inside(c, category, region),
        CategoryKind::Polygon => content.polygon_points_inside(c, category, region),
        _ => {
            let own: Vec<&Instance> = scene.instances.iter().filter(|i| i.category == c).collect();
            let inside = region.contains_each(&own.iter().map(|i| i.position).collect::<Vec<_>>());
            own.into_iter()
                .zip(inside)
                .filter_map(|(i, inside)| inside.then_some(*i))
                .collect()
        }
    }
}

/// A neighbour grid of `positions` over the region's bounding box, with cells of `cell`; entries are tagged
/// with their index.
fn point_grid(region: &Region, positions: &[DVec2], cell: f64) -> SpatialGrid {
    let (lo, hi) = region.bbox();
    let mut grid = SpatialGrid::new(lo, hi, cell);
    for (k, p) in positions.iter().enumerate() {
        grid.insert(GridEntry {
            position: *p,
            tag: 0,
            id: k as u32,
        });
    }
    grid
}

/// Graphs and polygons meet the other categories through distance maps, not pair statistics.
fn meets_through_maps(gx: &Group, gy: &Group) -> bool {
    gx.kind() == CategoryKind::Polygon || gy.kind() != CategoryKind::Distribution
}

/// Whether the pair (X, Y), in either order, is listed for an oriented rdf.
fn wants_oriented(oriented: &[(String, String)], gx: &Group, gy: &Group) -> bool {
    oriented.iter().any(|(a, b)| {
        (a == &gx.category.name && b == &gy.category.name)
            || (b == &gx.category.name && a == &gy.category.name)
    })
}

/// The exemplar being learned: its groups in priority order, a neighbour grid of each (cells of `max_radius`),
/// and the scale of the rdf.
struct Exemplar<'a> {
    region: &'a Region,
    /// The region indexed for the window-edge correction of every point.
    prepared: PreparedRegion<'a>,
    area: f64,
    content: &'a structure::Structures,
    groups: Vec<Group<'a>>,
    grids: Vec<SpatialGrid>,
    max_radius: f64,
    bin_width: f64,
    n_bins: usize,
}

impl Exemplar<'_> {
    /// The per-category statistics of every group, with how the instances of distributions face the roads of
    /// higher priority.
    fn category_colors(&self) -> Vec<CategoryColor> {
        let mut categories = Vec::with_capacity(self.groups.len());
        for (gi, g) in self.groups.iter().enumerate() {
            let mut color = category_color(g, self.area, &self.grids[gi], self.max_radius);
            if g.kind() == CategoryKind::Distribution {
                let roads: Vec<String> = self.groups[..gi]
                    .iter()
                    .filter(|o| o.kind() == CategoryKind::Graph)
                    .map(|o| o.category.name.clone())
                    .collect();
                if !roads.is_empty() {
                    color.facing =
                        facing::road_facing(&g.instances, self.content, roads, self.max_radius);
                }
            }
            categories.push(color);
        }
        categories
    }

    /// The rdf of every pair (X, Y) with Y of equal or higher priority, and the oriented rdf of the pairs listed
    /// in `oriented`.
    fn pair_interactions(&self, oriented: &[(String, String)]) -> Vec<PairInteraction> {
        let mut pairs = Vec::new();
        for (xi, gx) in self.groups.iter().enumerate() {
            for (yi, gy) in self.groups.iter().enumerate().take(xi + 1) {
                if xi != yi && meets_through_maps(gx, gy) {
                    continue;
                }
                pairs.push(PairInteraction {
                    category: gx.category.name.clone(),
                    other: gy.category.name.clone(),
                    interaction: Interaction::Rdf {
                        hist: self.pair_rdf(xi, yi),
                    },
                });
                if wants_oriented(oriented, gx, gy) {
                    pairs.push(PairInteraction {
                        category: gx.category.name.clone(),
                        other: gy.category.name.clone(),
                        interaction: Interaction::OrientedRdf {
                            distance_bin: self.bin_width,
                            angle_bins: ORIENTED_ANGLE_BINS,
                            values: self.pair_oriented_rdf(xi, yi),
                        },
                    });
                }
            }
        }
        pairs
    }

    /// The window-corrected rdf of groups `xi` and `yi`.
    fn pair_rdf(&self, xi: usize, yi: usize) -> Histogram {
        let (gx, gy) = (&self.groups[xi], &self.groups[yi]);
        let same = xi == yi;
        let polygon_grid;
        let (grid, width, n_bins) = if same && gx.kind() == CategoryKind::Polygon {
            // dense points: the rdf spans the polygons' own scale
            let radius = self.content.polygon_radius(gx.category, self.region);
            polygon_grid = point_grid(self.region, &gx.positions, radius);
            (
                &polygon_grid,
                radius / DEFAULT_RDF_BINS as f64,
                DEFAULT_RDF_BINS,
            )
        } else {
            (&self.grids[yi], self.bin_width, self.n_bins)
        };
        Histogram {
            start: 0.0,
            bin_width: width,
            values: rdf(
                &self.prepared,
                self.area,
                &gx.positions,
                &gy.positions,
                grid,
                same,
                width,
                n_bins,
                1,
            ),
        }
    }

    /// The oriented rdf of groups `xi` and `yi`.
    fn pair_oriented_rdf(&self, xi: usize, yi: usize) -> Vec<f64> {
        rdf(
            &self.prepared,
            self.area,
            &self.groups[xi].positions,
            &self.groups[yi].positions,
            &self.grids[yi],
            xi == yi,
            self.bin_width,
            self.n_bins,
            ORIENTED_ANGLE_BINS,
        )
    }

    /// The histograms of the distances to the graphs and polygons of higher priority (Section 4.1
    /// distance-to-graph, thesis 6.2.1) at every later group.
    fn distance_map_interactions(&self) -> Vec<MapInteraction> {
        let mut out = Vec::new();
        let samples = region_samples(self.region);
        for (yi, gy) in self.groups.iter().enumerate() {
            let source = match gy.kind() {
                CategoryKind::Graph => MapSource::GraphDistance,
                CategoryKind::Polygon => MapSource::PolygonDistance,
                _ => continue,
            };
            let Some(field) = self
                .content
                .distance_field(gy.category, source, self.max_radius)
            else {
                continue;
            };
            let values: Vec<f64> = samples.iter().map(|p| field(*p)).collect();
            for gx in self.groups.iter().skip(yi + 1) {
                let at: Vec<f64> = gx.positions.iter().map(|p| field(*p)).collect();
                let bins = distance_bins(source, self.max_radius, &at);
                out.push(map_interaction(
                    gx,
                    &gy.category.name,
                    source,
                    &bins,
                    &values,
                    at.into_iter(),
                ));
            }
        }
        out
    }

    /// The statistics of the graph categories (see `structure`).
    fn graph_colors(&self) -> Vec<GraphColor> {
        self.groups
            .iter()
            .filter(|g| g.kind() == CategoryKind::Graph)
            .filter_map(|g| {
                self.content
                    .graph_color(g.category, self.region, &groups_before(&self.groups, g))
            })
            .collect()
    }

    /// The statistics of the polygon categories.
    fn polygon_colors(&self) -> Vec<PolygonColor> {
        self.groups
            .iter()
            .filter(|g| g.kind() == CategoryKind::Polygon)
            .filter_map(|g| self.content.polygon_color(g.category, self.region))
            .collect()
    }

    /// At most about 20 000 of the groups' points, relative to the region's corner, with their group's index.
    fn preview(&self) -> Vec<[f64; 3]> {
        let (lo, _) = self.region.bbox();
        let total: usize = self.groups.iter().map(|g| g.positions.len()).sum();
        let step = total.div_ceil(20_000).max(1);
        self.groups
            .iter()
            .enumerate()
            .flat_map(|(gi, g)| {
                g.positions
                    .iter()
                    .map(move |p| [p.x - lo.x, p.y - lo.y, gi as f64])
            })
            .step_by(step)
            .collect()
    }
}

/// The groups of higher priority than `g`: (category, kind, positions).
fn groups_before<'a>(groups: &'a [Group], g: &Group) -> Vec<(&'a Category, &'a [DVec2])> {
    groups
        .iter()
        .take_while(|o| !std::ptr::eq(o.category, g.category))
        .map(|o| (o.category, o.positions.as_slice()))
        .collect()
}

/// A map histogram of a group: the values `at` its points, on `bins`, with the region's `values` as its
/// region histogram (values beyond the bins land in the end bins).
fn map_interaction(
    g: &Group,
    map: &str,
    source: MapSource,
    bins: &Histogram,
    values: &[f64],
    at: impl Iterator<Item = f64>,
) -> MapInteraction {
    let clamp = |v: f64| v.clamp(bins.start, bins.end() - 1e-9 * bins.bin_width);
    let mut region_hist = bins.clone();
    for v in values {
        region_hist.add(clamp(*v), 1.0);
    }
    let mut hist = bins.clone();
    for v in at {
        hist.add(clamp(v), 1.0);
    }
    MapInteraction {
        category: g.category.name.clone(),
        map: map.to_string(),
        hist: hist.normalized(),
        region_hist: region_hist.normalized(),
        source,
    }
}

/// Count, density, smallest same-category distance, scale / rotation / size histograms and prototype weights.
fn category_color(g: &Group, area: f64, grid: &SpatialGrid, max_radius: f64) -> CategoryColor {
    let n = g.positions.len();
    let min_distance = (0..n)
        .into_par_iter()
        .map(|k| {
            let p = g.positions[k];
            let mut best = f64::INFINITY;
            grid.for_each_within(p, max_radius, |e, d2| {
                if e.id != k as u32 {
                    best = best.min(d2);
                }
            });
            best
        })
        .collect::<Vec<f64>>()
        .into_iter()
        .fold(f64::INFINITY, f64::min)
        .sqrt();
    // beyond max_radius the exact value does not matter to synthesis: report it only when seen
    let scales: Vec<f64> = g
        .instances
        .iter()
        .map(|i| i.scale)
        .filter(|s| s.is_finite())
        .collect();
    let (smin, smax) = scales
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
            (a.min(*s), b.max(*s))
        });
    let scale = if scales.is_empty() {
        Histogram {
            start: 1.0,
            bin_width: 1e-6,
            values: vec![1.0],
        }
    } else {
        let width = ((smax - smin) / 16.0).max(1e-6 * smax.abs().max(1.0));
        let mut h = Histogram::zeros(smin, width, ((smax - smin) / width).floor() as usize + 1);
        for s in &scales {
            h.add(*s, 1.0);
        }
        h.normalized()
    };
    let mut rotation = Histogram::zeros(0.0, TAU / 36.0, 36);
    for i in &g.instances {
        if i.rotation.is_finite() {
            let r = i.rotation.rem_euclid(TAU).min(TAU - 1e-12);
            rotation.add(r, 1.0);
        }
    }
    let max_proto = g
        .instances
        .iter()
        .map(|i| i.prototype.min(65_535) as usize)
        .max()
        .unwrap_or(0);
    let mut prototype_weights = vec![0.0; max_proto + 1];
    for i in &g.instances {
        prototype_weights[i.prototype.min(65_535) as usize] += 1.0;
    }
    let total: f64 = prototype_weights.iter().sum();
    prototype_weights.iter_mut().for_each(|w| *w /= total);
    CategoryColor {
        category: g.category.clone(),
        count: n,
        density: n as f64 / area,
        min_distance,
        scale,
        rotation: rotation.normalized(),
        prototype_weights,
        size: facing::size_histogram(&g.instances),
        facing: None,
    }
}

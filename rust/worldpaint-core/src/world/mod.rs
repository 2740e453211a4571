//! Worlds larger than one paste: a rectangle of any size cut into square tiles that are synthesized one by one,
//! each conditioned on its already-synthesized neighbours, and written as a tile set.
//!
//! Tiles are coloured in four checkerboard phases by the parity of their column and row. A tile of phase `k` is
//! synthesized after its (up to eight) neighbours of phases below `k`, with their instances within the region of
//! influence as fixed content: the conditioning a paste gets from what surrounds it (eq. (1)'s pair factors, hard
//! cores kept), so a tile border is no more visible than a paste's. A tile is at least as wide as the region of
//! influence, so two tiles of one phase (at least one tile apart) never see each other and everything a tile sees
//! lies in its eight neighbours: the tiles of a phase can run in any order, on any worker. Each tile draws from its
//! own generator, seeded from (seed, column, row), so the same seed gives the same world whatever the tile order,
//! the worker count or the machine.
//!
//! What fills the world is a [`map::ColorMap`]: one color everywhere, or a grid of labels whose colors blend across
//! each boundary; a tile is painted in blocks of one paint each ([`map::ColorMap::blocks`]).
//!
//! A tile needs only the terrain around it ([`WorldPlan::terrain_window`]) and the border strips of its earlier
//! neighbours ([`TileContent::border`]); its whole content goes to one tile file ([`tile_file`]). Memory is therefore
//! bounded by a tile, not by the world. The driver that runs the phases on a cluster is the Python package's
//! `worldpaint_engine.world` (Dask distributed): no scheduler lives here.

pub(crate) mod map;
pub(crate) mod obstacles;
pub(crate) mod tile_file;
pub(crate) mod villages;

use crate::error::check;
use crate::geom::DVec2;
use crate::paint::synthesize;
use crate::palette::Color;
use crate::scene::{Category, CategoryKind, Instance, Path, Scene};
use crate::synthesis::{mix_seed, SynthesisOptions};
use crate::terrain::Heightfield;
use crate::{Error, Region, Result};
pub use map::{Block, ColorMap, LabelGrid, Paint, DEFAULT_BAND_RADII};
pub use obstacles::Obstacles;
use std::sync::Arc;
pub use villages::{grow_world_villages, village_side, VillageSite, WorldVillages};

/// Instances a tile is sized to hold by default: a tile then takes about a second and some tens of MB.
pub(crate) const TILE_INSTANCES: f64 = 100_000.0;

/// Most tiles a world is cut into (a manifest of this many entries is still read at once).
pub const MAX_TILES: usize = 1_000_000;

/// A tile by its column (along X) and row (along Y), from the world's min corner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileId {
    /// Along X, from 0.
    pub column: u32,
    /// Along Y, from 0.
    pub row: u32,
}

/// How a world rectangle is cut into tiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldPlan {
    /// The world's corner with the smaller coordinates (m).
    pub min: DVec2,
    /// The world's corner with the larger coordinates (m); the last column and row are cut there.
    pub max: DVec2,
    /// Side of a tile (m).
    pub tile: f64,
    /// Tiles along X.
    pub columns: u32,
    /// Tiles along Y.
    pub rows: u32,
    /// Radius of the region of influence (m): how far a tile sees into its neighbours.
    pub influence: f64,
}

impl WorldPlan {
    /// A plan for the rectangle `[min, max]` with tiles of side `tile` and a region of influence `influence`;
    /// the tile must be at least as wide as the region of influence (see the module documentation).
    pub fn new(min: DVec2, max: DVec2, tile: f64, influence: f64) -> Result<Self> {
        for (what, v) in [
            ("world min x", min.x),
            ("world min y", min.y),
            ("world max x", max.x),
            ("world max y", max.y),
        ] {
            check::finite(what, v)?;
        }
        if !(max.x > min.x && max.y > min.y) {
            return Err(Error::BadRegion {
                reason: format!(
                    "the world's max corner {max} must lie above and right of its min corner {min}"
                ),
            });
        }
        check::positive("tile size", tile)?;
        check::non_negative("influence radius", influence)?;
        if tile < influence {
            return Err(Error::invalid(
                format!("tile size {tile} m"),
                format!("must be at least the region of influence ({influence} m), so that a tile sees only its neighbours"),
            ));
        }
        let count = |extent: f64| (extent / tile).ceil().max(1.0);
        let (columns, rows) = (count(max.x - min.x), count(max.y - min.y));
        crate::limits::check("the world", columns * rows, MAX_TILES as u64, "tiles")?;
        Ok(WorldPlan {
            min,
            max,
            tile,
            columns: columns as u32,
            rows: rows as u32,
            influence,
        })
    }

    /// A plan for painting `map` over `[min, max]`: the region of influence is the colors' largest radius, and
    /// the tile (unless given) holds about `TILE_INSTANCES` instances of the densest color. A map that does not
    /// cover the world is refused.
    pub fn for_map(min: DVec2, max: DVec2, map: &ColorMap, tile: Option<f64>) -> Result<Self> {
        let influence = map.influence();
        let density = map.max_density();
        let extent = (max - min).max_element();
        let tile = match tile {
            Some(t) => t,
            // as many equal tiles as the size asks along the longer side (none left narrow at the end)
            None if density > 0.0 => {
                let ideal = (TILE_INSTANCES / density).sqrt();
                (extent / (extent / ideal).round().max(1.0)).max(influence)
            }
            None => extent.max(influence),
        };
        let plan = WorldPlan::new(min, max, tile, influence)?;
        map.check_covers(plan.min, plan.max)?;
        plan.check_instances(map, density)?;
        Ok(plan)
    }

    /// Refuses a plan whose tiles or whole world would hold more instances (at the densest color's density) than
    /// the engine's budget allows, before any tile is started: a tile is at most one synthesis call's
    /// ([`crate::limits::MAX_INSTANCES`]), and the world has its own bound ([`crate::limits::MAX_WORLD_INSTANCES`]).
    fn check_instances(&self, map: &ColorMap, density: f64) -> Result<()> {
        let extent = self.max - self.min;
        let tile_area = self.tile.min(extent.x) * self.tile.min(extent.y);
        let names: Vec<&str> = map.colors().iter().map(|c| c.name.as_str()).collect();
        let what = if names.len() == 1 {
            format!("color '{}'", names[0])
        } else {
            format!("colors '{}'", names.join("', '"))
        };
        crate::limits::check(
            &format!(
                "a tile of {} m of {what} (at {density} instances per m²)",
                self.tile
            ),
            density * tile_area,
            crate::limits::MAX_INSTANCES,
            "instances",
        )?;
        crate::limits::check(
            &format!(
                "a world of {} x {} m of {what} (at {density} instances per m²)",
                extent.x, extent.y
            ),
            density * extent.x * extent.y,
            crate::limits::MAX_WORLD_INSTANCES,
            "instances",
        )
    }

    /// Every tile, row by row.
    pub fn tiles(&self) -> Vec<TileId> {
        (0..self.rows)
            .flat_map(|row| (0..self.columns).map(move |column| TileId { column, row }))
            .collect()
    }

    /// The tile's checkerboard phase, 0..4: tiles of one phase never touch.
    pub fn phase(&self, t: TileId) -> usize {
        (t.column % 2 + 2 * (t.row % 2)) as usize
    }

    /// The tile's rectangle (min, max); the last column and row end at the world's max corner.
    pub fn rect(&self, t: TileId) -> (DVec2, DVec2) {
        let lo = self.min + DVec2::new(t.column as f64, t.row as f64) * self.tile;
        (lo, (lo + DVec2::splat(self.tile)).min(self.max))
    }

    /// The neighbours of `t` that are synthesized before it (earlier phases): those it is conditioned on.
    pub fn earlier_neighbours(&self, t: TileId) -> Vec<TileId> {
        let mut out = Vec::new();
        for dr in -1i64..=1 {
            for dc in -1i64..=1 {
                let (c, r) = (t.column as i64 + dc, t.row as i64 + dr);
                if (dc, dr) == (0, 0)
                    || c < 0
                    || r < 0
                    || c >= self.columns as i64
                    || r >= self.rows as i64
                {
                    continue;
                }
                let n = TileId {
                    column: c as u32,
                    row: r as u32,
                };
                if self.phase(n) < self.phase(t) {
                    out.push(n);
                }
            }
        }
        out
    }

    /// The part of the terrain a tile reads: its rectangle grown by the region of influence and by two terrain
    /// cells `cell` (the slope at a window's edge is one-sided, so the edge stays out of what is sampled).
    pub fn terrain_window(&self, t: TileId, cell: f64) -> (DVec2, DVec2) {
        let (lo, hi) = self.rect(t);
        let grow = DVec2::splat(self.influence + 2.0 * cell);
        (lo - grow, hi + grow)
    }

    fn check_tile(&self, t: TileId) -> Result<()> {
        if t.column >= self.columns || t.row >= self.rows {
            return Err(Error::invalid(
                format!("tile ({}, {})", t.column, t.row),
                format!(
                    "lies outside the world's {} x {} tiles",
                    self.columns, self.rows
                ),
            ));
        }
        Ok(())
    }
}

/// The instances of one tile (or of a border strip of it), with category indices into `categories` (the color's
/// category names, in the color's order) and the terrain height under each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileContent {
    /// Which tile.
    pub tile: TileId,
    /// The tile's min corner: positions are stored relative to it.
    pub origin: DVec2,
    /// The color's category names.
    pub categories: Vec<String>,
    /// The instances (world XY).
    pub instances: Vec<Instance>,
    /// Terrain height under each instance (0 without a terrain).
    pub heights: Vec<f32>,
}

impl TileContent {
    /// The instances within the region of influence of the tile's edge: all its later neighbours can see.
    pub fn border(&self, plan: &WorldPlan) -> TileContent {
        let (lo, hi) = plan.rect(self.tile);
        let near_edge = |p: DVec2| {
            let inside = (p - lo).min(hi - p).min_element();
            inside <= plan.influence
        };
        let keep: Vec<usize> = (0..self.instances.len())
            .filter(|&k| near_edge(self.instances[k].position))
            .collect();
        TileContent {
            instances: keep.iter().map(|&k| self.instances[k]).collect(),
            heights: keep.iter().map(|&k| self.heights[k]).collect(),
            categories: self.categories.clone(),
            ..*self
        }
    }

    /// How many instances of each category.
    pub fn counts(&self) -> Vec<usize> {
        let mut counts = vec![0; self.categories.len()];
        for i in &self.instances {
            if let Some(c) = counts.get_mut(i.category) {
                *c += 1;
            }
        }
        counts
    }
}

/// Refuses a chain length a tile cannot run in reasonable time: it must be positive and at most
/// [`crate::limits::MAX_ITERATIONS_PER_INSTANCE`] proposals per instance.
pub fn check_iterations(iterations_per_instance: f64) -> Result<()> {
    check::positive("iterations per instance", iterations_per_instance)?;
    crate::limits::check(
        "the chain",
        iterations_per_instance,
        crate::limits::MAX_ITERATIONS_PER_INSTANCE,
        "proposals per instance",
    )
}

/// A clear error for colors a world cannot be filled with: tiles hold instances, and a color's roads are the
/// world's (its graph categories are not painted; see [`synthesize_tile`]), but a coast cannot be.
pub(crate) fn paintable(color: &Color) -> Result<()> {
    if !color.kind.is_statistics() {
        return Err(Error::invalid(
            format!("color '{}'", color.name),
            "is an arrangement; a world is filled with colors of distributions",
        ));
    }
    if let Some(c) = color.categories.iter().find(|c| {
        !matches!(
            c.category.kind,
            CategoryKind::Distribution | CategoryKind::Graph
        )
    }) {
        return Err(Error::invalid(
            format!("color '{}'", color.name),
            format!(
                "has the coast or area category '{}'; world tiles hold instances and the villages' roads only",
                c.category.name
            ),
        ));
    }
    Ok(())
}

/// The categories a world's roads are painted as: its graph categories whose name holds "road" (any case), else
/// its only graph category (of two graph categories, a river and a stream, neither). A color that learned how its
/// content stands from roads of such a category keeps it so from the world's roads.
pub fn road_categories(categories: &[Category]) -> Vec<usize> {
    let graphs: Vec<usize> = (0..categories.len())
        .filter(|&k| categories[k].kind == CategoryKind::Graph)
        .collect();
    let named: Vec<usize> = graphs
        .iter()
        .copied()
        .filter(|&k| categories[k].name.to_lowercase().contains("road"))
        .collect();
    if named.is_empty() && graphs.len() == 1 {
        graphs
    } else {
        named
    }
}

/// The categories of `color` a tile paints: its distributions (None when it has nothing else, as every color
/// before roads could enter a world).
fn distribution_only(color: &Color) -> Option<Vec<String>> {
    let all = color
        .categories
        .iter()
        .all(|c| c.category.kind == CategoryKind::Distribution);
    (!all).then(|| {
        color
            .categories
            .iter()
            .filter(|c| c.category.kind == CategoryKind::Distribution)
            .map(|c| c.category.name.clone())
            .collect()
    })
}

/// Synthesize tile `t` of `plan` with `map`, conditioned on `neighbours` (the border strips of its earlier
/// neighbours), on `terrain` (at least the tile's [`WorldPlan::terrain_window`]; `None` on flat ground).
/// `iterations_per_instance` overrides the colors' chain length. The tile's blocks are synthesized in turn, each
/// conditioned on the blocks before it; the first draws from the tile's seed, the others from seeds derived from
/// it and their place in the order. A block's instances on the `obstacles` (houses, roads) are removed at once.
///
/// The tiles paint the colors' distribution categories only: a world's roads are its villages' (the obstacles'),
/// and they enter each block as the paths of the map's road categories ([`road_categories`]), so a color that
/// learned how far its trees or houses stand from its roads keeps them so from the world's.
#[allow(clippy::too_many_arguments)]
pub fn synthesize_tile(
    plan: &WorldPlan,
    t: TileId,
    map: &ColorMap,
    obstacles: &Obstacles,
    terrain: Option<Arc<Heightfield>>,
    neighbours: &[TileContent],
    seed: u64,
    iterations_per_instance: Option<f64>,
) -> Result<TileContent> {
    plan.check_tile(t)?;
    let names: Vec<String> = map.categories().iter().map(|c| c.name.clone()).collect();
    let mut scene = Scene {
        categories: map.categories().to_vec(),
        terrain: terrain.clone(),
        ..Default::default()
    };
    for category in road_categories(map.categories()) {
        scene
            .paths
            .extend(obstacles.roads().iter().map(|points| Path {
                category,
                points: points.clone(),
                locked: true,
            }));
    }
    for n in neighbours {
        if n.categories != names {
            return Err(Error::invalid(
                format!("neighbour tile ({}, {})", n.tile.column, n.tile.row),
                format!(
                    "holds categories {:?}, not the map's {names:?}",
                    n.categories
                ),
            ));
        }
        scene.instances.extend_from_slice(&n.instances);
    }
    let tile_seed = mix_seed(seed, ((t.column as u64) << 32) | t.row as u64);
    let mut opts = SynthesisOptions {
        seed: tile_seed,
        influence_radius: Some(plan.influence),
        // the tile's terrain is a window of the world's, which does not hold the exemplar's ground
        exemplar_on_terrain: false,
        ..Default::default()
    };
    if let Some(it) = iterations_per_instance {
        check_iterations(it)?;
        opts.iterations_per_instance = it;
    }
    let (min, max) = plan.rect(t);
    let borrowed = scene.instances.len();
    let mut colors = std::collections::HashMap::new();
    for (k, block) in map.blocks(min, max).into_iter().enumerate() {
        let color = match colors.entry(block.paint) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(map.color_of(block.paint)?),
        };
        opts.seed = if k == 0 {
            tile_seed
        } else {
            mix_seed(tile_seed, k as u64)
        };
        opts.categories = distribution_only(color);
        let region = Region::Rect {
            min: block.min,
            max: block.max,
        };
        let painted = synthesize(&scene, color, &region, &opts)?;
        scene.instances.extend(
            painted
                .instances
                .into_iter()
                .filter(|i| !obstacles.covers(i.position)),
        );
    }
    let instances = scene.instances.split_off(borrowed);
    let heights = instances
        .iter()
        .map(|i| {
            terrain
                .as_deref()
                .and_then(|h| h.height_at(i.position))
                .unwrap_or(0.0) as f32
        })
        .collect();
    Ok(TileContent {
        tile: t,
        origin: min,
        categories: names,
        instances,
        heights,
    })
}

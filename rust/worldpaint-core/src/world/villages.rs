//! Villages in a world (issue 43): village sites grow their villages on the world's terrain before any tile, joined
//! by roads laid at world scale, and the tiles are then synthesized around them ([`super::obstacles`]).
//!
//! Readings chosen:
//! * The roads between villages are the village road model (`village::roads`: the anisotropic shortest path with
//!   slope, curvature and re-use costs), coarse to fine: first on a coarse grid over the whole world, at most
//!   [`WORLD_ROAD_NODES`] nodes a side, where the first site starts the network and each next site, nearest the
//!   sites already joined first (Prim's order), is joined to it by a through road with re-use, so every village is
//!   reachable from every other; then each coarse road is laid again on the villages' grid, piece by piece
//!   ([`PIECE_LENGTH`] of road each), within a corridor of [`CORRIDOR_COARSE_CELLS`] coarse cells around it. A
//!   10 km road is then a search over a few hundred thousand nodes, not the world's millions. A piece the fine
//!   search cannot lay keeps its coarse course.
//! * Each village grows in a square around its site, as large as its buildings need at [`BUILDINGS_PER_HECTARE`],
//!   with the world roads that cross the square as its ways in and its existing roads; its own roads join them.
//!   Villages grow in parallel, each from its own seed.

use crate::geom::{polyline_distance, DVec2, Region};
use crate::grid::Grid;
use crate::terrain::Heightfield;
use crate::village::encyclopedia::Encyclopedia;
use crate::village::encyclopedia::RoadParams;
use crate::village::fit::{border_crossings, scenario_for};
use crate::village::generate::{generate_village, Village, VillageRequest};
use crate::village::roads::RoadNetwork;
use crate::village::Road;
use crate::village::{Environment, Land, Site};
use crate::{Error, Result};
use rayon::prelude::*;

/// Most nodes along a side of the coarse grid the roads between villages are laid on.
pub(crate) const WORLD_ROAD_NODES: f64 = 400.0;
/// Road (m) a coarse road is laid again in at a time.
pub(crate) const PIECE_LENGTH: f64 = 500.0;
/// Half-width of the corridor a coarse road is laid again within, in coarse cells.
pub(crate) const CORRIDOR_COARSE_CELLS: f64 = 3.0;
/// Density a village's square is sized for: a hamlet of 20 buildings gets about 630 m, a village of 100 1.4 km.
pub(crate) const BUILDINGS_PER_HECTARE: f64 = 0.5;
/// Most buildings a village site may ask for.
pub(crate) const MAX_SITE_BUILDINGS: usize = 2_000;

/// Where a village grows, of which type and size, from which seed.
#[derive(Clone, Debug, PartialEq)]
pub struct VillageSite {
    /// World XY (m).
    pub position: DVec2,
    /// A village type of the encyclopedia.
    pub village_type: String,
    /// Buildings it asks for.
    pub buildings: usize,
    /// Seed of its growth.
    pub seed: u64,
}

/// The villages of a world and the roads joining them.
#[derive(Clone, Debug, Default)]
pub struct WorldVillages {
    /// The roads between villages.
    pub roads: Vec<Road>,
    /// One per site, in the sites' order (its roads are its own, not the world's).
    pub villages: Vec<Village>,
    /// Width of every road (m): its carriageway.
    pub road_width: f64,
}

/// The square a village of `buildings` grows in around `site` (m, its side).
pub fn village_side(buildings: usize) -> f64 {
    (buildings.max(1) as f64 / BUILDINGS_PER_HECTARE * 10_000.0).sqrt()
}

/// Refuses sites a world cannot grow: off the terrain or the world, of an unknown type, asking for no building or
/// too many, or so close that their squares overlap.
fn check_sites(
    sites: &[VillageSite],
    enc: &Encyclopedia,
    terrain: &Heightfield,
    min: DVec2,
    max: DVec2,
) -> Result<()> {
    let (tmin, tmax) = terrain.bbox();
    let (lo, hi) = (min.max(tmin), max.min(tmax));
    for (k, s) in sites.iter().enumerate() {
        let at = format!(
            "village site {} at x {:.1}, y {:.1}",
            k + 1,
            s.position.x,
            s.position.y
        );
        let p = s.position;
        if !(p.is_finite() && p.x >= lo.x && p.y >= lo.y && p.x <= hi.x && p.y <= hi.y) {
            return Err(Error::RegionOffTerrain {
                reason: format!(
                    "{at} lies off the world's terrain (x {:.1}..{:.1}, y {:.1}..{:.1})",
                    lo.x, hi.x, lo.y, hi.y
                ),
            });
        }
        if !enc.village_types.contains_key(&s.village_type) {
            let known: Vec<&str> = enc.village_types.keys().map(String::as_str).collect();
            return Err(Error::invalid(
                at,
                format!(
                    "the encyclopedia has no village type '{}' (it has {})",
                    s.village_type,
                    known.join(", ")
                ),
            ));
        }
        if s.buildings == 0 || s.buildings > MAX_SITE_BUILDINGS {
            return Err(Error::invalid(
                at,
                format!(
                    "asks for {} buildings: from 1 to {MAX_SITE_BUILDINGS}",
                    s.buildings
                ),
            ));
        }
        for (j, o) in sites.iter().enumerate().take(k) {
            let apart = (village_side(s.buildings) + village_side(o.buildings)) / 2.0;
            let d = (s.position - o.position).abs();
            if d.x < apart && d.y < apart {
                return Err(Error::invalid(
                    at,
                    format!(
                        "{:.0} m from village site {}; their villages of {} and {} buildings need {apart:.0} m \
                         apart along X or Y",
                        s.position.distance(o.position),
                        j + 1,
                        s.buildings,
                        o.buildings
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The order sites join the road network: the first, then each nearest the sites already joined.
fn prim_order(sites: &[VillageSite]) -> Vec<usize> {
    let mut order = vec![0];
    let mut left: Vec<usize> = (1..sites.len()).collect();
    while !left.is_empty() {
        let (k, _) = left
            .iter()
            .enumerate()
            .map(|(k, &s)| {
                let d = order
                    .iter()
                    .map(|&o| sites[o].position.distance(sites[s].position))
                    .fold(f64::INFINITY, f64::min);
                (k, d)
            })
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        order.push(left.remove(k));
    }
    order
}

/// The roads joining every site to the others, laid on a coarse grid over the world.
fn world_roads(
    sites: &[VillageSite],
    enc: &Encyclopedia,
    terrain: &Heightfield,
    min: DVec2,
    max: DVec2,
    cell: f64,
) -> Result<Vec<Road>> {
    if sites.len() < 2 {
        return Ok(Vec::new());
    }
    let coarse = cell.max((max - min).max_element() / WORLD_ROAD_NODES);
    let land = Land::new(
        terrain,
        &Region::Rect { min, max },
        &Environment::default(),
        coarse,
    )?;
    let order = prim_order(sites);
    let params = enc.road_params(&sites[order[0]].village_type);
    let occupied = vec![false; land.grid().len()];
    let mut network = RoadNetwork::new(&land, &[sites[order[0]].position], &[])?;
    for &k in &order[1..] {
        let joined = network.link_connection(&land, &params, &occupied, sites[k].position)?;
        if !joined.reached {
            return Err(Error::invalid(
                format!("village site {}", k + 1),
                "no road can join it to the other villages (water or the world's edge cuts it off)",
            ));
        }
    }
    let half_width = CORRIDOR_COARSE_CELLS * coarse;
    network
        .roads
        .iter()
        .map(|road| {
            let pieces = pieces(&road.points, PIECE_LENGTH);
            let fine = pieces
                .par_iter()
                .map(|piece| {
                    Ok(refined(piece, terrain, &params, cell, half_width)?
                        .unwrap_or_else(|| piece.clone()))
                })
                .collect::<Result<Vec<Vec<DVec2>>>>()?;
            let mut points: Vec<DVec2> = Vec::new();
            for piece in fine {
                let skip = usize::from(!points.is_empty());
                points.extend(piece.into_iter().skip(skip));
            }
            Ok(Road { points })
        })
        .collect()
}

/// `points` cut at vertices into pieces of at least `length` of road each (the last may be shorter); consecutive
/// pieces share their joining vertex.
fn pieces(points: &[DVec2], length: f64) -> Vec<Vec<DVec2>> {
    let mut out = Vec::new();
    let mut piece: Vec<DVec2> = Vec::new();
    let mut run = 0.0;
    for (k, &p) in points.iter().enumerate() {
        if let Some(&last) = piece.last() {
            run += last.distance(p);
        }
        piece.push(p);
        if run >= length && k + 1 < points.len() {
            out.push(std::mem::replace(&mut piece, vec![p]));
            run = 0.0;
        }
    }
    if piece.len() >= 2 {
        out.push(piece);
    }
    out
}

/// `piece` laid again on a grid of `cell` within `half_width` of it, from its first point to its last (which it
/// keeps exactly); `None` when no road joins them there.
fn refined(
    piece: &[DVec2],
    terrain: &Heightfield,
    params: &RoadParams,
    cell: f64,
    half_width: f64,
) -> Result<Option<Vec<DVec2>>> {
    let (Some(&first), Some(&last)) = (piece.first(), piece.last()) else {
        return Ok(None);
    };
    let (tmin, tmax) = terrain.bbox();
    let (lo, hi) = piece
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let (lo, hi) = ((lo - half_width).max(tmin), (hi + half_width).min(tmax));
    let grid = Grid::nodes_covering(lo, hi, cell)?;
    let n = grid.len();
    let height: Vec<f32> = (0..n)
        .map(|k| terrain.height_at(grid.point_of(k).min(tmax)).unwrap_or(0.0) as f32)
        .collect();
    let inside: Vec<bool> = (0..n)
        .map(|k| polyline_distance(grid.point_of(k), piece) <= half_width)
        .collect();
    let land = Land::from_maps(
        grid,
        height,
        [inside, vec![false; n], vec![false; n], vec![false; n]],
    )?;
    let mut network = RoadNetwork::new(&land, &[first], &[])?;
    let joined = network.link_connection(&land, params, &vec![false; n], last)?;
    if !joined.reached {
        return Ok(None);
    }
    // the through road (a cycle road the search may add after it is not the piece)
    let Some(mut points) = joined
        .roads
        .first()
        .and_then(|&k| network.roads.get(k))
        .map(|r| r.points.clone())
        .filter(|p| p.len() >= 2)
    else {
        return Ok(None);
    };
    // the search lays it from the last point back to the first, between the nodes nearest them
    if points[0].distance(first) > points[points.len() - 1].distance(first) {
        points.reverse();
    }
    let end = points.len() - 1;
    points[0] = first;
    points[end] = last;
    Ok(Some(points))
}

/// Grows every site's village on `terrain` within the world `min`–`max`, after the roads joining them; `cell` is the
/// villages' grid cell (m). A site off the terrain, of an unknown type, of no building or too many, or too near
/// another is refused before anything grows.
pub fn grow_world_villages(
    terrain: &Heightfield,
    min: DVec2,
    max: DVec2,
    sites: &[VillageSite],
    enc: &Encyclopedia,
    cell: f64,
) -> Result<WorldVillages> {
    enc.validate()?;
    crate::error::check::positive("the villages' grid cell", cell)?;
    check_sites(sites, enc, terrain, min, max)?;
    let roads = world_roads(sites, enc, terrain, min, max, cell)?;
    let lines: Vec<Vec<DVec2>> = roads.iter().map(|r| r.points.clone()).collect();
    let villages = sites
        .par_iter()
        .map(|s| {
            let half = DVec2::splat(village_side(s.buildings) / 2.0);
            let region = Region::Rect {
                min: (s.position - half).max(min),
                max: (s.position + half).min(max),
            };
            let existing: Vec<Vec<DVec2>> = lines
                .iter()
                .flat_map(|l| region.clip_polyline(l).0)
                .filter(|l| l.len() >= 2)
                .collect();
            let connections = border_crossings(&region, &roads);
            let village_type = &enc.village_types[&s.village_type];
            let scenario = scenario_for(enc, &s.village_type, village_type, s.buildings, 1.0, 0.2);
            let request = VillageRequest {
                site: Site {
                    terrain,
                    region,
                    environment: Environment::default(),
                    cell,
                },
                connections,
                existing_roads: existing,
                encyclopedia: enc,
                scenario: &scenario,
                seed: s.seed,
                parcel_cell: cell / 2.0,
            };
            generate_village(&request, &|_, _| true)
        })
        .collect::<Result<Vec<Village>>>()?;
    Ok(WorldVillages {
        roads,
        villages,
        road_width: enc.roads.width,
    })
}

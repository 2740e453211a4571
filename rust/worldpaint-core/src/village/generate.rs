//! The village pipeline of Fig. 3.2: given a terrain, a region of interest, connection points, the environment
//! and a growth scenario, grow the skeleton (3.2: each new building seed connected to the roads at once), then
//! the land parcels and footprints (3.3), then the houses (3.4).

use super::encyclopedia::{
    BuildingKind, Encyclopedia, Placement, RoadParams, Scenario, ScenarioEvent,
};
use super::footprint::footprint_indexed;
use super::house::build_house;
use super::interest::{criteria, interest, InterestCriterion, StaticInterestMaps, VillageState};
use super::land::{Land, Site};
use super::metrics::on_water;
use super::parcels::{parcels_with, ParcelOptions, ParcelSeed};
use super::road_index::RoadIndex;
use super::roads::RoadNetwork;
use super::seeding::{causes, seed_building, Ring};
use super::spurs::used_roads;
use super::{BuildingSeed, HouseFootprint, HouseMesh, Parcel, Road};
use crate::error::{Error, Result};
use crate::geom::Region;
use crate::graph::SegmentIndex;
use crate::progress::Counted;
use crate::synthesis::mix_seed;
use glam::DVec2;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::Instant;

/// Candidates tried per building before the best one seen is taken (Algorithm 1's loop bound).
const MAX_ATTEMPTS: usize = 20_000;
/// Candidates tried around the standing buildings for a building seeded beside one, before it is seeded as the
/// others are.
const CLUSTER_ATTEMPTS: usize = 1024;
/// Failed placements of one building type in a row after which the rest of its request is reported unplaced
/// without trying: each failure costs [`MAX_ATTEMPTS`] candidate positions.
const MAX_FAILURES_IN_A_ROW: usize = 32;
/// Candidates a building type left unplaced is judged by, to say why ([`VillageReport::unplaced_causes`]).
pub const UNPLACED_CANDIDATES: usize = 4096;

/// Everything a village is generated from.
pub struct VillageRequest<'a> {
    /// The terrain, the region of interest `Ω`, the water and walls, and the skeleton's grid cell.
    pub site: Site<'a>,
    /// Connection points `Ψ` to the outside world; empty: where existing roads cross the region's border, else the
    /// lowest point of the border. Before any building, each point after the first is joined to the roads by a
    /// through road (with re-use, so existing roads serve where they can).
    pub connections: Vec<DVec2>,
    /// Roads already there (kept as they are; new roads re-use them).
    pub existing_roads: Vec<Vec<DVec2>>,
    /// The building types and their placement per village type.
    pub encyclopedia: &'a Encyclopedia,
    /// What to build, in order.
    pub scenario: &'a Scenario,
    /// Seed of every random choice: the same request gives the same village.
    pub seed: u64,
    /// Grid cell (m) of the land conquest (the skeleton's cell when 0).
    pub parcel_cell: f64,
}

/// The stages reported to the progress callback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VillageStage {
    /// Building seeds and the roads to them (3.2).
    Skeleton,
    /// Parcels and footprints (3.3).
    Parcels,
    /// House geometry (3.4).
    Houses,
}

/// What happened while the village grew: what a layout team reads to tune the encyclopedia.
#[derive(Clone, Debug, Default)]
pub struct VillageReport {
    /// Buildings the scenario asks for (its counts summed).
    pub requested: usize,
    /// Seeds placed and reached by a road.
    pub seeded: usize,
    /// Of those, the seeds placed by taking the best candidate after too many failed aggregation tests.
    pub fallbacks: usize,
    /// Buildings for which no location had a positive interest.
    pub unplaced: Vec<String>,
    /// Why, per building type left unplaced: of candidates drawn over the land when its first building found no
    /// place, how many each interest criterion forbade (in [`InterestCriterion::ALL`] order), how many lay where
    /// nothing can be built, and how many had an interest of 0 that no criterion forbade; out of
    /// [`UNPLACED_CANDIDATES`].
    pub unplaced_causes: BTreeMap<String, [usize; 9]>,
    /// Seeds the roads could not reach (dropped).
    pub unreachable: usize,
    /// Seeds that lost access to the roads in the parcel conquest (dropped, 3.3.2).
    pub without_access: usize,
    /// Seeds whose parcel was too small for the building's smallest footprint (no house).
    pub without_footprint: usize,
    /// Roads that had to be steeper than the encyclopedia's maximum grade (the terrain left no other way).
    pub roads_over_max_grade: usize,
    /// Cycle roads built (3.2.4).
    pub cycles: usize,
    /// New dead-end roads left unused by the buildings, removed before the parcels (see `village::spurs`).
    pub pruned_roads: usize,
    /// The connection points `Ψ` the roads started from: the request's, or those found when it gave none.
    pub connections: Vec<DVec2>,
    /// Seconds spent in the skeleton, the parcels and footprints, and the houses.
    pub seconds: [f64; 3],
}

/// A generated village. `parcels`, `footprints` and `houses` are given per kept seed, in `seeds` order.
#[derive(Clone, Debug, Default)]
pub struct Village {
    /// The seeds that got a parcel and a footprint; the others are counted in the report.
    pub seeds: Vec<BuildingSeed>,
    /// The new roads (the existing ones are not repeated).
    pub roads: Vec<Road>,
    /// One per seed.
    pub parcels: Vec<Parcel>,
    /// One per seed, inside its parcel.
    pub footprints: Vec<HouseFootprint>,
    /// One per seed, on its footprint.
    pub houses: Vec<HouseMesh>,
    /// The land the village was generated on (`None` only in a default value).
    pub land: Option<Land>,
    /// What happened while it grew.
    pub report: VillageReport,
}

/// Default connection points: where the existing roads cross the border of `Ω`, else the lowest border node.
pub(crate) fn default_connections(
    land: &Land,
    region: &Region,
    existing: &[Vec<DVec2>],
) -> Vec<DVec2> {
    let mut points: Vec<DVec2> = Vec::new();
    for road in existing {
        for s in road.windows(2) {
            for t in region.segment_crossings(s[0], s[1]) {
                points.push(s[0] + (s[1] - s[0]) * t);
            }
        }
    }
    if !points.is_empty() {
        return points;
    }
    let g = land.grid();
    let border = (0..g.len()).filter(|&k| {
        if !land.inside()[k] || land.water()[k] {
            return false;
        }
        let (i, j) = g.ij(k);
        i == 0
            || j == 0
            || i + 1 == g.nx
            || j + 1 == g.ny
            || !land.inside()[g.index(i - 1, j)]
            || !land.inside()[g.index(i + 1, j)]
            || !land.inside()[g.index(i, j - 1)]
            || !land.inside()[g.index(i, j + 1)]
    });
    border
        .min_by(|a, b| {
            land.height()[*a]
                .total_cmp(&land.height()[*b])
                .then(a.cmp(b))
        })
        .map(|k| vec![g.point_of(k)])
        .unwrap_or_default()
}

/// Building `i`'s draw in [0, 1) of the village's `seed` for the choice `key` (whether its footprint is turned,
/// skewed, whether it is seeded beside another...): independent of the thread count and of the other choices.
fn draw(seed: u64, key: u64, i: usize) -> f64 {
    (mix_seed(mix_seed(seed, key), i as u64) >> 11) as f64 / (1u64 << 53) as f64
}

/// The rings a building placed by `placement` is seeded in beside one of `seeds`: between the sociability's
/// `λ_min` and `λ_0` towards each.
fn rings_around(seeds: &[BuildingSeed], placement: &Placement) -> Vec<Ring> {
    seeds
        .iter()
        .map(|b| {
            let shape = placement
                .sociability_with
                .get(&b.building)
                .unwrap_or(&placement.sociability);
            Ring {
                centre: b.position,
                inner: shape.min,
                outer: shape.zero.max(shape.min),
            }
        })
        .collect()
}

/// Marks the nodes within `radius` of `p` in `mask`.
fn stamp(land: &Land, mask: &mut [bool], p: DVec2, radius: f64) {
    let g = land.grid();
    let r = (radius / g.cell).ceil() as i64;
    let f = (p - g.origin) / g.cell;
    let (ci, cj) = (f.x.round() as i64, f.y.round() as i64);
    for j in (cj - r).max(0)..=(cj + r).min(g.ny as i64 - 1) {
        for i in (ci - r).max(0)..=(ci + r).min(g.nx as i64 - 1) {
            let k = g.index(i as usize, j as usize);
            if g.point_of(k).distance(p) <= radius {
                mask[k] = true;
            }
        }
    }
}

/// Where a building whose new road `road` (from the building on) ends at it stands: beside the road's last
/// metres, at its preferred distance from a road (accessibility `λ_0`, at least clear of the road and its own
/// smallest footprint), on the side farther from the other buildings (nearer them for a building seeded beside
/// one). The road reaches the building's door, and its lot fronts the road's side, not the cap of the dead end
/// (3.3.1: a parcel is conquered from the road beside its seed). `None` when neither side is free: too close to
/// another building (sociability's `λ_min`), another road, the water or the border.
fn beside_its_road(
    at: &Placing,
    network: &RoadNetwork,
    road: &[DVec2],
    seeds: &[BuildingSeed],
) -> Option<DVec2> {
    let (land, placement, kind, road_width) = (at.land, at.placement, at.kind, at.road_width);
    let (&end, &next) = (road.first()?, road.get(1)?);
    let along = (next - end).try_normalize()?;
    let size = placement.footprint_sizes(kind);
    let clear = 0.5 * road_width + 0.5 * size.min[0].max(size.min[1]);
    let off = placement.accessibility.zero.max(clear);
    let back = (0.5 * size.min[0].min(size.min[1])).min(end.distance(next));
    let nearest = |p: DVec2| -> Option<f64> {
        let mut nearest = f64::INFINITY;
        for b in seeds {
            let shape = placement
                .sociability_with
                .get(&b.building)
                .unwrap_or(&placement.sociability);
            let d = b.position.distance(p);
            if d < shape.min {
                return None;
            }
            nearest = nearest.min(d);
        }
        Some(nearest)
    };
    [1.0, -1.0]
        .into_iter()
        .filter_map(|side| {
            let p = end + along * back + along.perp() * (side * off);
            let (i, j) = land.grid().nearest(p)?;
            let free = land.buildable(land.grid().index(i, j)) && network.distance(p) >= clear;
            free.then(|| nearest(p).map(|d| (d, p)))?
        })
        .max_by(|a, b| {
            let farther = a.0.total_cmp(&b.0);
            if at.beside_one {
                farther.reverse()
            } else {
                farther
            }
        })
        .map(|(_, p)| p)
}

/// Generates a village; `progress(stage, fraction)` returning `false` cancels (`Error::Cancelled`). The thesis's
/// stages, each a function of its own: the ways through the region, the skeleton of seeds and roads (3.2), the
/// parcels and footprints (3.3), the houses (3.4).
pub fn generate_village(
    request: &VillageRequest,
    progress: &(dyn Fn(VillageStage, f64) -> bool + Sync),
) -> Result<Village> {
    let enc = request.encyclopedia;
    enc.validate()?;
    enc.check_scenario(request.scenario)?;
    let started = Instant::now();
    let reached = |stage: VillageStage, fraction: f64| {
        if progress(stage, fraction) {
            Ok(())
        } else {
            Err(Error::Cancelled)
        }
    };
    let land = request.site.land()?;
    if !land.inside().iter().any(|v| *v) {
        return Err(Error::bad_region(
            "the village region holds no node of its grid; use a finer cell",
        ));
    }
    let mut report = VillageReport {
        requested: request.scenario.building_count() as usize,
        ..Default::default()
    };
    let mut network = ways_through(request, &land, &mut report, &reached)?;
    let seeds = skeleton(request, &land, &mut network, &mut report, &reached)?;
    report.seconds[0] = started.elapsed().as_secs_f64();

    let stage = Instant::now();
    reached(VillageStage::Parcels, 0.0)?;
    let existing = request.existing_roads.len().min(network.roads.len());
    let mut roads = roads_in_use(request, network, existing, &seeds, &mut report);
    let lots = parcels_and_footprints(request, &land, &roads, seeds, &mut report, progress)?;
    report.seconds[1] = stage.elapsed().as_secs_f64();

    let stage = Instant::now();
    reached(VillageStage::Houses, 0.0)?;
    let houses = houses(request, &land, &lots, progress)?;
    report.seconds[2] = stage.elapsed().as_secs_f64();
    progress(VillageStage::Houses, 1.0);

    Ok(Village {
        seeds: lots.seeds,
        roads: roads.split_off(existing),
        parcels: lots.parcels,
        footprints: lots.footprints,
        houses,
        land: Some(land),
        report,
    })
}

/// The roads the village starts from: the existing ones and, before any building, a through road from each
/// connection point after the first (built by the village's first type; the village grows on the ways through it).
fn ways_through(
    request: &VillageRequest,
    land: &Land,
    report: &mut VillageReport,
    reached: &dyn Fn(VillageStage, f64) -> Result<()>,
) -> Result<RoadNetwork> {
    let connections = if request.connections.is_empty() {
        default_connections(land, &request.site.region, &request.existing_roads)
    } else {
        request.connections.clone()
    };
    reached(VillageStage::Skeleton, 0.0)?;
    let (first, others) = connections.split_at(connections.len().min(1));
    let mut network = RoadNetwork::new(land, first, &request.existing_roads)?;
    let no_buildings = vec![false; land.grid().len()];
    let first_type = request.scenario.events.iter().find_map(|e| match e {
        ScenarioEvent::ChangeVillageType { village_type } => Some(village_type.as_str()),
        ScenarioEvent::Generate { .. } => None,
    });
    let through_roads = request
        .encyclopedia
        .road_params(first_type.unwrap_or_default());
    for &p in others {
        reached(VillageStage::Skeleton, 0.0)?;
        let through = network.link_connection(land, &through_roads, &no_buildings, p)?;
        report.roads_over_max_grade += through.over_max_grade as usize;
    }
    report.connections = network.connections().to_vec();
    Ok(network)
}

/// Every domination radius the scenario may ask for, so that the static maps compute each once.
fn domination_radii(enc: &Encyclopedia, scenario: &Scenario) -> Result<Vec<f64>> {
    let mut radii: Vec<f64> = Vec::new();
    let mut current: Option<&str> = None;
    for e in &scenario.events {
        match e {
            ScenarioEvent::ChangeVillageType { village_type } => current = Some(village_type),
            ScenarioEvent::Generate { building, .. } => {
                if let Some(v) = current {
                    let r = enc.placement(v, building)?.domination_radius;
                    if !radii.contains(&r) {
                        radii.push(r);
                    }
                }
            }
        }
    }
    Ok(radii)
}

/// The skeleton as it grows (3.2): the buildings seeded so far and the land they hold.
struct Skeleton {
    seeds: Vec<BuildingSeed>,
    religious: Vec<bool>,
    fortress: Vec<bool>,
    occupied: Vec<bool>,
}

/// 3.2: the scenario's buildings seeded one by one where their interest is highest, each joined to the roads by a
/// new road that goes on past it as a street.
fn skeleton(
    request: &VillageRequest,
    land: &Land,
    network: &mut RoadNetwork,
    report: &mut VillageReport,
    reached: &dyn Fn(VillageStage, f64) -> Result<()>,
) -> Result<Vec<BuildingSeed>> {
    let enc = request.encyclopedia;
    let maps = StaticInterestMaps::new(land, &domination_radii(enc, request.scenario)?);
    reached(VillageStage::Skeleton, 0.0)?;
    let mut rng = ChaCha8Rng::seed_from_u64(mix_seed(request.seed, 0x5EED));
    let mut grown = Skeleton {
        seeds: Vec::new(),
        religious: Vec::new(),
        fortress: Vec::new(),
        occupied: vec![false; land.grid().len()],
    };
    let mut village_type = String::new();
    let mut roads = enc.roads.clone();
    let total = report.requested.max(1) as f64;
    let mut done = 0usize;
    for e in &request.scenario.events {
        let (count, building) = match e {
            ScenarioEvent::ChangeVillageType { village_type: v } => {
                village_type = v.clone();
                roads = enc.road_params(v);
                continue;
            }
            ScenarioEvent::Generate { count, building } => (*count, building),
        };
        let placement = enc.placement(&village_type, building)?;
        let kind = enc
            .buildings
            .get(building)
            .ok_or_else(|| Error::unknown("building type", building))?;
        let mut failed_in_a_row = 0;
        for _ in 0..count {
            reached(VillageStage::Skeleton, done as f64 / total)?;
            done += 1;
            if failed_in_a_row >= MAX_FAILURES_IN_A_ROW {
                // the land has no more room for this building: the rest of the request cannot be placed either
                report.unplaced.push(building.clone());
                continue;
            }
            let road_distance = |p: DVec2, max: f64| network.distance_within(p, max);
            let state = VillageState::new(
                &grown.seeds,
                &grown.religious,
                &grown.fortress,
                &road_distance,
                !network.roads.is_empty(),
            );
            // a building of the cluster share is seeded beside a standing one where there is room
            let near = if !grown.seeds.is_empty()
                && draw(request.seed, 0xC1A5, done) < placement.cluster_share
            {
                let rings = rings_around(&grown.seeds, placement);
                seed_building(
                    land,
                    &maps,
                    &state,
                    placement,
                    &rings,
                    &mut rng,
                    CLUSTER_ATTEMPTS,
                )
            } else {
                None
            };
            let beside_one = near.is_some();
            let found = near.or_else(|| {
                seed_building(land, &maps, &state, placement, &[], &mut rng, MAX_ATTEMPTS)
            });
            let Some(found) = found else {
                if !report.unplaced_causes.contains_key(building) {
                    // drawn from a generator of its own: saying why changes nothing of the village
                    let mut why = ChaCha8Rng::seed_from_u64(mix_seed(request.seed, 0x3A7));
                    let tally = causes(
                        land,
                        &maps,
                        &state,
                        placement,
                        &mut why,
                        UNPLACED_CANDIDATES,
                    );
                    report.unplaced_causes.insert(building.clone(), tally);
                }
                report.unplaced.push(building.clone());
                failed_in_a_row += 1;
                continue;
            };
            failed_in_a_row = 0;
            let seed = BuildingSeed {
                building: building.clone(),
                village_type: village_type.clone(),
                position: found.position,
            };
            let at = Placing {
                land,
                roads: &roads,
                road_width: enc.roads.width,
                placement,
                kind,
                beside_one,
            };
            if grown.connect(&at, network, seed, report)? {
                report.fallbacks += found.fallback as usize;
            }
        }
    }
    Ok(grown.seeds)
}

/// What a building is placed with: the land, the roads its village type builds (and the encyclopedia's road
/// width), its placement and its type, and whether it was seeded beside a standing building.
struct Placing<'a> {
    land: &'a Land,
    roads: &'a RoadParams,
    road_width: f64,
    placement: &'a Placement,
    kind: &'a BuildingKind,
    beside_one: bool,
}

impl Skeleton {
    /// Joins the building `seed` (placed where its interest is highest) to the roads and keeps it where the road
    /// reached it, beside its road's end; one the roads cannot reach is dropped (false).
    fn connect(
        &mut self,
        at: &Placing,
        network: &mut RoadNetwork,
        mut seed: BuildingSeed,
        report: &mut VillageReport,
    ) -> Result<bool> {
        let (land, roads, width, kind) = (at.land, at.roads, at.road_width, at.kind);
        // a house this close to a road fronts it: its footprint, grown from the road side, can reach the seed
        let size = at.placement.footprint_sizes(kind);
        let frontage = 0.5 * width + size.max[0].max(size.max[1]);
        let connection = network.connect(land, roads, &self.occupied, seed.position, frontage)?;
        if !connection.reached {
            report.unreachable += 1;
            return Ok(false);
        }
        report.seeded += 1;
        report.roads_over_max_grade += connection.over_max_grade as usize;
        report.cycles += connection.cycle as usize;
        if let Some(&r) = connection.roads.first() {
            let road = &network.roads[r].points;
            let beside = beside_its_road(at, network, road, &self.seeds);
            seed.position = beside.unwrap_or(seed.position);
        }
        let radius = 0.5 * size.min[0].max(size.min[1]);
        stamp(land, &mut self.occupied, seed.position, radius);
        // the building's road goes on past it as a street for the houses that come next
        if let (Some(&r), false) = (connection.roads.first(), connection.cycle) {
            network.lay_street(land, roads, &self.occupied, r);
        }
        self.seeds.push(seed);
        self.religious.push(kind.religious);
        self.fortress.push(kind.fortress);
        Ok(true)
    }
}

/// The network's roads without the new dead ends no building uses: the existing roads (the first `existing`)
/// first, then the new ones kept.
fn roads_in_use(
    request: &VillageRequest,
    mut network: RoadNetwork,
    existing: usize,
    seeds: &[BuildingSeed],
    report: &mut VillageReport,
) -> Vec<Road> {
    let positions: Vec<DVec2> = seeds.iter().map(|s| s.position).collect();
    let keep = used_roads(
        &network.roads,
        existing,
        &positions,
        network.connections(),
        0.1 * request.site.cell,
    );
    report.pruned_roads = keep.iter().filter(|&&k| !k).count();
    std::mem::take(&mut network.roads)
        .into_iter()
        .zip(&keep)
        .filter_map(|(r, &k)| k.then_some(r))
        .collect()
}

/// The seeds that got a parcel and a footprint, with them, in the same order.
struct Lots {
    seeds: Vec<BuildingSeed>,
    parcels: Vec<Parcel>,
    footprints: Vec<HouseFootprint>,
}

/// 3.3: each seed's parcel conquered from its road, and the building's footprint inside it; the seeds that lose
/// their access or whose parcel holds no footprint (or only one over the water) are counted and dropped.
fn parcels_and_footprints(
    request: &VillageRequest,
    land: &Land,
    roads: &[Road],
    seeds: Vec<BuildingSeed>,
    report: &mut VillageReport,
    progress: &(dyn Fn(VillageStage, f64) -> bool + Sync),
) -> Result<Lots> {
    let enc = request.encyclopedia;
    let placements: Vec<_> = seeds
        .iter()
        .map(|s| enc.placement(&s.village_type, &s.building))
        .collect::<Result<Vec<_>>>()?;
    let parcel_seeds: Vec<ParcelSeed> = seeds
        .iter()
        .zip(&placements)
        .map(|(s, p)| ParcelSeed {
            position: s.position,
            params: &p.parcel,
        })
        .collect();
    let parcel_cell = if request.parcel_cell > 0.0 {
        request.parcel_cell
    } else {
        request.site.cell
    };
    let conquered = parcels_with(
        land,
        roads,
        enc.roads.width,
        &parcel_seeds,
        parcel_cell,
        &ParcelOptions::default(),
        &|f| progress(VillageStage::Parcels, 0.8 * f),
    )?;
    let footprints = Counted::new(conquered.len(), |f| {
        progress(VillageStage::Parcels, 0.8 + 0.2 * f)
    });
    // each building's draws of whether its footprint is turned or skewed, and by how much
    let draw = |key: u64, i: usize| draw(request.seed, key, i);
    let index = RoadIndex::new(roads, enc.roads.width.max(8.0));
    let found: Vec<Option<HouseFootprint>> = conquered
        .par_iter()
        .zip(seeds.par_iter().zip(placements.par_iter()))
        .enumerate()
        .map(|(i, (parcel, (s, placement)))| {
            let parcel = parcel.as_ref().filter(|_| footprints.go_on())?;
            let size =
                placement.footprint_sizes_drawn(enc.buildings.get(&s.building)?, draw(0x7E2D, i));
            let sizes = (size.min, size.max);
            let grown =
                |turn: f64| footprint_indexed(parcel, &index, enc.roads.width, sizes, 1.0, turn);
            // a skewed footprint that finds no room in its parcel stands along the road
            let fp = if draw(0x5E3A, i) < placement.skew_share {
                let turn = std::f64::consts::FRAC_PI_2 * (2.0 * draw(0x5E3B, i) - 1.0);
                grown(turn).or_else(|| grown(0.0))
            } else {
                grown(0.0)
            };
            footprints.done_one();
            fp
        })
        .collect();
    footprints.finish()?;
    let mut lots = Lots {
        seeds: Vec::new(),
        parcels: Vec::new(),
        footprints: Vec::new(),
    };
    for ((s, parcel), fp) in seeds.into_iter().zip(conquered).zip(found) {
        let Some(parcel) = parcel else {
            report.without_access += 1;
            continue;
        };
        // a parcel on the shore may still leave its footprint's edge over the water
        let Some(fp) = fp.filter(|f| !on_water(land, f)) else {
            report.without_footprint += 1;
            continue;
        };
        let index = lots.seeds.len();
        lots.seeds.push(s);
        lots.parcels.push(Parcel {
            seed: index,
            ..parcel
        });
        lots.footprints.push(HouseFootprint { seed: index, ..fp });
    }
    Ok(lots)
}

/// 3.4: a house on each footprint, its storeys drawn from the building type's range, its floor on the terrain.
fn houses(
    request: &VillageRequest,
    land: &Land,
    lots: &Lots,
    progress: &(dyn Fn(VillageStage, f64) -> bool + Sync),
) -> Result<Vec<HouseMesh>> {
    let enc = request.encyclopedia;
    let terrain = request.site.terrain;
    let ground = |p: DVec2| terrain.height_at(p).unwrap_or_else(|| land.height_at(p));
    let built = Counted::new(lots.footprints.len(), |f| progress(VillageStage::Houses, f));
    let houses: Vec<HouseMesh> = lots
        .footprints
        .par_iter()
        .zip(lots.seeds.par_iter())
        .enumerate()
        .filter_map(|(k, (fp, s))| {
            let kind = enc.buildings.get(&s.building).filter(|_| built.go_on())?;
            let seed = mix_seed(request.seed, k as u64 + 1);
            let span = (kind.storeys[1] - kind.storeys[0] + 1) as u64;
            let storeys = kind.storeys[0] + (seed % span) as u32;
            let (mut mesh, _) = build_house(fp, kind, storeys, &ground, seed);
            mesh.seed = k;
            built.done_one();
            Some(mesh)
        })
        .collect();
    built.finish()?;
    Ok(houses)
}

/// What an interest map is shown for: one building type of one village type, in a village as it stands.
pub struct InterestRequest<'a> {
    /// The terrain, the region of interest `Ω`, the water and walls, and the cell of the grid the criteria are
    /// read on.
    pub site: Site<'a>,
    /// Where the placement parameters come from.
    pub encyclopedia: &'a Encyclopedia,
    /// The village type `V` (a key of the encyclopedia's `village_types`).
    pub village_type: &'a str,
    /// The building type `B` (a key of the encyclopedia's `buildings`).
    pub building: &'a str,
    /// One criterion `f_i`, or `None` for the combined interest `I(p, B, V)`.
    pub criterion: Option<InterestCriterion>,
    /// The buildings and roads already there (the dynamic criteria depend on them).
    pub buildings: &'a [BuildingSeed],
    /// The roads already there, as polylines.
    pub roads: &'a [Vec<DVec2>],
}

/// The interest (or one criterion) at each of `points`, as Fig. 3.5 shows it; 0 outside the region.
pub fn interest_at(request: &InterestRequest, points: &[DVec2]) -> Result<Vec<f64>> {
    let enc = request.encyclopedia;
    let placement = enc.placement(request.village_type, request.building)?;
    let land = request.site.land()?;
    let maps = StaticInterestMaps::new(&land, &[placement.domination_radius]);
    let flags = |pick: fn(&super::encyclopedia::BuildingKind) -> bool| -> Vec<bool> {
        request
            .buildings
            .iter()
            .map(|b| enc.buildings.get(&b.building).is_some_and(pick))
            .collect()
    };
    let (religious, fortress) = (flags(|k| k.religious), flags(|k| k.fortress));
    let index = SegmentIndex::new(
        request
            .roads
            .iter()
            .flat_map(|r| r.windows(2).map(|s| (s[0], s[1])))
            .collect(),
    );
    let road_distance = |p: DVec2, max: f64| index.distance(p, max);
    let state = VillageState::new(
        request.buildings,
        &religious,
        &fortress,
        &road_distance,
        !index.is_empty(),
    );
    Ok(points
        .par_iter()
        .map(|p| {
            if !request.site.region.contains(*p) {
                return 0.0;
            }
            match request.criterion {
                None => interest(&land, &maps, &state, placement, *p),
                Some(c) => {
                    let k = InterestCriterion::ALL
                        .iter()
                        .position(|x| *x == c)
                        .unwrap_or(0);
                    criteria(&land, &maps, &state, placement, *p)[k]
                }
            }
        })
        .collect())
}

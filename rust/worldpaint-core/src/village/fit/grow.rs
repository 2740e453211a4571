//! Villages grown for a fit: a candidate at several seeds, and every village type of an encyclopedia ranked by
//! how near its villages come to the real one (the nearest is where a fit starts by default).

use super::objective::objective;
use super::{scenario_for, FitTarget};
use crate::village::encyclopedia::{Encyclopedia, Scenario};
use crate::village::figures::{village_figures, SitedBuilding, VillageFigures};
use crate::village::generate::{generate_village, VillageRequest};
use crate::{Error, Result};
use rayon::prelude::*;

/// Share of farms a shipped type is grown with when ranked: the thesis's scenarios' one farm in five.
pub(crate) const PRESET_FARM_SHARE: f64 = 0.2;

/// The figures of a village grown on `target` with `enc`'s `scenario`; `None` when it was cancelled or could not
/// grow. `keep_going` is asked between buildings.
fn grow_one(
    target: &FitTarget,
    enc: &Encyclopedia,
    scenario: &Scenario,
    seed: u64,
    parcel_cell: f64,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Result<Option<VillageFigures>> {
    let request = VillageRequest {
        site: target.site.clone(),
        connections: target.connections.clone(),
        existing_roads: Vec::new(),
        encyclopedia: enc,
        scenario,
        seed,
        parcel_cell,
    };
    match generate_village(&request, &|_, _| keep_going()) {
        Ok(v) => {
            let buildings: Vec<SitedBuilding> = v
                .footprints
                .iter()
                .map(SitedBuilding::of_footprint)
                .collect();
            Ok(Some(village_figures(
                &buildings,
                &v.roads,
                &target.site.region,
            )))
        }
        Err(Error::Cancelled) => Ok(None),
        // parameters that leave no place to build: no figures, the worst objective
        Err(Error::BadRegion { .. } | Error::Invalid { .. }) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The figures of villages grown on `target` with `enc`'s `scenario`, one per seed, in parallel and gathered in
/// the seeds' order (`None`: that seed grew no village, or was cancelled). `keep_going` is asked between
/// buildings.
pub fn grow_village_figures(
    target: &FitTarget,
    enc: &Encyclopedia,
    scenario: &Scenario,
    seeds: &[u64],
    parcel_cell: f64,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Option<VillageFigures>>> {
    seeds
        .par_iter()
        .map(|seed| grow_one(target, enc, scenario, *seed, parcel_cell, keep_going))
        .collect()
}

/// A village type of the encyclopedia grown on a real village's site.
#[derive(Clone, Debug)]
pub struct RankedType {
    /// Its name in the encyclopedia.
    pub name: String,
    /// Its objective against the real village.
    pub objective: f64,
    /// The figures of its villages, one per seed.
    pub grown: Vec<Option<VillageFigures>>,
}

/// Every village type of `enc` grown on `target` at `seeds` (the real count of buildings, a church where the
/// type builds one and a fifth of the rest farms), nearest to the real village first, ties by name. `Ok` with
/// fewer types when `keep_going` stopped it.
pub fn rank_village_types(
    target: &FitTarget,
    enc: &Encyclopedia,
    seeds: &[u64],
    parcel_cell: f64,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<RankedType>> {
    let buildings = target.figures.layout.houses;
    let mut ranked = Vec::new();
    for (name, village_type) in &enc.village_types {
        if !keep_going() {
            break;
        }
        let scenario = scenario_for(enc, name, village_type, buildings, 1.0, PRESET_FARM_SHARE);
        let grown = grow_village_figures(target, enc, &scenario, seeds, parcel_cell, keep_going)?;
        ranked.push(RankedType {
            name: name.clone(),
            objective: objective(&target.figures, &grown),
            grown,
        });
    }
    ranked.sort_by(|a, b| {
        a.objective
            .total_cmp(&b.objective)
            .then_with(|| a.name.cmp(&b.name))
    });
    Ok(ranked)
}

//! A village type learned from a real village (issue 42; the thesis sets its encyclopedia by hand, 3.1): the
//! parameters of a base village type (see [`space`]) are searched by CMA-ES (the `cmaes` crate: Hansen's
//! covariance matrix adaptation, made for noisy, non-separable black-box problems of tens of dimensions) so
//! that villages grown with them on the real village's terrain, region and connection points have the real
//! village's figures ([`village_figures`]; the distance is [`objective`]'s).
//!
//! Readings chosen:
//! * The search starts from the village type whose villages come nearest the real one (each grown at the fit's
//!   seeds) unless the options name one.
//! * The scenario is the base's: a church when the base builds churches, then houses, then farms; its counts
//!   are the real village's building count times a learned factor (the generator loses buildings in narrow
//!   parcels and the real count includes outbuildings), split by a learned share of farms.
//! * Each candidate is grown at the same few seeds (common random numbers: two candidates differ by their
//!   parameters, not by their luck), all candidates of a generation and all their seeds in parallel; results
//!   are gathered in order, so a fit is the same whatever the number of threads.
//! * A budget of evaluations (candidates; by default as many as grow about 60,000 buildings, so that a fit is
//!   repeatable) and of seconds; the search ends before a generation that would not
//!   leave time for the finalists and the step at the pace so far. Past the seconds, or when the progress callback returns
//!   `false`, the villages growing are cancelled and the best type of the generations completed is kept.
//! * The type kept is not the best at the fit's seeds, which is partly the best at their luck: the finalists are
//!   grown again at four times as many held-out seeds, which alone judge them ([`search`]); the one kept then
//!   takes a step on its shares of turned and skewed footprints towards the real orientation to the road
//!   ([`space::ParameterSpace::orientation_step`]) and, where its hairpins per km are off, that step with its grade
//!   limit moved one and two steps more towards them ([`space::ParameterSpace::grade_steps`]); the nearest of
//!   these at those seeds is kept where it comes nearer than the point.

mod grow;
pub(crate) mod objective;
mod search;
pub(crate) mod space;

use super::encyclopedia::{Encyclopedia, Scenario, ScenarioEvent, VillageType};
use super::figures::{village_figures, SitedBuilding, VillageFigures};
use super::{Road, Site};
use crate::geom::Region;
use crate::{Error, Result};
use glam::DVec2;
pub use grow::{grow_village_figures, rank_village_types, RankedType};
use search::Search;
use space::ParameterSpace;

/// Fewest buildings a real village must hold to be learned from.
pub const MIN_BUILDINGS: usize = 5;
/// Crossings of the border closer than this (m) are one way into the village.
const CROSSING_MERGE: f64 = 60.0;

/// Where `roads` cross the border of `region`: a real village's ways in, each crossing within 60 m
/// of one already found merged into it.
pub fn border_crossings(region: &Region, roads: &[Road]) -> Vec<DVec2> {
    let mut out: Vec<DVec2> = Vec::new();
    for s in roads.iter().flat_map(|r| r.points.windows(2)) {
        for t in region.segment_crossings(s[0], s[1]) {
            let p = s[0] + (s[1] - s[0]) * t;
            if out.iter().all(|c| c.distance(p) > CROSSING_MERGE) {
                out.push(p);
            }
        }
    }
    out
}

/// The real village a type is learned from: where it stands and its figures.
#[derive(Clone, Debug)]
pub struct FitTarget<'a> {
    /// The terrain, the village's region and its environment (the region is where the figures are measured).
    pub site: Site<'a>,
    /// Where roads come into the region.
    pub connections: Vec<DVec2>,
    /// The real village's figures.
    pub figures: VillageFigures,
}

impl<'a> FitTarget<'a> {
    /// The real village of `buildings` and `roads` in `site`'s region, refused with a clear message when it
    /// cannot be learned from: fewer than [`MIN_BUILDINGS`] buildings in the region, no road in it, or a region
    /// outside the terrain.
    pub fn new(
        site: Site<'a>,
        connections: Vec<DVec2>,
        buildings: &[SitedBuilding],
        roads: &[Road],
    ) -> Result<FitTarget<'a>> {
        let (lo, hi) = site.region.bbox();
        let (tlo, thi) = site.terrain.bbox();
        if lo.x < tlo.x || lo.y < tlo.y || hi.x > thi.x || hi.y > thi.y {
            return Err(Error::RegionOffTerrain {
                reason: format!(
                "the selected village reaches off the terrain (selection {:.0}..{:.0} x {:.0}..{:.0} m, terrain \
                 {:.0}..{:.0} x {:.0}..{:.0} m): select a village on the terrain",
                lo.x, hi.x, lo.y, hi.y, tlo.x, thi.x, tlo.y, thi.y
            ),
            });
        }
        let figures = village_figures(buildings, roads, &site.region);
        if figures.layout.houses < MIN_BUILDINGS {
            return Err(Error::EmptyExemplar {
                reason: format!(
                    "the selected village holds {} buildings: a village type is learned from at least \
                     {MIN_BUILDINGS}",
                    figures.layout.houses
                ),
            });
        }
        if figures.road_length <= 0.0 {
            return Err(Error::EmptyExemplar {
                reason: "the selected village has no road: a village type is learned from buildings and the roads \
                         that serve them"
                    .into(),
            });
        }
        Ok(FitTarget {
            site,
            connections,
            figures,
        })
    }
}

/// The seeds a village of `buildings` is grown at: as many as hold about 200 buildings, 3 to 8. A small village's
/// figures vary more from seed to seed and it grows faster: a 22-building hamlet's objective moves from one set of
/// three seeds to another by as much as between a good type and a poor one (1.1 to 2.8 for one type), and a search
/// at four seeds kept the types luckiest at them. Two seeds a candidate left the objective moving as much for any
/// village.
pub(crate) fn seeds_for(buildings: usize) -> Vec<u64> {
    let count = (200 / buildings.max(1)).clamp(3, 8);
    (1..=count as u64).collect()
}

/// Buildings a search grows in all at the fit's seeds by default (candidates times seeds times the real count).
const GROWN_BUILDINGS: usize = 60_000;

/// The candidates a search of a village of `buildings` at `seeds` evaluates by default: as many as grow about
/// [`GROWN_BUILDINGS`] buildings, 20 to 1,000. A budget of work rather than of seconds makes a fit repeatable on
/// any machine that finishes it in time: searched until a time ran out, a fit grew as many candidates as the
/// machine's pace allowed (245 to 427 a village here), and the type learned changed with the count. About 8 minutes on two
/// cores (Encamp's 96 buildings at 3 seeds: 208 candidates; the hamlet's 22 at 8: 340).
pub(crate) fn evaluations_for(buildings: usize, seeds: usize) -> usize {
    (GROWN_BUILDINGS / (buildings * seeds).max(1)).clamp(20, 1000)
}

/// How a village type is learned.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// The village type the search starts from; `None`: the one whose villages come nearest the real village.
    pub base_type: Option<String>,
    /// The name of the learned type in the encyclopedia.
    pub name: String,
    /// Seeds each candidate is grown at; empty: as many as hold about 200 buildings, 3 to 8 (a small village varies
    /// more).
    pub seeds: Vec<u64>,
    /// Seed of the search.
    pub seed: u64,
    /// Most candidates evaluated; 0: as many as grow about 60,000 buildings at the fit's seeds (a budget of work, so
    /// that the same village and seed learn the same type whatever the machine's pace).
    pub max_evaluations: usize,
    /// Most seconds spent (the villages growing then are cancelled).
    pub max_seconds: f64,
    /// Initial step of the search, in unit coordinates (each parameter's range is 1).
    pub step: f64,
    /// Candidates per generation; 0: CMA-ES's default, 4 + 3 ln(dimensions).
    pub population: usize,
    /// Share of farms the search starts from.
    pub farm_share: f64,
    /// Grid cell (m) of the land conquest.
    pub parcel_cell: f64,
    /// Candidates grown again at held-out seeds when the search ends (the best candidates of the best generations
    /// and the distribution's final mean), the nearest there kept; 0: the best at the fit's seeds.
    pub finalists: usize,
}

impl Default for FitOptions {
    fn default() -> FitOptions {
        FitOptions {
            base_type: None,
            name: "learned".into(),
            seeds: Vec::new(),
            seed: 1,
            max_evaluations: 0,
            max_seconds: 540.0,
            step: 0.15,
            population: 0,
            farm_share: 0.2,
            parcel_cell: 1.0,
            finalists: 3,
        }
    }
}

/// Where a fit stands, for a progress bar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitProgress {
    /// Candidates evaluated so far.
    pub evaluations: usize,
    /// The budget of evaluations.
    pub max_evaluations: usize,
    /// Generations completed.
    pub generation: usize,
    /// The best objective so far (the base type's before the first generation ends).
    pub best: f64,
    /// Seconds since the fit started.
    pub seconds: f64,
}

/// A learned village type.
#[derive(Clone, Debug)]
pub struct FittedVillage {
    /// The encyclopedia given, with the learned type added under the options' name.
    pub encyclopedia: Encyclopedia,
    /// The learned type.
    pub village_type: VillageType,
    /// The scenario that grows the real village's count of buildings with it.
    pub scenario: Scenario,
    /// The village type the search started from.
    pub base_type: String,
    /// Its objective at the fit's seeds.
    pub objective: f64,
    /// Its objective at four times as many held-out seeds (`None`: no finalists were grown, or the fit was
    /// stopped first).
    pub held_out_objective: Option<f64>,
    /// The base type's objective at the fit's seeds.
    pub base_objective: f64,
    /// Candidates evaluated (the base type's included).
    pub evaluations: usize,
    /// Generations of the search completed.
    pub generations: usize,
    /// Seconds the fit took.
    pub seconds: f64,
    /// Stopped by the callback, or cut by the time budget within a generation (a search whose next generation
    /// and finalists would not fit in the time left ends there, not early).
    pub stopped_early: bool,
}

/// The scenario of `village_type` for `buildings` real buildings: a church if the type builds churches, then
/// houses and farms, `buildings × count_factor` in all.
pub fn scenario_for(
    enc: &Encyclopedia,
    name: &str,
    village_type: &VillageType,
    buildings: usize,
    count_factor: f64,
    farm_share: f64,
) -> Scenario {
    let total = ((buildings as f64 * count_factor).round() as usize).max(1);
    let church = usize::from(
        village_type
            .buildings
            .keys()
            .any(|b| enc.buildings.get(b).is_some_and(|k| k.religious) && b == "church"),
    );
    let farms = if village_type.buildings.contains_key("farm") {
        ((total.saturating_sub(church)) as f64 * farm_share).round() as usize
    } else {
        0
    };
    let houses = total.saturating_sub(church + farms).max(1);
    let mut events = vec![ScenarioEvent::ChangeVillageType {
        village_type: name.into(),
    }];
    for (building, count) in [("church", church), ("house", houses), ("farm", farms)] {
        if count > 0 {
            events.push(ScenarioEvent::Generate {
                count: count as u32,
                building: building.into(),
            });
        }
    }
    Scenario { events }
}

/// Learns a village type from `target`, starting from `options.base_type` of `enc` (or the type whose villages
/// come nearest, ranked at the fit's seeds). `progress` is called between buildings and after each generation;
/// returning `false` stops the fit, keeping the best type so far (a stop before the search began is
/// [`Error::Cancelled`]).
pub fn fit_village_type(
    target: &FitTarget,
    enc: &Encyclopedia,
    options: &FitOptions,
    progress: &(dyn Fn(&FitProgress) -> bool + Sync),
) -> Result<FittedVillage> {
    let seeds = if options.seeds.is_empty() {
        seeds_for(target.figures.layout.houses)
    } else {
        options.seeds.clone()
    };
    if enc.village_types.contains_key(&options.name) {
        return Err(Error::invalid(
            "learned village type name",
            format!(
                "'{}' is already a village type of the encyclopedia",
                options.name
            ),
        ));
    }
    let options = &FitOptions {
        max_evaluations: match options.max_evaluations {
            0 => evaluations_for(target.figures.layout.houses, seeds.len()),
            n => n,
        },
        ..options.clone()
    };
    let search = Search::new(target, enc, options, seeds, progress);
    let base_type = match &options.base_type {
        Some(b) => b.clone(),
        None => search.nearest_type()?,
    };
    let starts = space::Starts::of(&target.figures, options.farm_share);
    let space = ParameterSpace::new(enc, &base_type, starts)?;
    let outcome = search.run(&space)?;
    let c = space.candidate(&outcome.point);
    let scenario = search.scenario(&c);
    let mut encyclopedia = enc.clone();
    let mut village_type = c.village_type;
    village_type.description = format!(
        "Learned from a real village of {} buildings, starting from '{base_type}'.",
        target.figures.layout.houses
    );
    encyclopedia
        .village_types
        .insert(options.name.clone(), village_type.clone());
    Ok(FittedVillage {
        encyclopedia,
        village_type,
        scenario,
        base_type,
        objective: outcome.objective,
        held_out_objective: outcome.held_out,
        base_objective: outcome.base_objective,
        evaluations: outcome.evaluations,
        generations: outcome.generations,
        seconds: search.seconds(),
        stopped_early: outcome.stopped_early,
    })
}

#[cfg(test)]
mod tests {
    use super::{evaluations_for, seeds_for};

    #[test]
    fn a_small_village_is_grown_at_more_seeds() {
        // about 200 buildings a candidate: Andorra's hamlet of 22 at 8 seeds, a town of 96 at 3
        assert_eq!(seeds_for(22), (1..=8).collect::<Vec<u64>>());
        assert_eq!(seeds_for(40).len(), 5);
        assert_eq!(seeds_for(96).len(), 3);
        assert_eq!(seeds_for(5).len(), 8);
        assert_eq!(seeds_for(0).len(), 8);
        assert_eq!(seeds_for(100_000).len(), 3);
    }

    #[test]
    fn the_default_budget_grows_as_many_buildings_whatever_the_village() {
        assert_eq!(evaluations_for(96, 3), 208);
        assert_eq!(evaluations_for(22, 8), 340);
        // a larger village, fewer candidates; the bounds hold for a town and for nothing
        assert!(evaluations_for(51, 3) > evaluations_for(96, 3));
        assert_eq!(evaluations_for(5_000, 3), 20);
        assert_eq!(evaluations_for(0, 0), 1000);
    }
}

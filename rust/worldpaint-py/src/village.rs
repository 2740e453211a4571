//! Villages: `generate_village`, `village_interest`, and the shipped encyclopedia and scenario presets (JSON).

use crate::arrays::ArrayArg;
use crate::convert::{column, points_from_py, points_to_py, region_from_py, rows_to_py};
use crate::terrain::Terrain;
use crate::{guarded, input_err, with_progress, with_stages};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{
    border_crossings, fit_village_type, interest_at, BuildingSeed, DVec2, Encyclopedia,
    Environment, FitOptions, FitTarget, Heightfield, HouseMesh, InterestCriterion, InterestRequest,
    Road, Scenario, Site, SitedBuilding, Village, VillageFigures, VillageReport, VillageRequest,
    VillageStage, UNPLACED_CANDIDATES,
};

const ENCYCLOPEDIA: &str = include_str!("../../../assets/villages/encyclopedia.json");
const SCENARIOS: &str = include_str!("../../../assets/villages/scenarios.json");

/// The shipped building encyclopedia (JSON text).
#[pyfunction]
pub(crate) fn default_encyclopedia() -> &'static str {
    ENCYCLOPEDIA
}

/// The shipped growth scenario presets (JSON text: {"presets": {name: {"events": [...]}}}).
#[pyfunction]
pub(crate) fn scenario_presets() -> &'static str {
    SCENARIOS
}

/// Checks an encyclopedia (JSON) and returns its village types and building types.
#[pyfunction]
pub(crate) fn encyclopedia_contents(encyclopedia: &str) -> PyResult<(Vec<String>, Vec<String>)> {
    let e = guarded(|| Encyclopedia::from_json(encyclopedia))?;
    Ok((
        e.village_types.keys().cloned().collect(),
        e.buildings.keys().cloned().collect(),
    ))
}

pub(crate) fn polylines(list: Option<&Bound<'_, PyAny>>, what: &str) -> PyResult<Vec<Vec<DVec2>>> {
    let mut out = Vec::new();
    let Some(list) = list.filter(|l| !l.is_none()) else {
        return Ok(out);
    };
    for (i, item) in list
        .try_iter()
        .map_err(|_| input_err(format!("{what} must be a list of (N, 2) arrays")))?
        .enumerate()
    {
        let pts = points_from_py(&ArrayArg::from(item?), &format!("{what} {i}"))?;
        if pts.iter().any(|p| !p.is_finite()) {
            return Err(input_err(format!("{what} {i} has a non-finite point")));
        }
        out.push(pts);
    }
    Ok(out)
}

/// The keyword arguments that describe the water and the walls around a village.
const SURROUNDINGS: &str = "water_level, water_areas, rivers, river_half_width, walls";

/// Where a village stands: the terrain, the region, the grid cell and the surroundings, read from the keyword
/// arguments `water_level` (float or None), `water_areas`, `rivers` and `walls` (lists of (N, 2) polylines) and
/// `river_half_width` (m, default 4); any other keyword is refused, naming the ones there are.
fn site<'a>(
    terrain: &'a worldpaint_core::Heightfield,
    region: worldpaint_core::Region,
    cell: f64,
    surroundings: Option<&Bound<'_, PyDict>>,
) -> PyResult<Site<'a>> {
    let mut environment = Environment::default();
    let mut river_half_width = 4.0;
    for (key, value) in surroundings.into_iter().flat_map(|d| d.iter()) {
        let key: String = key.extract()?;
        let lines = |what: &str| polylines(Some(&value), what);
        match key.as_str() {
            "water_level" => {
                environment.water_level = value
                    .extract::<Option<f64>>()
                    .map_err(|_| input_err("water_level must be a number or None"))?;
                if environment.water_level.is_some_and(|w| !w.is_finite()) {
                    return Err(input_err("water_level must be finite"));
                }
            }
            "river_half_width" => {
                river_half_width = value
                    .extract::<f64>()
                    .ok()
                    .filter(|w| w.is_finite() && *w >= 0.0)
                    .ok_or_else(|| input_err("river_half_width must be zero or more"))?;
            }
            "water_areas" => environment.water_areas = lines("water area")?,
            "rivers" => {
                environment.rivers = lines("river")?.into_iter().map(|r| (r, 0.0)).collect()
            }
            "walls" => environment.walls = lines("wall")?,
            other => {
                return Err(input_err(format!(
                    "unknown argument '{other}' (the surroundings are {SURROUNDINGS})"
                )))
            }
        }
    }
    for river in &mut environment.rivers {
        river.1 = river_half_width;
    }
    Ok(Site {
        terrain,
        region,
        environment,
        cell,
    })
}

pub(crate) fn encyclopedia_of(text: Option<&str>) -> PyResult<Encyclopedia> {
    guarded(|| Encyclopedia::from_json(text.unwrap_or(ENCYCLOPEDIA)))
}

/// A stage's name as the user reads it, and its share of the whole generation: (name, start, span).
fn stage_share(stage: VillageStage) -> (&'static str, f64, f64) {
    match stage {
        VillageStage::Skeleton => ("growing the skeleton", 0.0, 0.7),
        VillageStage::Parcels => ("parcels and footprints", 0.7, 0.15),
        VillageStage::Houses => ("houses", 0.85, 0.15),
    }
}

/// Generates a village (thesis ch. 3) on `terrain` inside `region` following `scenario` (JSON {"events": [...]}).
///
/// Returns {"seeds": {"positions", "heights", "building", "village_type"}, "roads": [{"points", "heights"}],
/// "parcels": [float64 (N, 2)], "footprints": float64 (M, 4, 2), "houses": [{"vertices": (V, 3), "loop_starts",
/// "loop_totals", "indices", "materials"}], "connections": (K, 2), "report": {...}}; footprints and houses are per
/// kept seed, in order. `progress(fraction) -> bool` may cancel (raises `Cancelled`); a callback taking a second
/// argument also gets the stage's name ("growing the skeleton", "parcels and footprints", "houses"). The keywords
/// `water_level`, `water_areas`, `rivers`, `river_half_width` and `walls` describe the surroundings; any other
/// keyword is refused.
#[pyfunction]
#[pyo3(signature = (terrain, region, scenario, seed=0, *, encyclopedia=None, connections=None, existing_roads=None,
                    cell=2.0, parcel_cell=1.0, progress=None, **surroundings))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn generate_village<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    region: &Bound<'py, PyAny>,
    scenario: &str,
    seed: u64,
    encyclopedia: Option<&str>,
    connections: Option<ArrayArg<'py>>,
    existing_roads: Option<&Bound<'py, PyAny>>,
    cell: f64,
    parcel_cell: f64,
    progress: Option<Py<PyAny>>,
    surroundings: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let region = region_from_py(region)?;
    let encyclopedia = encyclopedia_of(encyclopedia)?;
    let scenario = guarded(|| Scenario::from_json(scenario))?;
    let connections = match connections {
        Some(c) => points_from_py(&c, "connections")?,
        None => Vec::new(),
    };
    let request = VillageRequest {
        site: site(&hf, region, cell, surroundings)?,
        connections,
        existing_roads: polylines(existing_roads, "existing road")?,
        encyclopedia: &encyclopedia,
        scenario: &scenario,
        seed,
        parcel_cell,
    };
    let village = with_stages(py, progress, |report| {
        worldpaint_core::generate_village(&request, &|stage, f| {
            let (name, start, span) = stage_share(stage);
            report(start + span * f, Some(name))
        })
    })?;

    village_to_py(py, &village, &hf, &encyclopedia)
}

/// A generated village as `generate_village` returns it.
pub(crate) fn village_to_py<'py>(
    py: Python<'py>,
    village: &Village,
    hf: &Heightfield,
    encyclopedia: &Encyclopedia,
) -> PyResult<Bound<'py, PyDict>> {
    let height = |p: &DVec2| hf.height_at(*p).unwrap_or(f64::NAN);
    let out = PyDict::new(py);
    out.set_item("seeds", seeds_to_py(py, &village.seeds, &height)?)?;
    out.set_item("roads", roads_to_py(py, &village.roads, &height)?)?;
    let parcels = PyList::empty(py);
    for p in &village.parcels {
        parcels.append(points_to_py(py, &p.contour))?;
    }
    out.set_item("parcels", parcels)?;
    let mut fp = numpy::ndarray::Array3::<f64>::zeros((village.footprints.len(), 4, 2));
    for (k, f) in village.footprints.iter().enumerate() {
        for (c, p) in f.corners.iter().enumerate() {
            fp[[k, c, 0]] = p.x;
            fp[[k, c, 1]] = p.y;
        }
    }
    out.set_item("footprints", fp.into_pyarray(py))?;
    out.set_item("houses", houses_to_py(py, &village.houses)?)?;
    out.set_item("connections", points_to_py(py, &village.report.connections))?;
    out.set_item("report", report_to_py(py, &village.report, encyclopedia)?)?;
    Ok(out)
}

/// The kept seeds' positions, ground heights, building and village types (see [`generate_village`]).
fn seeds_to_py<'py>(
    py: Python<'py>,
    village_seeds: &[BuildingSeed],
    height: &dyn Fn(&DVec2) -> f64,
) -> PyResult<Bound<'py, PyDict>> {
    let seeds = PyDict::new(py);
    let positions: Vec<DVec2> = village_seeds.iter().map(|s| s.position).collect();
    seeds.set_item("positions", points_to_py(py, &positions))?;
    seeds.set_item(
        "heights",
        positions
            .iter()
            .map(height)
            .collect::<Vec<f64>>()
            .into_pyarray(py),
    )?;
    seeds.set_item(
        "building",
        village_seeds
            .iter()
            .map(|s| s.building.clone())
            .collect::<Vec<String>>(),
    )?;
    seeds.set_item(
        "village_type",
        village_seeds
            .iter()
            .map(|s| s.village_type.clone())
            .collect::<Vec<String>>(),
    )?;
    Ok(seeds)
}

/// The new roads' points and ground heights (see [`generate_village`]).
pub(crate) fn roads_to_py<'py>(
    py: Python<'py>,
    village_roads: &[Road],
    height: &dyn Fn(&DVec2) -> f64,
) -> PyResult<Bound<'py, PyList>> {
    let roads = PyList::empty(py);
    for r in village_roads {
        let d = PyDict::new(py);
        d.set_item("points", points_to_py(py, &r.points))?;
        d.set_item(
            "heights",
            r.points
                .iter()
                .map(height)
                .collect::<Vec<f64>>()
                .into_pyarray(py),
        )?;
        roads.append(d)?;
    }
    Ok(roads)
}

/// Each house as a mesh's arrays (see [`generate_village`]).
fn houses_to_py<'py>(
    py: Python<'py>,
    village_houses: &[HouseMesh],
) -> PyResult<Bound<'py, PyList>> {
    let houses = PyList::empty(py);
    for h in village_houses {
        let d = PyDict::new(py);
        d.set_item("seed", h.seed)?;
        d.set_item("vertices", rows_to_py(py, h.vertices.iter().copied())?)?;
        let mut starts = Vec::with_capacity(h.faces.len());
        let mut totals = Vec::with_capacity(h.faces.len());
        let mut indices = Vec::new();
        for f in &h.faces {
            starts.push(indices.len() as i32);
            totals.push(f.len() as i32);
            indices.extend(f.iter().map(|i| *i as i32));
        }
        d.set_item("loop_starts", starts.into_pyarray(py))?;
        d.set_item("loop_totals", totals.into_pyarray(py))?;
        d.set_item("indices", indices.into_pyarray(py))?;
        d.set_item(
            "materials",
            h.materials
                .iter()
                .map(|m| *m as i32)
                .collect::<Vec<i32>>()
                .into_pyarray(py),
        )?;
        houses.append(d)?;
    }
    Ok(houses)
}

/// The village's report with the road figures it was built with (see [`generate_village`]).
fn report_to_py<'py>(
    py: Python<'py>,
    report: &VillageReport,
    encyclopedia: &Encyclopedia,
) -> PyResult<Bound<'py, PyDict>> {
    let r = PyDict::new(py);
    r.set_item("requested", report.requested)?;
    r.set_item("seeded", report.seeded)?;
    r.set_item("fallbacks", report.fallbacks)?;
    r.set_item("unplaced", report.unplaced.clone())?;
    // per building type left unplaced: of UNPLACED_CANDIDATES candidates over the land, how many each criterion
    // forbade, how many lay where nothing can be built ("land"), and how many nothing drew it to ("no_interest")
    let causes = PyDict::new(py);
    for (building, counts) in &report.unplaced_causes {
        let by = PyDict::new(py);
        for (criterion, n) in InterestCriterion::ALL.iter().zip(counts) {
            by.set_item(criterion.name(), n)?;
        }
        by.set_item("land", counts[7])?;
        by.set_item("no_interest", counts[8])?;
        causes.set_item(building, by)?;
    }
    r.set_item("unplaced_causes", causes)?;
    r.set_item("unplaced_candidates", UNPLACED_CANDIDATES)?;
    r.set_item("unreachable", report.unreachable)?;
    r.set_item("without_access", report.without_access)?;
    r.set_item("without_footprint", report.without_footprint)?;
    r.set_item("roads_over_max_grade", report.roads_over_max_grade)?;
    r.set_item("cycles", report.cycles)?;
    r.set_item("seconds", report.seconds.to_vec())?;
    r.set_item("road_width", encyclopedia.roads.width)?;
    r.set_item("max_grade", encyclopedia.roads.max_grade)?;
    Ok(r)
}

/// One interest criterion ("sociability", "worship", "accessibility", "slope", "water", "fortification",
/// "domination") or, with `criterion=None`, the combined interest, at world XY `points` (float64 (N, 2)), for a
/// building type of a village type, in the village made of `buildings` (list of (building type, x, y)) and
/// `roads`. Values lie in [-1, 1] (the interest in [0, 1]); 0 outside the region. The surroundings are keywords,
/// as for `generate_village`.
#[pyfunction]
#[pyo3(signature = (terrain, region, points, village_type, building, criterion=None, *, encyclopedia=None,
                    buildings=None, roads=None, cell=2.0, **surroundings))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn village_interest<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    region: &Bound<'py, PyAny>,
    points: ArrayArg<'py>,
    village_type: &str,
    building: &str,
    criterion: Option<&str>,
    encyclopedia: Option<&str>,
    buildings: Option<Vec<(String, f64, f64)>>,
    roads: Option<&Bound<'py, PyAny>>,
    cell: f64,
    surroundings: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    let hf = terrain.get().hf.clone();
    let region = region_from_py(region)?;
    let encyclopedia = encyclopedia_of(encyclopedia)?;
    let criterion = match criterion {
        None => None,
        Some(name) => Some(InterestCriterion::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = InterestCriterion::ALL.iter().map(|c| c.name()).collect();
            input_err(format!(
                "unknown criterion '{name}' (one of {})",
                names.join(", ")
            ))
        })?),
    };
    let pts = points_from_py(&points, "points")?;
    let buildings: Vec<BuildingSeed> = buildings
        .unwrap_or_default()
        .into_iter()
        .map(|(b, x, y)| BuildingSeed {
            building: b,
            village_type: village_type.to_string(),
            position: DVec2::new(x, y),
        })
        .collect();
    let roads = polylines(roads, "road")?;
    let request = InterestRequest {
        site: site(&hf, region, cell, surroundings)?,
        encyclopedia: &encyclopedia,
        village_type,
        building,
        criterion,
        buildings: &buildings,
        roads: &roads,
    };
    let values = py.detach(|| guarded(|| interest_at(&request, &pts)))?;
    Ok(values.into_pyarray(py))
}

/// Learns a village type from a real village (issue 42): the buildings (centres float64 (N, 2) and long-axis
/// `orientations` (N,), radians from +X) and `roads` (list of (N, 2)) inside `region` on `terrain`, starting from
/// the encyclopedia's `base_type` (None: the type whose villages come nearest); CMA-ES grows villages on the same
/// terrain, region and `connections` at `seeds` until their figures match the real village's, within
/// `max_evaluations` candidates (0: as many as grow about 60,000 buildings, so that the same village and seed learn
/// the same type on any machine that finishes in time) and `max_seconds`; without `connections`, the village's roads come in where the given
/// roads cross the region's border.
///
/// Returns {"encyclopedia": JSON with the learned type added as `name`, "scenario": JSON growing the real village's
/// count of buildings with it, "base_type", "objective" (at the fit's seeds), "held_out_objective" (at four times as
/// many held-out seeds, or None), "base_objective", "evaluations", "generations", "seconds", "stopped_early",
/// "real": the real village's figures}. `progress(fraction) -> bool` returning False
/// stops the fit and keeps the best type so far (`stopped_early`). The surroundings are keywords, as for
/// `generate_village`. A region with fewer than 5 buildings, no road or reaching off the terrain is refused.
#[pyfunction]
#[pyo3(signature = (terrain, region, buildings, orientations, roads, *, encyclopedia=None, base_type=None,
                    name="learned", connections=None, seeds=None, seed=1, max_evaluations=0, max_seconds=540.0,
                    cell=2.0, parcel_cell=1.0, progress=None, **surroundings))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn learn_village<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    region: &Bound<'py, PyAny>,
    buildings: ArrayArg<'py>,
    orientations: ArrayArg<'py>,
    roads: &Bound<'py, PyAny>,
    encyclopedia: Option<&str>,
    base_type: Option<&str>,
    name: &str,
    connections: Option<ArrayArg<'py>>,
    seeds: Option<Vec<u64>>,
    seed: u64,
    max_evaluations: usize,
    max_seconds: f64,
    cell: f64,
    parcel_cell: f64,
    progress: Option<Py<PyAny>>,
    surroundings: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let region = region_from_py(region)?;
    let encyclopedia = encyclopedia_of(encyclopedia)?;
    let centres = points_from_py(&buildings, "buildings")?;
    let turns = column(Some(orientations), centres.len(), 0.0, "orientations")?;
    if centres.iter().any(|p| !p.is_finite()) || turns.iter().any(|t| !t.is_finite()) {
        return Err(input_err("buildings and orientations must be finite"));
    }
    if max_seconds.is_nan() || max_seconds <= 0.0 {
        return Err(input_err("max_seconds must be more than 0"));
    }
    let sited: Vec<SitedBuilding> = centres
        .iter()
        .zip(&turns)
        .map(|(c, o)| SitedBuilding {
            centre: *c,
            orientation: *o,
        })
        .collect();
    let roads: Vec<Road> = polylines(Some(roads), "road")?
        .into_iter()
        .map(|points| Road { points })
        .collect();
    let site = site(&hf, region, cell, surroundings)?;
    let connections = match connections {
        Some(c) => points_from_py(&c, "connections")?,
        None => border_crossings(&site.region, &roads),
    };
    let target = guarded(|| FitTarget::new(site, connections, &sited, &roads))?;
    let defaults = FitOptions::default();
    let options = FitOptions {
        base_type: base_type.map(str::to_string),
        name: name.to_string(),
        seeds: seeds.unwrap_or(defaults.seeds),
        seed,
        max_evaluations,
        max_seconds,
        parcel_cell,
        ..defaults
    };
    let fitted = with_progress(py, progress, |report| {
        fit_village_type(&target, &encyclopedia, &options, &|p| {
            let by_count = p.evaluations as f64 / p.max_evaluations.max(1) as f64;
            report((by_count.max(p.seconds / max_seconds)).min(1.0))
        })
    })?;
    let out = PyDict::new(py);
    out.set_item("encyclopedia", fitted.encyclopedia.to_json())?;
    out.set_item("scenario", fitted.scenario.to_json())?;
    out.set_item("base_type", &fitted.base_type)?;
    out.set_item("objective", fitted.objective)?;
    out.set_item("held_out_objective", fitted.held_out_objective)?;
    out.set_item("base_objective", fitted.base_objective)?;
    out.set_item("evaluations", fitted.evaluations)?;
    out.set_item("generations", fitted.generations)?;
    out.set_item("seconds", fitted.seconds)?;
    out.set_item("stopped_early", fitted.stopped_early)?;
    out.set_item("real", figures_to_py(py, &target.figures)?)?;
    Ok(out)
}

/// A village's figures as a dict (see `learn_village`).
fn figures_to_py<'py>(py: Python<'py>, f: &VillageFigures) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("buildings", f.layout.houses)?;
    d.set_item("mean_nearest_neighbour", f.layout.mean_nearest_neighbour)?;
    d.set_item("share_within_20m", f.layout.share_within_20m)?;
    d.set_item("road_length_per_house", f.layout.road_length_per_house)?;
    d.set_item("mean_road_distance", f.layout.mean_road_distance)?;
    d.set_item("buildings_per_hectare", f.buildings_per_hectare)?;
    d.set_item("road_length", f.road_length)?;
    d.set_item("hairpins_per_km", f.network.hairpins_per_km)?;
    d.set_item("dead_end_share", f.network.dead_end_share)?;
    d.set_item("orientation_to_road", f.orientation_to_road.to_vec())?;
    Ok(d)
}

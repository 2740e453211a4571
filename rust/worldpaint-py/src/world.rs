//! Worlds in tiles: the plan, one tile's synthesis and the tile files. The driver that runs the tiles' phases (Dask)
//! is the package's Python module `worldpaint_engine.world`.

use crate::convert::{instances_to_py, parse_color};
use crate::guarded;
use crate::terrain::Terrain;
use crate::village::{encyclopedia_of, polylines, roads_to_py, village_to_py};
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use worldpaint_core::{
    check_iterations, decode_tile, encode_tile, grow_world_villages, synthesize_tile, ColorMap,
    DVec2, LabelGrid, Obstacles, TileId, VillageSite, WorldPlan,
};

/// What fills a world: a color's JSON (one color everywhere), or a map {"labels": uint32 (ny, nx) array, row 0 at
/// the smallest Y, "origin": (x, y) of its corner with the smaller coordinates, "cell": side of a cell (m),
/// "legend": {label: color JSON}, "band": width of the transition band (m; None: three regions of influence)}.
fn paint_from_py(paint: &Bound<'_, PyAny>) -> PyResult<ColorMap> {
    if let Ok(json) = paint.extract::<String>() {
        let color = parse_color(&json)?;
        return guarded(|| ColorMap::uniform(color));
    }
    let Ok(map) = paint.cast::<PyDict>() else {
        return Err(crate::input_err(
            "a world is filled with a color's JSON or a map (a dict of labels, origin, cell, legend and band)",
        ));
    };
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        map.get_item(key)?
            .ok_or_else(|| crate::input_err(format!("the map has no '{key}'")))
    };
    let labels: PyReadonlyArray2<'_, u32> = get("labels")?.extract().map_err(|_| {
        crate::input_err("the map's labels must be a 2-D array of unsigned 32-bit integers")
    })?;
    let labels = labels.as_array();
    let (ny, nx) = labels.dim();
    let labels: Vec<u32> = labels.iter().copied().collect();
    let (x, y): (f64, f64) = get("origin")?.extract()?;
    let cell: f64 = get("cell")?.extract()?;
    let legend_dict = get("legend")?;
    let legend_dict = legend_dict
        .cast::<PyDict>()
        .map_err(|_| crate::input_err("the map's legend must be a dict {label: color JSON}"))?;
    let mut legend = Vec::new();
    for (label, color) in legend_dict.iter() {
        let label: u32 = label.extract().map_err(|_| {
            crate::input_err(format!(
                "the map's legend has the label {label}, not a whole number from 0"
            ))
        })?;
        legend.push((label, parse_color(&color.extract::<String>()?)?));
    }
    let band: Option<f64> = match map.get_item("band")? {
        Some(b) => b.extract()?,
        None => None,
    };
    let grid = LabelGrid {
        origin: DVec2::new(x, y),
        cell,
        nx,
        ny,
        labels,
    };
    guarded(|| ColorMap::new(grid, legend, band))
}

fn plan_from_py(plan: &Bound<'_, PyDict>) -> PyResult<WorldPlan> {
    let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
        plan.get_item(key)?
            .ok_or_else(|| crate::input_err(format!("the world plan has no '{key}'")))
    };
    let corner = |key: &str| -> PyResult<DVec2> {
        let (x, y): (f64, f64) = get(key)?.extract()?;
        Ok(DVec2::new(x, y))
    };
    let (min, max) = (corner("min")?, corner("max")?);
    let (tile, influence): (f64, f64) = (get("tile")?.extract()?, get("influence")?.extract()?);
    guarded(|| WorldPlan::new(min, max, tile, influence))
}

/// How `paint` (a color's JSON, or a map: see `world_tile`) fills the world rectangle `min`–`max`: {"min", "max",
/// "tile" (side, m), "influence" (m), "columns", "rows", "tiles": [(column, row, phase, [(column, row) of the earlier
/// neighbours it is conditioned on])], "categories": the tiles' category names}, tiles in phase order. `tile`
/// overrides the side (at least the colors' region of influence). A plan past the work budget (tiles, instances a
/// tile or the world would hold, `iterations_per_instance` when given), or a map that does not cover the rectangle
/// or is not read (a label with no legend entry...), raises `InputError` before any tile is started.
#[pyfunction]
#[pyo3(signature = (paint, min, max, *, tile=None, iterations_per_instance=None))]
pub(crate) fn world_plan<'py>(
    py: Python<'py>,
    paint: &Bound<'py, PyAny>,
    min: (f64, f64),
    max: (f64, f64),
    tile: Option<f64>,
    iterations_per_instance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let map = paint_from_py(paint)?;
    let (min, max) = (DVec2::new(min.0, min.1), DVec2::new(max.0, max.1));
    let plan = guarded(|| {
        if let Some(it) = iterations_per_instance {
            check_iterations(it)?;
        }
        WorldPlan::for_map(min, max, &map, tile)
    })?;
    let d = PyDict::new(py);
    d.set_item("min", (plan.min.x, plan.min.y))?;
    d.set_item("max", (plan.max.x, plan.max.y))?;
    d.set_item("tile", plan.tile)?;
    d.set_item("influence", plan.influence)?;
    d.set_item("columns", plan.columns)?;
    d.set_item("rows", plan.rows)?;
    let mut tiles = plan.tiles();
    tiles.sort_by_key(|&t| (plan.phase(t), t.row, t.column));
    let tiles: Vec<_> = tiles
        .into_iter()
        .map(|t| {
            let after: Vec<(u32, u32)> = plan
                .earlier_neighbours(t)
                .iter()
                .map(|n| (n.column, n.row))
                .collect();
            (t.column, t.row, plan.phase(t), after)
        })
        .collect();
    d.set_item("tiles", tiles)?;
    let categories: Vec<&str> = map.categories().iter().map(|c| c.name.as_str()).collect();
    d.set_item("categories", categories)?;
    Ok(d)
}

/// Synthesizes tile (`column`, `row`) of `plan` (as `world_plan` returns it) with `paint`, conditioned on
/// `neighbours` (the border bytes its earlier neighbours returned) and on `terrain` (at least the part around the
/// tile; None on flat ground). `paint` is a color's JSON (one color everywhere) or a map: {"labels": uint32 (ny, nx)
/// array, row 0 at the smallest Y, "origin": (x, y) of its corner with the smaller coordinates, "cell": side of a
/// cell (m), "legend": {label: color JSON}, "band": width of the transition band across each boundary (m; None:
/// three regions of influence)}. Instances on `obstacles` ({"footprints": outlines, "roads": polylines, "width": m})
/// are removed. Returns (the tile file's bytes, the tile's border bytes for its later neighbours,
/// the instance count of each of the plan's categories).
/// What a world's instances keep off: {"footprints": list of (N, 2) outlines, "roads": list of (N, 2) polylines,
/// "width": the roads' width (m)}; None: nothing.
fn obstacles_from_py(obstacles: Option<&Bound<'_, PyDict>>) -> PyResult<Obstacles> {
    let Some(o) = obstacles else {
        return Ok(Obstacles::default());
    };
    let footprints = polylines(o.get_item("footprints")?.as_ref(), "footprint")?;
    let roads = polylines(o.get_item("roads")?.as_ref(), "road")?;
    let width: f64 = match o.get_item("width")? {
        Some(w) => w.extract()?,
        None => 0.0,
    };
    if !(width.is_finite() && width >= 0.0) {
        return Err(crate::input_err(format!(
            "the roads' width {width} must be a length of 0 or more"
        )));
    }
    Ok(Obstacles::new(&footprints, &roads, width))
}

#[pyfunction]
#[pyo3(signature = (paint, plan, column, row, neighbours, seed, *, terrain=None, iterations_per_instance=None,
                    obstacles=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn world_tile<'py>(
    py: Python<'py>,
    paint: &Bound<'py, PyAny>,
    plan: &Bound<'py, PyDict>,
    column: u32,
    row: u32,
    neighbours: Vec<Bound<'py, PyBytes>>,
    seed: u64,
    terrain: Option<&Bound<'py, Terrain>>,
    iterations_per_instance: Option<f64>,
    obstacles: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, Vec<usize>)> {
    let map = paint_from_py(paint)?;
    let obstacles = obstacles_from_py(obstacles)?;
    let plan = plan_from_py(plan)?;
    let neighbours = neighbours
        .iter()
        .map(|b| guarded(|| decode_tile(b.as_bytes())))
        .collect::<PyResult<Vec<_>>>()?;
    let terrain = terrain.map(|t| t.get().hf.clone());
    let t = TileId { column, row };
    let (file, border, counts) = py.detach(|| {
        guarded(|| {
            let tile = synthesize_tile(
                &plan,
                t,
                &map,
                &obstacles,
                terrain,
                &neighbours,
                seed,
                iterations_per_instance,
            )?;
            Ok((
                encode_tile(&tile)?,
                encode_tile(&tile.border(&plan))?,
                tile.counts(),
            ))
        })
    })?;
    Ok((PyBytes::new(py, &file), PyBytes::new(py, &border), counts))
}

/// The content of a tile file's bytes: {"column", "row", "categories" (the names), and the instance
/// columns of an edit ("positions", "heights" (the terrain's, as the tile was synthesized on it), "rotations",
/// "scales", "category_index", "prototype", "tints")}. A damaged file raises `FileFormatError`.
#[pyfunction]
pub(crate) fn read_world_tile<'py>(
    py: Python<'py>,
    data: &Bound<'py, PyBytes>,
) -> PyResult<Bound<'py, PyDict>> {
    let tile = guarded(|| decode_tile(data.as_bytes()))?;
    let d = PyDict::new(py);
    d.set_item("column", tile.tile.column)?;
    d.set_item("row", tile.tile.row)?;
    d.set_item("categories", &tile.categories)?;
    instances_to_py(py, &d, &tile.instances, None)?;
    let heights: Vec<f64> = tile.heights.iter().map(|&h| h as f64).collect();
    d.set_item("heights", heights.into_pyarray(py))?;
    Ok(d)
}

/// Grows the villages of a world on `terrain` within `min`–`max`: `sites` is a list of {"position": (x, y), "type":
/// a village type of the encyclopedia, "buildings": how many, "seed"}; the roads joining them are laid first, over
/// the whole world, then each village grows in a square around its site with those roads as its ways in. `cell` is
/// the villages' grid cell (m). Returns {"roads": the roads between villages as `generate_village` gives roads,
/// "road_width": m, "villages": one `generate_village` result per site}. A site off the terrain, of an unknown type,
/// of no building or too many, or too near another raises `InputError` before anything grows.
#[pyfunction]
#[pyo3(signature = (terrain, min, max, sites, *, encyclopedia=None, cell=2.0))]
pub(crate) fn world_villages<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    min: (f64, f64),
    max: (f64, f64),
    sites: Vec<Bound<'py, PyDict>>,
    encyclopedia: Option<&str>,
    cell: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let encyclopedia = encyclopedia_of(encyclopedia)?;
    let sites = sites
        .iter()
        .enumerate()
        .map(|(k, d)| {
            let get = |key: &str| -> PyResult<Bound<'_, PyAny>> {
                d.get_item(key)?.ok_or_else(|| {
                    crate::input_err(format!("village site {} has no '{key}'", k + 1))
                })
            };
            let (x, y): (f64, f64) = get("position")?.extract()?;
            Ok(VillageSite {
                position: DVec2::new(x, y),
                village_type: get("type")?.extract()?,
                buildings: get("buildings")?.extract()?,
                seed: get("seed")?.extract()?,
            })
        })
        .collect::<PyResult<Vec<VillageSite>>>()?;
    let (min, max) = (DVec2::new(min.0, min.1), DVec2::new(max.0, max.1));
    let world =
        py.detach(|| guarded(|| grow_world_villages(&hf, min, max, &sites, &encyclopedia, cell)))?;
    let height = |p: &DVec2| hf.height_at(*p).unwrap_or(f64::NAN);
    let out = PyDict::new(py);
    out.set_item("roads", roads_to_py(py, &world.roads, &height)?)?;
    out.set_item("road_width", world.road_width)?;
    let villages = world
        .villages
        .iter()
        .map(|v| village_to_py(py, v, &hf, &encyclopedia))
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("villages", villages)?;
    Ok(out)
}

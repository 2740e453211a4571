//! Worlds in tiles: the plan, one tile's synthesis and the tile files. The driver that runs the tiles' phases (Dask)
//! is the package's Python module `worldpaint_engine.world`.

use crate::convert::{instances_to_py, parse_color};
use crate::guarded;
use crate::terrain::Terrain;
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use worldpaint_core::{
    check_iterations, decode_tile, encode_tile, synthesize_tile, ColorMap, DVec2, LabelGrid,
    TileId, WorldPlan,
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
/// three regions of influence)}. Returns (the tile file's bytes, the tile's border bytes for its later neighbours,
/// the instance count of each of the plan's categories).
#[pyfunction]
#[pyo3(signature = (paint, plan, column, row, neighbours, seed, *, terrain=None, iterations_per_instance=None))]
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
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, Vec<usize>)> {
    let map = paint_from_py(paint)?;
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

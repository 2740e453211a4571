//! Real places: `import_place` (the core's `place` module).

use crate::convert::{heights_of, points_to_py, rows_to_py};
use crate::{input_err, with_stages};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::PathBuf;
use worldpaint_core::DVec2;
use worldpaint_core::{Heightfield, Place, PlaceOptions};

/// Imports a real place: OpenStreetMap layers (GeoJSON files), an elevation model (ESRI ASCII grid `.asc`, SRTM
/// `.hgt` or GeoTIFF) and a tree inventory (CSV), any of them but not all may be missing, in one local metric frame
/// (metres east and north of `origin`, a (lon, lat) pair; None: the centre of the layers). `cell`: the terrain's
/// cell (m, None: the elevation model's own spacing); `margin`: terrain kept around the features (m).
/// `progress(fraction, stage)` may cancel (raises `Cancelled`).
///
/// Returns {"frame", "sources", "terrain", "buildings", "roads", "waterways", "areas", "places", "trees", "report"}
/// (see the stub's `PlaceDict`): columns of numpy arrays and lists per kind, names "" where a feature has none,
/// ground heights NaN off the terrain, footprints and area rings as lists of (N, 2) arrays (outer rings
/// counter-clockwise, holes clockwise).
#[pyfunction]
#[pyo3(signature = (geojson_paths, dem_path=None, inventory_path=None, *, origin=None, cell=None, margin=200.0,
                    progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn import_place<'py>(
    py: Python<'py>,
    geojson_paths: Vec<PathBuf>,
    dem_path: Option<PathBuf>,
    inventory_path: Option<PathBuf>,
    origin: Option<(f64, f64)>,
    cell: Option<f64>,
    margin: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = PlaceOptions {
        origin: origin.map(|(lon, lat)| [lon, lat]),
        cell,
        margin,
    };
    let place = with_stages(py, progress, |report| {
        worldpaint_core::import_place(
            &geojson_paths,
            dem_path.as_deref(),
            inventory_path.as_deref(),
            &options,
            &|fraction, stage| report(fraction, Some(stage)),
        )
    })?;
    place_to_py(py, &place)
}

fn names<'a>(names: impl Iterator<Item = &'a Option<String>>) -> Vec<String> {
    names.map(|n| n.clone().unwrap_or_default()).collect()
}

fn rings_to_py<'py>(py: Python<'py>, rings: &[Vec<DVec2>]) -> PyResult<Bound<'py, PyList>> {
    PyList::new(py, rings.iter().map(|r| points_to_py(py, r)))
}

fn lines_to_py<'py>(
    py: Python<'py>,
    lines: &[&Vec<DVec2>],
    terrain: Option<&Heightfield>,
) -> PyResult<(Bound<'py, PyList>, Bound<'py, PyList>)> {
    Ok((
        PyList::new(py, lines.iter().map(|l| points_to_py(py, l)))?,
        PyList::new(
            py,
            lines
                .iter()
                .map(|l| heights_of(l, terrain).into_pyarray(py)),
        )?,
    ))
}

fn place_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("frame", frame_to_py(py, place)?)?;
    out.set_item("sources", sources_to_py(py, place)?)?;
    out.set_item("terrain", terrain_to_py(py, place)?)?;
    out.set_item("buildings", buildings_to_py(py, place)?)?;
    out.set_item("roads", roads_to_py(py, place)?)?;
    out.set_item("waterways", waterways_to_py(py, place)?)?;
    out.set_item("areas", areas_to_py(py, place)?)?;
    out.set_item("places", places_to_py(py, place)?)?;
    out.set_item("trees", trees_to_py(py, place)?)?;
    out.set_item("report", report_to_py(py, place)?)?;
    Ok(out)
}

/// The local frame: the lon/lat origin and the projection.
fn frame_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let frame = PyDict::new(py);
    frame.set_item("origin", place.frame.origin.map(|[lon, lat]| (lon, lat)))?;
    frame.set_item("projection", place.frame.projection.clone())?;
    Ok(frame)
}

/// The files the place was read from.
fn sources_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let sources = PyDict::new(py);
    sources.set_item("layers", place.sources.layers.clone())?;
    sources.set_item("elevation", place.sources.elevation.clone())?;
    sources.set_item("inventory", place.sources.inventory.clone())?;
    Ok(sources)
}

/// The terrain grid, heights as (ny, nx) float32; None without an elevation model.
fn terrain_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyAny>> {
    match place.terrain.as_ref() {
        Some(t) => {
            let d = PyDict::new(py);
            d.set_item("origin", (t.origin.x, t.origin.y))?;
            d.set_item("cell", t.cell)?;
            d.set_item("nx", t.nx)?;
            d.set_item("ny", t.ny)?;
            let h = Array2::from_shape_vec((t.ny, t.nx), t.heights.clone())
                .map_err(|e| input_err(format!("terrain of inconsistent size: {e}")))?;
            d.set_item("heights", h.into_pyarray(py))?;
            Ok(d.into_any())
        }
        None => Ok(py.None().into_bound(py)),
    }
}

/// The buildings: centroid, ground height, footprint size and orientation, area, type, tag, name, rings.
fn buildings_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let terrain = place.terrain.as_ref();
    let b = &place.buildings;
    let d = PyDict::new(py);
    let centroids: Vec<DVec2> = b.iter().map(|b| b.centroid).collect();
    d.set_item("centroid", points_to_py(py, &centroids))?;
    d.set_item("height", heights_of(&centroids, terrain).into_pyarray(py))?;
    d.set_item("size", rows_to_py(py, b.iter().map(|b| b.size))?)?;
    d.set_item(
        "orientation",
        b.iter()
            .map(|b| b.orientation)
            .collect::<Vec<f64>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "area",
        b.iter()
            .map(|b| b.area)
            .collect::<Vec<f64>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "type",
        b.iter().map(|b| b.kind.name()).collect::<Vec<&str>>(),
    )?;
    d.set_item(
        "building",
        b.iter()
            .map(|b| b.tags.get("building").cloned().unwrap_or_default())
            .collect::<Vec<String>>(),
    )?;
    d.set_item("name", names(b.iter().map(|b| &b.name)))?;
    d.set_item(
        "footprints",
        PyList::new(
            py,
            b.iter()
                .map(|b| rings_to_py(py, &b.footprint))
                .collect::<PyResult<Vec<_>>>()?,
        )?,
    )?;
    Ok(d)
}

/// The roads and paths: class, highway tag, name, points and their ground heights.
fn roads_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let terrain = place.terrain.as_ref();
    let r = &place.roads;
    let d = PyDict::new(py);
    d.set_item(
        "kind",
        r.iter().map(|r| r.class.name()).collect::<Vec<&str>>(),
    )?;
    d.set_item(
        "highway",
        r.iter().map(|r| r.highway.clone()).collect::<Vec<String>>(),
    )?;
    d.set_item("name", names(r.iter().map(|r| &r.name)))?;
    let (points, heights) = lines_to_py(
        py,
        &r.iter().map(|r| &r.points).collect::<Vec<_>>(),
        terrain,
    )?;
    d.set_item("points", points)?;
    d.set_item("heights", heights)?;
    Ok(d)
}

/// The waterway lines: kind, name, points and their ground heights.
fn waterways_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let terrain = place.terrain.as_ref();
    let w = &place.waterways;
    let d = PyDict::new(py);
    d.set_item(
        "kind",
        w.iter().map(|w| w.kind.clone()).collect::<Vec<String>>(),
    )?;
    d.set_item("name", names(w.iter().map(|w| &w.name)))?;
    let (points, heights) = lines_to_py(
        py,
        &w.iter().map(|w| &w.points).collect::<Vec<_>>(),
        terrain,
    )?;
    d.set_item("points", points)?;
    d.set_item("heights", heights)?;
    Ok(d)
}

/// The areas: class, tag, name, rings.
fn areas_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let a = &place.areas;
    let d = PyDict::new(py);
    d.set_item(
        "kind",
        a.iter().map(|a| a.class.name()).collect::<Vec<&str>>(),
    )?;
    d.set_item(
        "tag",
        a.iter().map(|a| a.tag.clone()).collect::<Vec<String>>(),
    )?;
    d.set_item("name", names(a.iter().map(|a| &a.name)))?;
    d.set_item(
        "rings",
        PyList::new(
            py,
            a.iter()
                .map(|a| rings_to_py(py, &a.rings))
                .collect::<PyResult<Vec<_>>>()?,
        )?,
    )?;
    Ok(d)
}

/// The named places: position, ground height, kind, name.
fn places_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let terrain = place.terrain.as_ref();
    let p = &place.places;
    let d = PyDict::new(py);
    let positions: Vec<DVec2> = p.iter().map(|p| p.position).collect();
    d.set_item("position", points_to_py(py, &positions))?;
    d.set_item("height", heights_of(&positions, terrain).into_pyarray(py))?;
    d.set_item(
        "kind",
        p.iter().map(|p| p.kind.clone()).collect::<Vec<String>>(),
    )?;
    d.set_item("name", names(p.iter().map(|p| &p.name)))?;
    Ok(d)
}

/// The inventory trees: position, ground height, species, size (NaN when unknown).
fn trees_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let terrain = place.terrain.as_ref();
    let t = &place.trees;
    let d = PyDict::new(py);
    let positions: Vec<DVec2> = t.iter().map(|t| t.position).collect();
    d.set_item("position", points_to_py(py, &positions))?;
    d.set_item("height", heights_of(&positions, terrain).into_pyarray(py))?;
    d.set_item(
        "species",
        t.iter().map(|t| t.species.clone()).collect::<Vec<String>>(),
    )?;
    d.set_item(
        "size",
        t.iter()
            .map(|t| t.size.unwrap_or(f64::NAN))
            .collect::<Vec<f64>>()
            .into_pyarray(py),
    )?;
    Ok(d)
}

/// What the import read, left out and filled.
fn report_to_py<'py>(py: Python<'py>, place: &Place) -> PyResult<Bound<'py, PyDict>> {
    let r = &place.report;
    let d = PyDict::new(py);
    d.set_item("features", r.features)?;
    d.set_item("unreadable", r.unreadable)?;
    d.set_item("left_out", r.left_out)?;
    d.set_item("trees_not_alive", r.trees_not_alive)?;
    d.set_item("trees_unreadable", r.trees_unreadable)?;
    let terrain_report = r.terrain.as_ref();
    d.set_item("holes_filled", terrain_report.map_or(0, |t| t.holes_filled))?;
    d.set_item("hole_share", terrain_report.map_or(0.0, |t| t.hole_share))?;
    d.set_item(
        "source_spacing",
        terrain_report.map(|t| (t.source_spacing[0], t.source_spacing[1])),
    )?;
    Ok(d)
}

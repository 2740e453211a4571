//! The engine's exemplar generators, for the demo, the asset scripts and the tests.

use crate::convert::{
    categories_to_py, instances_to_py, points_to_py, region_from_py, structures_to_py,
};
use crate::guarded;
use crate::terrain::Terrain;
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{DVec2, Region, Scene};

/// Runs a point generator on a region with the GIL released: float64 (N, 2).
fn generated_points<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    generate: impl FnOnce(&Region) -> Vec<DVec2> + Send,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let region = region_from_py(region)?;
    let pts = py.detach(|| guarded(|| Ok(generate(&region))))?;
    Ok(points_to_py(py, &pts))
}

/// Runs a scene generator with the GIL released: the scene, and its categories and instance columns (heights on
/// its terrain) as a dict.
fn generated_scene<'py>(
    py: Python<'py>,
    generate: impl FnOnce() -> Scene + Send,
) -> PyResult<(Scene, Bound<'py, PyDict>)> {
    let scene = py.detach(|| guarded(|| Ok(generate())))?;
    let d = PyDict::new(py);
    d.set_item("categories", categories_to_py(py, &scene.categories)?)?;
    instances_to_py(py, &d, &scene.instances, scene.terrain.as_deref())?;
    Ok((scene, d))
}

/// Points of a Poisson process of the given density (per m²) in the region: float64 (N, 2).
#[pyfunction]
pub(crate) fn exemplar_uniform<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    density: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::uniform_points(r, density, seed)
    })
}

/// Points of a Thomas cluster process (parents per m², mean children per parent, spread sigma in m).
#[pyfunction]
pub(crate) fn exemplar_clustered<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    parent_density: f64,
    children_mean: f64,
    sigma: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::clustered_points(r, parent_density, children_mean, sigma, seed)
    })
}

/// Points with a hard-core spacing (no pair closer than min_distance) at about the given density.
#[pyfunction]
pub(crate) fn exemplar_hard_core<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    density: f64,
    min_distance: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::hard_core_points(r, density, min_distance, seed)
    })
}

/// The multi-category slope exemplar: {"terrain": Terrain, "categories": [...], "positions", "heights",
/// "rotations", "scales", "category_index", "prototype"}.
#[pyfunction]
pub(crate) fn exemplar_slope_scene<'py>(
    py: Python<'py>,
    size: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let (scene, d) = generated_scene(py, || worldpaint_core::slope_scene(size, seed))?;
    match scene.terrain {
        Some(hf) => d.set_item("terrain", Py::new(py, Terrain { hf })?)?,
        None => d.set_item("terrain", py.None())?,
    }
    Ok(d)
}

/// The village exemplar (square `size` from the origin): grid streets, houses 8–15 m from them and trees away from
/// both: {"categories": [...], "paths": [{"category", "points", "heights"}], and the instance columns}.
#[pyfunction]
pub(crate) fn exemplar_village<'py>(
    py: Python<'py>,
    size: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let (scene, d) = generated_scene(py, || worldpaint_core::village_scene(size, seed))?;
    structures_to_py(
        py,
        &d,
        ["paths", "contours"],
        &scene.paths,
        &scene.contours,
        None,
    )?;
    Ok(d)
}

/// A deterministic terrain of smooth hills, size × size metres sampled every `cell` metres.
#[pyfunction]
pub(crate) fn exemplar_demo_terrain(
    py: Python<'_>,
    size: f64,
    cell: f64,
    seed: u64,
) -> PyResult<Terrain> {
    let hf = py.detach(|| guarded(|| Ok(worldpaint_core::demo_terrain(size, cell, seed))))?;
    Ok(Terrain { hf: hf.into() })
}

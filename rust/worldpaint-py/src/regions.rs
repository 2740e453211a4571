//! Regions: containment, area and bounds for the add-on's checks; polygons filled as a mesh for display.

use crate::arrays::ArrayArg;
use crate::convert::{heights_of, points_from_py, points_to_py, region_from_py, rows_to_py};
use crate::terrain::{terrain_of, Terrain};
use crate::{guarded, input_err};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{triangulate, Polygons};

/// Which of the points (float64 (N, 2)) lie inside the region: bool (N).
#[pyfunction]
pub(crate) fn region_contains<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    xy: ArrayArg<'py>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let region = region_from_py(region)?;
    let pts = points_from_py(&xy, "xy")?;
    let inside: Vec<bool> =
        py.detach(|| guarded(|| Ok(pts.iter().map(|p| region.contains(*p)).collect())))?;
    Ok(inside.into_pyarray(py))
}

/// Area of the region in m².
#[pyfunction]
pub(crate) fn region_area(region: &Bound<'_, PyAny>) -> PyResult<f64> {
    let region = region_from_py(region)?;
    guarded(|| Ok(region.area()))
}

/// ((xmin, ymin), (xmax, ymax)) of the region.
#[pyfunction]
pub(crate) fn region_bbox(region: &Bound<'_, PyAny>) -> PyResult<((f64, f64), (f64, f64))> {
    let region = region_from_py(region)?;
    let (a, b) = guarded(|| Ok(region.bbox()))?;
    Ok(((a.x, a.y), (b.x, b.y)))
}

/// The filled mesh of closed contours (float64 (N, 2) arrays, combined by the even-odd rule: a lake in an island
/// is a hole), with inner vertices about `spacing` apart so it can follow the terrain: {"vertices": float64 (V, 2),
/// "heights": float64 (V) (terrain height, NaN off it or without terrain), "triangles": int32 (T, 3)}.
#[pyfunction]
#[pyo3(signature = (contours, spacing, terrain=None))]
pub(crate) fn fill_polygons<'py>(
    py: Python<'py>,
    contours: &Bound<'py, PyAny>,
    spacing: f64,
    terrain: Option<Py<Terrain>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut loops = Vec::new();
    let items = contours
        .try_iter()
        .map_err(|_| input_err("contours must be a list of (N, 2) arrays"))?;
    for (i, c) in items.enumerate() {
        let points = points_from_py(&ArrayArg::from(c?), &format!("contour {i}"))?;
        if points.iter().any(|p| !p.is_finite()) {
            return Err(input_err(format!("contour {i} has a non-finite point")));
        }
        loops.push(points);
    }
    if !spacing.is_finite() {
        return Err(input_err("spacing must be a finite number"));
    }
    let mesh = py.detach(|| guarded(|| Ok(triangulate(&Polygons::new(&loops), spacing))))?;
    let d = PyDict::new(py);
    d.set_item("vertices", points_to_py(py, &mesh.vertices))?;
    let terrain = terrain_of(&terrain);
    d.set_item(
        "heights",
        heights_of(&mesh.vertices, terrain.map(|t| t.as_ref())).into_pyarray(py),
    )?;
    let triangles = mesh.triangles.iter().map(|t| t.map(|i| i as i32));
    d.set_item("triangles", rows_to_py(py, triangles)?)?;
    Ok(d)
}

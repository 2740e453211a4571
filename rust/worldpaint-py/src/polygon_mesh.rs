//! Polygons filled as a mesh for display.

use crate::arrays::ArrayArg;
use crate::convert::{heights_of, points_from_py, points_to_py, rows_to_py};
use crate::terrain::{terrain_of, Terrain};
use crate::{guarded, input_err};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{triangulate, Polygons};

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

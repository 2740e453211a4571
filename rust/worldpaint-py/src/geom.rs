//! Regions: containment, area and bounds for the add-on's checks; the height of a terrain mesh under points.

use crate::arrays::ArrayArg;
use crate::convert::{points_from_py, region_from_py};
use crate::guarded;
use crate::terrain::mesh_from_py;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use worldpaint_core::VerticalLookup;

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

/// A terrain mesh binned for vertical look-ups: the height of its highest triangle under points, where a ray from
/// above meets it first.
///
/// `TerrainSurface(vertices, triangles)` bins a triangle mesh given in world space (float64 (V, 3), and (T, 3) vertex
/// indices of any integer dtype); vertical triangles, and those with a vertex that is not a finite number, are left
/// out.
#[pyclass(module = "worldpaint_engine", frozen)]
pub(crate) struct TerrainSurface {
    lookup: VerticalLookup,
}

#[pymethods]
impl TerrainSurface {
    #[new]
    fn new(py: Python<'_>, vertices: ArrayArg<'_>, triangles: ArrayArg<'_>) -> PyResult<Self> {
        let (verts, tris) = mesh_from_py(&vertices, &triangles)?;
        let lookup = py.detach(|| guarded(|| VerticalLookup::new(&verts, &tris)))?;
        Ok(TerrainSurface { lookup })
    }

    /// The height of the highest triangle over each world XY point (float64 (N, 2)): float64 (N), NaN over none.
    fn heights<'py>(
        &self,
        py: Python<'py>,
        xy: ArrayArg<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pts = points_from_py(&xy, "xy")?;
        let lookup = &self.lookup;
        let heights = py.detach(|| guarded(|| Ok(lookup.heights(&pts))))?;
        Ok(heights.into_pyarray(py))
    }
}

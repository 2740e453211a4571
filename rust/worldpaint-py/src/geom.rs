//! Regions: containment, area and bounds for the add-on's checks.

use crate::arrays::ArrayArg;
use crate::convert::{points_from_py, region_from_py};
use crate::guarded;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;

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

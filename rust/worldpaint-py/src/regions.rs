//! Regions: containment, area and bounds for the add-on's checks.

use crate::convert::{points_from_py, region_from_py};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

/// Which of the points (float64 (N, 2)) lie inside the region: bool (N).
#[pyfunction]
fn region_contains<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    xy: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let region = region_from_py(region)?;
    let pts = points_from_py(&xy, "xy")?;
    let inside: Vec<bool> = py.detach(|| pts.iter().map(|p| region.contains(*p)).collect());
    Ok(inside.into_pyarray(py))
}

/// Area of the region in m².
#[pyfunction]
fn region_area(region: &Bound<'_, PyAny>) -> PyResult<f64> {
    Ok(region_from_py(region)?.area())
}

/// ((xmin, ymin), (xmax, ymax)) of the region.
#[pyfunction]
fn region_bbox(region: &Bound<'_, PyAny>) -> PyResult<((f64, f64), (f64, f64))> {
    let (a, b) = region_from_py(region)?.bbox();
    Ok(((a.x, a.y), (b.x, b.y)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(region_contains, m)?)?;
    m.add_function(wrap_pyfunction!(region_area, m)?)?;
    m.add_function(wrap_pyfunction!(region_bbox, m)?)?;
    Ok(())
}

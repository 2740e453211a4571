//! Colors between two colors.

use crate::convert::parse_color;
use crate::guarded;
use pyo3::prelude::*;

/// The color between `a` and `b` (JSON) at `t` ∈ [0, 1], by optimal transport of every histogram, named `name`;
/// its preview shows an arrangement painted with it.
#[pyfunction]
pub(crate) fn interpolate_colors(
    py: Python<'_>,
    a: &str,
    b: &str,
    t: f64,
    name: &str,
) -> PyResult<String> {
    let (a, b) = (parse_color(a)?, parse_color(b)?);
    let name = name.to_string();
    py.detach(|| {
        guarded(|| {
            let c = worldpaint_core::interpolate_colors(&a, &b, t, &name)?;
            worldpaint_core::with_painted_preview(c)?.to_json()
        })
    })
}

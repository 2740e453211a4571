//! Learning a color from an example.

use crate::convert::region_from_py;
use crate::scene::PyScene;
use crate::{guarded, input_err};
use pyo3::prelude::*;
use worldpaint_core::AnalysisOptions;

pub(crate) fn analysis_options(options: Option<&Bound<'_, PyAny>>) -> PyResult<AnalysisOptions> {
    let mut o = AnalysisOptions::default();
    let Some(d) = options else { return Ok(o) };
    if d.is_none() {
        return Ok(o);
    }
    let get = |k: &str| -> Option<Bound<'_, PyAny>> { d.get_item(k).ok().filter(|v| !v.is_none()) };
    if let Some(v) = get("bin_width") {
        o.bin_width = Some(
            v.extract()
                .map_err(|_| input_err("options 'bin_width' must be a number"))?,
        );
    }
    if let Some(v) = get("max_radius") {
        o.max_radius = Some(
            v.extract()
                .map_err(|_| input_err("options 'max_radius' must be a number"))?,
        );
    }
    if let Some(v) = get("oriented") {
        o.oriented = v.extract().map_err(|_| {
            input_err("options 'oriented' must be a list of (category, category) pairs")
        })?;
    }
    if let Some(v) = get("maps") {
        o.maps = v
            .extract()
            .map_err(|_| input_err("options 'maps' must be a list of map names"))?;
    }
    Ok(o)
}

/// Learn a color (returned as JSON) from the instances of `scene` inside `region`. `options`: {"bin_width",
/// "max_radius", "oriented": [(a, b), ...], "maps": [...]}, all optional.
#[pyfunction]
#[pyo3(signature = (scene, region, name, *, options=None))]
pub(crate) fn learn_color(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    region: &Bound<'_, PyAny>,
    name: &str,
    options: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let opts = analysis_options(options)?;
    let name = name.to_string();
    py.detach(|| guarded(|| worldpaint_core::learn_color(scene, &region, &name, &opts)?.to_json()))
}

//! How far one color is from another, and how well a color reproduces its example (with its picture).

use crate::convert::parse_color;
use crate::terrain::{terrain_of, Terrain};
use crate::{guarded, input_err, with_progress};
use numpy::ndarray::Array3;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{draw_fidelity, Fidelity};

/// How far `candidate` is from `reference` (both color JSON): {"density_ratio": {category: ratio},
/// "rdf_l2": [(a, b, l2), ...], "map_tv": [(category, map, tv), ...], "too_few": [category, ...] (left out of
/// the worst figures: fewer than ten instances in the reference), "worst_density_error", "max_rdf_l2",
/// "max_map_tv"}.
#[pyfunction]
pub(crate) fn compare<'py>(
    py: Python<'py>,
    reference: &str,
    candidate: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let a = parse_color(reference)?;
    let b = parse_color(candidate)?;
    let f = py.detach(|| guarded(|| Ok(worldpaint_core::compare(&a, &b))))?;
    fidelity_to_py(py, &f)
}

/// The dict `compare` returns, of a fidelity.
pub(crate) fn fidelity_to_py<'py>(py: Python<'py>, f: &Fidelity) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let ratios = PyDict::new(py);
    for (name, r) in &f.density_ratio {
        ratios.set_item(name, *r)?;
    }
    d.set_item("density_ratio", ratios)?;
    d.set_item("rdf_l2", f.rdf_l2.clone())?;
    d.set_item("map_tv", f.map_tv.clone())?;
    d.set_item("too_few", f.too_few.clone())?;
    d.set_item("worst_density_error", f.worst_density_error())?;
    d.set_item("max_rdf_l2", f.max_rdf_l2())?;
    d.set_item("max_map_tv", f.max_map_tv())?;
    Ok(d)
}

/// The palette's fidelity view of `color` (JSON): how well the color reproduces its example.
///
/// The color is synthesized with `seed` into its own example region of an empty scene, on `terrain` (a `Terrain`:
/// the one the color was learned on) when the color has terrain maps, else without terrain and without its terrain
/// maps; what it painted is learned back with the color's bins and maps and compared with it (as `compare`), and
/// the two are plotted (see `worldpaint_core::draw_fidelity`): each category's pair-correlation function with
/// itself over distance, the example's solid and the self-synthesis's dashed and lighter, over a grey line at 1;
/// beside it, when the color has a slope map, the slope histograms, likewise. The picture holds no text.
///
/// Returns the keys of `compare` and {"image": uint8 (height, width, 4) RGBA, rows from the top, "max_distance"
/// (m) and "max_pcf" (the pcf axes' ends), "max_slope_degrees" (the slope axis's end; None without a slope panel),
/// "candidate": the self-synthesis's color JSON}. `progress(fraction) -> bool` follows the synthesis and may
/// return False to cancel (raises `Cancelled`). The same color, terrain and seed give the same result.
#[pyfunction]
#[pyo3(signature = (color, terrain=None, seed=0, *, width=256, height=128, progress=None))]
pub(crate) fn fidelity<'py>(
    py: Python<'py>,
    color: &str,
    terrain: Option<Py<Terrain>>,
    seed: u64,
    width: u32,
    height: u32,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let color = parse_color(color)?;
    let heightfield = terrain_of(&terrain).cloned();
    let (candidate, fid, plot) = with_progress(py, progress, |report| {
        let candidate = worldpaint_core::self_synthesis(&color, heightfield, seed, report)?;
        let fid = worldpaint_core::compare(&color, &candidate);
        let plot = draw_fidelity(&color, &candidate, width, height)?;
        Ok((candidate, fid, plot))
    })?;
    let d = fidelity_to_py(py, &fid)?;
    let shape = (plot.height as usize, plot.width as usize, 4);
    let image = Array3::from_shape_vec(shape, plot.rgba)
        .map_err(|e| input_err(format!("plot of inconsistent size: {e}")))?;
    d.set_item("image", image.into_pyarray(py))?;
    d.set_item("max_distance", plot.extent.max_distance)?;
    d.set_item("max_pcf", plot.extent.max_pcf)?;
    d.set_item("max_slope_degrees", plot.extent.max_slope_degrees)?;
    d.set_item("candidate", guarded(|| candidate.to_json())?)?;
    Ok(d)
}

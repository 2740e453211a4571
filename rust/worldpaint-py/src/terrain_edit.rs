//! Terrain that adapts: `embed_roads`.

use crate::arrays::ArrayArg;
use crate::convert::{height_change, points_from_py, rows_to_py};
use crate::terrain::Terrain;
use crate::{guarded, input_err};
use numpy::ndarray::Ix2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{embed_roads as embed, DVec2, EmbeddedRoad, RoadEmbeddingOptions};

/// Road centrelines from a list of float64 (N, 2) or (N, 3) arrays; with `use_heights`, the third column gives the
/// carriageway's heights.
fn roads_from_py(
    list: &Bound<'_, PyAny>,
    width: f64,
    bank_width: f64,
    use_heights: bool,
) -> PyResult<Vec<EmbeddedRoad>> {
    let mut out = Vec::new();
    let items = list
        .try_iter()
        .map_err(|_| input_err("roads must be a list of (N, 2) or (N, 3) arrays"))?;
    for (i, item) in items.enumerate() {
        let a = ArrayArg::from(item?).read::<f64, Ix2>(&format!("road {i}"), &[2, 3])?;
        let a = a.as_array();
        if a.iter().any(|v| !v.is_finite()) {
            return Err(input_err(format!("road {i} has a non-finite point")));
        }
        let centreline = a
            .rows()
            .into_iter()
            .map(|r| DVec2::new(r[0], r[1]))
            .collect();
        let heights = (use_heights && a.ncols() == 3).then(|| a.column(2).to_vec());
        out.push(EmbeddedRoad {
            centreline,
            heights,
            width,
            bank_width,
        });
    }
    Ok(out)
}

/// Embeds road centrelines into the terrain: a level carriageway of `width` along each, cut and fill banks of
/// `bank_width` blending into the natural slope. With `use_heights`, (N, 3) roads give the carriageway heights;
/// otherwise it follows the terrain smoothed along the road (`smoothing`: the Gaussian's standard deviation in
/// metres, None for twice the width). Returns a dict: "displacement" (the height change at the world XY `points`,
/// float64 (M,), 0 outside the terrain), "profiles" (per road, float64 (K, 3) carriageway samples), "residual",
/// "cycles", "converged".
#[pyfunction]
#[pyo3(signature = (terrain, roads, points, width=5.0, bank_width=8.0, *, use_heights=false, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn embed_roads<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    roads: &Bound<'py, PyAny>,
    points: ArrayArg<'py>,
    width: f64,
    bank_width: f64,
    use_heights: bool,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let roads = roads_from_py(roads, width, bank_width, use_heights)?;
    if roads.is_empty() {
        return Err(input_err("no road to embed"));
    }
    let pts = points_from_py(&points, "points")?;
    let options = RoadEmbeddingOptions {
        smoothing,
        ..Default::default()
    };
    let (embedding, change) = py.detach(|| {
        guarded(|| {
            let e = embed(&hf, &roads, &options)?;
            let change = height_change(&hf, &e.terrain, &pts);
            Ok((e, change))
        })
    })?;
    let out = PyDict::new(py);
    out.set_item("displacement", change.into_pyarray(py))?;
    let profiles = PyList::empty(py);
    for p in &embedding.profiles {
        profiles.append(rows_to_py(py, p.points.iter().map(|q| [q.x, q.y, q.z]))?)?;
    }
    out.set_item("profiles", profiles)?;
    out.set_item("residual", embedding.diffusion.residual)?;
    out.set_item("cycles", embedding.diffusion.cycles)?;
    out.set_item("converged", embedding.diffusion.converged)?;
    Ok(out)
}

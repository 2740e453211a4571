//! Painting a color into a region: the keyword arguments the painting functions share, and synthesis.

use crate::convert::{categories_to_py, instances_to_py, structures_to_py};
use crate::with_progress;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{Color, Region, Scene, SynthesisOptions};

/// What a function painting a color into a region works from: the engine's scene, the color, the region, the
/// synthesis options and the progress callback.
pub(crate) struct Painting<'a> {
    pub(crate) scene: &'a Scene,
    pub(crate) color: Color,
    pub(crate) region: Region,
    pub(crate) opts: SynthesisOptions,
    pub(crate) progress: Option<Py<PyAny>>,
}

/// Declares the Python function `$name(scene, color, region, seed=0, *, influence_radius=None,
/// iterations_per_instance=None, only_categories=None, progress=None, guides=None)` that paints a color into a region, with
/// the doc comments given before the name, and hands its arguments converted to a [`Painting`] to `$paint`.
/// pyo3 reads a Python signature off the function's own parameters, so the functions that take the same arguments
/// share them through this declaration.
macro_rules! color_painter {
    ($(#[$doc:meta])* $name:ident => $paint:ident) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = (scene, color, region, seed=0, *, influence_radius=None, iterations_per_instance=None,
                            only_categories=None, progress=None, guides=None))]
        #[allow(clippy::too_many_arguments)]
        pub(crate) fn $name<'py>(
            py: Python<'py>,
            scene: &Bound<'py, $crate::scene::PyScene>,
            color: &str,
            region: &Bound<'py, PyAny>,
            seed: u64,
            influence_radius: Option<f64>,
            iterations_per_instance: Option<f64>,
            only_categories: Option<Vec<String>>,
            progress: Option<Py<PyAny>>,
            guides: Option<&Bound<'py, PyAny>>,
        ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
            let mut opts = $crate::paint::synthesis_options(
                seed,
                influence_radius,
                iterations_per_instance,
                only_categories,
            );
            opts.guides = $crate::arrangement::guides_from_py(guides)?;
            let painting = $crate::paint::Painting {
                scene: scene.get().scene(),
                region: $crate::convert::region_from_py(region)?,
                color: $crate::convert::parse_color(color)?,
                opts,
                progress,
            };
            $paint(py, painting)
        }
    };
}
pub(crate) use color_painter;

color_painter! {
    /// Synthesize `color` (JSON) inside `region` of `scene`: its unlocked instances inside the region are replaced, the
    /// locked ones inside it and those around it condition the result.
    ///
    /// Returns {"categories": [...], "positions": float64 (N, 2), "heights": float64 (N) (terrain height, NaN without
    /// terrain), "rotations", "scales", "category_index": int32, "prototype": int32} for the *new* instances, and
    /// "paths" and "contours": lists of {"category", "points" (N, 2), "heights" (N)} of the new roads and islands;
    /// category indices refer to the returned category list (the given ones, then the color's new ones).
    /// `progress(fraction) -> bool` may return False to cancel (raises `Cancelled`).
    synthesize => synthesized
}

fn synthesized<'py>(py: Python<'py>, p: Painting<'_>) -> PyResult<Bound<'py, PyDict>> {
    let result = with_progress(py, p.progress, |report| {
        worldpaint_core::synthesize_with_progress(p.scene, &p.color, &p.region, &p.opts, report)
    })?;
    let d = PyDict::new(py);
    d.set_item("categories", categories_to_py(py, &result.categories)?)?;
    let terrain = p.scene.terrain.as_deref();
    instances_to_py(py, &d, &result.instances, terrain)?;
    structures_to_py(
        py,
        &d,
        ["paths", "contours"],
        &result.paths,
        &result.contours,
        terrain,
    )?;
    Ok(d)
}

/// The synthesis options of the keyword arguments the synthesizing functions share.
pub(crate) fn synthesis_options(
    seed: u64,
    influence_radius: Option<f64>,
    iterations_per_instance: Option<f64>,
    only_categories: Option<Vec<String>>,
) -> SynthesisOptions {
    let mut opts = SynthesisOptions {
        seed,
        influence_radius,
        categories: only_categories,
        ..Default::default()
    };
    if let Some(it) = iterations_per_instance {
        opts.iterations_per_instance = it;
    }
    opts
}

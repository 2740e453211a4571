//! The scene handed to the engine: the terrain and the instance columns, converted once.

use crate::arrays::ArrayArg;
use crate::convert::{scene_from_py, InstanceColumns, Structures};
use crate::terrain::Terrain;
use pyo3::prelude::*;
use worldpaint_core::Scene;

/// A scene the engine works on: `Scene(terrain, categories, positions, category_index, *, rotations=None,
/// scales=None, prototype=None, locked=None, tints=None)`. `terrain` is a `Terrain` or None; `categories` a list of {"name",
/// "layer", "kind", "priority"} dicts (all but the name optional); `positions` float64 (N, 2) world XY;
/// `category_index` int32 (N) into `categories`; `rotations` (radians about Z), `scales`, `prototype` (int32) and
/// `locked` (bool: placed by hand, never removed by a tool) and `tints` (float32: colour variation) are optional
/// columns. `paths` (of graph categories: roads,
/// rivers) and `contours` (closed, of polygon categories: islands, lakes) are lists of {"category": int, "points":
/// float64 (N, 2), "locked": bool (default True)}. Immutable: learning reads it, and every tool returns an edit of it.
#[pyclass(module = "worldpaint_engine", frozen, name = "Scene")]
pub(crate) struct PyScene {
    scene: Scene,
}

#[pymethods]
impl PyScene {
    #[new]
    #[pyo3(signature = (terrain, categories, positions, category_index, *, rotations=None, scales=None,
                        prototype=None, locked=None, tints=None, paths=None, contours=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        terrain: Option<Py<Terrain>>,
        categories: &Bound<'_, PyAny>,
        positions: ArrayArg<'_>,
        category_index: ArrayArg<'_>,
        rotations: Option<ArrayArg<'_>>,
        scales: Option<ArrayArg<'_>>,
        prototype: Option<ArrayArg<'_>>,
        locked: Option<ArrayArg<'_>>,
        tints: Option<ArrayArg<'_>>,
        paths: Option<&Bound<'_, PyAny>>,
        contours: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let columns = InstanceColumns {
            positions,
            category_index,
            rotations,
            scales,
            prototype,
            locked,
            tints,
        };
        let scene = scene_from_py(
            &terrain,
            categories,
            columns,
            &Structures { paths, contours },
        )?;
        Ok(PyScene { scene })
    }

    fn __len__(&self) -> usize {
        self.scene.instances.len()
    }
}

impl PyScene {
    pub(crate) fn scene(&self) -> &Scene {
        &self.scene
    }
}

//! Python bindings of the worldpaint engine, module `worldpaint_engine`.
//!
//! Thin by design: numpy arrays and plain Python values are turned into `worldpaint_core` types, the engine runs
//! with the GIL released, and the results come back as numpy arrays. Colors and palettes cross the boundary as their
//! versioned JSON. Every error is a `worldpaint_engine.WorldPaintError`: bad input raises `InputError` (also a
//! `ValueError`, with `FileFormatError` for malformed files) carrying the engine's message, a cancelled
//! computation `Cancelled`. No algorithm lives here, and no panic crosses into Python: every call runs under
//! `guarded`, which reports a panic as `InternalError`. Array arguments take any real numeric dtype whose meaning is
//! clear (float32, integers, ...) and are cast to the engine's; an unusable one raises `InputError` naming the
//! argument (see `arrays`).
//!
//! One file per area of the engine, named after the engine's module it binds (`exemplar`, `palette`, `compare`,
//! `village`, ...); `arrays` and `convert` turn Python values into the engine's types and back. Everything is
//! imported from the engine's crate root.

mod analysis;
mod arrangement;
mod arrays;
mod compare;
mod convert;
mod exemplar;
mod geom;
mod interpolate;
mod paint;
mod palette;
mod place;
mod polygon_mesh;
mod scene;
mod sketch;
mod terrain;
mod terrain_edit;
mod tools;
mod variety;
mod village;
mod waterfall;
mod world;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The longest the engine works without calling the progress callback (so Esc and cancels are heard).
const CALLBACK_PERIOD: Duration = Duration::from_millis(100);

use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use worldpaint_core::Error;

// ---------------------------------------------------------------------------------------------------------------
// errors and the FFI guard: WorldPaintError <- InputError (also a ValueError) <- FileFormatError, NothingToLearn;
// Cancelled; InternalError

pyo3::create_exception!(
    worldpaint_engine,
    WorldPaintError,
    PyException,
    "Base of every error the engine raises."
);
pyo3::create_exception!(
    worldpaint_engine,
    Cancelled,
    WorldPaintError,
    "A long computation was cancelled by its caller; nothing was returned."
);
pyo3::create_exception!(
    worldpaint_engine,
    InternalError,
    WorldPaintError,
    "The engine failed where it should not have (a defect); the message says where."
);

// InputError derives from both WorldPaintError and ValueError, which `create_exception!` cannot express, so the
// input classes are made once at import by calling `type`.
static INPUT_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static FILE_FORMAT_ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static NOTHING_TO_LEARN: PyOnceLock<Py<PyType>> = PyOnceLock::new();

fn exception_class(
    py: Python<'_>,
    name: &str,
    bases: Bound<'_, PyTuple>,
    doc: &str,
) -> PyResult<Py<PyType>> {
    let namespace = PyDict::new(py);
    namespace.set_item("__module__", "worldpaint_engine")?;
    namespace.set_item("__doc__", doc)?;
    let class = py.get_type::<PyType>().call1((name, bases, namespace))?;
    Ok(class.cast_into::<PyType>()?.unbind())
}

/// An exception class made at import, with the name it is exported under.
type ClassSlot = (&'static str, &'static PyOnceLock<Py<PyType>>);

/// The input error classes, made on first use.
fn input_classes(py: Python<'_>) -> PyResult<[ClassSlot; 3]> {
    let input = INPUT_ERROR.get_or_try_init(py, || {
        let bases = PyTuple::new(py, [py.get_type::<WorldPaintError>(), py.get_type::<PyValueError>()])?;
        exception_class(
            py,
            "InputError",
            bases,
            "The engine rejected its input (a region, a terrain, a color, an option); the message says what was wrong \
             and where.",
        )
    })?;
    let subclass =
        |name: &str, doc: &str| exception_class(py, name, PyTuple::new(py, [input.bind(py)])?, doc);
    FILE_FORMAT_ERROR.get_or_try_init(py, || {
        subclass(
            "FileFormatError",
            "A palette, color, encyclopedia or scenario file is malformed, or of a format version this engine does not read.",
        )
    })?;
    NOTHING_TO_LEARN.get_or_try_init(py, || {
        subclass(
            "NothingToLearn",
            "The region to learn from holds no example content.",
        )
    })?;
    Ok([
        ("InputError", &INPUT_ERROR),
        ("FileFormatError", &FILE_FORMAT_ERROR),
        ("NothingToLearn", &NOTHING_TO_LEARN),
    ])
}

fn raise(class: &PyOnceLock<Py<PyType>>, message: String) -> PyErr {
    Python::attach(|py| {
        if let Err(e) = input_classes(py) {
            return e;
        }
        match class.get(py) {
            Some(c) => PyErr::from_type(c.bind(py).clone(), message),
            None => PyValueError::new_err(message),
        }
    })
}

pub(crate) fn engine_err(e: Error) -> PyErr {
    match e {
        Error::Cancelled => Cancelled::new_err("cancelled"),
        Error::UnsupportedVersion { .. } | Error::Parse { .. } => {
            raise(&FILE_FORMAT_ERROR, e.to_string())
        }
        Error::EmptyExemplar { .. } => raise(&NOTHING_TO_LEARN, e.to_string()),
        other => raise(&INPUT_ERROR, other.to_string()),
    }
}

pub(crate) fn input_err(msg: impl Into<String>) -> PyErr {
    raise(&INPUT_ERROR, format!("invalid input: {}", msg.into()))
}

/// Runs engine code so that neither an error nor a panic escapes as anything but a Python exception.
pub(crate) fn guarded<T>(f: impl FnOnce() -> worldpaint_core::Result<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(result) => result.map_err(engine_err),
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(InternalError::new_err(format!(
                "internal engine error: {what}"
            )))
        }
    }
}

/// A Python progress callback as the engine's `Fn(f64) -> bool`: `progress(fraction) -> bool`, or
/// `progress(fraction, stage) -> bool` for a computation in named stages when the callback takes a second argument.
/// The GIL is taken again only when the fraction has moved by a percent or the stage has changed; returning False
/// cancels, and an exception raised by the callback cancels too and is re-raised by [`Progress::finish`].
pub(crate) struct Progress {
    callback: Option<Py<PyAny>>,
    takes_stage: bool,
    error: Mutex<Option<PyErr>>,
    last: Mutex<(f64, Option<&'static str>, Instant)>,
}

/// Whether a callback accepts `(fraction, stage)`: callers that take only the fraction keep working.
fn takes_stage(py: Python<'_>, callback: &Py<PyAny>) -> bool {
    let bound = || -> PyResult<bool> {
        let signature = py
            .import("inspect")?
            .getattr("signature")?
            .call1((callback,))?;
        Ok(signature.call_method1("bind", (0.0, "")).is_ok())
    };
    bound().unwrap_or(false)
}

impl Progress {
    pub(crate) fn new(py: Python<'_>, callback: Option<Py<PyAny>>) -> Self {
        let takes_stage = callback.as_ref().is_some_and(|cb| takes_stage(py, cb));
        Progress {
            callback,
            takes_stage,
            error: Mutex::new(None),
            last: Mutex::new((f64::NEG_INFINITY, None, Instant::now())),
        }
    }

    pub(crate) fn report(&self, fraction: f64, stage: Option<&'static str>) -> bool {
        let Some(cb) = self.callback.as_ref() else {
            return true;
        };
        if let Ok(mut last) = self.last.lock() {
            // a long stretch of work without visible progress still reaches the callback, so Esc is heard
            if fraction < 1.0
                && fraction - last.0 < 0.01
                && stage == last.1
                && last.2.elapsed() < CALLBACK_PERIOD
            {
                return true;
            }
            *last = (fraction, stage, Instant::now());
        }
        Python::attach(|py| {
            let called = match stage {
                Some(name) if self.takes_stage => cb.call1(py, (fraction, name)),
                _ => cb.call1(py, (fraction,)),
            };
            match called {
                Ok(r) => r.extract::<bool>(py).unwrap_or(true),
                Err(e) => {
                    if let Ok(mut slot) = self.error.lock() {
                        *slot = Some(e);
                    }
                    false
                }
            }
        })
    }

    /// The engine's result, or the callback's own exception when it raised one.
    pub(crate) fn finish<T>(self, result: PyResult<T>) -> PyResult<T> {
        if let Ok(mut slot) = self.error.lock() {
            if let Some(e) = slot.take() {
                return Err(e);
            }
        }
        result
    }
}

/// Runs `f` (engine work) with the GIL released and the progress callback wired in.
pub(crate) fn with_progress<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    f: impl FnOnce(&(dyn Fn(f64) -> bool + Sync)) -> worldpaint_core::Result<T> + Send,
) -> PyResult<T> {
    with_stages(py, progress, |report| f(&|x| report(x, None)))
}

/// Runs `f` like [`with_progress`] for work in named stages: `f` reports the overall fraction with its stage's name.
pub(crate) fn with_stages<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    f: impl FnOnce(&(dyn Fn(f64, Option<&'static str>) -> bool + Sync)) -> worldpaint_core::Result<T>
        + Send,
) -> PyResult<T> {
    let progress = Progress::new(py, progress);
    let result = py.detach(|| guarded(|| f(&|x, stage| progress.report(x, stage))));
    progress.finish(result)
}

// The Python module: the engine's classes and functions, the error classes, the version and the palette format
// version. (A doc comment here would become the module's docstring, which is empty.)
#[pymodule]
#[pyo3(name = "_engine")]
mod worldpaint_engine {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::analysis::learn_color;
    #[pymodule_export]
    use crate::arrangement::{arrangement_edited, arrangement_summary, learn_arrangement};
    #[pymodule_export]
    use crate::compare::{compare, fidelity};
    #[pymodule_export]
    use crate::exemplar::{
        exemplar_clustered, exemplar_demo_terrain, exemplar_hard_core, exemplar_slope_scene,
        exemplar_uniform, exemplar_village,
    };
    #[pymodule_export]
    use crate::geom::{region_area, region_bbox, region_contains, TerrainSurface};
    #[pymodule_export]
    use crate::interpolate::interpolate_colors;
    #[pymodule_export]
    use crate::paint::synthesize;
    #[pymodule_export]
    use crate::palette::{
        color_renamed, color_summary, color_without_interactions, palette_from_json,
        palette_to_json,
    };
    #[pymodule_export]
    use crate::place::import_place;
    #[pymodule_export]
    use crate::polygon_mesh::fill_polygons;
    #[pymodule_export]
    use crate::scene::PyScene;
    #[pymodule_export]
    use crate::sketch::apply_sketch;
    #[pymodule_export]
    use crate::terrain::Terrain;
    #[pymodule_export]
    use crate::terrain_edit::embed_roads;
    #[pymodule_export]
    use crate::tools::{blur, clear_region, gradient, move_region, paste, stretch_region, Stroke};
    #[pymodule_export]
    use crate::variety::{assign_variants, decompose_model, generate_variants, texture_variety};
    #[pymodule_export]
    use crate::village::{
        default_encyclopedia, encyclopedia_contents, generate_village, learn_village,
        scenario_presets, village_interest,
    };
    #[pymodule_export]
    use crate::waterfall::build_waterfall;
    #[pymodule_export]
    use crate::world::{read_world_tile, world_plan, world_tile, world_villages};

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        let py = m.py();
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add(
            "PALETTE_FORMAT_VERSION",
            worldpaint_core::PALETTE_FORMAT_VERSION,
        )?;
        // the work budget, for drivers that check their input before calling the engine
        let limits = pyo3::types::PyDict::new(py);
        limits.set_item("grid_cells", worldpaint_core::MAX_GRID_CELLS)?;
        limits.set_item("instances", worldpaint_core::MAX_INSTANCES)?;
        limits.set_item("world_instances", worldpaint_core::MAX_WORLD_INSTANCES)?;
        limits.set_item("world_tiles", worldpaint_core::MAX_TILES)?;
        limits.set_item(
            "iterations_per_instance",
            worldpaint_core::MAX_ITERATIONS_PER_INSTANCE,
        )?;
        m.add("LIMITS", limits)?;
        m.add("WorldPaintError", py.get_type::<crate::WorldPaintError>())?;
        for (name, class) in crate::input_classes(py)? {
            if let Some(class) = class.get(py) {
                m.add(name, class.clone_ref(py))?;
            }
        }
        m.add("Cancelled", py.get_type::<crate::Cancelled>())?;
        m.add("InternalError", py.get_type::<crate::InternalError>())?;
        Ok(())
    }
}

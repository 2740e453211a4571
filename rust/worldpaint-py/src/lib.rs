//! Python bindings of the worldpaint engine, module `worldpaint_engine`.
//!
//! Thin by design: numpy arrays and plain Python values are turned into `worldpaint_core` types, the engine runs
//! with the GIL released, and the results come back as numpy arrays. Colors and palettes cross the boundary as their
//! versioned JSON. Engine errors become `worldpaint_engine.EngineError` (a `ValueError`) carrying the engine's
//! message; a cancelled synthesis raises `worldpaint_engine.Cancelled`. No algorithm lives here, and no panic
//! crosses into Python: an internal failure is reported as an `EngineError` too.

mod colors;
mod convert;
mod exemplars;
mod regions;
mod scene;
mod terrain;
mod terrain_edit;
mod tools;
mod village;
mod waterfall;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use worldpaint_core::Error;

pyo3::create_exception!(
    worldpaint_engine,
    EngineError,
    PyValueError,
    "The engine rejected its input or could not complete; the message says what and where."
);
pyo3::create_exception!(
    worldpaint_engine,
    Cancelled,
    PyException,
    "A long computation was cancelled by its caller."
);

// ---------------------------------------------------------------------------------------------------------------
// errors and the FFI guard

pub(crate) fn engine_err(e: Error) -> PyErr {
    match e {
        Error::Cancelled => Cancelled::new_err("cancelled"),
        other => EngineError::new_err(other.to_string()),
    }
}

pub(crate) fn input_err(msg: impl Into<String>) -> PyErr {
    EngineError::new_err(format!("invalid input: {}", msg.into()))
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
            Err(EngineError::new_err(format!(
                "internal engine error: {what}"
            )))
        }
    }
}

/// A Python progress callback `progress(fraction) -> bool` as the engine's `Fn(f64) -> bool`: the GIL is taken
/// again only when the fraction has moved by a percent; returning False cancels, and an exception raised by the
/// callback cancels too and is re-raised by [`Progress::finish`].
pub(crate) struct Progress {
    callback: Option<Py<PyAny>>,
    error: Mutex<Option<PyErr>>,
    last: Mutex<f64>,
}

impl Progress {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Self {
        Progress {
            callback,
            error: Mutex::new(None),
            last: Mutex::new(f64::NEG_INFINITY),
        }
    }

    pub(crate) fn report(&self, fraction: f64) -> bool {
        let Some(cb) = self.callback.as_ref() else {
            return true;
        };
        if let Ok(mut last) = self.last.lock() {
            if fraction < 1.0 && fraction - *last < 0.01 {
                return true;
            }
            *last = fraction;
        }
        Python::attach(|py| match cb.call1(py, (fraction,)) {
            Ok(r) => r.extract::<bool>(py).unwrap_or(true),
            Err(e) => {
                if let Ok(mut slot) = self.error.lock() {
                    *slot = Some(e);
                }
                false
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
    let progress = Progress::new(progress);
    let result = py.detach(|| guarded(|| f(&|x| progress.report(x))));
    progress.finish(result)
}

#[pymodule]
fn worldpaint_engine(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "PALETTE_FORMAT_VERSION",
        worldpaint_core::palette::PALETTE_FORMAT_VERSION,
    )?;
    m.add("EngineError", py.get_type::<EngineError>())?;
    m.add("Cancelled", py.get_type::<Cancelled>())?;
    m.add_class::<terrain::Terrain>()?;
    m.add_class::<scene::PyScene>()?;
    colors::register(m)?;
    regions::register(m)?;
    exemplars::register(m)?;
    tools::register(m)?;
    village::register(m)?;
    terrain_edit::register(m)?;
    waterfall::register(m)?;
    Ok(())
}

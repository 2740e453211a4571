//! Python bindings of the worldpaint engine, module `worldpaint_engine`.
//!
//! Thin by design: numpy arrays and plain Python values are turned into `worldpaint_core` types, the engine runs
//! with the GIL released, and the results come back as numpy arrays. Colors and palettes cross the boundary as their
//! versioned JSON. Engine errors become `worldpaint_engine.EngineError` (a `ValueError`) carrying the engine's
//! message; a cancelled synthesis raises `worldpaint_engine.Cancelled`. No algorithm lives here, and no panic
//! crosses into Python: an internal failure is reported as an `EngineError` too.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex};

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::geom::DVec2;
use worldpaint_core::palette::{Interaction, Palette};
use worldpaint_core::{
    AnalysisOptions, Category, CategoryKind, Color, Error, Heightfield, Instance, Region, Scene,
    SynthesisOptions,
};

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

fn engine_err(e: Error) -> PyErr {
    match e {
        Error::Cancelled => Cancelled::new_err("cancelled"),
        other => EngineError::new_err(other.to_string()),
    }
}

fn input_err(msg: impl Into<String>) -> PyErr {
    EngineError::new_err(format!("invalid input: {}", msg.into()))
}

/// Runs engine code so that neither an error nor a panic escapes as anything but a Python exception.
fn guarded<T>(f: impl FnOnce() -> worldpaint_core::Result<T>) -> PyResult<T> {
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

// ---------------------------------------------------------------------------------------------------------------
// plain Python values -> core types

fn field<'py>(obj: &Bound<'py, PyAny>, key: &str, what: &str) -> PyResult<Bound<'py, PyAny>> {
    obj.get_item(key)
        .map_err(|_| input_err(format!("{what} is missing the key '{key}'")))
}

fn vec2(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec2> {
    let v: Vec<f64> = obj
        .extract()
        .map_err(|_| input_err(format!("{what} must be a pair of numbers")))?;
    match v.as_slice() {
        [x, y] => Ok(DVec2::new(*x, *y)),
        _ => Err(input_err(format!(
            "{what} must have 2 coordinates, got {}",
            v.len()
        ))),
    }
}

/// `{"shape": "rect", "min": [x, y], "max": [x, y]}`, `{"shape": "circle", "center": [x, y], "radius": r}`,
/// `{"shape": "polygon", "points": [[x, y], ...]}` or `{"shape": "clipped", "within": [region, ...],
/// "without": [region, ...]}`.
fn region_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Region> {
    let shape: String = field(obj, "shape", "region")?
        .extract()
        .map_err(|_| input_err("region 'shape' must be a string"))?;
    let region = match shape.as_str() {
        "rect" => Region::Rect {
            min: vec2(&field(obj, "min", "rect region")?, "region 'min'")?,
            max: vec2(&field(obj, "max", "rect region")?, "region 'max'")?,
        },
        "circle" => Region::Circle {
            center: vec2(&field(obj, "center", "circle region")?, "region 'center'")?,
            radius: field(obj, "radius", "circle region")?
                .extract()
                .map_err(|_| input_err("region 'radius' must be a number"))?,
        },
        "polygon" => {
            let pts = field(obj, "points", "polygon region")?;
            let mut points = Vec::new();
            for p in pts
                .try_iter()
                .map_err(|_| input_err("region 'points' must be a list of pairs"))?
            {
                points.push(vec2(&p?, "a polygon point")?);
            }
            Region::Polygon { points }
        }
        "clipped" => {
            let parts = |key: &str| -> PyResult<Vec<Region>> {
                let mut out = Vec::new();
                let list = match obj.get_item(key) {
                    Ok(v) if !v.is_none() => v,
                    _ => return Ok(out),
                };
                for r in list
                    .try_iter()
                    .map_err(|_| input_err(format!("region '{key}' must be a list of regions")))?
                {
                    out.push(region_from_py(&r?)?);
                }
                Ok(out)
            };
            Region::Clipped {
                within: parts("within")?,
                without: parts("without")?,
            }
        }
        other => {
            return Err(input_err(format!(
                "unknown region shape '{other}' (rect, circle, polygon or clipped)"
            )))
        }
    };
    region.validate().map_err(engine_err)?;
    Ok(region)
}

fn region_to_py<'py>(py: Python<'py>, region: &Region) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    match region {
        Region::Rect { min, max } => {
            d.set_item("shape", "rect")?;
            d.set_item("min", [min.x, min.y])?;
            d.set_item("max", [max.x, max.y])?;
        }
        Region::Circle { center, radius } => {
            d.set_item("shape", "circle")?;
            d.set_item("center", [center.x, center.y])?;
            d.set_item("radius", *radius)?;
        }
        Region::Polygon { points } => {
            d.set_item("shape", "polygon")?;
            d.set_item(
                "points",
                points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
            )?;
        }
        Region::Clipped { within, without } => {
            d.set_item("shape", "clipped")?;
            for (key, parts) in [("within", within), ("without", without)] {
                let list = PyList::empty(py);
                for r in parts {
                    list.append(region_to_py(py, r)?)?;
                }
                d.set_item(key, list)?;
            }
        }
    }
    Ok(d)
}

fn kind_from_str(s: &str) -> PyResult<CategoryKind> {
    match s.to_ascii_lowercase().as_str() {
        "distribution" => Ok(CategoryKind::Distribution),
        "graph" => Ok(CategoryKind::Graph),
        "polygon" => Ok(CategoryKind::Polygon),
        "external" => Ok(CategoryKind::External),
        other => Err(input_err(format!(
            "unknown category kind '{other}' (distribution, graph, polygon or external)"
        ))),
    }
}

fn kind_to_str(k: CategoryKind) -> &'static str {
    match k {
        CategoryKind::Distribution => "distribution",
        CategoryKind::Graph => "graph",
        CategoryKind::Polygon => "polygon",
        CategoryKind::External => "external",
    }
}

/// A list of `{"name", "layer", "kind", "priority"}` dicts; layer, kind and priority are optional.
fn categories_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Category>> {
    let mut out = Vec::new();
    for (i, item) in obj
        .try_iter()
        .map_err(|_| input_err("categories must be a list of dicts"))?
        .enumerate()
    {
        let item = item?;
        let what = format!("category {i}");
        let name: String = field(&item, "name", &what)?
            .extract()
            .map_err(|_| input_err(format!("{what}: 'name' must be a string")))?;
        let layer: String = match item.get_item("layer") {
            Ok(v) if !v.is_none() => v
                .extract()
                .map_err(|_| input_err(format!("{what}: 'layer' must be a string")))?,
            _ => "default".to_string(),
        };
        let kind = match item.get_item("kind") {
            Ok(v) if !v.is_none() => {
                let s: String = v
                    .extract()
                    .map_err(|_| input_err(format!("{what}: 'kind' must be a string")))?;
                kind_from_str(&s)?
            }
            _ => CategoryKind::Distribution,
        };
        let priority: i32 = match item.get_item("priority") {
            Ok(v) if !v.is_none() => v
                .extract()
                .map_err(|_| input_err(format!("{what}: 'priority' must be an integer")))?,
            _ => i as i32,
        };
        out.push(Category {
            name,
            layer,
            kind,
            priority,
        });
    }
    Ok(out)
}

fn categories_to_py<'py>(py: Python<'py>, cats: &[Category]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for c in cats {
        let d = PyDict::new(py);
        d.set_item("name", &c.name)?;
        d.set_item("layer", &c.layer)?;
        d.set_item("kind", kind_to_str(c.kind))?;
        d.set_item("priority", c.priority)?;
        list.append(d)?;
    }
    Ok(list)
}

fn points_from_py(xy: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<DVec2>> {
    let a = xy.as_array();
    if a.ncols() != 2 {
        return Err(input_err(format!(
            "{what} must have shape (N, 2), got (N, {})",
            a.ncols()
        )));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| DVec2::new(r[0], r[1]))
        .collect())
}

fn points_to_py<'py>(py: Python<'py>, pts: &[DVec2]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    // the shape always matches the data, so this cannot fail
    Array2::from_shape_vec((pts.len(), 2), flat)
        .unwrap_or_else(|_| Array2::zeros((0, 2)))
        .into_pyarray(py)
}

fn column<T: Copy + numpy::Element>(
    a: Option<PyReadonlyArray1<'_, T>>,
    n: usize,
    default: T,
    what: &str,
) -> PyResult<Vec<T>> {
    match a {
        None => Ok(vec![default; n]),
        Some(a) => {
            let v: Vec<T> = a.as_array().iter().copied().collect();
            if v.len() != n {
                return Err(input_err(format!(
                    "{what} has {} entries but there are {n} positions",
                    v.len()
                )));
            }
            Ok(v)
        }
    }
}

/// The scene the engine works on: the category list, the instance arrays (one row per instance, checked against
/// the categories) and the terrain.
fn scene_from_py(
    terrain: &Option<Py<Terrain>>,
    categories: &Bound<'_, PyAny>,
    positions: &PyReadonlyArray2<'_, f64>,
    category_index: PyReadonlyArray1<'_, i32>,
    rotations: Option<PyReadonlyArray1<'_, f64>>,
    scales: Option<PyReadonlyArray1<'_, f64>>,
    prototype: Option<PyReadonlyArray1<'_, i32>>,
) -> PyResult<Scene> {
    let categories = categories_from_py(categories)?;
    let n_categories = categories.len();
    let pos = points_from_py(positions, "positions")?;
    let n = pos.len();
    let cat = column(Some(category_index), n, 0, "category_index")?;
    let rot = column(rotations, n, 0.0, "rotations")?;
    let sca = column(scales, n, 1.0, "scales")?;
    let pro = column(prototype, n, 0, "prototype")?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let c = cat[i];
        if c < 0 || c as usize >= n_categories {
            return Err(input_err(format!(
                "instance {i} has category index {c} but there are {n_categories} categories"
            )));
        }
        if !pos[i].is_finite() {
            return Err(input_err(format!("instance {i} has a non-finite position")));
        }
        out.push(Instance {
            position: pos[i],
            rotation: rot[i],
            scale: sca[i],
            category: c as usize,
            prototype: pro[i].max(0) as u32,
            locked: false,
        });
    }
    Ok(Scene {
        categories,
        instances: out,
        terrain: terrain_of(terrain).cloned(),
    })
}

/// The instance columns of a result as a dict of numpy arrays.
fn instances_to_py<'py>(
    py: Python<'py>,
    d: &Bound<'py, PyDict>,
    instances: &[Instance],
    terrain: Option<&Heightfield>,
) -> PyResult<()> {
    let pos: Vec<DVec2> = instances.iter().map(|i| i.position).collect();
    d.set_item("positions", points_to_py(py, &pos))?;
    let heights: Vec<f64> = pos
        .iter()
        .map(|p| terrain.and_then(|t| t.height_at(*p)).unwrap_or(f64::NAN))
        .collect();
    d.set_item("heights", Array1::from(heights).into_pyarray(py))?;
    d.set_item(
        "rotations",
        instances
            .iter()
            .map(|i| i.rotation)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "scales",
        instances
            .iter()
            .map(|i| i.scale)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "category_index",
        instances
            .iter()
            .map(|i| i.category as i32)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "prototype",
        instances
            .iter()
            .map(|i| i.prototype as i32)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    Ok(())
}

fn parse_color(json: &str) -> PyResult<Color> {
    guarded(|| Color::from_json(json))
}

// ---------------------------------------------------------------------------------------------------------------
// Terrain

/// The terrain as a heightfield with named maps ("elevation", "slope" in radians, ...).
///
/// `Terrain(vertices, triangles, cell=None)` rasterizes a triangle mesh given in world space (float64 (N, 3) and
/// uint32 (M, 3)); a regular grid mesh is used directly. `cell` overrides the sample spacing in metres.
#[pyclass(module = "worldpaint_engine", frozen)]
struct Terrain {
    hf: Arc<Heightfield>,
}

#[pymethods]
impl Terrain {
    #[new]
    #[pyo3(signature = (vertices, triangles, cell=None))]
    fn new(
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        triangles: PyReadonlyArray2<'_, u32>,
        cell: Option<f64>,
    ) -> PyResult<Self> {
        let v = vertices.as_array();
        let t = triangles.as_array();
        if v.ncols() != 3 {
            return Err(input_err(format!(
                "vertices must have shape (N, 3), got (N, {})",
                v.ncols()
            )));
        }
        if t.ncols() != 3 {
            return Err(input_err(format!(
                "triangles must have shape (M, 3), got (M, {})",
                t.ncols()
            )));
        }
        let verts: Vec<[f64; 3]> = v.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
        let tris: Vec<[u32; 3]> = t.rows().into_iter().map(|r| [r[0], r[1], r[2]]).collect();
        let hf = py.detach(|| guarded(|| Heightfield::from_mesh(&verts, &tris, cell)))?;
        Ok(Terrain { hf: hf.into() })
    }

    /// A terrain from a regular grid of heights, shape (ny, nx), sample (i, j) at origin + (i, j) * cell.
    #[staticmethod]
    fn from_grid(
        origin: (f64, f64),
        cell: f64,
        heights: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        let a = heights.as_array();
        let (ny, nx) = a.dim();
        let h: Vec<f32> = a.iter().map(|&z| z as f32).collect();
        let hf = guarded(|| Heightfield::new(DVec2::new(origin.0, origin.1), cell, nx, ny, h))?;
        Ok(Terrain { hf: hf.into() })
    }

    /// Terrain heights at world XY points (float64 (N, 2)); NaN outside the terrain.
    fn heights_at<'py>(
        &self,
        py: Python<'py>,
        xy: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let pts = points_from_py(&xy, "xy")?;
        let hf = &self.hf;
        let out: Vec<f64> = py.detach(|| {
            pts.iter()
                .map(|p| hf.height_at(*p).unwrap_or(f64::NAN))
                .collect()
        });
        Ok(out.into_pyarray(py))
    }

    /// Values of the named map ("elevation", "slope", ...) at world XY points; NaN outside the terrain.
    fn map_at<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        xy: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if !self.hf.maps.contains_key(name) {
            let known: Vec<&str> = self.hf.maps.keys().map(|k| k.as_str()).collect();
            return Err(input_err(format!(
                "the terrain has no map '{name}' (it has {})",
                known.join(", ")
            )));
        }
        let pts = points_from_py(&xy, "xy")?;
        let hf = &self.hf;
        let out: Vec<f64> = py.detach(|| {
            pts.iter()
                .map(|p| hf.map_at(name, *p).unwrap_or(f64::NAN))
                .collect()
        });
        Ok(out.into_pyarray(py))
    }

    /// ((xmin, ymin), (xmax, ymax)) of the terrain in world XY.
    fn bbox(&self) -> ((f64, f64), (f64, f64)) {
        let (a, b) = self.hf.bbox();
        ((a.x, a.y), (b.x, b.y))
    }

    /// Names of the terrain's scalar maps.
    fn map_names(&self) -> Vec<String> {
        self.hf.maps.keys().cloned().collect()
    }

    /// The heightfield grid: {"origin": (x, y), "cell": c, "nx": nx, "ny": ny, "heights": float32 (ny, nx)}.
    fn grid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("origin", (self.hf.origin.x, self.hf.origin.y))?;
        d.set_item("cell", self.hf.cell)?;
        d.set_item("nx", self.hf.nx)?;
        d.set_item("ny", self.hf.ny)?;
        let h = Array2::from_shape_vec((self.hf.ny, self.hf.nx), self.hf.heights.clone())
            .map_err(|e| input_err(format!("heightfield of inconsistent size: {e}")))?;
        d.set_item("heights", h.into_pyarray(py))?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let (a, b) = self.hf.bbox();
        format!(
            "Terrain({}x{} samples, cell {} m, x {:.1}..{:.1}, y {:.1}..{:.1})",
            self.hf.nx, self.hf.ny, self.hf.cell, a.x, b.x, a.y, b.y
        )
    }
}

fn terrain_of(t: &Option<Py<Terrain>>) -> Option<&Arc<Heightfield>> {
    t.as_ref().map(|t| &t.get().hf)
}

// ---------------------------------------------------------------------------------------------------------------
// learning, synthesis, comparison

fn analysis_options(options: Option<&Bound<'_, PyAny>>) -> PyResult<AnalysisOptions> {
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

/// Learn a color (returned as JSON) from the instances inside `region`.
///
/// `categories` is a list of {"name", "layer", "kind", "priority"} dicts; `positions` float64 (N, 2) world XY,
/// `category_index` int32 (N) into `categories`; optional `rotations` (radians about Z), `scales`, `prototype`.
/// `options`: {"bin_width", "max_radius", "oriented": [(a, b), ...], "maps": [...]}, all optional.
#[pyfunction]
#[pyo3(signature = (terrain, categories, positions, category_index, region, name, *, rotations=None, scales=None,
                    prototype=None, options=None))]
#[allow(clippy::too_many_arguments)]
fn learn_color(
    py: Python<'_>,
    terrain: Option<Py<Terrain>>,
    categories: &Bound<'_, PyAny>,
    positions: PyReadonlyArray2<'_, f64>,
    category_index: PyReadonlyArray1<'_, i32>,
    region: &Bound<'_, PyAny>,
    name: &str,
    rotations: Option<PyReadonlyArray1<'_, f64>>,
    scales: Option<PyReadonlyArray1<'_, f64>>,
    prototype: Option<PyReadonlyArray1<'_, i32>>,
    options: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let scene = scene_from_py(
        &terrain,
        categories,
        &positions,
        category_index,
        rotations,
        scales,
        prototype,
    )?;
    let region = region_from_py(region)?;
    let opts = analysis_options(options)?;
    let name = name.to_string();
    py.detach(|| guarded(|| worldpaint_core::learn_color(&scene, &region, &name, &opts)?.to_json()))
}

/// Synthesize `color` (JSON) inside `region`, conditioned on the given existing instances: those inside the region
/// are replaced, those around it form the region of influence.
///
/// Returns {"categories": [...], "positions": float64 (N, 2), "heights": float64 (N) (terrain height, NaN without
/// terrain), "rotations", "scales", "category_index": int32, "prototype": int32} for the *new* instances; category
/// indices refer to the returned category list (the given ones, then the color's new ones).
/// `progress(fraction) -> bool` may return False to cancel (raises `Cancelled`).
#[pyfunction]
#[pyo3(signature = (terrain, categories, positions, category_index, color, region, seed=0, *, rotations=None,
                    scales=None, prototype=None, influence_radius=None, iterations_per_instance=None,
                    only_categories=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn synthesize<'py>(
    py: Python<'py>,
    terrain: Option<Py<Terrain>>,
    categories: &Bound<'py, PyAny>,
    positions: PyReadonlyArray2<'py, f64>,
    category_index: PyReadonlyArray1<'py, i32>,
    color: &str,
    region: &Bound<'py, PyAny>,
    seed: u64,
    rotations: Option<PyReadonlyArray1<'py, f64>>,
    scales: Option<PyReadonlyArray1<'py, f64>>,
    prototype: Option<PyReadonlyArray1<'py, i32>>,
    influence_radius: Option<f64>,
    iterations_per_instance: Option<f64>,
    only_categories: Option<Vec<String>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene_from_py(
        &terrain,
        categories,
        &positions,
        category_index,
        rotations,
        scales,
        prototype,
    )?;
    let region = region_from_py(region)?;
    let color = parse_color(color)?;
    let mut opts = SynthesisOptions {
        seed,
        influence_radius,
        categories: only_categories,
        ..Default::default()
    };
    if let Some(it) = iterations_per_instance {
        opts.iterations_per_instance = it;
    }

    // The callback re-acquires the GIL only when the fraction has moved by a percent; an exception raised by it
    // cancels the synthesis and is re-raised here.
    let callback_error: Mutex<Option<PyErr>> = Mutex::new(None);
    let last_reported = Mutex::new(f64::NEG_INFINITY);
    let report = |fraction: f64| -> bool {
        let Some(cb) = progress.as_ref() else {
            return true;
        };
        if let Ok(mut last) = last_reported.lock() {
            if fraction < 1.0 && fraction - *last < 0.01 {
                return true;
            }
            *last = fraction;
        }
        Python::attach(|py| match cb.call1(py, (fraction,)) {
            Ok(r) => r.extract::<bool>(py).unwrap_or(true),
            Err(e) => {
                if let Ok(mut slot) = callback_error.lock() {
                    *slot = Some(e);
                }
                false
            }
        })
    };

    let result = py.detach(|| {
        guarded(|| {
            worldpaint_core::synthesis::synthesize_with_progress(
                &scene, &color, &region, &opts, &report,
            )
        })
    });
    if let Ok(mut slot) = callback_error.lock() {
        if let Some(e) = slot.take() {
            return Err(e);
        }
    }
    let result = result?;
    let d = PyDict::new(py);
    d.set_item("categories", categories_to_py(py, &result.categories)?)?;
    instances_to_py(py, &d, &result.instances, scene.terrain.as_deref())?;
    Ok(d)
}

/// How far `candidate` is from `reference` (both color JSON): {"density_ratio": {category: ratio},
/// "rdf_l2": [(a, b, l2), ...], "map_tv": [(category, map, tv), ...], "worst_density_error", "max_rdf_l2",
/// "max_map_tv"}.
#[pyfunction]
fn compare<'py>(py: Python<'py>, reference: &str, candidate: &str) -> PyResult<Bound<'py, PyDict>> {
    let a = parse_color(reference)?;
    let b = parse_color(candidate)?;
    let f = py.detach(|| guarded(|| Ok(worldpaint_core::compare(&a, &b))))?;
    let d = PyDict::new(py);
    let ratios = PyDict::new(py);
    for (name, r) in &f.density_ratio {
        ratios.set_item(name, *r)?;
    }
    d.set_item("density_ratio", ratios)?;
    d.set_item("rdf_l2", f.rdf_l2.clone())?;
    d.set_item("map_tv", f.map_tv.clone())?;
    d.set_item("worst_density_error", f.worst_density_error())?;
    d.set_item("max_rdf_l2", f.max_rdf_l2())?;
    d.set_item("max_map_tv", f.max_map_tv())?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------------------------
// colors and palettes

/// A palette file (versioned JSON) from a list of color JSON strings.
#[pyfunction]
fn palette_to_json(colors: Vec<String>) -> PyResult<String> {
    let colors = colors
        .iter()
        .map(|c| parse_color(c))
        .collect::<PyResult<Vec<_>>>()?;
    guarded(|| Palette { colors }.to_json())
}

/// The colors (JSON strings) of a palette file; unknown versions and malformed files raise `EngineError`.
#[pyfunction]
fn palette_from_json(text: &str) -> PyResult<Vec<String>> {
    guarded(|| {
        Palette::from_json(text)?
            .colors
            .iter()
            .map(|c| c.to_json())
            .collect()
    })
}

/// What the add-on shows of a color: {"name", "region", "region_area", "max_radius", "bin_width",
/// "categories": [{"name", "layer", "kind", "priority", "count", "density", "min_distance"}],
/// "pairs": [(category, other, kind)], "maps": [(category, map)], "preview": float64 (N, 3) (x, y relative to the
/// region's bbox min, category index), "preview_size": (w, h)}.
#[pyfunction]
fn color_summary<'py>(py: Python<'py>, color: &str) -> PyResult<Bound<'py, PyDict>> {
    let c = parse_color(color)?;
    let d = PyDict::new(py);
    d.set_item("name", &c.name)?;
    d.set_item("region", region_to_py(py, &c.region)?)?;
    d.set_item("region_area", c.region_area)?;
    d.set_item("max_radius", c.max_radius)?;
    d.set_item("bin_width", c.bin_width)?;
    let cats = PyList::empty(py);
    for cc in &c.categories {
        let e = PyDict::new(py);
        e.set_item("name", &cc.category.name)?;
        e.set_item("layer", &cc.category.layer)?;
        e.set_item("kind", kind_to_str(cc.category.kind))?;
        e.set_item("priority", cc.category.priority)?;
        e.set_item("count", cc.count)?;
        e.set_item("density", cc.density)?;
        e.set_item("min_distance", cc.min_distance)?;
        cats.append(e)?;
    }
    d.set_item("categories", cats)?;
    let pairs: Vec<(String, String, &str)> = c
        .pairs
        .iter()
        .map(|p| {
            let kind = match p.interaction {
                Interaction::Rdf { .. } => "rdf",
                Interaction::OrientedRdf { .. } => "oriented_rdf",
            };
            (p.category.clone(), p.other.clone(), kind)
        })
        .collect();
    d.set_item("pairs", pairs)?;
    d.set_item(
        "maps",
        c.maps
            .iter()
            .map(|m| (m.category.clone(), m.map.clone()))
            .collect::<Vec<_>>(),
    )?;
    let flat: Vec<f64> = c.preview.iter().flat_map(|p| *p).collect();
    let preview = Array2::from_shape_vec((c.preview.len(), 3), flat)
        .map_err(|e| input_err(format!("color preview of inconsistent size: {e}")))?;
    d.set_item("preview", preview.into_pyarray(py))?;
    let (lo, hi) = c.region.bbox();
    d.set_item("preview_size", (hi.x - lo.x, hi.y - lo.y))?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------------------------
// regions

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

// ---------------------------------------------------------------------------------------------------------------
// exemplar generators (demo scenes, asset scripts, tests)

/// Runs a point generator on a region with the GIL released: float64 (N, 2).
fn generated_points<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    generate: impl FnOnce(&Region) -> Vec<DVec2> + Send,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let region = region_from_py(region)?;
    let pts = py.detach(|| guarded(|| Ok(generate(&region))))?;
    Ok(points_to_py(py, &pts))
}

/// Points of a Poisson process of the given density (per m²) in the region: float64 (N, 2).
#[pyfunction]
fn exemplar_uniform<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    density: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::exemplar::uniform(r, density, seed)
    })
}

/// Points of a Thomas cluster process (parents per m², mean children per parent, spread sigma in m).
#[pyfunction]
fn exemplar_clustered<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    parent_density: f64,
    children_mean: f64,
    sigma: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::exemplar::clustered(r, parent_density, children_mean, sigma, seed)
    })
}

/// Points with a hard-core spacing (no pair closer than min_distance) at about the given density.
#[pyfunction]
fn exemplar_hard_core<'py>(
    py: Python<'py>,
    region: &Bound<'py, PyAny>,
    density: f64,
    min_distance: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    generated_points(py, region, |r| {
        worldpaint_core::exemplar::hard_core(r, density, min_distance, seed)
    })
}

/// The multi-category slope exemplar: {"terrain": Terrain, "categories": [...], "positions", "heights",
/// "rotations", "scales", "category_index", "prototype"}.
#[pyfunction]
fn exemplar_slope_scene<'py>(
    py: Python<'py>,
    size: f64,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = py.detach(|| guarded(|| Ok(worldpaint_core::exemplar::slope_scene(size, seed))))?;
    let d = PyDict::new(py);
    d.set_item("categories", categories_to_py(py, &scene.categories)?)?;
    instances_to_py(py, &d, &scene.instances, scene.terrain.as_deref())?;
    match scene.terrain {
        Some(hf) => d.set_item("terrain", Py::new(py, Terrain { hf })?)?,
        None => d.set_item("terrain", py.None())?,
    }
    Ok(d)
}

/// A deterministic terrain of smooth hills, size × size metres sampled every `cell` metres.
#[pyfunction]
fn exemplar_demo_terrain(py: Python<'_>, size: f64, cell: f64, seed: u64) -> PyResult<Terrain> {
    let hf =
        py.detach(|| guarded(|| Ok(worldpaint_core::exemplar::demo_terrain(size, cell, seed))))?;
    Ok(Terrain { hf: hf.into() })
}

// ---------------------------------------------------------------------------------------------------------------

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
    m.add_class::<Terrain>()?;
    m.add_function(wrap_pyfunction!(learn_color, m)?)?;
    m.add_function(wrap_pyfunction!(synthesize, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(palette_to_json, m)?)?;
    m.add_function(wrap_pyfunction!(palette_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(color_summary, m)?)?;
    m.add_function(wrap_pyfunction!(region_contains, m)?)?;
    m.add_function(wrap_pyfunction!(region_area, m)?)?;
    m.add_function(wrap_pyfunction!(region_bbox, m)?)?;
    m.add_function(wrap_pyfunction!(exemplar_uniform, m)?)?;
    m.add_function(wrap_pyfunction!(exemplar_clustered, m)?)?;
    m.add_function(wrap_pyfunction!(exemplar_hard_core, m)?)?;
    m.add_function(wrap_pyfunction!(exemplar_slope_scene, m)?)?;
    m.add_function(wrap_pyfunction!(exemplar_demo_terrain, m)?)?;
    Ok(())
}

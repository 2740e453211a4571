//! The painting tools: paste, brush strokes (paint, alpha, erase), move, stretch, gradients (linear, radial,
//! bilinear) and blur.
//!
//! Each takes a `Scene` (the terrain and the instance columns, converted once) and returns an *edit*:
//! {"categories", "removed": int64 indices of the scene's instances it removed, and the added instances' columns
//! ("positions", "heights", "rotations", "scales", "category_index", "prototype")}; the move and the stretch add
//! what they measured.

use crate::arrays::ArrayArg;
use crate::compare::fidelity_to_py;
use crate::convert::{
    edit_to_py, field, parse_color, points_from_py, points_to_py, region_from_py, region_to_py,
    vec2,
};
use crate::paint::{color_painter, synthesis_options, Painting};
use crate::scene::PyScene;
use crate::{engine_err, guarded, input_err, with_progress};
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::sync::Mutex;
use worldpaint_core::{
    bilinear_gradient as paint_bilinear, blur as blur_region, clear_region as clear, compare,
    gradient as paint_gradient, learned_back, move_region as move_content, painted_fidelity,
    paste as paste_color, stretch, AdaptOptions, BlurOptions, BrushMode, BrushOptions,
    BrushStroke as CoreStroke, DVec2, Falloff, GradientOptions, GradientShape, Scene,
    StretchOptions, StretchSide as Side, SynthesisOptions, ToolEdit as Edit,
};

fn edit_result<'py>(py: Python<'py>, edit: &Edit, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    edit_to_py(py, edit, scene.terrain.as_deref())
}

color_painter! {
    /// Paste `color` (JSON) into `region`: the unlocked instances inside it are replaced by a new arrangement
    /// consistent with its surroundings. Returns the edit, with "fidelity": what the region holds after the paste,
    /// learned back with the color's bins and maps and compared with the color (the dict `compare` returns), or
    /// None when it cannot be learned back, and "fidelity_error" then says why (the paste itself stands); for an
    /// arrangement color, "pattern": what the region holds against its reference ({"ring_share",
    /// "reference_ring_share", "interior", "elements", "count_ratio"}) instead. `progress(fraction) -> bool` may
    /// cancel.
    paste => pasted
}

fn pasted<'py>(py: Python<'py>, p: Painting<'_>) -> PyResult<Bound<'py, PyDict>> {
    if !p.color.kind.is_statistics() {
        let (edit, pattern) = with_progress(py, p.progress, |report| {
            let edit = paste_color(p.scene, &p.color, &p.region, &p.opts, report)?;
            let pattern = painted_fidelity(&edit.applied_to(p.scene), &p.region, &p.color)?;
            Ok((edit, pattern))
        })?;
        let d = edit_result(py, &edit, p.scene)?;
        d.set_item("fidelity", py.None())?;
        if let Some(f) = pattern {
            let figures = PyDict::new(py);
            figures.set_item("ring_share", f.ring_share)?;
            figures.set_item("reference_ring_share", f.reference_ring_share)?;
            figures.set_item("interior", f.interior)?;
            figures.set_item("elements", f.elements)?;
            figures.set_item("count_ratio", f.count_ratio)?;
            d.set_item("pattern", figures)?;
        }
        return Ok(d);
    }
    let (edit, fid) = with_progress(py, p.progress, |report| {
        let edit = paste_color(p.scene, &p.color, &p.region, &p.opts, report)?;
        let painted = learned_back(&edit.applied_to(p.scene), &p.region, &p.color);
        Ok((edit, painted.map(|c| compare(&p.color, &c))))
    })?;
    let d = edit_result(py, &edit, p.scene)?;
    match fid {
        Ok(f) => d.set_item("fidelity", fidelity_to_py(py, &f)?)?,
        Err(e) => {
            d.set_item("fidelity", py.None())?;
            d.set_item("fidelity_error", e.to_string())?;
        }
    }
    Ok(d)
}

/// Clear `region`: its unlocked content (instances, and the parts of paths and contours in it) is removed, of every
/// category or only of `category`. Returns the edit.
#[pyfunction]
#[pyo3(signature = (scene, region, *, category=None))]
pub(crate) fn clear_region<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    region: &Bound<'py, PyAny>,
    category: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let edit = py.detach(|| guarded(|| clear(scene, &region, category.as_deref())))?;
    edit_result(py, &edit, scene)
}

fn falloff_from_str(s: &str) -> PyResult<Falloff> {
    match s.to_ascii_lowercase().as_str() {
        "constant" => Ok(Falloff::Constant),
        "linear" => Ok(Falloff::Linear),
        "smooth" => Ok(Falloff::Smooth),
        other => Err(input_err(format!(
            "unknown falloff '{other}' (constant, linear or smooth)"
        ))),
    }
}

/// One brush stroke over a scene. `Stroke(scene, *, color=None, erase=False, only_categories=None, radius=20.0,
/// spacing=0.5, opacity=1.0, falloff="constant", seed=0, influence_radius=None, iterations_per_instance=None,
/// guides=None, shortest_edges=None)` paints `color` (JSON), or with `erase=True` removes unlocked instances (of
/// `only_categories`, all when None) within `radius` of the path, and cuts the roads, rivers and coasts of the road
/// or coast categories named there, removing the pieces shorter than `shortest_edges[category]` (m; by default the
/// category's shortest edge in the scene).
///
/// `follow(path, progress=None)` moves the brush along float64 (N, 2) points (a dab every `spacing × radius`, the
/// first at once) with the GIL released and returns the number of dabs; `edit()` is what the stroke has done so far
/// to the scene it started on; `dabs()` the dab centres. Other threads may call `edit()` while `follow` runs.
#[pyclass(module = "worldpaint_engine", frozen)]
pub(crate) struct Stroke {
    stroke: Mutex<CoreStroke>,
}

#[pymethods]
impl Stroke {
    #[new]
    #[pyo3(signature = (scene, *, color=None, erase=false, only_categories=None, radius=20.0,
                        spacing=0.5, opacity=1.0, falloff="constant", seed=0, influence_radius=None,
                        iterations_per_instance=None, guides=None, shortest_edges=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        scene: &Bound<'_, PyScene>,
        color: Option<&str>,
        erase: bool,
        only_categories: Option<Vec<String>>,
        radius: f64,
        spacing: f64,
        opacity: f64,
        falloff: &str,
        seed: u64,
        influence_radius: Option<f64>,
        iterations_per_instance: Option<f64>,
        guides: Option<&Bound<'_, PyAny>>,
        shortest_edges: Option<HashMap<String, f64>>,
    ) -> PyResult<Self> {
        let scene = scene.get().scene();
        let mode = match (erase, color) {
            (true, _) => BrushMode::Erase(only_categories),
            (false, Some(c)) => BrushMode::Paint(Box::new(parse_color(c)?)),
            (false, None) => return Err(input_err("a painting stroke needs a color")),
        };
        let opts = BrushOptions {
            radius,
            spacing,
            opacity,
            falloff: falloff_from_str(falloff)?,
            synthesis: SynthesisOptions {
                guides: crate::arrangement::guides_from_py(guides)?,
                ..synthesis_options(seed, influence_radius, iterations_per_instance, None)
            },
        };
        let mut stroke = CoreStroke::new(scene, mode, opts).map_err(engine_err)?;
        for (category, length) in shortest_edges.unwrap_or_default() {
            stroke
                .set_shortest_edge(&category, length)
                .map_err(engine_err)?;
        }
        Ok(Stroke {
            stroke: Mutex::new(stroke),
        })
    }

    #[pyo3(signature = (path, progress=None))]
    fn follow(
        &self,
        py: Python<'_>,
        path: ArrayArg<'_>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<usize> {
        let path = points_from_py(&path, "path")?;
        with_progress(py, progress, |report| {
            let mut stroke = self
                .stroke
                .lock()
                .map_err(|_| worldpaint_core::Error::invalid("the stroke", "failed earlier"))?;
            stroke.follow(&path, report)
        })
    }

    fn edit<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (edit, terrain) = py.detach(|| {
            self.stroke
                .lock()
                .map(|s| (s.edit(), s.scene().terrain.clone()))
                .map_err(|_| input_err("the stroke failed earlier"))
        })?;
        edit_to_py(py, &edit, terrain.as_deref())
    }

    fn dabs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let dabs = py.detach(|| {
            self.stroke
                .lock()
                .map(|s| s.dabs().to_vec())
                .map_err(|_| input_err("the stroke failed earlier"))
        })?;
        Ok(points_to_py(py, &dabs))
    }
}

/// Move the unlocked content of `source` by `offset` (x, y), adapting it to its new place with the statistics of
/// `color` (JSON; None: those of the moved content), an arrangement's elements rigidly; the content it lands on is
/// replaced. Returns the edit with "moved", "displaced", "reborn" and
/// "lost" counts.
#[pyfunction]
#[pyo3(signature = (scene, color, source, offset, seed=0, *,
                    influence_radius=None, steps=None,
                    reach=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn move_region<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    color: Option<&str>,
    source: &Bound<'py, PyAny>,
    offset: (f64, f64),
    seed: u64,
    influence_radius: Option<f64>,
    steps: Option<usize>,
    reach: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().scene();
    let source = region_from_py(source)?;
    let color = color.map(parse_color).transpose()?;
    let mut opts = AdaptOptions {
        seed,
        influence_radius,
        reach,
        ..Default::default()
    };
    if let Some(s) = steps {
        opts.steps = s;
    }
    let offset = DVec2::new(offset.0, offset.1);
    let moved = with_progress(py, None, |_| {
        move_content(scene, color.as_ref(), &source, offset, &opts)
    })?;
    let d = edit_result(py, &moved.edit, scene)?;
    d.set_item("moved", moved.moved)?;
    d.set_item("displaced", moved.displaced)?;
    d.set_item("reborn", moved.reborn)?;
    d.set_item("lost", moved.lost)?;
    d.set_item("stayed", moved.stayed)?;
    Ok(d)
}

/// Stretch (`amount` > 0, metres) or shrink (< 0) the rectangle `region` by dragging its `side` ("east", "west",
/// "north" or "south") with a seam-carving cut. `color` (JSON) fills the opened band and adapts the moved side;
/// None learns it from the region. Returns the edit with "seam" float64 (N, 2), "band", "region" (the resized
/// rectangle) and "pushed_off" (the instances beyond the cut it would have pushed off the terrain, not moved).
#[pyfunction]
#[pyo3(signature = (scene, region, side, amount, color=None, seed=0, *,
                    influence_radius=None,
                    iterations_per_instance=None, cell=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn stretch_region<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    region: &Bound<'py, PyAny>,
    side: &str,
    amount: f64,
    color: Option<&str>,
    seed: u64,
    influence_radius: Option<f64>,
    iterations_per_instance: Option<f64>,
    cell: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let side = match side.to_ascii_lowercase().as_str() {
        "east" => Side::East,
        "west" => Side::West,
        "north" => Side::North,
        "south" => Side::South,
        other => {
            return Err(input_err(format!(
                "unknown side '{other}' (east, west, north or south)"
            )))
        }
    };
    let color = color.map(parse_color).transpose()?;
    let synthesis = synthesis_options(seed, influence_radius, iterations_per_instance, None);
    let opts = StretchOptions {
        cell,
        adapt: AdaptOptions {
            seed,
            influence_radius,
            ..Default::default()
        },
        synthesis,
    };
    let out = with_progress(py, progress, |report| {
        stretch(scene, &region, side, amount, color.as_ref(), &opts, report)
    })?;
    let d = edit_result(py, &out.edit, scene)?;
    d.set_item("seam", points_to_py(py, &out.seam))?;
    d.set_item("band", region_to_py(py, &out.band)?)?;
    d.set_item("region", region_to_py(py, &out.region)?)?;
    d.set_item("pushed_off", out.pushed_off)?;
    Ok(d)
}

/// The shape of a gradient: along a line or about a centre between two colors, or over the region's box between
/// four.
enum Shape {
    Along(GradientShape),
    /// The colors (JSON) at the north-west and north-east corners; the two others take the south ones.
    Bilinear(String, String),
}

/// `{"kind": "linear", "from": (x, y), "to": (x, y)}`, `{"kind": "radial", "center": (x, y), "radius": r}` or
/// `{"kind": "bilinear", "north_west": color, "north_east": color}`.
fn gradient_shape(obj: &Bound<'_, PyAny>) -> PyResult<Shape> {
    let kind: String = field(obj, "kind", "gradient shape")?
        .extract()
        .map_err(|_| input_err("gradient 'kind' must be a string"))?;
    let color = |key: &str| -> PyResult<String> {
        field(obj, key, "bilinear gradient")?
            .extract()
            .map_err(|_| input_err(format!("gradient '{key}' must be a color (JSON)")))
    };
    match kind.as_str() {
        "linear" => Ok(Shape::Along(GradientShape::Linear {
            from: vec2(&field(obj, "from", "linear gradient")?, "gradient 'from'")?,
            to: vec2(&field(obj, "to", "linear gradient")?, "gradient 'to'")?,
        })),
        "radial" => Ok(Shape::Along(GradientShape::Radial {
            center: vec2(
                &field(obj, "center", "radial gradient")?,
                "gradient 'center'",
            )?,
            radius: field(obj, "radius", "radial gradient")?
                .extract()
                .map_err(|_| input_err("gradient 'radius' must be a number"))?,
        })),
        "bilinear" => Ok(Shape::Bilinear(color("north_west")?, color("north_east")?)),
        other => Err(input_err(format!(
            "unknown gradient kind '{other}' (linear, radial or bilinear)"
        ))),
    }
}

/// Paint a gradient from color `start` to color `end` (JSON) over `region`, along `shape` (see `gradient_shape`),
/// in `bands` bands (None: adapted to the region); a bilinear shape puts `start`, `end` and its two colors at the
/// corners of the region's box (south-west, south-east, north-west, north-east) in `bands` × `bands` cells.
/// Returns the edit.
#[pyfunction]
#[pyo3(signature = (scene, start, end, region, shape, bands=None, seed=0,
                    *, influence_radius=None,
                    iterations_per_instance=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn gradient<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    start: &str,
    end: &str,
    region: &Bound<'py, PyAny>,
    shape: &Bound<'py, PyAny>,
    bands: Option<usize>,
    seed: u64,
    influence_radius: Option<f64>,
    iterations_per_instance: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().scene();
    let (start, end) = (parse_color(start)?, parse_color(end)?);
    let region = region_from_py(region)?;
    let shape = gradient_shape(shape)?;
    let opts = GradientOptions {
        bands,
        synthesis: synthesis_options(seed, influence_radius, iterations_per_instance, None),
    };
    let edit = match shape {
        Shape::Along(shape) => with_progress(py, progress, |report| {
            paint_gradient(scene, &start, &end, &region, shape, &opts, report)
        })?,
        Shape::Bilinear(north_west, north_east) => {
            let (nw, ne) = (parse_color(&north_west)?, parse_color(&north_east)?);
            with_progress(py, progress, |report| {
                paint_bilinear(scene, [&start, &end, &nw, &ne], &region, &opts, report)
            })?
        }
    };
    edit_result(py, &edit, scene)
}

/// Blur the content of `region` into the colors around it (`windows` analyses around it, `cells` × `cells`
/// interpolated colors inside). Returns the edit.
#[pyfunction]
#[pyo3(signature = (scene, region, seed=0, *, windows=8, cells=4, influence_radius=None,
                    iterations_per_instance=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn blur<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    region: &Bound<'py, PyAny>,
    seed: u64,
    windows: usize,
    cells: usize,
    influence_radius: Option<f64>,
    iterations_per_instance: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let opts = BlurOptions {
        windows,
        cells,
        synthesis: synthesis_options(seed, influence_radius, iterations_per_instance, None),
    };
    let edit = with_progress(py, progress, |report| {
        blur_region(scene, &region, &opts, report)
    })?;
    edit_result(py, &edit, scene)
}

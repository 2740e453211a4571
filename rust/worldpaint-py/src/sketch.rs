//! Sketch-based terrain editing: `apply_sketch`.

use crate::arrays::ArrayArg;
use crate::convert::{field, height_change, points_from_py, rows_to_py};
use crate::terrain::Terrain;
use crate::{input_err, with_progress};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyTuple};
use worldpaint_core::{
    apply_sketch as apply, Camera, CurveSource, DVec2, DVec3, FeatureKind, SketchEdit,
    SketchOptions, SketchStroke,
};

fn triple(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v: Vec<f64> = obj
        .extract()
        .map_err(|_| input_err(format!("{what} must be three numbers")))?;
    match v.as_slice() {
        [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(input_err(format!(
            "{what} must have 3 coordinates, got {}",
            v.len()
        ))),
    }
}

fn pair(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec2> {
    crate::convert::vec2(obj, what)
}

/// `{"eye": [x, y, z], "forward": [...], "up": [...], "frame_min": [x, y], "frame_max": [x, y]}`: the camera's
/// eye, viewing direction and image up, and its frame on the plane one metre ahead (Blender's `view_frame` divided
/// by its depth).
fn camera_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Camera> {
    let what = "the camera";
    Camera::new(
        triple(&field(obj, "eye", what)?, "camera eye")?,
        triple(&field(obj, "forward", what)?, "camera forward")?,
        triple(&field(obj, "up", what)?, "camera up")?,
        pair(&field(obj, "frame_min", what)?, "camera frame_min")?,
        pair(&field(obj, "frame_max", what)?, "camera frame_max")?,
    )
    .map_err(crate::engine_err)
}

/// Refuses a stroke given as a list whose point is a boolean where a number belongs (numpy would read `True` as
/// 1.0), naming the stroke and the point.
fn refuse_booleans(stroke: &Bound<'_, PyAny>, i: usize) -> PyResult<()> {
    let is_list =
        |o: &Bound<'_, PyAny>| o.is_instance_of::<PyList>() || o.is_instance_of::<PyTuple>();
    if !is_list(stroke) {
        return Ok(());
    }
    for (j, point) in stroke.try_iter()?.enumerate() {
        let point = point?;
        if point.is_instance_of::<PyBool>() {
            return Err(input_err(format!(
                "stroke {i}, point {j}: a point is two numbers (x, y), got a boolean"
            )));
        }
        if is_list(&point) {
            for value in point.try_iter()? {
                if value?.is_instance_of::<PyBool>() {
                    return Err(input_err(format!(
                        "stroke {i}, point {j}: x and y must be numbers, got a boolean"
                    )));
                }
            }
        }
    }
    Ok(())
}

fn strokes_from_py(list: &Bound<'_, PyAny>) -> PyResult<Vec<SketchStroke>> {
    let items = list
        .try_iter()
        .map_err(|_| input_err("strokes must be a list of (N, 2) arrays"))?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        let item = item?;
        refuse_booleans(&item, i)?;
        let a = ArrayArg::from(item);
        out.push(SketchStroke {
            points: points_from_py(&a, &format!("stroke {i}"))?,
        });
    }
    Ok(out)
}

/// Deforms the terrain so that, seen from `camera`, its silhouettes follow the `strokes` (float64 (N, 2) arrays of
/// camera-frame points, 0–1 in x and y) and nothing hides them (thesis ch. 5). `reach`: distance (m) beyond which the
/// terrain stays as it was (None: eight times the largest height change, at most half the distance from the eye to the
/// nearest silhouette); `completion`: extend the silhouettes to the ground; `aspect`: the frame's width over its
/// height, with which the stroke ordering measures distances alike across and up the image (None: the camera frame's);
/// `max_change`: the largest height change (m) the sketch may ask for or make (None: the terrain's relief, at least a
/// quarter of its shorter side); `max_camera_distance`: how far (m) the eye may be from the terrain (None: its
/// diagonal). Strokes out of the frame, a camera under the ground, too far, seeing no terrain or wider than a Blender
/// camera, and a larger change are refused with the figure (`InputError`).
/// Returns a dict: "displacement" (the height change at the world XY `points`, float64 (M,)), "order" (stroke indices
/// front to back), "features" (float64 (K, 3) polylines) and "feature_kinds" ("silhouette" / "ridge"), "curves" (per
/// stroke its float64 (K, 3) curve), "sources" (per stroke the feature index it deforms, or -1 when it was embedded),
/// "lowered" (the protruding silhouettes as lowered), "rounds", "hidden_columns", "reach", "junctions" and "seconds"
/// (per step: ordering, features, matching, deformation, lowering). `progress(fraction) -> bool` may return False to
/// cancel.
#[pyfunction]
#[pyo3(signature = (terrain, camera, strokes, points, *, reach=None, completion=true, aspect=None, max_change=None,
    max_camera_distance=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply_sketch<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    camera: &Bound<'py, PyAny>,
    strokes: &Bound<'py, PyAny>,
    points: ArrayArg<'py>,
    reach: Option<f64>,
    completion: bool,
    aspect: Option<f64>,
    max_change: Option<f64>,
    max_camera_distance: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let camera = camera_from_py(camera)?;
    let strokes = strokes_from_py(strokes)?;
    let pts = points_from_py(&points, "points")?;
    for (name, value) in [
        ("reach", reach),
        ("max_change", max_change),
        ("max_camera_distance", max_camera_distance),
    ] {
        if let Some(r) = value {
            if !(r.is_finite() && r > 0.0) {
                return Err(input_err(format!("{name} {r} must be a positive distance")));
            }
        }
    }
    let limits = (max_change, max_camera_distance);
    let options = sketch_options(&camera, reach, completion, aspect, limits)?;
    let (edit, change) = with_progress(py, progress, |report| {
        let edit = apply(&hf, &camera, &strokes, &options, report)?;
        let change = height_change(&hf, &edit.deformation.terrain, &pts);
        Ok((edit, change))
    })?;
    sketch_to_py(py, &edit, change)
}

/// Apply Sketch's options from its keyword arguments (the aspect defaults to the camera frame's).
fn sketch_options(
    camera: &Camera,
    reach: Option<f64>,
    completion: bool,
    aspect: Option<f64>,
    (max_change, max_camera_distance): (Option<f64>, Option<f64>),
) -> PyResult<SketchOptions> {
    let mut options = SketchOptions {
        completion,
        ..SketchOptions::default()
    };
    options.deform.reach = reach;
    options.limits.max_change = max_change;
    options.limits.max_camera_distance = max_camera_distance;
    options.ordering.aspect = match aspect {
        Some(a) if a.is_finite() && a > 0.0 => a,
        Some(a) => return Err(input_err(format!("aspect {a} must be a positive ratio"))),
        None => {
            let size = camera.frame_max - camera.frame_min;
            size.x / size.y
        }
    };
    Ok(options)
}

/// What [`apply_sketch`] returns, from the edit and the height change at the points asked.
fn sketch_to_py<'py>(
    py: Python<'py>,
    edit: &SketchEdit,
    change: Vec<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("displacement", change.into_pyarray(py))?;
    out.set_item("order", edit.order.front_to_back.clone())?;
    out.set_item("junctions", edit.order.junctions.len())?;
    let xyz = |p: &[DVec3]| rows_to_py(py, p.iter().map(|q| [q.x, q.y, q.z]));
    let features = PyList::empty(py);
    let kinds = PyList::empty(py);
    for f in &edit.features {
        features.append(xyz(&f.points)?)?;
        kinds.append(match f.kind {
            FeatureKind::Silhouette => "silhouette",
            FeatureKind::Ridge => "ridge",
        })?;
    }
    out.set_item("features", features)?;
    out.set_item("feature_kinds", kinds)?;
    let curves = PyList::empty(py);
    let breaks = PyList::empty(py);
    for t in &edit.targets.targets {
        curves.append(xyz(&t.curve)?)?;
        breaks.append(t.breaks.clone())?;
    }
    out.set_item("curves", curves)?;
    out.set_item("curve_breaks", breaks)?;
    let sources: Vec<i64> = edit
        .targets
        .sources
        .iter()
        .map(|s| match s {
            CurveSource::Feature(f) => *f as i64,
            CurveSource::Embedded(_) => -1,
            CurveSource::Skyline => -2,
        })
        .collect();
    out.set_item("sources", sources)?;
    let lowered = PyList::empty(py);
    for l in &edit.deformation.lowered {
        lowered.append(xyz(l)?)?;
    }
    out.set_item("lowered", lowered)?;
    out.set_item("rounds", edit.deformation.rounds)?;
    out.set_item("hidden_columns", edit.deformation.hidden_columns)?;
    out.set_item("reach", edit.deformation.reach)?;
    let s = edit.seconds;
    let seconds = PyDict::new(py);
    for (k, v) in [
        ("ordering", s.ordering),
        ("features", s.features),
        ("matching", s.matching),
        ("deformation", s.deformation),
        ("lowering", s.lowering),
    ] {
        seconds.set_item(k, v)?;
    }
    out.set_item("seconds", seconds)?;
    Ok(out)
}

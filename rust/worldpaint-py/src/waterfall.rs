//! Waterfall scenes: `build_waterfall`.

use crate::arrays::ArrayArg;
use crate::convert::{height_change, points_from_py, rows_to_py};
use crate::terrain::Terrain;
use crate::{guarded, input_err};
use numpy::ndarray::Ix2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{
    build_waterfall_scene, Color, Controller, ControllerKind, DVec2, Error, Rock, WaterPart,
    WaterfallParams, WaterfallScene, WaterfallSceneOptions, WaterfallSceneReport, WaterfallType,
};

fn controllers_from_py(list: &Bound<'_, PyAny>) -> PyResult<Vec<Controller>> {
    let items = list
        .try_iter()
        .map_err(|_| input_err("controllers must be a list of dicts"))?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        let item = item?;
        let d = item
            .cast::<PyDict>()
            .map_err(|_| input_err(format!("controller {i} must be a dict")))?;
        let kind: String = d
            .get_item("kind")?
            .ok_or_else(|| input_err(format!("controller {i} has no \"kind\"")))?
            .extract()
            .map_err(|_| input_err(format!("controller {i}: \"kind\" must be a string")))?;
        let kind = match kind.as_str() {
            "contact" => ControllerKind::Contact,
            "free_fall" => ControllerKind::FreeFall,
            "pool" => ControllerKind::Pool,
            other => {
                return Err(input_err(format!(
                    "controller {i}: kind \"{other}\" is not one of contact, free_fall, pool"
                )))
            }
        };
        let pts = d
            .get_item("points")?
            .ok_or_else(|| input_err(format!("controller {i} has no \"points\"")))?;
        let pts = ArrayArg::from(pts).read::<f64, Ix2>(&format!("controller {i}: points"), &[3])?;
        let a = pts.as_array();
        let points = a
            .rows()
            .into_iter()
            .map(|r| DVec2::new(r[0], r[1]).extend(r[2]))
            .collect();
        let strength: Option<f64> = match d.get_item("strength")? {
            Some(v) if !v.is_none() => Some(
                v.extract()
                    .map_err(|_| input_err(format!("controller {i}: strength must be a number")))?,
            ),
            _ => None,
        };
        out.push(Controller {
            kind,
            points,
            strength,
        });
    }
    Ok(out)
}

fn type_name(t: WaterfallType) -> &'static str {
    match t {
        WaterfallType::Stream => "stream",
        WaterfallType::Horsetail => "horsetail",
        WaterfallType::Cascade => "cascade",
        WaterfallType::Rapid => "rapid",
        WaterfallType::Block => "block",
        WaterfallType::River => "river",
        WaterfallType::Ribbon => "ribbon",
        WaterfallType::Plunge => "plunge",
        WaterfallType::Ledge => "ledge",
        WaterfallType::Cataract => "cataract",
    }
}

/// Builds a waterfall scene on the terrain from user controllers (list of dicts {"kind": "contact" | "free_fall" |
/// "pool", "points": float64 (N, 3), "strength": float or None}) and reports, at the world XY `points` (M, 2):
/// "displacement" (M,) height change, "horizontal" (M, 2) overhang displacement, "is_water" (M,) bool; and
/// "water" (the integration mesh: vertices, triangles, speed, foam, rocks, disturbance, invalid, part 0 contact / 1
/// free-fall / 2 pool), "segments", the rocks synthesized along the riverbeds — "rocks" (R, 3) on the deformed
/// terrain, "rock_rotation" (R,) radians about Z, "rock_scale" (R,), "rock_prototype" (R,) int32 — and "report".
/// `rock_color` is the JSON of the color the rocks are synthesized from (None: the built-in river rocks); its
/// distribution categories follow the rock map.
#[pyfunction]
#[pyo3(signature = (terrain, controllers, points, seed=0, *, min_slope=None, overhang=None, falloff=None, freeboard=None, max_width=None, subdivide=true, rock_color=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_waterfall<'py>(
    py: Python<'py>,
    terrain: &Bound<'py, Terrain>,
    controllers: &Bound<'py, PyAny>,
    points: ArrayArg<'py>,
    seed: u64,
    min_slope: Option<f64>,
    overhang: Option<f64>,
    falloff: Option<f64>,
    freeboard: Option<f64>,
    max_width: Option<f64>,
    subdivide: bool,
    rock_color: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let hf = terrain.get().hf.clone();
    let controllers = controllers_from_py(controllers)?;
    let pts = points_from_py(&points, "points")?;
    let params = WaterfallParams {
        min_slope: min_slope.unwrap_or(WaterfallParams::default().min_slope),
        subdivide,
        ..Default::default()
    };
    let deform = (overhang, falloff, freeboard);
    let options = scene_options(deform, max_width, rock_color)?;
    let (s, change, shift, wet) = py.detach(|| {
        guarded(|| {
            let s = build_waterfall_scene(&hf, &controllers, &params, &options, seed)?;
            let change = height_change(&hf, &s.terrain.terrain, &pts);
            let hd = &s.terrain.horizontal;
            let shift: Vec<[f64; 2]> = pts
                .iter()
                .map(|p| match s.maps.node(*p) {
                    Some(k) => [hd.x.displacement[k], hd.y.displacement[k]],
                    None => [0.0, 0.0],
                })
                .collect();
            let wet: Vec<bool> = pts.iter().map(|p| s.maps.is_water(*p)).collect();
            Ok((s, change, shift, wet))
        })
    })?;
    let out = PyDict::new(py);
    out.set_item("displacement", change.into_pyarray(py))?;
    out.set_item("horizontal", rows_to_py(py, shift.into_iter())?)?;
    out.set_item("is_water", wet.into_pyarray(py))?;
    out.set_item("water", water_to_py(py, &s)?)?;
    out.set_item("segments", segments_to_py(py, &s)?)?;
    rocks_into_py(&out, &s.rocks)?;
    out.set_item("report", report_to_py(py, &s.report)?)?;
    Ok(out)
}

/// The scene's options from the keyword arguments (None: the default of each).
fn scene_options(
    (overhang, falloff, freeboard): (Option<f64>, Option<f64>, Option<f64>),
    max_width: Option<f64>,
    rock_color: Option<&str>,
) -> PyResult<WaterfallSceneOptions> {
    let mut options = WaterfallSceneOptions::default();
    if let Some(v) = overhang {
        options.deform.overhang = v;
    }
    if let Some(v) = falloff {
        options.deform.falloff = v;
    }
    if let Some(v) = freeboard {
        options.deform.freeboard = v;
    }
    if let Some(v) = max_width {
        options.integration.max_width = v;
        options.integration.min_width = options.integration.min_width.min(v);
    }
    if let Some(json) = rock_color {
        options.decoration.rock_color = Some(guarded(|| {
            Color::from_json(json)
                .map_err(|e| Error::invalid("rock_color is not a color", e.reason()))
        })?);
    }
    Ok(options)
}

/// The integration mesh as a dict of arrays (see [`build_waterfall`]).
fn water_to_py<'py>(py: Python<'py>, s: &WaterfallScene) -> PyResult<Bound<'py, PyDict>> {
    let m = &s.mesh;
    let water = PyDict::new(py);
    water.set_item(
        "vertices",
        rows_to_py(py, m.vertices.iter().map(|v| [v.x, v.y, v.z]))?,
    )?;
    water.set_item("triangles", rows_to_py(py, m.triangles.iter().copied())?)?;
    let speed: Vec<f64> = m.speed.iter().map(|v| v.length()).collect();
    water.set_item("speed", speed.into_pyarray(py))?;
    water.set_item(
        "speed_xy",
        rows_to_py(py, m.speed.iter().map(|v| [v.x, v.y]))?,
    )?;
    water.set_item("foam", m.foam.clone().into_pyarray(py))?;
    water.set_item("rocks", m.rocks.clone().into_pyarray(py))?;
    water.set_item("disturbance", m.disturbance.clone().into_pyarray(py))?;
    let part: Vec<i32> = m
        .part
        .iter()
        .map(|p| match p {
            WaterPart::Contact => 0,
            WaterPart::FreeFall => 1,
            WaterPart::Pool => 2,
        })
        .collect();
    water.set_item("part", part.into_pyarray(py))?;
    // 1 on the water of segments outside the valid range of their type, so the user can see them
    let invalid: Vec<f64> = m
        .part
        .iter()
        .zip(&m.element)
        .map(|(p, e)| match p {
            WaterPart::Pool => 0.0,
            _ => s
                .network
                .segments
                .get(*e)
                .map_or(0.0, |seg| f64::from(u8::from(!seg.valid))),
        })
        .collect();
    water.set_item("invalid", invalid.into_pyarray(py))?;
    Ok(water)
}

/// Each segment of the hydraulic graph as a dict (see [`build_waterfall`]).
fn segments_to_py<'py>(py: Python<'py>, s: &WaterfallScene) -> PyResult<Bound<'py, PyList>> {
    let segments = PyList::empty(py);
    for seg in &s.network.segments {
        let d = PyDict::new(py);
        let name = type_name(seg.kind_of_water);
        d.set_item("type", name)?;
        d.set_item("arc", seg.arc)?;
        d.set_item("controller", s.network.graph.arcs[seg.arc].controller)?;
        d.set_item("slope", seg.slope)?;
        d.set_item("flow", seg.flow)?;
        d.set_item("speed", seg.section.speed)?;
        d.set_item("width", seg.section.width)?;
        d.set_item("depth", seg.section.depth)?;
        d.set_item("valid", seg.valid)?;
        d.set_item(
            "points",
            rows_to_py(py, seg.points.iter().map(|p| [p.x, p.y, p.z]))?,
        )?;
        segments.append(d)?;
    }
    Ok(segments)
}

/// The rocks' positions, rotations, scales and prototypes into `out` (see [`build_waterfall`]).
fn rocks_into_py(out: &Bound<'_, PyDict>, rocks: &[Rock]) -> PyResult<()> {
    let py = out.py();
    out.set_item(
        "rocks",
        rows_to_py(py, rocks.iter().map(|r| r.position.to_array()))?,
    )?;
    let rotation: Vec<f64> = rocks.iter().map(|r| r.rotation).collect();
    out.set_item("rock_rotation", rotation.into_pyarray(py))?;
    let scale: Vec<f64> = rocks.iter().map(|r| r.scale).collect();
    out.set_item("rock_scale", scale.into_pyarray(py))?;
    let prototype: Vec<i32> = rocks
        .iter()
        .map(|r| i32::try_from(r.prototype).unwrap_or(i32::MAX))
        .collect();
    out.set_item("rock_prototype", prototype.into_pyarray(py))?;
    Ok(())
}

/// The scene's report as a dict (see [`build_waterfall`]).
fn report_to_py<'py>(py: Python<'py>, r: &WaterfallSceneReport) -> PyResult<Bound<'py, PyDict>> {
    let report = PyDict::new(py);
    let nodes = PyDict::new(py);
    nodes.set_item("source", r.sources)?;
    nodes.set_item("well", r.wells)?;
    nodes.set_item("branch", r.branches)?;
    nodes.set_item("pool", r.pools)?;
    report.set_item("nodes", nodes)?;
    report.set_item("arcs", r.arcs)?;
    report.set_item("segments", r.segments)?;
    report.set_item("invalid_segments", r.invalid_segments)?;
    report.set_item("max_flow_imbalance", r.max_flow_imbalance)?;
    report.set_item("water_nodes", r.water_nodes)?;
    report.set_item("rocks", r.rocks)?;
    report.set_item("converged", r.converged)?;
    Ok(report)
}

//! Element arrangements: `learn_arrangement`, `arrangement_summary`, `arrangement_edited`, and the guides that the
//! painting functions take for an arrangement color.

use crate::arrays::ArrayArg;
use crate::convert::{parse_color, points_from_py, region_from_py, rows_to_py};
use crate::scene::PyScene;
use crate::{engine_err, guarded, input_err};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use worldpaint_core::{PatternGuides, PatternRotation};

fn polylines(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<Vec<worldpaint_core::DVec2>>> {
    let items = obj
        .try_iter()
        .map_err(|_| input_err(format!("{what} must be a list of (N, 2) arrays")))?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        out.push(points_from_py(
            &ArrayArg::from(item?),
            &format!("{what} {i}"),
        )?);
    }
    Ok(out)
}

/// `{"start": (x, y), "boundaries": [(N, 2) arrays], "flow": [(N, 2) arrays]}`, every key optional: where an
/// arrangement color's pattern starts, the curves it must not cross, the curves it follows.
pub(crate) fn guides_from_py(obj: Option<&Bound<'_, PyAny>>) -> PyResult<PatternGuides> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(PatternGuides::default());
    };
    let get = |key: &str| obj.get_item(key).ok().filter(|v| !v.is_none());
    Ok(PatternGuides {
        start: get("start")
            .map(|v| crate::convert::vec2(&v, "guides 'start'"))
            .transpose()?,
        boundaries: get("boundaries")
            .map(|v| polylines(&v, "boundary curve"))
            .transpose()?
            .unwrap_or_default(),
        flow: get("flow")
            .map(|v| polylines(&v, "flow curve"))
            .transpose()?
            .unwrap_or_default(),
    })
}

/// Learn an arrangement color (returned as JSON) from the elements of `scene`'s arrangement categories inside
/// `region`: they become its reference, their categories its symbols.
#[pyfunction]
pub(crate) fn learn_arrangement(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    region: &Bound<'_, PyAny>,
    name: &str,
) -> PyResult<String> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let name = name.to_string();
    py.detach(|| guarded(|| worldpaint_core::learn_arrangement(scene, &region, &name)?.to_json()))
}

fn rotation_name(r: PatternRotation) -> &'static str {
    match r {
        PatternRotation::None => "none",
        PatternRotation::BestFit => "best_fit",
        PatternRotation::Flow => "flow",
    }
}

/// What the add-on shows of an arrangement color, or None for a color of statistics: {"positions": float64 (N, 2)
/// (the reference relative to the color's region bbox min), "symbols": int (N), "edges": int (E, 2) (its
/// connectivity, flips applied), "boundary": bool (N) (elements not used as references), "rotation" ("none",
/// "best_fit", "flow"), "scale_noise", "rotation_noise", "color_noise", "relax_every", "flips" (count)}.
#[pyfunction]
pub(crate) fn arrangement_summary<'py>(
    py: Python<'py>,
    color: &str,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let c = parse_color(color)?;
    let Some(pattern) = c.arrangement() else {
        return Ok(None);
    };
    let reference = pattern.reference().map_err(engine_err)?;
    let (lo, _) = c.region.bbox();
    let d = PyDict::new(py);
    d.set_item(
        "positions",
        rows_to_py(
            py,
            pattern
                .elements
                .iter()
                .map(|e| [e.position.x - lo.x, e.position.y - lo.y]),
        )?,
    )?;
    d.set_item(
        "symbols",
        pattern
            .elements
            .iter()
            .map(|e| e.symbol)
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "edges",
        rows_to_py(
            py,
            reference
                .edges()
                .into_iter()
                .map(|(a, b)| [a as i64, b as i64]),
        )?,
    )?;
    d.set_item(
        "boundary",
        (0..pattern.elements.len())
            .map(|i| reference.is_boundary(i))
            .collect::<Vec<_>>(),
    )?;
    d.set_item("rotation", rotation_name(pattern.rotation))?;
    d.set_item("scale_noise", pattern.scale_noise)?;
    d.set_item("rotation_noise", pattern.rotation_noise)?;
    d.set_item("color_noise", pattern.color_noise)?;
    d.set_item("relax_every", pattern.relax_every)?;
    d.set_item("flips", pattern.flips.len())?;
    match reference.lattice() {
        Some(lattice) => {
            let l = PyDict::new(py);
            l.set_item("name", lattice.name())?;
            l.set_item("spacing", lattice.basis[0].length())?;
            l.set_item("spread", lattice.spread)?;
            d.set_item("lattice", l)?;
        }
        None => d.set_item("lattice", py.None())?,
    }
    Ok(Some(d))
}

/// The arrangement color (JSON) with its settings changed: `rotation` ("none", "best_fit", "flow"), noise, the
/// relaxation period, and `flip`: the two reference elements (indices) whose shared edge is flipped (seed Fig. 3).
#[pyfunction]
#[pyo3(signature = (color, *, rotation=None, scale_noise=None, rotation_noise=None, color_noise=None, relax_every=None,
                    flip=None))]
pub(crate) fn arrangement_edited(
    color: &str,
    rotation: Option<&str>,
    scale_noise: Option<f64>,
    rotation_noise: Option<f64>,
    color_noise: Option<f64>,
    relax_every: Option<usize>,
    flip: Option<(usize, usize)>,
) -> PyResult<String> {
    let mut c = parse_color(color)?;
    let name = c.name.clone();
    let Some(pattern) = c.arrangement_mut() else {
        return Err(input_err(format!("color '{name}' is not an arrangement")));
    };
    if let Some(r) = rotation {
        pattern.rotation = match r.to_ascii_lowercase().as_str() {
            "none" => PatternRotation::None,
            "best_fit" => PatternRotation::BestFit,
            "flow" => PatternRotation::Flow,
            other => {
                return Err(input_err(format!(
                    "unknown rotation mode '{other}' (none, best_fit or flow)"
                )))
            }
        };
    }
    if let Some(v) = scale_noise {
        pattern.scale_noise = v;
    }
    if let Some(v) = rotation_noise {
        pattern.rotation_noise = v;
    }
    if let Some(v) = color_noise {
        pattern.color_noise = v;
    }
    if let Some(v) = relax_every {
        pattern.relax_every = v;
    }
    if let Some((a, b)) = flip {
        guarded(|| pattern.flip(a, b))?;
    }
    guarded(|| {
        c.validate()?;
        c.to_json()
    })
}

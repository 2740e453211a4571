//! Colors and palettes as the add-on keeps and shows them: a color renamed or with interactions switched off,
//! palette files, and a color's summary.

use crate::convert::{kind_to_str, parse_color, region_to_py, rows_to_py};
use crate::guarded;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{Interaction, MapSource, Palette};

/// The same color (JSON) under another name.
#[pyfunction]
pub(crate) fn color_renamed(color: &str, name: &str) -> PyResult<String> {
    let mut c = parse_color(color)?;
    c.name = name.to_string();
    guarded(|| c.to_json())
}

/// A palette file (versioned JSON) from a list of color JSON strings.
#[pyfunction]
pub(crate) fn palette_to_json(colors: Vec<String>) -> PyResult<String> {
    let colors = colors
        .iter()
        .map(|c| parse_color(c))
        .collect::<PyResult<Vec<_>>>()?;
    guarded(|| Palette { colors }.to_json())
}

/// The colors (JSON strings) of a palette file; unknown versions and malformed files raise
/// `FileFormatError`.
#[pyfunction]
pub(crate) fn palette_from_json(text: &str) -> PyResult<Vec<String>> {
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
/// "pairs": [(category, other, kind)] (kind "rdf" or "oriented_rdf"), "maps": [(category, map, kind)] (kind "map" for
/// a terrain map, "graph_distance" or "polygon_distance" where `map` is the graph or polygon category), "preview": float64 (N, 3) (x, y relative to the
/// region's bbox min, category index), "preview_size": (w, h)}.
#[pyfunction]
pub(crate) fn color_summary<'py>(py: Python<'py>, color: &str) -> PyResult<Bound<'py, PyDict>> {
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
            .map(|m| {
                let kind = match m.source {
                    MapSource::Terrain => "map",
                    MapSource::GraphDistance => "graph_distance",
                    MapSource::PolygonDistance => "polygon_distance",
                };
                (m.category.clone(), m.map.clone(), kind)
            })
            .collect::<Vec<_>>(),
    )?;
    d.set_item("shortest_edges", c.shortest_edges())?;
    d.set_item("preview", rows_to_py(py, c.preview.iter().copied())?)?;
    let (lo, hi) = c.region.bbox();
    d.set_item("preview_size", (hi.x - lo.x, hi.y - lo.y))?;
    Ok(d)
}

/// The color (JSON) with the interactions `off` switched off: (category, other) pairs naming a pair's rdf, a map (by
/// its map or its graph or polygon category) or a graph's clearance from `other`, as `color_summary` lists them.
#[pyfunction]
pub(crate) fn color_without_interactions(
    color: &str,
    off: Vec<(String, String)>,
) -> PyResult<String> {
    let c = parse_color(color)?;
    guarded(|| c.without_interactions(&off).to_json())
}

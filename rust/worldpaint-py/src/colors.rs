//! Learning, synthesizing, comparing, interpolating and renaming colors; palettes; what the add-on shows of a color.

use crate::convert::{
    categories_to_py, instances_to_py, kind_to_str, parse_color, region_from_py, region_to_py,
    rows_to_py, structures_to_py,
};
use crate::scene::PyScene;
use crate::terrain::{terrain_of, Terrain};
use crate::{guarded, input_err, with_progress};
use numpy::ndarray::Array3;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{
    draw_fidelity, AnalysisOptions, Color, Fidelity, Interaction, MapSource, Palette, Region,
    Scene, SynthesisOptions,
};

pub(crate) fn analysis_options(options: Option<&Bound<'_, PyAny>>) -> PyResult<AnalysisOptions> {
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

/// Learn a color (returned as JSON) from the instances of `scene` inside `region`. `options`: {"bin_width",
/// "max_radius", "oriented": [(a, b), ...], "maps": [...]}, all optional.
#[pyfunction]
#[pyo3(signature = (scene, region, name, *, options=None))]
pub(crate) fn learn_color(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    region: &Bound<'_, PyAny>,
    name: &str,
    options: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let scene = scene.get().scene();
    let region = region_from_py(region)?;
    let opts = analysis_options(options)?;
    let name = name.to_string();
    py.detach(|| guarded(|| worldpaint_core::learn_color(scene, &region, &name, &opts)?.to_json()))
}

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
            let mut opts = $crate::colors::synthesis_options(
                seed,
                influence_radius,
                iterations_per_instance,
                only_categories,
            );
            opts.guides = $crate::arrangement::guides_from_py(guides)?;
            let painting = $crate::colors::Painting {
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

/// The color between `a` and `b` (JSON) at `t` ∈ [0, 1], by optimal transport of every histogram, named `name`;
/// its preview shows an arrangement painted with it.
#[pyfunction]
pub(crate) fn interpolate_colors(
    py: Python<'_>,
    a: &str,
    b: &str,
    t: f64,
    name: &str,
) -> PyResult<String> {
    let (a, b) = (parse_color(a)?, parse_color(b)?);
    let name = name.to_string();
    py.detach(|| {
        guarded(|| {
            let c = worldpaint_core::interpolate_colors(&a, &b, t, &name)?;
            worldpaint_core::with_painted_preview(c)?.to_json()
        })
    })
}

/// The same color (JSON) under another name.
#[pyfunction]
pub(crate) fn color_renamed(color: &str, name: &str) -> PyResult<String> {
    let mut c = parse_color(color)?;
    c.name = name.to_string();
    guarded(|| c.to_json())
}

/// How far `candidate` is from `reference` (both color JSON): {"density_ratio": {category: ratio},
/// "rdf_l2": [(a, b, l2), ...], "map_tv": [(category, map, tv), ...], "worst_density_error", "max_rdf_l2",
/// "max_map_tv"}.
#[pyfunction]
pub(crate) fn compare<'py>(
    py: Python<'py>,
    reference: &str,
    candidate: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let a = parse_color(reference)?;
    let b = parse_color(candidate)?;
    let f = py.detach(|| guarded(|| Ok(worldpaint_core::compare(&a, &b))))?;
    fidelity_to_py(py, &f)
}

/// The dict `compare` returns, of a fidelity.
pub(crate) fn fidelity_to_py<'py>(py: Python<'py>, f: &Fidelity) -> PyResult<Bound<'py, PyDict>> {
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

/// The palette's fidelity view of `color` (JSON): how well the color reproduces its example.
///
/// The color is synthesized with `seed` into its own example region of an empty scene, on `terrain` (a `Terrain`:
/// the one the color was learned on) when the color has terrain maps, else without terrain and without its terrain
/// maps; what it painted is learned back with the color's bins and maps and compared with it (as `compare`), and
/// the two are plotted (see `worldpaint_core::fidelity_plot`): each category's pair-correlation function with
/// itself over distance, the example's solid and the self-synthesis's dashed and lighter, over a grey line at 1;
/// beside it, when the color has a slope map, the slope histograms, likewise. The picture holds no text.
///
/// Returns the keys of `compare` and {"image": uint8 (height, width, 4) RGBA, rows from the top, "max_distance"
/// (m) and "max_pcf" (the pcf axes' ends), "max_slope_degrees" (the slope axis's end; None without a slope panel),
/// "candidate": the self-synthesis's color JSON}. `progress(fraction) -> bool` follows the synthesis and may
/// return False to cancel (raises `Cancelled`). The same color, terrain and seed give the same result.
#[pyfunction]
#[pyo3(signature = (color, terrain=None, seed=0, *, width=256, height=128, progress=None))]
pub(crate) fn fidelity<'py>(
    py: Python<'py>,
    color: &str,
    terrain: Option<Py<Terrain>>,
    seed: u64,
    width: u32,
    height: u32,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let color = parse_color(color)?;
    let heightfield = terrain_of(&terrain).cloned();
    let (candidate, fid, plot) = with_progress(py, progress, |report| {
        let candidate = worldpaint_core::self_synthesis(&color, heightfield, seed, report)?;
        let fid = worldpaint_core::compare(&color, &candidate);
        let plot = draw_fidelity(&color, &candidate, width, height)?;
        Ok((candidate, fid, plot))
    })?;
    let d = fidelity_to_py(py, &fid)?;
    let shape = (plot.height as usize, plot.width as usize, 4);
    let image = Array3::from_shape_vec(shape, plot.rgba)
        .map_err(|e| input_err(format!("plot of inconsistent size: {e}")))?;
    d.set_item("image", image.into_pyarray(py))?;
    d.set_item("max_distance", plot.extent.max_distance)?;
    d.set_item("max_pcf", plot.extent.max_pcf)?;
    d.set_item("max_slope_degrees", plot.extent.max_slope_degrees)?;
    d.set_item("candidate", guarded(|| candidate.to_json())?)?;
    Ok(d)
}

// ---------------------------------------------------------------------------------------------------------------
// colors and palettes

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

//! Plain Python values and numpy arrays to and from the engine's types: regions, categories, scenes, edits.

use crate::arrays::{ArrayArg, Number};
use crate::terrain::{terrain_of, Terrain};
use crate::{engine_err, guarded, input_err};
use numpy::ndarray::{Array1, Array2, Ix1, Ix2};
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{
    Category, CategoryKind, Color, Contour, DVec2, Heightfield, Instance, Path, Region, Scene,
    ToolEdit,
};

pub(crate) fn field<'py>(
    obj: &Bound<'py, PyAny>,
    key: &str,
    what: &str,
) -> PyResult<Bound<'py, PyAny>> {
    obj.get_item(key)
        .map_err(|_| input_err(format!("{what} is missing the key '{key}'")))
}

pub(crate) fn vec2(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec2> {
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
pub(crate) fn region_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Region> {
    let region = region_part_from_py(obj, 0)?;
    region.validate().map_err(engine_err)?;
    Ok(region)
}

/// A part of a region nested `depth` deep, not yet validated. The depth is checked before going deeper: a region
/// nested thousands deep would overflow the stack.
fn region_part_from_py(obj: &Bound<'_, PyAny>, depth: u64) -> PyResult<Region> {
    guarded(|| {
        worldpaint_core::check(
            "the region's nesting",
            depth as f64,
            worldpaint_core::MAX_REGION_DEPTH,
            "levels",
        )
    })?;
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
                    out.push(region_part_from_py(&r?, depth + 1)?);
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
    Ok(region)
}

pub(crate) fn region_to_py<'py>(py: Python<'py>, region: &Region) -> PyResult<Bound<'py, PyDict>> {
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

pub(crate) fn kind_from_str(s: &str) -> PyResult<CategoryKind> {
    match s.to_ascii_lowercase().as_str() {
        "distribution" => Ok(CategoryKind::Distribution),
        "graph" => Ok(CategoryKind::Graph),
        "polygon" => Ok(CategoryKind::Polygon),
        "external" => Ok(CategoryKind::External),
        "arrangement" => Ok(CategoryKind::Arrangement),
        other => Err(input_err(format!(
            "unknown category kind '{other}' (distribution, graph, polygon, external or arrangement)"
        ))),
    }
}

pub(crate) fn kind_to_str(k: CategoryKind) -> &'static str {
    match k {
        CategoryKind::Distribution => "distribution",
        CategoryKind::Graph => "graph",
        CategoryKind::Polygon => "polygon",
        CategoryKind::External => "external",
        CategoryKind::Arrangement => "arrangement",
    }
}

/// A list of `{"name", "layer", "kind", "priority"}` dicts; layer, kind and priority are optional.
pub(crate) fn categories_from_py(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Category>> {
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

pub(crate) fn categories_to_py<'py>(
    py: Python<'py>,
    cats: &[Category],
) -> PyResult<Bound<'py, PyList>> {
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

/// World XY points from an (N, 2) array argument named `what`.
pub(crate) fn points_from_py(xy: &ArrayArg<'_>, what: &str) -> PyResult<Vec<DVec2>> {
    let xy = xy.read::<f64, Ix2>(what, &[2])?;
    let a = xy.as_array();
    Ok(a.rows()
        .into_iter()
        .map(|r| DVec2::new(r[0], r[1]))
        .collect())
}

pub(crate) fn points_to_py<'py>(py: Python<'py>, pts: &[DVec2]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    // the shape always matches the data, so this cannot fail
    Array2::from_shape_vec((pts.len(), 2), flat)
        .unwrap_or_else(|_| Array2::zeros((0, 2)))
        .into_pyarray(py)
}

/// Rows of `N` values as a numpy array (R, N).
pub(crate) fn rows_to_py<'py, const N: usize, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: impl Iterator<Item = [T; N]>,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let flat: Vec<T> = rows.flatten().collect();
    let n = flat.len() / N;
    Ok(Array2::from_shape_vec((n, N), flat)
        .map_err(|e| input_err(e.to_string()))?
        .into_pyarray(py))
}

/// The values of an optional (N,) array argument named `what`, `default` for each of the `n` positions without it.
pub(crate) fn column<T: Number>(
    a: Option<ArrayArg<'_>>,
    n: usize,
    default: T,
    what: &str,
) -> PyResult<Vec<T>> {
    match a {
        None => Ok(vec![default; n]),
        Some(a) => {
            let v: Vec<T> = a
                .read::<T, Ix1>(what, &[])?
                .as_array()
                .iter()
                .copied()
                .collect();
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

/// The instance columns of a scene as given, one row per instance; each optional but the first two.
pub(crate) struct InstanceColumns<'py> {
    pub(crate) positions: ArrayArg<'py>,
    pub(crate) category_index: ArrayArg<'py>,
    pub(crate) rotations: Option<ArrayArg<'py>>,
    pub(crate) scales: Option<ArrayArg<'py>>,
    pub(crate) prototype: Option<ArrayArg<'py>>,
    pub(crate) locked: Option<ArrayArg<'py>>,
    pub(crate) tints: Option<ArrayArg<'py>>,
}

/// The scene the engine works on: the category list, the instance arrays (one row per instance, checked against
/// the categories; `locked` marks hand-placed instances the tools never remove) and the terrain.
pub(crate) fn scene_from_py(
    terrain: &Option<Py<Terrain>>,
    categories: &Bound<'_, PyAny>,
    columns: InstanceColumns<'_>,
    structures: &Structures<'_, '_>,
) -> PyResult<Scene> {
    let categories = categories_from_py(categories)?;
    let n_categories = categories.len();
    let pos = points_from_py(&columns.positions, "positions")?;
    let n = pos.len();
    let cat = column(Some(columns.category_index), n, 0, "category_index")?;
    let rot = column(columns.rotations, n, 0.0, "rotations")?;
    let sca = column(columns.scales, n, 1.0, "scales")?;
    let pro = column(columns.prototype, n, 0, "prototype")?;
    let lock = column(columns.locked, n, false, "locked")?;
    let tint = column(columns.tints, n, 0.0, "tints")?;
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
        if !tint[i].is_finite() {
            return Err(input_err(format!("instance {i} has a non-finite tint")));
        }
        out.push(Instance {
            position: pos[i],
            rotation: rot[i],
            scale: sca[i],
            category: c as usize,
            prototype: pro[i].max(0) as u32,
            locked: lock[i],
            tint: tint[i] as f32,
        });
    }
    let paths = polylines_from_py(structures.paths, &categories, CategoryKind::Graph, "path")?
        .into_iter()
        .map(|(category, points, locked)| Path {
            category,
            points,
            locked,
        })
        .collect();
    let contours = polylines_from_py(
        structures.contours,
        &categories,
        CategoryKind::Polygon,
        "contour",
    )?
    .into_iter()
    .map(|(category, points, locked)| Contour {
        category,
        points,
        locked,
    })
    .collect();
    Ok(Scene {
        categories,
        instances: out,
        paths,
        contours,
        terrain: terrain_of(terrain).cloned(),
    })
}

/// The paths and contours of a scene as Python gives them: lists of {"category": int, "points": (N, 2),
/// "locked": bool} (locked optional, default True: drawn by hand), or None.
pub(crate) struct Structures<'a, 'py> {
    pub(crate) paths: Option<&'a Bound<'py, PyAny>>,
    pub(crate) contours: Option<&'a Bound<'py, PyAny>>,
}

/// (category, points, locked) of each polyline of a list, checked against the categories and their kind.
fn polylines_from_py(
    list: Option<&Bound<'_, PyAny>>,
    categories: &[Category],
    kind: CategoryKind,
    what: &str,
) -> PyResult<Vec<(usize, Vec<DVec2>, bool)>> {
    let mut out = Vec::new();
    let Some(list) = list.filter(|l| !l.is_none()) else {
        return Ok(out);
    };
    let items = list
        .try_iter()
        .map_err(|_| input_err(format!("{what}s must be a list of dicts")))?;
    for (i, item) in items.enumerate() {
        let item = item?;
        let name = format!("{what} {i}");
        let category: i64 = field(&item, "category", &name)?
            .extract()
            .map_err(|_| input_err(format!("{name}: 'category' must be an integer")))?;
        let c = usize::try_from(category)
            .ok()
            .filter(|&c| c < categories.len())
            .ok_or_else(|| {
                input_err(format!(
                    "{name} has category index {category} but there are {} categories",
                    categories.len()
                ))
            })?;
        if categories[c].kind != kind {
            return Err(input_err(format!(
                "{name} is of category '{}', which is a {}, not a {}",
                categories[c].name,
                kind_to_str(categories[c].kind),
                kind_to_str(kind)
            )));
        }
        let points = ArrayArg::from(field(&item, "points", &name)?);
        let points = points_from_py(&points, &format!("{name} points"))?;
        if points.iter().any(|p| !p.is_finite()) {
            return Err(input_err(format!("{name} has a non-finite point")));
        }
        let locked = match item.get_item("locked") {
            Ok(v) if !v.is_none() => v
                .extract()
                .map_err(|_| input_err(format!("{name}: 'locked' must be a bool")))?,
            _ => true,
        };
        out.push((c, points, locked));
    }
    Ok(out)
}

/// Polylines as a list of {"category": int, "points": float64 (N, 2), "heights": float64 (N) (terrain height,
/// NaN off the terrain)}.
pub(crate) fn polylines_to_py<'py, 'a>(
    py: Python<'py>,
    lines: impl Iterator<Item = (usize, &'a [DVec2])>,
    terrain: Option<&Heightfield>,
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for (category, points) in lines {
        let d = PyDict::new(py);
        d.set_item("category", category)?;
        d.set_item("points", points_to_py(py, points))?;
        d.set_item("heights", heights_of(points, terrain).into_pyarray(py))?;
        list.append(d)?;
    }
    Ok(list)
}

/// Terrain heights at `points` (NaN off the terrain or without one).
pub(crate) fn heights_of(points: &[DVec2], terrain: Option<&Heightfield>) -> Array1<f64> {
    points
        .iter()
        .map(|p| terrain.and_then(|t| t.height_at(*p)).unwrap_or(f64::NAN))
        .collect()
}

/// How much the height changed from `before` to `after` at `points` (0 where either has no height there).
pub(crate) fn height_change(
    before: &Heightfield,
    after: &Heightfield,
    points: &[DVec2],
) -> Vec<f64> {
    points
        .iter()
        .map(|p| match (after.height_at(*p), before.height_at(*p)) {
            (Some(new), Some(old)) => new - old,
            _ => 0.0,
        })
        .collect()
}

/// The paths and contours of a result as the "paths" and "contours" lists of [`polylines_to_py`].
pub(crate) fn structures_to_py<'py>(
    py: Python<'py>,
    d: &Bound<'py, PyDict>,
    keys: [&str; 2],
    paths: &[Path],
    contours: &[Contour],
    terrain: Option<&Heightfield>,
) -> PyResult<()> {
    let paths = paths.iter().map(|p| (p.category, p.points.as_slice()));
    d.set_item(keys[0], polylines_to_py(py, paths, terrain)?)?;
    let contours = contours.iter().map(|c| (c.category, c.points.as_slice()));
    d.set_item(keys[1], polylines_to_py(py, contours, terrain)?)?;
    Ok(())
}

/// The instance columns of a result as a dict of numpy arrays.
pub(crate) fn instances_to_py<'py>(
    py: Python<'py>,
    d: &Bound<'py, PyDict>,
    instances: &[Instance],
    terrain: Option<&Heightfield>,
) -> PyResult<()> {
    let pos: Vec<DVec2> = instances.iter().map(|i| i.position).collect();
    d.set_item("positions", points_to_py(py, &pos))?;
    d.set_item("heights", heights_of(&pos, terrain).into_pyarray(py))?;
    d.set_item("rotations", instance_column(py, instances, |i| i.rotation))?;
    d.set_item("scales", instance_column(py, instances, |i| i.scale))?;
    d.set_item(
        "category_index",
        instance_column(py, instances, |i| i.category as i32),
    )?;
    d.set_item(
        "prototype",
        instance_column(py, instances, |i| i.prototype as i32),
    )?;
    d.set_item("tints", instance_column(py, instances, |i| i.tint))?;
    Ok(())
}

/// One value of each instance as a numpy array.
fn instance_column<'py, T: numpy::Element>(
    py: Python<'py>,
    instances: &[Instance],
    value: impl Fn(&Instance) -> T,
) -> Bound<'py, PyArray1<T>> {
    instances
        .iter()
        .map(value)
        .collect::<Vec<_>>()
        .into_pyarray(py)
}

pub(crate) fn parse_color(json: &str) -> PyResult<Color> {
    guarded(|| Color::from_json(json))
}

/// An edit as a dict: {"categories": [...], "removed": int64 (K) indices of the removed input instances, the added
/// instances' columns as [`instances_to_py`] writes them, "removed_paths" and "removed_contours": int64 indices of
/// the input's paths and contours removed (a cut one is removed and its remaining pieces added), "added_paths" and
/// "added_contours" as [`polylines_to_py`] writes them, "unseen_maps": {map name: share of the painted region
/// where the map read values the color's example never showed}}.
pub(crate) fn edit_to_py<'py>(
    py: Python<'py>,
    edit: &ToolEdit,
    terrain: Option<&Heightfield>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("categories", categories_to_py(py, &edit.categories)?)?;
    let indices = |v: &[usize]| {
        v.iter()
            .map(|&k| k as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
    };
    d.set_item("removed", indices(&edit.removed))?;
    instances_to_py(py, &d, &edit.added, terrain)?;
    d.set_item("removed_paths", indices(&edit.removed_paths))?;
    d.set_item("removed_contours", indices(&edit.removed_contours))?;
    structures_to_py(
        py,
        &d,
        ["added_paths", "added_contours"],
        &edit.added_paths,
        &edit.added_contours,
        terrain,
    )?;
    let unseen = PyDict::new(py);
    for (name, share) in &edit.unseen_maps {
        unseen.set_item(name, share)?;
    }
    d.set_item("unseen_maps", unseen)?;
    Ok(d)
}

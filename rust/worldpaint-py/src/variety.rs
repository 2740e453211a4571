//! Model variety: `decompose_model`, `generate_variants`, `assign_variants`, `texture_variety`.
//!
//! A model crosses as a dict {"vertices": float64 (N, 3), "loop_totals": int (F,) (corners per face), "corners": int
//! (sum,) (vertex per corner, face after face), "uvs": float64 (sum, 2) or None, "materials": int (F,) or None}, as
//! Blender's mesh arrays read it. An image crosses as uint8 (H, W, 4) RGBA, rows from the bottom as Blender's
//! `Image.pixels`.

use crate::arrays::ArrayArg;
use crate::convert::{field, points_from_py, rows_to_py};
use crate::{guarded, input_err, with_progress};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use worldpaint_core::{
    atlas_images, check_assembly, memory_report, model_error_about, pack_components,
    pick_texture_variants, Atlas, DVec2, DVec3, Decomposition, Error, GenerateOptions, Generation,
    Image, IntersectionLabels, MemoryReport, Model, Rejection, TextureComponent, VariantClass,
};

fn int_column(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<i64>> {
    let a: PyReadonlyArray1<'_, i64> = obj
        .extract()
        .map_err(|_| input_err(format!("{what} must be an int64 array")))?;
    Ok(a.as_array().to_vec())
}

fn model_from_py(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Model> {
    let vertices: PyReadonlyArray2<'_, f64> = field(obj, "vertices", what)?
        .extract()
        .map_err(|_| input_err(format!("{what}: 'vertices' must be a float64 (N, 3) array")))?;
    let v = vertices.as_array();
    if v.ncols() != 3 {
        return Err(input_err(format!("{what}: 'vertices' must have 3 columns")));
    }
    let vertices: Vec<DVec3> = v
        .rows()
        .into_iter()
        .map(|r| DVec3::new(r[0], r[1], r[2]))
        .collect();
    let totals = int_column(
        &field(obj, "loop_totals", what)?,
        &format!("{what} loop_totals"),
    )?;
    let corners = int_column(&field(obj, "corners", what)?, &format!("{what} corners"))?;
    let mut faces = Vec::with_capacity(totals.len());
    let mut at = 0usize;
    for (f, &n) in totals.iter().enumerate() {
        let n = usize::try_from(n)
            .map_err(|_| input_err(format!("{what}: face {f} has a negative size")))?;
        let Some(face) = corners.get(at..at + n) else {
            return Err(input_err(format!(
                "{what}: the corners end before face {f}"
            )));
        };
        faces.push(
            face.iter()
                .map(|&c| {
                    u32::try_from(c)
                        .map_err(|_| input_err(format!("{what}: face {f} has a bad vertex {c}")))
                })
                .collect::<PyResult<Vec<u32>>>()?,
        );
        at += n;
    }
    let mut model =
        guarded(|| Model::new(vertices, faces.clone()).map_err(|e| model_error_about(e, what)))?;
    if let Ok(uvs) = obj.get_item("uvs") {
        if !uvs.is_none() {
            let uv = points_from_py(&ArrayArg::from(uvs), &format!("{what} uvs"))?;
            if uv.len() != at {
                return Err(input_err(format!(
                    "{what}: {} uvs for {at} corners",
                    uv.len()
                )));
            }
            let mut per_face: Vec<Vec<DVec2>> = Vec::with_capacity(faces.len());
            let mut k = 0;
            for face in &faces {
                per_face.push(uv[k..k + face.len()].to_vec());
                k += face.len();
            }
            model = guarded(|| {
                model
                    .with_uvs(per_face)
                    .map_err(|e| model_error_about(e, what))
            })?;
        }
    }
    if let Ok(materials) = obj.get_item("materials") {
        if !materials.is_none() {
            let m = int_column(&materials, &format!("{what} materials"))?;
            let m = m
                .into_iter()
                .map(|x| {
                    u32::try_from(x)
                        .map_err(|_| input_err(format!("{what}: a negative material index")))
                })
                .collect::<PyResult<Vec<u32>>>()?;
            model = guarded(|| {
                model
                    .with_materials(m)
                    .map_err(|e| model_error_about(e, what))
            })?;
        }
    }
    Ok(model)
}

fn model_to_py<'py>(py: Python<'py>, model: &Model) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item(
        "vertices",
        rows_to_py(py, model.vertices.iter().map(|v| [v.x, v.y, v.z]))?,
    )?;
    d.set_item(
        "loop_totals",
        model
            .faces
            .iter()
            .map(|f| f.len() as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "corners",
        model
            .faces
            .iter()
            .flatten()
            .map(|&v| v as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    match &model.uvs {
        Some(uvs) => d.set_item(
            "uvs",
            rows_to_py(py, uvs.iter().flatten().map(|u| [u.x, u.y]))?,
        )?,
        None => d.set_item("uvs", py.None())?,
    }
    match &model.materials {
        Some(m) => d.set_item(
            "materials",
            m.iter()
                .map(|&x| x as i64)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?,
        None => d.set_item("materials", py.None())?,
    }
    Ok(d)
}

fn labels_of(labels: &Bound<'_, PyAny>) -> PyResult<Vec<u32>> {
    int_column(labels, "labels")?
        .into_iter()
        .map(|l| u32::try_from(l).map_err(|_| input_err("labels must be non-negative")))
        .collect()
}

/// Decompose `model` into components by a label per face (int64 (F,)), with the component labelled `root` as the
/// root (None: the largest). Returns {"labels": [label per component], "faces": [face count per component],
/// "regions": [(a, b, vertex count)] (component indices), "root", "fully_cyclic", "tree_like", "components": [the
/// component's sub-mesh as a model dict, its vertices numbered as every variant of it must keep them]}.
#[pyfunction]
#[pyo3(signature = (model, labels, root=None))]
pub(crate) fn decompose_model<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    labels: &Bound<'py, PyAny>,
    root: Option<u32>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = model_from_py(model, "model")?;
    let labels = labels_of(labels)?;
    let decomposition = guarded(|| Decomposition::from_labels(&model, &labels, root))?;
    let d = PyDict::new(py);
    let components = PyList::empty(py);
    for c in 0..decomposition.components.len() {
        let piece = guarded(|| decomposition.component_model(&model, c))?;
        components.append(model_to_py(py, &piece)?)?;
    }
    d.set_item(
        "labels",
        decomposition
            .components
            .iter()
            .map(|c| c.label)
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "faces",
        decomposition
            .components
            .iter()
            .map(|c| c.faces.len())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "regions",
        decomposition
            .regions
            .iter()
            .map(|r| (r.components.0, r.components.1, r.vertices.len()))
            .collect::<Vec<_>>(),
    )?;
    d.set_item("root", decomposition.root)?;
    d.set_item("fully_cyclic", decomposition.is_fully_cyclic())?;
    d.set_item("tree_like", decomposition.is_tree_like())?;
    d.set_item("components", components)?;
    Ok(d)
}

fn class_name(c: VariantClass) -> &'static str {
    match c {
        VariantClass::Local => "local",
        VariantClass::SolidTransform => "solid_transform",
        VariantClass::RegionChange => "region_change",
    }
}

/// Assemble `count` variants of `model` decomposed by `labels` (see `decompose_model`), from `variants`: per component
/// a list of model dicts (edits of its sub-mesh). `cycles`: (component, max repeat) pairs of local cycles. `picks`:
/// per component the variant picked by hand (0 its original; the count and seed are then unused). `names`: per
/// component the name the user knows it by (its collection), `variant_names`: per component the name of each
/// variant (its copy object); messages about a copy name both. Returns
/// {"classes": per component the class of each given variant, "total": #V as a string, "exhausted": whether every
/// assembly was tried (a count of #V or more tries them all), "models": the accepted variants as model dicts,
/// "face_origin": per model int64 (F,) the original face each face copies (-1: a face an edit added), "hashes",
/// "rejected": [(reason, detail)], "memory": {"overhead_percent" (the atlas over
/// the original, the seed's Table 2), "original_bytes", "shared_bytes", "full_bytes"}}. `progress(fraction) -> bool` may cancel.
#[pyfunction]
#[pyo3(signature = (model, labels, variants, count, seed=0, *, root=None, cycles=None, picks=None, names=None,
    variant_names=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn generate_variants<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    labels: &Bound<'py, PyAny>,
    variants: &Bound<'py, PyAny>,
    count: usize,
    seed: u64,
    root: Option<u32>,
    cycles: Option<Vec<(usize, u32)>>,
    picks: Option<Vec<usize>>,
    names: Option<Vec<String>>,
    variant_names: Option<Vec<Vec<String>>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = model_from_py(model, "model")?;
    let labels = labels_of(labels)?;
    let names = CopyNames {
        parts: names,
        copies: variant_names,
    };
    let edits = edits_from_py(variants, &names)?;
    let cycles = cycles.unwrap_or_default();
    let (classes, total, generation, memory) = with_progress(py, progress, |report| {
        let decomposition = Decomposition::from_labels(&model, &labels, root)?;
        let n = decomposition.components.len();
        if edits.len() > n {
            return Err(worldpaint_core::Error::invalid(
                "variants",
                format!("{} lists for {n} components", edits.len()),
            ));
        }
        let (atlas, classes) = atlas_of(&model, decomposition, edits, &cycles, &names)?;
        if !report(0.1) {
            return Err(worldpaint_core::Error::Cancelled);
        }
        let labels = IntersectionLabels::of_model(&model);
        let options = GenerateOptions {
            count,
            seed,
            max_attempts: 0,
        };
        let generation = generation_of(&atlas, &labels, &options, picks.as_deref())?;
        let choices: Vec<_> = generation.accepted.iter().map(|(c, _)| c.clone()).collect();
        let memory = memory_report(&atlas, &choices)?;
        Ok((classes, atlas.count(), generation, memory))
    })?;
    generation_to_py(py, classes, total, &generation, &memory)
}

/// The names the user gave the parts (their collections) and the copies (their objects), for the messages.
struct CopyNames {
    parts: Option<Vec<String>>,
    copies: Option<Vec<Vec<String>>>,
}

impl CopyNames {
    fn part(&self, c: usize) -> String {
        self.parts
            .as_ref()
            .and_then(|n| n.get(c))
            .cloned()
            .unwrap_or_else(|| format!("component {c}"))
    }

    fn copy(&self, c: usize, k: usize) -> String {
        self.copies
            .as_ref()
            .and_then(|n| n.get(c))
            .and_then(|n| n.get(k))
            .cloned()
            .unwrap_or_else(|| format!("copy {}", k + 1))
    }
}

/// The copies of each part as models, each refused by its name when it is not one.
fn edits_from_py(variants: &Bound<'_, PyAny>, names: &CopyNames) -> PyResult<Vec<Vec<Model>>> {
    let mut edits: Vec<Vec<Model>> = Vec::new();
    for (c, list) in variants
        .try_iter()
        .map_err(|_| input_err("variants must be a list (per component) of lists of models"))?
        .enumerate()
    {
        let list = list?;
        let mut own = Vec::new();
        for (k, item) in list
            .try_iter()
            .map_err(|_| {
                input_err(format!(
                    "variants of component {c} must be a list of models"
                ))
            })?
            .enumerate()
        {
            own.push(model_from_py(
                &item?,
                &format!("copy '{}' in '{}'", names.copy(c, k), names.part(c)),
            )?);
        }
        edits.push(own);
    }
    Ok(edits)
}

/// The atlas of the model's parts with the copies added (and each copy's class) and the local cycles allowed.
fn atlas_of(
    model: &Model,
    decomposition: Decomposition,
    edits: Vec<Vec<Model>>,
    cycles: &[(usize, u32)],
    names: &CopyNames,
) -> worldpaint_core::Result<(Atlas, Vec<Vec<&'static str>>)> {
    let n = decomposition.components.len();
    let mut atlas = Atlas::new(model, decomposition)?;
    atlas.set_names((0..n).map(|c| names.part(c)).collect())?;
    let mut classes = Vec::new();
    for (c, list) in edits.into_iter().enumerate() {
        let mut own = Vec::new();
        for (k, edit) in list.into_iter().enumerate() {
            own.push(class_name(atlas.add_named_variant(
                c,
                &names.copy(c, k),
                edit,
            )?));
        }
        classes.push(own);
    }
    for &(c, max_repeat) in cycles {
        atlas.add_local_cycle(c, max_repeat)?;
    }
    Ok((atlas, classes))
}

/// The variants generated (`picks`: the one assembly of those variants, kept or rejected).
fn generation_of(
    atlas: &Atlas,
    labels: &IntersectionLabels,
    options: &GenerateOptions,
    picks: Option<&[usize]>,
) -> worldpaint_core::Result<Generation> {
    let generation = match picks {
        None => worldpaint_core::generate_variants(atlas, labels, options)?,
        Some(variants) => {
            let choice = atlas.choice_of_variants(variants)?;
            let mut one = Generation {
                accepted: Vec::new(),
                rejected: Vec::new(),
                exhausted: false,
            };
            match check_assembly(atlas, labels, &choice)? {
                Ok(assembled) => one.accepted.push((choice, assembled)),
                Err(why) => one.rejected.push((choice, why)),
            }
            one
        }
    };
    Ok(generation)
}

/// What [`generate_variants`] returns, from its parts.
fn generation_to_py<'py>(
    py: Python<'py>,
    classes: Vec<Vec<&'static str>>,
    total: u128,
    generation: &Generation,
    memory: &MemoryReport,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("classes", classes)?;
    let m = PyDict::new(py);
    m.set_item("overhead_percent", memory.overhead_percent)?;
    m.set_item("original_bytes", memory.original_bytes)?;
    m.set_item("shared_bytes", memory.shared_bytes)?;
    m.set_item("full_bytes", memory.full_bytes)?;
    d.set_item("memory", m)?;
    d.set_item("total", total.to_string())?;
    d.set_item("exhausted", generation.exhausted)?;
    let models = PyList::empty(py);
    for (_, assembled) in &generation.accepted {
        models.append(model_to_py(py, &assembled.model)?)?;
    }
    d.set_item("models", models)?;
    let origins = PyList::empty(py);
    for (_, assembled) in &generation.accepted {
        origins.append(
            assembled
                .face_origin
                .iter()
                .map(|o| o.map_or(-1, i64::from))
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
    }
    d.set_item("face_origin", origins)?;
    d.set_item(
        "hashes",
        generation
            .accepted
            .iter()
            .map(|(_, a)| a.hash.to_string())
            .collect::<Vec<_>>(),
    )?;
    d.set_item(
        "rejected",
        generation
            .rejected
            .iter()
            .map(|(_, r)| match r {
                Rejection::SelfIntersection(a, b) => {
                    ("self_intersection", format!("faces {a} and {b}"))
                }
                Rejection::Crack(gap) => ("crack", format!("{gap:.2e} m")),
            })
            .collect::<Vec<_>>(),
    )?;
    Ok(d)
}

/// The variant (0..count) of each instance at the XY `positions` (float64 (N, 2)): `fixed` (int64 (N,), -1: to
/// choose) where given; the others pick the variant least used within `window` metres (seeded).
#[pyfunction]
#[pyo3(signature = (positions, fixed, count, window=50.0, seed=0))]
pub(crate) fn assign_variants<'py>(
    py: Python<'py>,
    positions: ArrayArg<'py>,
    fixed: &Bound<'py, PyAny>,
    count: u32,
    window: f64,
    seed: u64,
) -> PyResult<Bound<'py, numpy::PyArray1<i64>>> {
    let positions = points_from_py(&positions, "positions")?;
    let fixed: Vec<Option<u32>> = int_column(fixed, "fixed")?
        .into_iter()
        .map(|v| u32::try_from(v).ok())
        .collect();
    let out = py.detach(|| {
        guarded(|| worldpaint_core::assign_variants(&positions, &fixed, count, window, seed))
    })?;
    Ok(out
        .into_iter()
        .map(i64::from)
        .collect::<Vec<_>>()
        .into_pyarray(py))
}

fn image_from_py(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Image> {
    let a: PyReadonlyArray3<'_, u8> = obj
        .extract()
        .map_err(|_| input_err(format!("{what} must be a uint8 (height, width, 4) array")))?;
    let a = a.as_array();
    let (h, w, channels) = a.dim();
    if channels != 4 {
        return Err(input_err(format!(
            "{what} has {channels} channels where 4 (RGBA) are needed"
        )));
    }
    let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(input_err(format!("{what} is too large")));
    };
    let rgba: Vec<u8> = a.iter().copied().collect();
    guarded(|| Image::new(width, height, rgba))
}

fn image_to_py<'py>(py: Python<'py>, image: &Image) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
    let shape = (image.height as usize, image.width as usize, 4);
    let array = Array3::from_shape_vec(shape, image.rgba.clone())
        .map_err(|e| input_err(format!("an image of inconsistent size: {e}")))?;
    Ok(array.into_pyarray(py))
}

/// An error about one painted image, named.
fn about_edit(e: Error, name: &str) -> Error {
    match e {
        Error::Invalid { what, reason } if what == "painted image" => Error::invalid(name, reason),
        other => other,
    }
}

/// Texture variety (seed §5): each of `edits` (images the size of `base`, uint8 (H, W, 4)) compared with the `base`
/// texture becomes a texture component T_k = (P, M, C) over `model`'s texture coordinates; the components are packed
/// into the fewest atlases with no two conflicting ones together, and `count` variants each pick components at random
/// (each with `probability`, face locking; seeded). `names` name the edits in errors. Returns {"components": [{"texels":
/// |P|, "face_texels": |M|, "faces": int64 C}], "conflicts": [(i, j)], "atlas_of": int64 (K,), "atlases", "exact"
/// (the count is proven the fewest), "images": the atlases as uint8 (H, W, 4), "chosen": per variant the components
/// it shows, "face_atlas": int64 (count, F) the atlas each face of the model binds in each variant (-1: the base)}.
#[pyfunction]
#[pyo3(signature = (model, base, edits, count, probability=0.5, seed=0, *, names=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn texture_variety<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    base: &Bound<'py, PyAny>,
    edits: &Bound<'py, PyAny>,
    count: usize,
    probability: f64,
    seed: u64,
    names: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model = model_from_py(model, "model")?;
    let base = image_from_py(base, "base texture")?;
    let mut painted = Vec::new();
    for (k, item) in edits
        .try_iter()
        .map_err(|_| input_err("edits must be a list of images"))?
        .enumerate()
    {
        painted.push(image_from_py(&item?, &format!("texture edit {}", k + 1))?);
    }
    let names: Vec<String> = (0..painted.len())
        .map(|k| {
            names
                .as_ref()
                .and_then(|n| n.get(k))
                .map_or_else(|| format!("texture edit {}", k + 1), |n| format!("'{n}'"))
        })
        .collect();
    let faces = model.faces.len();
    let (components, packing, images, picks) = py.detach(|| {
        guarded(|| {
            if painted.is_empty() {
                return Err(Error::invalid(
                    "texture edits",
                    "none given: paint at least one",
                ));
            }
            let components = painted
                .iter()
                .zip(&names)
                .map(|(edit, name)| {
                    TextureComponent::from_edit(&model, &base, edit)
                        .map_err(|e| about_edit(e, name))
                })
                .collect::<worldpaint_core::Result<Vec<_>>>()?;
            let packing = pack_components(&components);
            let images = atlas_images(&base, &components, &packing);
            let picks =
                pick_texture_variants(&components, &packing, faces, probability, count, seed)?;
            Ok((components, packing, images, picks))
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("components", components_to_py(py, &components)?)?;
    let mut conflicts = Vec::new();
    for i in 0..components.len() {
        for j in i + 1..components.len() {
            if components[i].conflicts(&components[j]) {
                conflicts.push((i, j));
            }
        }
    }
    d.set_item("conflicts", conflicts)?;
    d.set_item(
        "atlas_of",
        packing
            .atlas_of
            .iter()
            .map(|&a| a as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item("atlases", packing.atlases)?;
    d.set_item("exact", packing.exact)?;
    let out = PyList::empty(py);
    for image in &images {
        out.append(image_to_py(py, image)?)?;
    }
    d.set_item("images", out)?;
    d.set_item(
        "chosen",
        picks.iter().map(|p| p.chosen.clone()).collect::<Vec<_>>(),
    )?;
    let mut face_atlas = Array2::<i64>::from_elem((count, faces), -1);
    for (row, pick) in face_atlas.rows_mut().into_iter().zip(&picks) {
        for (cell, atlas) in row.into_iter().zip(&pick.face_atlas) {
            *cell = atlas.map_or(-1, |a| a as i64);
        }
    }
    d.set_item("face_atlas", face_atlas.into_pyarray(py))?;
    Ok(d)
}

/// Each texture component's texel counts and faces (see [`texture_variety`]).
fn components_to_py<'py>(
    py: Python<'py>,
    components: &[TextureComponent],
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for c in components {
        let item = PyDict::new(py);
        item.set_item("texels", c.pixel_mask.len())?;
        item.set_item("face_texels", c.face_mask.len())?;
        item.set_item(
            "faces",
            c.faces
                .iter()
                .map(|&f| i64::from(f))
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        list.append(item)?;
    }
    Ok(list)
}

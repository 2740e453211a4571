//! The terrain class: a heightfield with its maps, shared (not copied) by every engine call that uses it.

use crate::arrays::ArrayArg;
use crate::convert::points_from_py;
use crate::{guarded, input_err};
use numpy::ndarray::{Array2, Ix1, Ix2};
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;
use worldpaint_core::{DVec2, Heightfield};

/// The terrain as a heightfield with named maps ("elevation", "slope" in radians, ...).
///
/// `Terrain(vertices, triangles, cell=None)` rasterizes a triangle mesh given in world space (float64 (N, 3), and
/// (M, 3) vertex indices of any integer dtype); a regular grid mesh is used directly. `cell` overrides the sample
/// spacing in metres.
#[pyclass(module = "worldpaint_engine", frozen)]
pub(crate) struct Terrain {
    pub(crate) hf: Arc<Heightfield>,
}

#[pymethods]
impl Terrain {
    #[new]
    #[pyo3(signature = (vertices, triangles, cell=None))]
    fn new(
        py: Python<'_>,
        vertices: ArrayArg<'_>,
        triangles: ArrayArg<'_>,
        cell: Option<f64>,
    ) -> PyResult<Self> {
        let (verts, tris) = mesh_from_py(&vertices, &triangles)?;
        let hf = py.detach(|| guarded(|| Heightfield::from_mesh(&verts, &tris, cell)))?;
        Ok(Terrain { hf: hf.into() })
    }

    /// A terrain from a regular grid of heights, shape (ny, nx), sample (i, j) at origin + (i, j) * cell.
    #[staticmethod]
    fn from_grid(origin: (f64, f64), cell: f64, heights: ArrayArg<'_>) -> PyResult<Self> {
        let heights = heights.checked::<f64, Ix2>("heights", &[])?;
        let (ny, nx) = match heights.shape() {
            &[ny, nx] => (ny, nx),
            _ => (0, 0), // not reached: the array is 2-D
        };
        // refused before the copy or the cast: a broadcast array of any shape costs Python nothing
        guarded(|| {
            worldpaint_core::check(
                "the terrain grid",
                nx as f64 * ny as f64,
                worldpaint_core::MAX_GRID_CELLS,
                "cells",
            )
        })?;
        let heights = heights.read()?;
        let h: Vec<f32> = heights.as_array().iter().map(|&z| z as f32).collect();
        let hf = guarded(|| Heightfield::new(DVec2::new(origin.0, origin.1), cell, nx, ny, h))?;
        Ok(Terrain { hf: hf.into() })
    }

    /// Terrain heights at world XY points (float64 (N, 2)); NaN outside the terrain.
    fn heights_at<'py>(
        &self,
        py: Python<'py>,
        xy: ArrayArg<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let hf = &self.hf;
        sample_points(py, &xy, |p| hf.height_at(p))
    }

    /// Values of the named map ("elevation", "slope", ...) at world XY points; NaN outside the terrain.
    fn map_at<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        xy: ArrayArg<'py>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if !self.hf.maps.contains_key(name) {
            let known: Vec<&str> = self.hf.maps.keys().map(|k| k.as_str()).collect();
            return Err(input_err(format!(
                "the terrain has no map '{name}' (it has {})",
                known.join(", ")
            )));
        }
        let hf = &self.hf;
        sample_points(py, &xy, |p| hf.map_at(name, p))
    }

    /// A copy of the terrain with the map `name` from a value per vertex of a world-space triangle mesh (float64
    /// (N, 3) vertices, (M, 3) triangles, float64 (N,) values): a weight-painted group, an attribute, an image read
    /// through the UVs. Values are interpolated in each triangle onto the terrain's grid.
    fn with_vertex_map(
        &self,
        py: Python<'_>,
        name: &str,
        vertices: ArrayArg<'_>,
        triangles: ArrayArg<'_>,
        values: ArrayArg<'_>,
    ) -> PyResult<Self> {
        let (verts, tris) = mesh_from_py(&vertices, &triangles)?;
        let values = values.read::<f64, Ix1>("values", &[])?;
        let values: Vec<f64> = values.as_array().iter().copied().collect();
        let mut hf = (*self.hf).clone();
        py.detach(|| guarded(|| hf.add_mesh_map(name, &verts, &tris, &values)))?;
        Ok(Terrain { hf: hf.into() })
    }

    /// A copy of the terrain with the map `name`: the XY distance (m) to the given geometry (float64 (N, 2)
    /// vertices, (E, 2) edges and (M, 3) triangles between them; vertices alone count as points).
    fn with_distance_map(
        &self,
        py: Python<'_>,
        name: &str,
        vertices: ArrayArg<'_>,
        edges: ArrayArg<'_>,
        triangles: ArrayArg<'_>,
    ) -> PyResult<Self> {
        let verts = points_from_py(&vertices, "vertices")?;
        let edges = edges.read::<u32, Ix2>("edges", &[2])?;
        let edges: Vec<[u32; 2]> = edges
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1]])
            .collect();
        let tris = triangles_from_py(&triangles)?;
        let mut hf = (*self.hf).clone();
        py.detach(|| guarded(|| hf.add_distance_map(name, &verts, &edges, &tris)))?;
        Ok(Terrain { hf: hf.into() })
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

/// A triangle mesh: world XYZ vertices and triangles as vertex indices.
type Mesh = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// World XYZ vertices (float64 (N, 3)) and triangles ((M, 3) vertex indices of any integer dtype).
pub(crate) fn mesh_from_py(vertices: &ArrayArg<'_>, triangles: &ArrayArg<'_>) -> PyResult<Mesh> {
    let vertices = vertices.read::<f64, Ix2>("vertices", &[3])?;
    let verts = vertices
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect();
    Ok((verts, triangles_from_py(triangles)?))
}

fn triangles_from_py(triangles: &ArrayArg<'_>) -> PyResult<Vec<[u32; 3]>> {
    let triangles = triangles.read::<u32, Ix2>("triangles", &[3])?;
    Ok(triangles
        .as_array()
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect())
}

/// `value` at each world XY point of `xy` (float64 (N, 2)), NaN where it has none, computed without the GIL.
fn sample_points<'py>(
    py: Python<'py>,
    xy: &ArrayArg<'py>,
    value: impl Fn(DVec2) -> Option<f64> + Sync,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let pts = points_from_py(xy, "xy")?;
    let out: Vec<f64> =
        py.detach(|| guarded(|| Ok(pts.iter().map(|p| value(*p).unwrap_or(f64::NAN)).collect())))?;
    Ok(out.into_pyarray(py))
}

pub(crate) fn terrain_of(t: &Option<Py<Terrain>>) -> Option<&Arc<Heightfield>> {
    t.as_ref().map(|t| &t.get().hf)
}

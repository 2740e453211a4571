//! The low-polygon model the method works on (seed §3.1): vertices, polygons, and optionally per-corner texture
//! coordinates and a material index per face. The seed's models are polygon soups with self-intersections and
//! disconnected parts (its Fig. 2); nothing here asks for a manifold or a connected mesh, only for indices that
//! exist, finite numbers and polygons of three distinct corners or more.

use crate::error::{Error, Result};
use glam::{DVec2, DVec3};
use std::collections::HashMap;

/// Most vertices or faces one model may have (far above a low-polygon model; refuses a typo before allocating).
pub(crate) const MAX_MODEL_ITEMS: usize = 10_000_000;

/// A model's error as one about `what` (a copy names itself and its part): the invalid input "model vertex 3: ..."
/// reads "`what`: vertex 3: ...". Other errors, and those about "model" itself, pass unchanged.
pub fn error_about(error: Error, what: &str) -> Error {
    if what == "model" || !error.is_invalid_input() {
        return error;
    }
    let reason = error.reason();
    Error::invalid(what, reason.strip_prefix("model ").unwrap_or(&reason))
}

/// A low-polygon mesh: what Blender passes for one object.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    /// Vertex positions (m).
    pub vertices: Vec<DVec3>,
    /// Polygons as vertex indices, counter-clockwise seen from outside.
    pub faces: Vec<Vec<u32>>,
    /// Texture coordinates per face corner (`uvs[f][c]` for corner `c` of face `f`), as Blender's UV loops.
    pub uvs: Option<Vec<Vec<DVec2>>>,
    /// A material index per face (Blender's `material_index`).
    pub materials: Option<Vec<u32>>,
}

impl Model {
    /// A model of `vertices` and `faces`, checked.
    pub fn new(vertices: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Result<Model> {
        let model = Model {
            vertices,
            faces,
            uvs: None,
            materials: None,
        };
        model.validate()?;
        Ok(model)
    }

    /// The model with per-corner texture coordinates, checked against its faces.
    pub fn with_uvs(mut self, uvs: Vec<Vec<DVec2>>) -> Result<Model> {
        self.uvs = Some(uvs);
        self.validate()?;
        Ok(self)
    }

    /// The model with a material index per face, checked against its faces.
    pub fn with_materials(mut self, materials: Vec<u32>) -> Result<Model> {
        self.materials = Some(materials);
        self.validate()?;
        Ok(self)
    }

    /// Checks every rule of a model: sizes within `MAX_MODEL_ITEMS`, finite vertices, faces of three or more
    /// distinct existing vertices, one texture coordinate per corner, one material per face.
    pub fn validate(&self) -> Result<()> {
        crate::limits::check(
            "model vertices",
            self.vertices.len() as f64,
            MAX_MODEL_ITEMS as u64,
            "vertices",
        )?;
        crate::limits::check(
            "model faces",
            self.faces.len() as f64,
            MAX_MODEL_ITEMS as u64,
            "faces",
        )?;
        if let Some(i) = self.vertices.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("model vertex {i}"),
                format!(
                    "coordinates must be finite numbers, got {}",
                    self.vertices[i]
                ),
            ));
        }
        let n = self.vertices.len();
        for (f, face) in self.faces.iter().enumerate() {
            if face.len() < 3 {
                return Err(Error::invalid(
                    format!("model face {f}"),
                    format!("a polygon needs 3 corners or more, got {}", face.len()),
                ));
            }
            for (c, &v) in face.iter().enumerate() {
                if v as usize >= n {
                    return Err(Error::invalid(
                        format!("model face {f}"),
                        format!("corner {c} refers to vertex {v}, but the model has {n} vertices"),
                    ));
                }
                if face[..c].contains(&v) {
                    return Err(Error::invalid(
                        format!("model face {f}"),
                        format!("vertex {v} appears twice in the polygon"),
                    ));
                }
            }
        }
        if let Some(uvs) = &self.uvs {
            crate::error::check::same_len("model uvs (faces)", uvs.len(), self.faces.len())?;
            for (f, (corners, face)) in uvs.iter().zip(&self.faces).enumerate() {
                crate::error::check::same_len(
                    &format!("model uvs of face {f}"),
                    corners.len(),
                    face.len(),
                )?;
                if corners.iter().any(|uv| !uv.is_finite()) {
                    return Err(Error::invalid(
                        format!("model uvs of face {f}"),
                        "texture coordinates must be finite numbers",
                    ));
                }
            }
        }
        if let Some(materials) = &self.materials {
            crate::error::check::same_len("model materials", materials.len(), self.faces.len())?;
        }
        Ok(())
    }

    /// The material index of face `f` (0 when the model has none).
    pub fn material(&self, f: usize) -> u32 {
        self.materials
            .as_ref()
            .and_then(|m| m.get(f).copied())
            .unwrap_or(0)
    }

    /// The triangles of the model, each polygon fanned from its first corner, as (face, vertex indices).
    pub fn triangles(&self) -> Vec<(u32, [u32; 3])> {
        let mut out = Vec::with_capacity(self.faces.len() * 2);
        for (f, face) in self.faces.iter().enumerate() {
            for k in 1..face.len().saturating_sub(1) {
                out.push((f as u32, [face[0], face[k], face[k + 1]]));
            }
        }
        out
    }

    /// The undirected edges of the polygons with the number of faces that use each, sorted by edge.
    pub fn edge_uses(&self) -> Vec<((u32, u32), u32)> {
        let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
        for face in &self.faces {
            for (k, &a) in face.iter().enumerate() {
                let b = face[(k + 1) % face.len()];
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut out: Vec<_> = uses.into_iter().collect();
        out.sort_unstable();
        out
    }

    /// Whether every edge is shared by exactly two faces (a closed surface: watertight).
    pub fn is_watertight(&self) -> bool {
        !self.faces.is_empty() && self.edge_uses().iter().all(|&(_, n)| n == 2)
    }

    /// The model without the vertices that no face uses (the order of the others kept).
    pub(crate) fn compacted(mut self) -> Model {
        let mut used = vec![u32::MAX; self.vertices.len()];
        for face in &self.faces {
            for &v in face {
                used[v as usize] = 0;
            }
        }
        let mut next = 0u32;
        for slot in used.iter_mut() {
            if *slot == 0 {
                *slot = next;
                next += 1;
            }
        }
        let mut k = 0;
        self.vertices.retain(|_| {
            k += 1;
            used[k - 1] != u32::MAX
        });
        for face in &mut self.faces {
            for v in face.iter_mut() {
                *v = used[*v as usize];
            }
        }
        self
    }

    /// The smallest box holding every vertex (zero box when there are none).
    pub fn bounds(&self) -> (DVec3, DVec3) {
        if self.vertices.is_empty() {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        self.vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(v), hi.max(v)),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> Model {
        let v = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        Model::new(
            v,
            vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![2, 0, 3]],
        )
        .unwrap()
    }

    #[test]
    fn a_tetrahedron_is_watertight_and_an_open_one_is_not() {
        let t = tetra();
        assert!(t.is_watertight());
        assert_eq!(t.triangles().len(), 4);
        let mut open = t.clone();
        open.faces.pop();
        assert!(!open.is_watertight());
    }

    #[test]
    fn bad_indices_and_numbers_are_refused_with_their_place() {
        let e = Model::new(vec![DVec3::ZERO; 3], vec![vec![0, 1, 5]]).unwrap_err();
        assert!(e.to_string().contains("face 0"), "{e}");
        assert!(e.to_string().contains("vertex 5"), "{e}");
        let e =
            Model::new(vec![DVec3::new(f64::NAN, 0.0, 0.0); 3], vec![vec![0, 1, 2]]).unwrap_err();
        assert!(e.to_string().contains("finite"), "{e}");
        let e = Model::new(vec![DVec3::ZERO; 3], vec![vec![0, 1]]).unwrap_err();
        assert!(e.to_string().contains("3 corners"), "{e}");
        let e = tetra().with_uvs(vec![vec![DVec2::ZERO; 3]]).unwrap_err();
        assert!(e.to_string().contains("uvs"), "{e}");
    }
}

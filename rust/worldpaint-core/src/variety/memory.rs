//! Memory overhead of the atlas, as the seed's Table 2 reports it (§6.2: "+54 %" for the birch's 729 trees).
//!
//! The seed gives the figure without its accounting; the reading chosen is a game-style mesh in memory and a variant
//! stored as what it does not share with its component:
//! - a vertex is [`VERTEX_BYTES`] (position, normal and texture coordinate as 32-bit floats), a triangle
//!   [`TRIANGLE_BYTES`] (three 32-bit indices);
//! - the original is its vertices and triangles; the atlas stores each component once (the vertices of a connecting
//!   region once per side), and each further variant as the vertices it moved or added ([`SPARSE_VERTEX_BYTES`]: a
//!   vertex and its index) plus its own triangles when its faces differ from the component's (deleting foliage costs
//!   indices only, moving vertices costs vertices only, as the seed explains its birch and rock figures), plus
//!   [`FRAME_BYTES`] per stored frame;
//! - an assembly stored as components is, per placed component, a variant number and a placement
//!   ([`INSTANCE_BYTES`]); as a full mesh it is its own vertices and triangles.
//!
//! Overhead (Table 2's column) = atlas / original − 1.

use super::assemble::Choice;
use super::atlas::{Atlas, RegionChange};
use crate::error::Result;
use rayon::prelude::*;

/// Bytes of one vertex: position, normal, texture coordinate (8 × f32).
pub(crate) const VERTEX_BYTES: u64 = 32;
/// Bytes of one triangle: three u32 indices.
pub(crate) const TRIANGLE_BYTES: u64 = 12;
/// Bytes of one vertex stored sparsely in a variant: the vertex and its u32 index.
pub(crate) const SPARSE_VERTEX_BYTES: u64 = VERTEX_BYTES + 4;
/// Bytes of one frame: a 3 × 4 matrix of f32.
pub(crate) const FRAME_BYTES: u64 = 48;
/// Bytes of one placed component of an assembly: a u16 variant number and a 3 × 4 f32 placement.
pub(crate) const INSTANCE_BYTES: u64 = 2 + FRAME_BYTES;

/// One row of Table 2, with the bytes behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryReport {
    /// Components of the decomposition.
    pub components: usize,
    /// Variants of the largest node of the main graph.
    pub variations: usize,
    /// Assemblies counted.
    pub objects: usize,
    /// The original model (bytes).
    pub original_bytes: u64,
    /// The atlas: components and variants (bytes).
    pub atlas_bytes: u64,
    /// The assemblies stored as components and placements, atlas included (bytes).
    pub shared_bytes: u64,
    /// The assemblies stored as full meshes (bytes).
    pub full_bytes: u64,
    /// Table 2's overhead: atlas over original, minus one, in percent.
    pub overhead_percent: f64,
}

fn triangles(faces: &[Vec<u32>]) -> u64 {
    faces.iter().map(|f| f.len().saturating_sub(2) as u64).sum()
}

/// The memory of `choices` assembled from `atlas`, stored both ways.
pub fn memory_report(atlas: &Atlas, choices: &[Choice]) -> Result<MemoryReport> {
    let model = atlas.model();
    let original_bytes =
        model.vertices.len() as u64 * VERTEX_BYTES + triangles(&model.faces) * TRIANGLE_BYTES;
    let d = atlas.decomposition();
    let mut atlas_bytes = 0u64;
    for c in 0..d.components.len() {
        let variants = atlas.variants(c);
        let Some(base) = variants.first() else {
            continue;
        };
        atlas_bytes += base.model.vertices.len() as u64 * VERTEX_BYTES
            + triangles(&base.model.faces) * TRIANGLE_BYTES;
        for v in &variants[1..] {
            let own = v
                .model
                .vertices
                .iter()
                .enumerate()
                .filter(|&(k, p)| {
                    base.model
                        .vertices
                        .get(k)
                        .is_none_or(|b| b.distance(*p) > 0.0)
                })
                .count() as u64;
            let faces = if v.model.faces == base.model.faces {
                0
            } else {
                triangles(&v.model.faces)
            };
            let frames = v
                .regions
                .iter()
                .filter(|(_, c)| matches!(c, RegionChange::Solid(_)))
                .count() as u64;
            atlas_bytes +=
                own * SPARSE_VERTEX_BYTES + faces * TRIANGLE_BYTES + frames * FRAME_BYTES;
        }
    }
    let sizes: Vec<(u64, u64)> = choices
        .par_iter()
        .map(|choice| {
            atlas.assemble(choice).map(|a| {
                let full = a.model.vertices.len() as u64 * VERTEX_BYTES
                    + triangles(&a.model.faces) * TRIANGLE_BYTES;
                let placed = choice.picks.iter().map(|p| p.len() as u64).sum::<u64>();
                (full, placed * INSTANCE_BYTES)
            })
        })
        .collect::<Result<_>>()?;
    let full_bytes = sizes.iter().map(|s| s.0).sum();
    let shared_bytes = atlas_bytes + sizes.iter().map(|s| s.1).sum::<u64>();
    let variations = atlas
        .graphs()
        .first()
        .map(|g| g.nodes.iter().map(Vec::len).max().unwrap_or(0))
        .unwrap_or(0);
    Ok(MemoryReport {
        components: d.components.len(),
        variations,
        objects: choices.len(),
        original_bytes,
        atlas_bytes,
        shared_bytes,
        full_bytes,
        overhead_percent: (atlas_bytes as f64 / original_bytes.max(1) as f64 - 1.0) * 100.0,
    })
}

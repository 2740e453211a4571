//! Polygons as a filled triangle mesh, for showing islands, lakes and fields: a constrained Delaunay triangulation
//! (spade) of the contours' edges and of a grid of inner points, so that the mesh can follow the terrain inside
//! too; the triangles kept are those inside by the even-odd rule (a lake in an island stays open).

use crate::contour::Polygons;
use crate::geom::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Inner points keep this fraction of the spacing from the border, so no sliver triangles hug it.
const BORDER_CLEARANCE: f64 = 0.4;
/// At most this many inner points per side of the contours' bounding box.
const MAX_GRID: f64 = 400.0;

/// A planar triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct TriangleMesh {
    /// Vertex positions, world XY (m): the contours' vertices and the inner points.
    pub vertices: Vec<DVec2>,
    /// Triples of vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Total area of the triangles (m²).
    pub fn area(&self) -> f64 {
        triangles_area(&self.vertices, &self.triangles, |a, b, c| {
            0.5 * (b - a).perp_dot(c - a).abs()
        })
    }
}

/// The summed area of `triangles` (indices into `vertices`), `area` giving each from its three corners.
pub(crate) fn triangles_area<V: Copy>(
    vertices: &[V],
    triangles: &[[u32; 3]],
    area: impl Fn(V, V, V) -> f64,
) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            area(a, b, c)
        })
        .sum()
}

/// The filled mesh of `polygons` with inner points about `spacing` apart (0 or less: none). Self-crossing contour
/// edges are kept where they do not cross an edge already constrained.
pub fn triangulate(polygons: &Polygons, spacing: f64) -> TriangleMesh {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for contour in polygons.contours() {
        let handles: Vec<_> = contour
            .iter()
            .filter_map(|p| {
                lo = lo.min(*p);
                hi = hi.max(*p);
                cdt.insert(Point2::new(p.x, p.y)).ok()
            })
            .collect();
        for i in 0..handles.len() {
            let (a, b) = (handles[i], handles[(i + 1) % handles.len()]);
            if a != b {
                cdt.try_add_constraint(a, b);
            }
        }
    }
    if spacing > 0.0 && lo.x < hi.x {
        let step = spacing.max((hi - lo).max_element() / MAX_GRID);
        let (nx, ny) = (
            ((hi.x - lo.x) / step) as usize,
            ((hi.y - lo.y) / step) as usize,
        );
        for j in 0..=ny {
            for i in 0..=nx {
                let p = lo + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * step;
                if polygons.contains(p) && polygons.distance(p, step) > BORDER_CLEARANCE * step {
                    // a point the triangulation rejects (never for finite input) is only a missing inner vertex
                    let _ = cdt.insert(Point2::new(p.x, p.y));
                }
            }
        }
    }
    let vertices: Vec<DVec2> = cdt
        .vertices()
        .map(|v| DVec2::new(v.position().x, v.position().y))
        .collect();
    let triangles = cdt
        .inner_faces()
        .filter_map(|f| {
            let t = f.vertices().map(|v| v.fix().index() as u32);
            let centroid = t.iter().map(|&i| vertices[i as usize]).sum::<DVec2>() / 3.0;
            polygons.contains(centroid).then_some(t)
        })
        .collect();
    TriangleMesh {
        vertices,
        triangles,
    }
}

//! Maps an artist makes in the scene, brought onto the terrain's grid so that a color can learn them like slope
//! (Section 3: external maps are any scalar field on the ground): a value per vertex of a mesh (a weight-painted
//! vertex group, a float or color attribute, an image read through the UVs), interpolated in each triangle as the
//! heights are, and the distance to some geometry (water, rocks, roads) by an exact distance transform.
//!
//! Names: the maps "elevation" and "slope" are the terrain's own and cannot be replaced.

use crate::distance::distance_transform;
use crate::error::{check, Error, Result};
use crate::geom::check_triangle_indices;
use crate::terrain::{rasterize, Heightfield};
use glam::DVec2;

/// The terrain's own maps, which a scene map may not replace.
const OWN_MAPS: [&str; 2] = ["elevation", "slope"];

impl Heightfield {
    /// Adds the map `name` from a value per vertex of a triangle mesh (world XYZ vertices, as the terrain was
    /// made from), interpolated linearly in each triangle onto the grid's nodes. Where triangles overlap in XY the
    /// largest value wins; nodes no triangle covers take their nearest covered node's value.
    pub fn add_mesh_map(
        &mut self,
        name: &str,
        vertices: &[[f64; 3]],
        triangles: &[[u32; 3]],
        values: &[f64],
    ) -> Result<()> {
        check_scene_map_name(name)?;
        check::same_len(
            &format!("values of map '{name}'"),
            values.len(),
            vertices.len(),
        )?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("value {k} of map '{name}'"),
                "is not finite",
            ));
        }
        check_triangle_indices("triangle", vertices.len(), triangles)?;
        // the value stands in for the height: the same planar interpolation per triangle
        let lifted: Vec<[f64; 3]> = vertices
            .iter()
            .zip(values)
            .map(|(v, value)| [v[0], v[1], *value])
            .collect();
        let values = rasterize(
            &lifted,
            triangles,
            self.origin,
            self.cell,
            self.cell,
            self.nx,
            self.ny,
        );
        self.add_map(name, values)
    }

    /// Adds the map `name`: the XY distance (m) from every node to the nearest of the given geometry — points
    /// (`vertices` that no edge or triangle uses count as points too), `edges` between vertices and the area of
    /// `triangles`. Geometry is marked on the nodes it covers (edges sampled at a quarter cell), so distances are
    /// exact to within about half a cell. An error when none of it lies over the terrain.
    pub fn add_distance_map(
        &mut self,
        name: &str,
        vertices: &[DVec2],
        edges: &[[u32; 2]],
        triangles: &[[u32; 3]],
    ) -> Result<()> {
        check_scene_map_name(name)?;
        if let Some(k) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("vertex {k} of map '{name}'"),
                "is not finite",
            ));
        }
        let n = vertices.len();
        if let Some(k) = edges
            .iter()
            .position(|e| e.iter().any(|&i| i as usize >= n))
        {
            return Err(Error::invalid(
                format!("edge {k} of map '{name}'"),
                format!("refers to a vertex beyond the {n} given"),
            ));
        }
        check_triangle_indices("triangle", n, triangles)?;
        let mut mask = vec![false; self.nx * self.ny];
        for v in vertices {
            self.mark(&mut mask, *v);
        }
        for e in edges {
            let (a, b) = (vertices[e[0] as usize], vertices[e[1] as usize]);
            let steps = ((b - a).length() / (0.25 * self.cell)).ceil().max(1.0);
            // beyond the work budget a grid's edge is sampled no finer than its nodes can tell apart
            let steps = steps.min(4.0 * (self.nx + self.ny) as f64) as usize;
            for s in 1..steps {
                self.mark(&mut mask, a.lerp(b, s as f64 / steps as f64));
            }
        }
        for t in triangles {
            self.mark_triangle(&mut mask, t.map(|i| vertices[i as usize]));
        }
        if !mask.iter().any(|m| *m) {
            return Err(Error::invalid(
                format!("map '{name}'"),
                "measures the distance to geometry none of which lies over the terrain",
            ));
        }
        let distances = distance_transform(self.nx, self.ny, self.cell, &mask);
        self.add_map(name, distances)
    }

    /// Marks the node nearest `p` when it lies on the grid (within half a cell of its border).
    fn mark(&self, mask: &mut [bool], p: DVec2) {
        let g = (p - self.origin) / self.cell;
        let (i, j) = (g.x.round(), g.y.round());
        if i >= 0.0 && j >= 0.0 && (i as usize) < self.nx && (j as usize) < self.ny {
            mask[j as usize * self.nx + i as usize] = true;
        }
    }

    /// Marks the nodes inside a triangle (its vertices are marked with the points).
    fn mark_triangle(&self, mask: &mut [bool], t: [DVec2; 3]) {
        let lo = ((t[0].min(t[1]).min(t[2]) - self.origin) / self.cell).ceil();
        let hi = ((t[0].max(t[1]).max(t[2]) - self.origin) / self.cell).floor();
        let (i0, j0) = (lo.x.max(0.0) as usize, lo.y.max(0.0) as usize);
        if hi.x < 0.0 || hi.y < 0.0 {
            return;
        }
        let (i1, j1) = (
            (hi.x as usize).min(self.nx - 1),
            (hi.y as usize).min(self.ny - 1),
        );
        let side = |a: DVec2, b: DVec2, p: DVec2| (b - a).perp_dot(p - a);
        let area = side(t[0], t[1], t[2]);
        if area == 0.0 {
            return;
        }
        for j in j0..=j1 {
            for i in i0..=i1 {
                let p = self.origin + DVec2::new(i as f64, j as f64) * self.cell;
                let inside = (0..3).all(|k| side(t[k], t[(k + 1) % 3], p) * area >= 0.0);
                if inside {
                    mask[j * self.nx + i] = true;
                }
            }
        }
    }
}

fn check_scene_map_name(name: &str) -> Result<()> {
    if name.is_empty() || OWN_MAPS.contains(&name) {
        return Err(Error::invalid(
            format!("map name '{name}'"),
            "is empty or the name of one of the terrain's own maps (elevation, slope)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat 100 m × 100 m terrain of 1 m cells, and its grid as a mesh of two triangles per cell.
    fn flat() -> (Heightfield, Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let n = 101;
        let hf = Heightfield::new(DVec2::ZERO, 1.0, n, n, vec![0.0; n * n]).unwrap();
        let vertices = (0..n * n)
            .map(|k| [(k % n) as f64, (k / n) as f64, 0.0])
            .collect();
        let mut triangles = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let a = (j * n + i) as u32;
                let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
                triangles.extend([[a, b, d], [a, d, c]]);
            }
        }
        (hf, vertices, triangles)
    }

    #[test]
    fn a_vertex_map_is_read_back_between_vertices() {
        let (mut hf, vertices, triangles) = flat();
        let values: Vec<f64> = vertices.iter().map(|v| 0.01 * v[0] + 0.5).collect();
        hf.add_mesh_map("group:moisture", &vertices, &triangles, &values)
            .unwrap();
        for x in [0.0, 12.25, 50.5, 99.9] {
            let got = hf.map_at("group:moisture", DVec2::new(x, 33.3)).unwrap();
            assert!((got - (0.01 * x + 0.5)).abs() < 1e-5, "{x}: {got}");
        }
    }

    #[test]
    fn a_distance_map_measures_to_a_segment_and_a_triangle() {
        let (mut hf, ..) = flat();
        // a river along y = 20 from x = 10 to 90, and a pond: the triangle (60, 60), (80, 60), (70, 80)
        let vertices = [
            (10.0, 20.0),
            (90.0, 20.0),
            (60.0, 60.0),
            (80.0, 60.0),
            (70.0, 80.0),
        ]
        .map(|(x, y)| DVec2::new(x, y));
        hf.add_distance_map("distance:water", &vertices, &[[0, 1]], &[[2, 3, 4]])
            .unwrap();
        let at = |x, y| hf.map_at("distance:water", DVec2::new(x, y)).unwrap();
        assert!(at(50.0, 20.0) < 1e-6);
        assert!((at(50.0, 30.0) - 10.0).abs() < 0.75, "{}", at(50.0, 30.0));
        assert!((at(0.0, 20.0) - 10.0).abs() < 0.75, "{}", at(0.0, 20.0));
        assert!(at(70.0, 65.0) < 1e-6, "inside the pond");
        assert!((at(70.0, 50.0) - 10.0).abs() < 0.75, "{}", at(70.0, 50.0));
    }

    #[test]
    fn bad_scene_maps_are_refused() {
        let (mut hf, vertices, triangles) = flat();
        let ones = vec![1.0; vertices.len()];
        assert!(hf
            .add_mesh_map("slope", &vertices, &triangles, &ones)
            .is_err());
        assert!(hf
            .add_mesh_map("group:a", &vertices, &triangles, &ones[1..])
            .is_err());
        let mut nan = ones.clone();
        nan[7] = f64::NAN;
        assert!(hf
            .add_mesh_map("group:a", &vertices, &triangles, &nan)
            .is_err());
        let far = [DVec2::new(500.0, 500.0)];
        let err = hf.add_distance_map("distance:far", &far, &[], &[]);
        assert!(err.is_err_and(|e| e.to_string().contains("none of which")));
        assert!(hf
            .add_distance_map("distance:bad", &far, &[[0, 1]], &[])
            .is_err());
    }
}

//! Horizontal displacement (thesis 4.4.2 "Overhang Constraints": "we generate a horizontal displacement map based
//! on the same diffusion technique"): a plan vector fixed on some cells, each channel diffused like the heights.
//! On a heightfield the map is applied by resampling, `H'(p) = H(p − D(p))`, which shifts relief sideways
//! (a heightfield cannot hold a true overhang; the displacement map can drive a mesh that does).

use super::diffusion::{diffuse, Constraints, Diffusion, DiffusionOptions};
use crate::error::{Error, Result};
use crate::terrain::Heightfield;
use glam::DVec2;

/// Plan displacements fixed on cells: the two channels share their fixed cells.
#[derive(Clone, Debug)]
pub struct HorizontalConstraints {
    /// The X component of the fixed displacements (m).
    pub x: Constraints,
    /// The Y component of the fixed displacements (m).
    pub y: Constraints,
}

impl HorizontalConstraints {
    /// No constraint on the grid of `terrain`.
    pub fn for_terrain(terrain: &Heightfield) -> HorizontalConstraints {
        HorizontalConstraints {
            x: Constraints::for_terrain(terrain),
            y: Constraints::for_terrain(terrain),
        }
    }

    /// Fixes cell `(i, j)` at the plan displacement `v` unless it is already fixed; whether it was set.
    pub(crate) fn set_if_free(&mut self, i: usize, j: usize, v: DVec2) -> Result<bool> {
        if !v.is_finite() {
            return Err(Error::invalid(
                format!("the horizontal displacement at cell ({i}, {j})"),
                format!("({}, {}) is not finite", v.x, v.y),
            ));
        }
        if self.x.get(i, j).is_some() {
            return Ok(false);
        }
        self.x.set(i, j, v.x)?;
        self.y.set(i, j, v.y)?;
        Ok(true)
    }

    /// Fixes every node a plan polyline passes through (sampled at most half a cell apart) at the displacement
    /// `v`; parts off the grid are skipped. Returns the number of nodes written.
    pub fn polyline(&mut self, origin: DVec2, points: &[DVec2], v: DVec2) -> Result<usize> {
        if points.is_empty() {
            return Err(Error::invalid("the curve", "has no point"));
        }
        if let Some(k) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::invalid(
                "the curve",
                format!("point {k} is not finite"),
            ));
        }
        let cell = self.x.cell;
        let (nx, ny) = (self.x.nx, self.x.ny);
        let mut written = 0;
        let mut visit = |p: DVec2, this: &mut Self| -> Result<()> {
            let f = ((p - origin) / cell).round();
            let on_grid = f.x >= 0.0 && f.y >= 0.0 && f.x < nx as f64 && f.y < ny as f64;
            if on_grid && this.set_if_free(f.x as usize, f.y as usize, v)? {
                written += 1;
            }
            Ok(())
        };
        visit(points[0], self)?;
        for w in points.windows(2) {
            let steps = ((w[0].distance(w[1]) / (0.5 * cell)).ceil() as usize).clamp(1, 10_000_000);
            for s in 1..=steps {
                visit(w[0].lerp(w[1], s as f64 / steps as f64), self)?;
            }
        }
        Ok(written)
    }
}

/// The two diffused channels of a horizontal displacement map.
#[derive(Clone, Debug)]
pub struct HorizontalDisplacement {
    /// The X component of the displacement (m).
    pub x: Diffusion,
    /// The Y component of the displacement (m).
    pub y: Diffusion,
}

/// Diffuses each channel (the same solver, falloff and tolerance as [`diffuse`]).
pub fn diffuse_horizontal(
    constraints: &HorizontalConstraints,
    options: &DiffusionOptions,
) -> Result<HorizontalDisplacement> {
    if constraints.x.nx != constraints.y.nx || constraints.x.ny != constraints.y.ny {
        return Err(Error::invalid(
            "a horizontal displacement",
            "its two channels have different grids",
        ));
    }
    // the falloff is measured from the same fixed cells in both channels
    Ok(HorizontalDisplacement {
        x: diffuse(&constraints.x, options)?,
        y: diffuse(&constraints.y, options)?,
    })
}

impl HorizontalDisplacement {
    /// The terrain shifted by the map: `H'(p) = H(p − D(p))` (bilinear, clamped to the grid).
    pub fn apply(&self, terrain: &Heightfield) -> Result<Heightfield> {
        let (nx, ny) = (terrain.nx, terrain.ny);
        let fits = |d: &Diffusion| d.nx == nx && d.ny == ny && d.displacement.len() == nx * ny;
        if !(fits(&self.x) && fits(&self.y)) {
            return Err(Error::invalid(
                format!("a {}x{} horizontal displacement", self.x.nx, self.x.ny),
                format!("does not fit a {nx}x{ny} terrain"),
            ));
        }
        let (lo, hi) = terrain.bbox();
        let heights = (0..nx * ny)
            .map(|k| {
                let p =
                    terrain.origin + DVec2::new((k % nx) as f64, (k / nx) as f64) * terrain.cell;
                let d = DVec2::new(self.x.displacement[k], self.y.displacement[k]);
                let q = (p - d).clamp(lo, hi);
                terrain.height_at(q).unwrap_or(terrain.heights[k] as f64) as f32
            })
            .collect();
        Heightfield::new(terrain.origin, terrain.cell, nx, ny, heights)
    }
}

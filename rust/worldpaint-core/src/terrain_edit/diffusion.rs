//! Diffusion of constraints into a displacement map (thesis 4.4.2, 5.3.3): constrained cells keep their
//! displacement, cells farther than the falloff radius from every constrained cell keep 0, and every other cell
//! becomes the mean of its 4 neighbours (the discrete Laplace equation), solved by multigrid.

use super::multigrid;
use crate::distance::distance_transform;
use crate::error::{check, Error, Result};
use crate::limits;
use crate::terrain::{Heightfield, MAX_AUTO_NODES};
use std::borrow::Cow;

/// Fixed displacements on the cells of a grid (the grid of a heightfield: cell `(i, j)` at
/// `origin + (i, j)·cell`, row-major).
#[derive(Clone, Debug)]
pub struct Constraints {
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) cell: f64,
    /// NaN on free cells.
    values: Vec<f64>,
}

impl Constraints {
    /// No constraint on an `nx × ny` grid of `cell` metres.
    pub fn new(nx: usize, ny: usize, cell: f64) -> Result<Constraints> {
        if nx == 0 || ny == 0 {
            return Err(Error::invalid(
                format!("a constraint grid of {nx}x{ny} cells"),
                "is empty",
            ));
        }
        check::positive("constraint grid cell", cell)?;
        limits::check(
            "a constraint grid",
            nx as f64 * ny as f64,
            4 * MAX_AUTO_NODES as u64,
            "cells",
        )?;
        Ok(Constraints {
            nx,
            ny,
            cell,
            values: vec![f64::NAN; nx.saturating_mul(ny)],
        })
    }

    /// No constraint on the grid of `terrain`.
    pub fn for_terrain(terrain: &Heightfield) -> Constraints {
        Constraints {
            nx: terrain.nx,
            ny: terrain.ny,
            cell: terrain.cell,
            values: vec![f64::NAN; terrain.nx * terrain.ny],
        }
    }

    /// Cells along X.
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// Cells along Y.
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// Cell size (m).
    pub fn cell(&self) -> f64 {
        self.cell
    }

    fn index(&self, i: usize, j: usize) -> Result<usize> {
        if i >= self.nx || j >= self.ny {
            return Err(Error::invalid(
                format!("constraint cell ({i}, {j})"),
                format!("lies outside the {}x{} grid", self.nx, self.ny),
            ));
        }
        Ok(j * self.nx + i)
    }

    /// Fixes cell `(i, j)` at `value`, replacing any earlier value.
    pub fn set(&mut self, i: usize, j: usize, value: f64) -> Result<()> {
        let k = self.index(i, j)?;
        check::finite(&format!("the constraint at cell ({i}, {j})"), value)?;
        self.values[k] = value;
        Ok(())
    }

    /// Fixes cell `(i, j)` at `value` unless it is already fixed; whether it was set.
    pub(crate) fn set_if_free(&mut self, i: usize, j: usize, value: f64) -> Result<bool> {
        let k = self.index(i, j)?;
        if !self.values[k].is_nan() {
            return Ok(false);
        }
        self.set(i, j, value)?;
        Ok(true)
    }

    /// The fixed value of cell `(i, j)`, if any (`None` also outside the grid).
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        let k = self.index(i, j).ok()?;
        let v = self.values[k];
        (!v.is_nan()).then_some(v)
    }

    /// Frees cell `(i, j)`.
    pub fn clear(&mut self, i: usize, j: usize) -> Result<()> {
        let k = self.index(i, j)?;
        self.values[k] = f64::NAN;
        Ok(())
    }

    /// Number of fixed cells.
    pub fn count(&self) -> usize {
        self.values.iter().filter(|v| !v.is_nan()).count()
    }

    /// Whether each cell is fixed, row-major.
    pub fn mask(&self) -> Vec<bool> {
        self.values.iter().map(|v| !v.is_nan()).collect()
    }
}

/// How to diffuse.
#[derive(Clone, Debug)]
pub struct DiffusionOptions {
    /// Cells farther than this (m) from every constrained cell keep a displacement of 0; `None`: no limit (the
    /// displacement then spreads over the whole grid, with no flux across its border).
    pub falloff: Option<f64>,
    /// Stop when no free cell differs from the mean of its neighbours by more than this fraction of the largest
    /// constraint magnitude.
    pub tolerance: f64,
    /// Most iterations: preconditioned conjugate-gradient steps (one V-cycle each), or sweeps for [`diffuse_jacobi`].
    pub max_cycles: usize,
}

impl Default for DiffusionOptions {
    fn default() -> Self {
        DiffusionOptions {
            falloff: None,
            tolerance: 1e-5,
            max_cycles: 100,
        }
    }
}

/// A displacement map and what the solver did.
#[derive(Clone, Debug)]
pub struct Diffusion {
    /// Cells along X (those of the constraints).
    pub nx: usize,
    /// Cells along Y.
    pub ny: usize,
    /// Row-major displacement `D` (m).
    pub displacement: Vec<f64>,
    /// Iterations after the first guess: conjugate-gradient steps, each preconditioned by one V-cycle (multigrid),
    /// or Jacobi sweeps.
    pub cycles: usize,
    /// Largest `|mean of neighbours − value|` over the free cells at the end (m).
    pub residual: f64,
    /// The absolute tolerance the residual was held to (m).
    pub tolerance: f64,
    /// Whether the residual reached the tolerance.
    pub converged: bool,
    /// Cells solved for (the box around the free cells), fixed ones included.
    pub solved_cells: usize,
}

impl Diffusion {
    /// `H + D` on the terrain whose grid the constraints were written on.
    pub fn apply(&self, terrain: &Heightfield) -> Result<Heightfield> {
        if terrain.nx != self.nx || terrain.ny != self.ny {
            return Err(Error::invalid(
                format!("a {}x{} displacement", self.nx, self.ny),
                format!("does not fit a {}x{} terrain", terrain.nx, terrain.ny),
            ));
        }
        displaced(terrain, &self.displacement)
    }
}

/// `terrain` with `displacement` (one value a node, of the same grid) added to its heights, its slope made anew;
/// its other maps (water, land use, ...) describe the same ground and are kept.
pub(crate) fn displaced(terrain: &Heightfield, displacement: &[f64]) -> Result<Heightfield> {
    let heights = terrain
        .heights
        .iter()
        .zip(displacement)
        .map(|(h, d)| (*h as f64 + d) as f32)
        .collect();
    let mut out = Heightfield::new(
        terrain.origin,
        terrain.cell,
        terrain.nx,
        terrain.ny,
        heights,
    )?;
    for (name, map) in &terrain.maps {
        out.maps.entry(name.clone()).or_insert_with(|| map.clone());
    }
    Ok(out)
}

/// The solver to run.
#[derive(Clone, Copy)]
enum Method {
    Multigrid,
    Jacobi,
}

/// Diffuses the constraints into a displacement map by multigrid.
pub fn diffuse(constraints: &Constraints, options: &DiffusionOptions) -> Result<Diffusion> {
    run(constraints, options, Method::Multigrid)
}

/// The same diffusion by plain Jacobi iteration (each free cell the mean of its neighbours' previous values), to
/// the same residual or `options.max_cycles` iterations: the baseline multigrid is measured against.
pub fn diffuse_jacobi(constraints: &Constraints, options: &DiffusionOptions) -> Result<Diffusion> {
    run(constraints, options, Method::Jacobi)
}

fn run(c: &Constraints, options: &DiffusionOptions, method: Method) -> Result<Diffusion> {
    check_options(options)?;
    let (nx, ny) = (c.nx, c.ny);
    let scale = c
        .values
        .iter()
        .filter(|v| !v.is_nan())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let tolerance = options.tolerance * scale;
    let nothing = |solved_cells| Diffusion {
        nx,
        ny,
        displacement: vec![0.0; nx * ny],
        cycles: 0,
        residual: 0.0,
        tolerance,
        converged: true,
        solved_cells,
    };
    if scale == 0.0 {
        // no constraint, or all of them 0: nothing moves
        return Ok(nothing(0));
    }
    let fixed = fixed_with_falloff(c, options.falloff);
    let Some(b) = SolveBox::around_free(&fixed, nx, ny) else {
        // every cell is fixed
        return Ok(Diffusion {
            displacement: fixed,
            ..nothing(0)
        });
    };
    let boxed = b.cut(&fixed);
    // run on a worker of the thread pool: the solver's many short parallel loops then start there instead of
    // each being handed over from the calling thread
    let (bx, by) = (b.width(), b.height());
    let solved = rayon::scope(|_| match method {
        Method::Multigrid => multigrid::solve(bx, by, &boxed, tolerance, options.max_cycles),
        Method::Jacobi => multigrid::jacobi(bx, by, &boxed, tolerance, options.max_cycles),
    });
    Ok(Diffusion {
        nx,
        ny,
        displacement: b.paste(&fixed, solved.u),
        cycles: solved.cycles,
        residual: solved.residual,
        tolerance,
        converged: solved.residual <= tolerance,
        solved_cells: bx * by,
    })
}

/// Refuses a tolerance that is not positive and a negative falloff radius.
fn check_options(options: &DiffusionOptions) -> Result<()> {
    check::positive("diffusion tolerance", options.tolerance)?;
    if let Some(r) = options.falloff {
        if !(r >= 0.0) {
            return Err(Error::OutOfRange {
                what: "falloff radius".into(),
                rule: "zero or more".into(),
                value: r,
            });
        }
    }
    Ok(())
}

/// The constraints' values (NaN on free cells), with the free cells farther than `falloff` from every
/// constrained cell fixed at 0.
fn fixed_with_falloff(c: &Constraints, falloff: Option<f64>) -> Vec<f64> {
    let mut fixed = c.values.clone();
    if let Some(radius) = falloff {
        let distance = distance_transform(c.nx, c.ny, c.cell, &c.mask());
        for (v, d) in fixed.iter_mut().zip(&distance) {
            if v.is_nan() && (*d as f64) > radius {
                *v = 0.0;
            }
        }
    }
    fixed
}

/// The box of cells solved for: the free cells' bounds with one ring of fixed cells (or the grid's border)
/// around them, so cutting it out changes nothing.
struct SolveBox {
    nx: usize,
    ny: usize,
    i0: usize,
    j0: usize,
    i1: usize,
    j1: usize,
}

impl SolveBox {
    /// The box around the free (NaN) cells of the row-major `fixed`; `None` when every cell is fixed.
    fn around_free(fixed: &[f64], nx: usize, ny: usize) -> Option<SolveBox> {
        let (mut i0, mut j0, mut i1, mut j1) = (nx, ny, 0, 0);
        for (k, v) in fixed.iter().enumerate() {
            if v.is_nan() {
                let (i, j) = (k % nx, k / nx);
                i0 = i0.min(i);
                j0 = j0.min(j);
                i1 = i1.max(i);
                j1 = j1.max(j);
            }
        }
        if i0 > i1 {
            return None;
        }
        Some(SolveBox {
            nx,
            ny,
            i0: i0.saturating_sub(1),
            j0: j0.saturating_sub(1),
            i1: (i1 + 1).min(nx - 1),
            j1: (j1 + 1).min(ny - 1),
        })
    }

    fn width(&self) -> usize {
        self.i1 - self.i0 + 1
    }

    fn height(&self) -> usize {
        self.j1 - self.j0 + 1
    }

    fn whole(&self) -> bool {
        self.width() == self.nx && self.height() == self.ny
    }

    /// The box's part of a row-major grid (the grid itself when the box is whole).
    fn cut<'a>(&self, grid: &'a [f64]) -> Cow<'a, [f64]> {
        if self.whole() {
            Cow::Borrowed(grid)
        } else {
            let (nx, i0, i1) = (self.nx, self.i0, self.i1);
            Cow::Owned(
                (self.j0..=self.j1)
                    .flat_map(|j| grid[j * nx + i0..=j * nx + i1].iter().copied())
                    .collect(),
            )
        }
    }

    /// The whole grid: the box's solution `u` inside, the fixed values (0 on free cells) outside.
    fn paste(&self, fixed: &[f64], u: Vec<f64>) -> Vec<f64> {
        if self.whole() {
            return u;
        }
        let (nx, i0, i1) = (self.nx, self.i0, self.i1);
        let mut d: Vec<f64> = fixed
            .iter()
            .map(|v| if v.is_nan() { 0.0 } else { *v })
            .collect();
        for (bj, row) in u.chunks(self.width()).enumerate() {
            let j = self.j0 + bj;
            d[j * nx + i0..=j * nx + i1].copy_from_slice(row);
        }
        d
    }
}
/// Largest `|mean of the 4 neighbours − value|` over the nodes of the row-major `nx` × `ny` grid `values` that
/// `free` accepts (by index): the residual of the discrete Laplace equation, computed without the solvers' code.
pub fn laplace_residual(values: &[f64], nx: usize, ny: usize, free: impl Fn(usize) -> bool) -> f64 {
    let mut worst = 0.0f64;
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if !free(k) {
                continue;
            }
            let mut n = Vec::with_capacity(4);
            if i > 0 {
                n.push(values[k - 1]);
            }
            if i + 1 < nx {
                n.push(values[k + 1]);
            }
            if j > 0 {
                n.push(values[k - nx]);
            }
            if j + 1 < ny {
                n.push(values[k + nx]);
            }
            worst = worst.max((n.iter().sum::<f64>() / n.len() as f64 - values[k]).abs());
        }
    }
    worst
}

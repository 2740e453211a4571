//! A map of colors over a world (issue 43): which palette color fills which part of it, as a grid of labels and a
//! legend (label → color), and across each boundary a transition band in which the two colors blend by
//! displacement interpolation, as the Gradient tool's bands do (`tools::gradient`), so that density and pair
//! correlation change smoothly and no border shows.
//!
//! Readings chosen:
//! * A point takes the color of the map cell it lies in; its distance to the nearest cell of another color `b`
//!   is read from an exact distance transform per color, interpolated between cell centres, so the band follows
//!   the boundary more finely than the map's cells.
//! * Within half the band of the boundary, the point's paint is `a` and `b` interpolated at `t`, which runs from 0
//!   at half a band inside `a` to 1 at half a band inside `b`, quantized into slabs one region of influence wide
//!   (as the Gradient tool's adaptive bands, and at least two); where three colors meet, the nearest other color
//!   blends.
//! * A tile is painted in blocks: the tile is split in halves, along its longer side, until each block has one
//!   paint (down to half a slab); each block is synthesized in turn, conditioned on the tile's earlier neighbours
//!   and on the blocks before it. A tile away from every boundary is one block, painted as a one-color world's.

use crate::distance::distance_transform;
use crate::error::check;
use crate::geom::DVec2;
use crate::interpolate::interpolate_colors;
use crate::palette::Color;
use crate::scene::Category;
use crate::{Error, Result};
use std::collections::HashMap;

/// Width of the transition band by default, in regions of influence of the map's colors ("a few").
pub const DEFAULT_BAND_RADII: f64 = 3.0;

/// A grid of labels over the world: cell (`i`, `j`) is the square from `origin + (i, j) · cell` to
/// `origin + (i + 1, j + 1) · cell`, its label `labels[j · nx + i]` (row 0 at the smallest Y).
#[derive(Clone, Debug, PartialEq)]
pub struct LabelGrid {
    /// The grid's corner with the smaller coordinates, world XY (m).
    pub origin: DVec2,
    /// Side of a cell (m).
    pub cell: f64,
    /// Cells along X.
    pub nx: usize,
    /// Cells along Y.
    pub ny: usize,
    /// A label per cell, row by row.
    pub labels: Vec<u32>,
}

/// What a part of a world is painted with: one of the map's colors, or two of them mixed at one slab of a band.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Paint {
    /// The map's color of this index.
    Pure(usize),
    /// Colors `a` < `b` of the map, interpolated at `t = (slab + 0.5) / slabs`.
    Mix {
        /// The first color (t = 0).
        a: usize,
        /// The second color (t = 1).
        b: usize,
        /// Which slab of the band, from `a`'s side.
        slab: usize,
    },
}

/// A rectangle of a tile and the paint it is synthesized with.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// The corner with the smaller coordinates (m).
    pub min: DVec2,
    /// The corner with the larger coordinates (m).
    pub max: DVec2,
    /// Its paint.
    pub paint: Paint,
}

/// Which colors fill which parts of a world (see the module documentation).
#[derive(Clone, Debug)]
pub struct ColorMap {
    /// The color index of each cell (`None`: the first color everywhere).
    grid: Option<(LabelGrid, Vec<usize>)>,
    colors: Vec<Color>,
    band: f64,
    slabs: usize,
    categories: Vec<Category>,
}

impl ColorMap {
    /// One color everywhere.
    pub fn uniform(color: Color) -> Result<ColorMap> {
        super::paintable(&color)?;
        Ok(ColorMap {
            grid: None,
            band: 0.0,
            slabs: 2,
            categories: color
                .categories
                .iter()
                .map(|c| c.category.clone())
                .collect(),
            colors: vec![color],
        })
    }

    /// The map of `grid`'s labels, each painted with its `legend` color, blending across a band `band` metres wide
    /// (`None`: [`DEFAULT_BAND_RADII`] times the colors' largest region of influence). Refused with a clear message:
    /// a grid whose labels do not match its size, a cell not a positive finite number, a label of the grid with no
    /// legend entry, a label listed twice, a color a world cannot be filled with, a band not finite or negative.
    pub fn new(grid: LabelGrid, legend: Vec<(u32, Color)>, band: Option<f64>) -> Result<ColorMap> {
        check::positive("the map's cell", grid.cell)?;
        check::finite("the map's origin x", grid.origin.x)?;
        check::finite("the map's origin y", grid.origin.y)?;
        check::same_len("the map's labels", grid.labels.len(), grid.nx * grid.ny)?;
        if grid.labels.is_empty() {
            return Err(Error::invalid("the map", "has no cell"));
        }
        if legend.is_empty() {
            return Err(Error::invalid("the map's legend", "has no entry"));
        }
        let mut index = HashMap::new();
        for (k, (label, color)) in legend.iter().enumerate() {
            super::paintable(color)?;
            if index.insert(*label, k).is_some() {
                return Err(Error::invalid(
                    "the map's legend",
                    format!("lists label {label} twice"),
                ));
            }
        }
        let cells = grid
            .labels
            .iter()
            .enumerate()
            .map(|(k, label)| {
                index.get(label).copied().ok_or_else(|| {
                    let centre = grid.origin
                        + (DVec2::new((k % grid.nx) as f64, (k / grid.nx) as f64) + 0.5)
                            * grid.cell;
                    let known: Vec<String> = legend.iter().map(|(l, _)| l.to_string()).collect();
                    Error::invalid(
                        "the map",
                        format!(
                            "its label {label} (first at x {:.1}, y {:.1}) has no legend entry (the legend has {})",
                            centre.x,
                            centre.y,
                            known.join(", ")
                        ),
                    )
                })
            })
            .collect::<Result<Vec<usize>>>()?;
        let colors: Vec<Color> = legend.into_iter().map(|(_, c)| c).collect();
        let influence = largest_radius(&colors);
        let band = match band {
            Some(b) => check::non_negative("the transition band's width", b)?,
            None => DEFAULT_BAND_RADII * influence,
        };
        let slabs = if influence > 0.0 {
            ((band / influence).round() as usize).clamp(2, crate::tools::gradient::MAX_BANDS)
        } else {
            2
        };
        let mut categories: Vec<Category> = Vec::new();
        for c in colors.iter().flat_map(|c| &c.categories) {
            if categories.iter().all(|k| k.name != c.category.name) {
                categories.push(c.category.clone());
            }
        }
        Ok(ColorMap {
            grid: Some((grid, cells)),
            colors,
            band,
            slabs,
            categories,
        })
    }

    /// The colors, in the legend's order.
    pub fn colors(&self) -> &[Color] {
        &self.colors
    }

    /// Every category of the map's colors, each name once, in the legend's order: a tile's categories.
    pub fn categories(&self) -> &[Category] {
        &self.categories
    }

    /// The transition band's width (m).
    pub fn band(&self) -> f64 {
        self.band
    }

    /// The largest region of influence of the colors (m).
    pub fn influence(&self) -> f64 {
        largest_radius(&self.colors)
    }

    /// The largest total density of the colors (instances per m²).
    pub fn max_density(&self) -> f64 {
        self.colors
            .iter()
            .map(|c| c.categories.iter().map(|k| k.density).sum::<f64>())
            .fold(0.0, f64::max)
    }

    /// Refuses a map that does not cover the rectangle `min`–`max` (a cell's width of slack at each side).
    pub fn check_covers(&self, min: DVec2, max: DVec2) -> Result<()> {
        let Some((g, _)) = &self.grid else {
            return Ok(());
        };
        let (lo, hi) = (
            g.origin,
            g.origin + DVec2::new(g.nx as f64, g.ny as f64) * g.cell,
        );
        let slack = g.cell;
        if min.x < lo.x - slack
            || min.y < lo.y - slack
            || max.x > hi.x + slack
            || max.y > hi.y + slack
        {
            return Err(Error::invalid(
                "the map",
                format!(
                    "covers x {:.1}..{:.1}, y {:.1}..{:.1}, not the whole world x {:.1}..{:.1}, y {:.1}..{:.1}",
                    lo.x, hi.x, lo.y, hi.y, min.x, max.x, min.y, max.y
                ),
            ));
        }
        Ok(())
    }

    /// The color of paint `p` (named after the colors it mixes).
    pub fn color_of(&self, p: Paint) -> Result<Color> {
        match p {
            Paint::Pure(k) => Ok(self.colors[k].clone()),
            Paint::Mix { a, b, slab } => {
                let t = (slab as f64 + 0.5) / self.slabs as f64;
                let (ca, cb) = (&self.colors[a], &self.colors[b]);
                interpolate_colors(ca, cb, t, &format!("{} → {} ({t:.2})", ca.name, cb.name))
            }
        }
    }

    /// The blocks the rectangle `min`–`max` (a tile) is painted in, in the order they are synthesized.
    pub fn blocks(&self, min: DVec2, max: DVec2) -> Vec<Block> {
        let Some((grid, cells)) = &self.grid else {
            return vec![Block {
                min,
                max,
                paint: Paint::Pure(0),
            }];
        };
        let field = Field::around(grid, cells, self.colors.len(), min, max, self.band);
        // paint samples half a slab apart, at their cells' centres
        let step = if self.band > 0.0 {
            self.band / self.slabs as f64 / 2.0
        } else {
            grid.cell / 2.0
        };
        let size = max - min;
        let (nx, ny) = (
            ((size.x / step).ceil() as usize).max(1),
            ((size.y / step).ceil() as usize).max(1),
        );
        let (hx, hy) = (size.x / nx as f64, size.y / ny as f64);
        let paints: Vec<Paint> = (0..nx * ny)
            .map(|k| {
                let p =
                    min + DVec2::new(((k % nx) as f64 + 0.5) * hx, ((k / nx) as f64 + 0.5) * hy);
                self.paint_at(&field, p)
            })
            .collect();
        let mut out = Vec::new();
        split(
            &paints,
            nx,
            (0, 0, nx, ny),
            &mut |(i0, j0, i1, j1), paint| {
                let corner = |i: usize, j: usize| {
                    DVec2::new(
                        if i == nx {
                            max.x
                        } else {
                            min.x + i as f64 * hx
                        },
                        if j == ny {
                            max.y
                        } else {
                            min.y + j as f64 * hy
                        },
                    )
                };
                out.push(Block {
                    min: corner(i0, j0),
                    max: corner(i1, j1),
                    paint,
                });
            },
        );
        out
    }

    /// The paint at `p`.
    fn paint_at(&self, field: &Field, p: DVec2) -> Paint {
        let Some(a) = field.color_at(p) else {
            return Paint::Pure(0);
        };
        if self.band <= 0.0 {
            return Paint::Pure(a);
        }
        // the nearest boundary with another color
        let nearest = (0..self.colors.len())
            .filter(|&c| c != a)
            .map(|c| (c, field.distance(c, p)))
            .min_by(|x, y| x.1.total_cmp(&y.1));
        let Some((b, s)) = nearest.filter(|(_, s)| *s < self.band / 2.0) else {
            return Paint::Pure(a);
        };
        // t from `a` towards `b`: 0 half a band inside a, ½ on the boundary
        let t = (0.5 - s.max(0.0) / self.band).clamp(0.0, 0.5);
        let slab = ((t * self.slabs as f64) as usize).min(self.slabs - 1);
        if a < b {
            Paint::Mix { a, b, slab }
        } else {
            Paint::Mix {
                a: b,
                b: a,
                slab: self.slabs - 1 - slab,
            }
        }
    }
}

/// The largest region of influence of `colors` (m).
fn largest_radius(colors: &[Color]) -> f64 {
    colors.iter().map(|c| c.max_radius).fold(0.0, f64::max)
}

/// Splits the cell rectangle `r` = (i0, j0, i1, j1) of the row-major `paints` (`nx` wide) in halves along its
/// longer side until each part has one paint; calls `emit` for each part, in order.
fn split(
    paints: &[Paint],
    nx: usize,
    r: (usize, usize, usize, usize),
    emit: &mut dyn FnMut((usize, usize, usize, usize), Paint),
) {
    let (i0, j0, i1, j1) = r;
    let first = paints[j0 * nx + i0];
    let uniform = (j0..j1).all(|j| (i0..i1).all(|i| paints[j * nx + i] == first));
    if uniform {
        emit(r, first);
    } else if i1 - i0 >= j1 - j0 {
        let mid = (i0 + i1) / 2;
        split(paints, nx, (i0, j0, mid, j1), emit);
        split(paints, nx, (mid, j0, i1, j1), emit);
    } else {
        let mid = (j0 + j1) / 2;
        split(paints, nx, (i0, j0, i1, mid), emit);
        split(paints, nx, (i0, mid, i1, j1), emit);
    }
}

/// The map's cells around a tile and each color's distance field over them.
struct Field<'a> {
    grid: &'a LabelGrid,
    cells: &'a [usize],
    /// The window's first cell and its size in cells.
    i0: usize,
    j0: usize,
    nx: usize,
    ny: usize,
    /// Per color, the distance (m) from each window cell's centre to the nearest centre of that color's cells
    /// (`None`: the color is not in the window).
    distances: Vec<Option<Vec<f32>>>,
}

impl<'a> Field<'a> {
    /// The window of cells within `band` (and a cell) of the rectangle `min`–`max`: every boundary a point of the
    /// rectangle blends across lies in it.
    fn around(
        grid: &'a LabelGrid,
        cells: &'a [usize],
        colors: usize,
        min: DVec2,
        max: DVec2,
        band: f64,
    ) -> Field<'a> {
        let reach = band + 2.0 * grid.cell;
        let index =
            |v: f64, o: f64, n: usize| (((v - o) / grid.cell).floor().max(0.0) as usize).min(n);
        let (i0, i1) = (
            index(min.x - reach, grid.origin.x, grid.nx),
            index(max.x + reach, grid.origin.x, grid.nx - 1) + 1,
        );
        let (j0, j1) = (
            index(min.y - reach, grid.origin.y, grid.ny),
            index(max.y + reach, grid.origin.y, grid.ny - 1) + 1,
        );
        let (i0, j0) = (i0.min(i1 - 1), j0.min(j1 - 1));
        let (nx, ny) = (i1 - i0, j1 - j0);
        let distances = (0..colors)
            .map(|c| {
                let mask: Vec<bool> = (0..nx * ny)
                    .map(|k| cells[(j0 + k / nx) * grid.nx + i0 + k % nx] == c)
                    .collect();
                mask.iter()
                    .any(|m| *m)
                    .then(|| distance_transform(nx, ny, grid.cell, &mask))
            })
            .collect();
        Field {
            grid,
            cells,
            i0,
            j0,
            nx,
            ny,
            distances,
        }
    }

    /// The color of the map cell `p` lies in (the nearest cell for a point off the map).
    fn color_at(&self, p: DVec2) -> Option<usize> {
        let g = self.grid;
        let q = (p - g.origin) / g.cell;
        let i = (q.x.floor().max(0.0) as usize).min(g.nx - 1);
        let j = (q.y.floor().max(0.0) as usize).min(g.ny - 1);
        self.cells.get(j * g.nx + i).copied()
    }

    /// The distance (m) from `p` to the nearest cell of color `c`: the distance between cell centres interpolated
    /// bilinearly at `p`, less half a cell (0 on the boundary, half a cell at the centre of a cell next to it).
    fn distance(&self, c: usize, p: DVec2) -> f64 {
        let Some(d) = &self.distances[c] else {
            return f64::INFINITY;
        };
        let g = self.grid;
        // window coordinates of p, in cells, from the first cell's centre
        let q = (p - g.origin) / g.cell - DVec2::new(self.i0 as f64, self.j0 as f64) - 0.5;
        let x = q.x.clamp(0.0, (self.nx - 1) as f64);
        let y = q.y.clamp(0.0, (self.ny - 1) as f64);
        let (ix, iy) = (
            (x as usize).min(self.nx.saturating_sub(2)),
            (y as usize).min(self.ny.saturating_sub(2)),
        );
        let (fx, fy) = (x - ix as f64, y - iy as f64);
        let at = |i: usize, j: usize| d[j.min(self.ny - 1) * self.nx + i.min(self.nx - 1)] as f64;
        let v = (at(ix, iy) * (1.0 - fx) + at(ix + 1, iy) * fx) * (1.0 - fy)
            + (at(ix, iy + 1) * (1.0 - fx) + at(ix + 1, iy + 1) * fx) * fy;
        (v - 0.5 * g.cell).max(0.0)
    }
}

//! The height of a triangle mesh under points, where a ray cast down from above meets it first: the add-on snaps its
//! point clouds onto their terrain mesh with it. Exact on any mesh (irregular triangles, holes, overhangs), where a
//! [`crate::Heightfield`] samples a grid.
//!
//! The triangles are binned by a uniform XY grid in compressed rows: a count per cell, their prefix sums, then the
//! slots filled in triangle order. A slot holds its own copy of what the test reads of its triangle, so a point
//! reads its cell's candidates in one run of memory. A point takes the highest triangle of its cell that holds it.
//! Coordinates are float32 about the mesh's XY corner, which keeps sub-millimetre precision over tens of kilometres.

use super::{check_triangle_indices, DVec2};
use crate::error::Result;
use crate::limits;
use rayon::prelude::*;
use std::ops::Range;

/// Barycentric slack: a point on an edge between two triangles is in both (float32 rounding would miss both).
const INSIDE: f32 = 1e-5;
/// The grid's cells hold about this many triangles' bounding boxes.
const TRIANGLES_PER_CELL: f64 = 4.0;
/// The grid has at most this many cells along its longer side (its cells grow for a mesh of sparse triangles).
const MAX_CELLS_PER_SIDE: f64 = 4096.0;
/// A triangle whose XY edges span no more than this (|det|) is vertical: a vertical ray never meets it.
const VERTICAL: f64 = 1e-12;
/// Bands of grid rows binned at once per thread: each band reads every triangle's box, and more bands than
/// threads even out their loads.
const BANDS_PER_THREAD: usize = 4;

/// What the test of a point reads of one triangle, about the mesh's XY corner: its first corner (x, y, z), its edges
/// to the second and the third corner (x, y, z each), and one over the determinant of the edges' XY; 40 bytes. (An
/// array rather than a struct, so that the slots are allocated zeroed and their memory is first touched by the
/// threads that fill them.)
type Slot = [f32; 10];

/// The height of the triangle of `slot` at the local XY point, when the point lies in it.
#[inline]
fn height_in(slot: &Slot, x: f32, y: f32) -> Option<f32> {
    let [ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, inv_det] = *slot;
    let (dx, dy) = (x - ax, y - ay);
    let u = (dx * e2y - dy * e2x) * inv_det;
    let v = (e1x * dy - e1y * dx) * inv_det;
    let inside = u >= -INSIDE && v >= -INSIDE && u + v <= 1.0 + INSIDE;
    inside.then_some(az + u * e1z + v * e2z)
}

/// A triangle that can be met from above: its slot and its XY box about the mesh's corner.
struct Upright {
    slot: Slot,
    lo: DVec2,
    hi: DVec2,
}

/// The triangle `t` of the mesh about `origin`, unless it is vertical or has a vertex that is not a finite number.
fn upright(vertices: &[[f64; 3]], origin: DVec2, t: &[u32; 3]) -> Option<Upright> {
    let local = |i: u32| {
        let [x, y, z] = vertices[i as usize];
        [x - origin.x, y - origin.y, z]
    };
    let (a, b, c) = (local(t[0]), local(t[1]), local(t[2]));
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    // (coordinates far enough apart overflow, which leaves the triangle out too)
    if !(det.abs() > VERTICAL && det.is_finite())
        || [a, e1, e2].iter().flatten().any(|v| !v.is_finite())
    {
        return None;
    }
    let corners = [
        DVec2::new(a[0], a[1]),
        DVec2::new(a[0] + e1[0], a[1] + e1[1]),
        DVec2::new(a[0] + e2[0], a[1] + e2[1]),
    ];
    let f32s = |v: [f64; 3]| v.map(|c| c as f32);
    let ([ax, ay, az], [e1x, e1y, e1z], [e2x, e2y, e2z]) = (f32s(a), f32s(e1), f32s(e2));
    Some(Upright {
        slot: [ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, (1.0 / det) as f32],
        lo: corners[0].min(corners[1]).min(corners[2]),
        hi: corners[0].max(corners[1]).max(corners[2]),
    })
}

/// The cells a triangle's box meets, as (first column, first row, last column, last row); 16 bits each, since the
/// grid has at most 4,097 cells a side.
type CellBox = [u16; 4];

/// The cells (`j * nx + i`) of the box `b` in the grid rows `rows`, row by row.
fn cells_in(b: &CellBox, rows: &Range<usize>, nx: usize) -> impl Iterator<Item = usize> {
    let [i0, j0, i1, j1] = b.map(usize::from);
    (j0.max(rows.start)..(j1 + 1).min(rows.end))
        .flat_map(move |j| (i0..=i1).map(move |i| j * nx + i))
}

/// The grid the triangles are binned by: `nx` × `ny` square cells from the mesh's corner.
#[derive(Clone, Copy, Debug)]
struct Cells {
    /// One over the side of a cell (a product is cheaper than a quotient, for every triangle and point).
    per_metre: f64,
    nx: usize,
    ny: usize,
}

impl Cells {
    /// The grid of `count` triangles whose boxes reach `reach` from the mesh's corner: cells of about four
    /// triangles' boxes, at most 4,096 along the longer side (4,097 where the division rounds up).
    fn fitting(count: usize, reach: DVec2) -> Cells {
        let span = if count > 0 {
            reach.max(DVec2::splat(1e-9))
        } else {
            DVec2::ONE
        };
        let cell = (span.x * span.y * TRIANGLES_PER_CELL / count.max(1) as f64)
            .sqrt()
            .max(span.max_element() / MAX_CELLS_PER_SIDE);
        // (`as` saturates: a cell of infinite size makes one)
        let side = |extent: f64| (extent / cell).floor() as usize + 1;
        Cells {
            per_metre: 1.0 / cell,
            nx: side(span.x),
            ny: side(span.y),
        }
    }

    /// The cell (column, row) of a point about the mesh's corner; one beyond the grid is in its border cell (`as`
    /// takes a negative or NaN index to 0).
    #[inline]
    fn of(&self, local: DVec2) -> (usize, usize) {
        let column = ((local.x * self.per_metre) as usize).min(self.nx - 1);
        let row = ((local.y * self.per_metre) as usize).min(self.ny - 1);
        (column, row)
    }
}

/// The bins of the triangles whose cell boxes are `boxes` (`total` slots in all; `slot_of` gives a triangle's slot):
/// counts, offsets, then the slots, within a cell in triangle order. The grid is cut in bands of rows, each counted
/// and filled by one task (a band's cells, and so its slots, are one range); the bins are the same whatever the
/// bands.
fn fill(
    cells: Cells,
    boxes: &[Option<CellBox>],
    total: usize,
    slot_of: impl Fn(usize) -> Option<Slot> + Sync,
) -> (Vec<u32>, Vec<Slot>) {
    let (nx, ny) = (cells.nx, cells.ny);
    let rows_per_band = ny
        .div_ceil(BANDS_PER_THREAD * rayon::current_num_threads())
        .max(1);
    let band_cells = rows_per_band * nx;
    let rows_of = |band: usize| band * rows_per_band..((band + 1) * rows_per_band).min(ny);
    let mut starts = vec![0u32; nx * ny + 1];
    starts[1..]
        .par_chunks_mut(band_cells)
        .enumerate()
        .for_each(|(band, counts)| {
            let (rows, first) = (rows_of(band), band * band_cells);
            for b in boxes.iter().flatten() {
                for k in cells_in(b, &rows, nx) {
                    counts[k - first] += 1;
                }
            }
        });
    for k in 0..nx * ny {
        starts[k + 1] += starts[k];
    }
    let mut slots = vec![[0.0f32; 10]; total];
    let mut bands = Vec::new();
    let mut rest = &mut slots[..];
    for k in (0..nx * ny).step_by(band_cells) {
        let size = starts[(k + band_cells).min(nx * ny)] - starts[k];
        let (band, tail) = rest.split_at_mut(size as usize);
        bands.push(band);
        rest = tail;
    }
    bands
        .into_par_iter()
        .enumerate()
        .for_each(|(band, band_slots)| {
            let (rows, first) = (rows_of(band), band * band_cells);
            let offsets = &starts[first..(first + band_cells).min(nx * ny)];
            let mut next: Vec<u32> = offsets.iter().map(|s| s - offsets[0]).collect();
            for (t, b) in boxes.iter().enumerate() {
                let Some(b) = b else { continue };
                if usize::from(b[1]) >= rows.end || usize::from(b[3]) < rows.start {
                    continue;
                }
                if let Some(slot) = slot_of(t) {
                    for k in cells_in(b, &rows, nx) {
                        band_slots[next[k - first] as usize] = slot;
                        next[k - first] += 1;
                    }
                }
            }
        });
    (starts, slots)
}

/// A triangle mesh in world space binned by a uniform XY grid, answering the height of its highest triangle over
/// XY points.
#[derive(Clone, Debug)]
pub struct VerticalLookup {
    /// The smallest world XY of the mesh's finite vertices: slots and points are read about it.
    origin: DVec2,
    cells: Cells,
    /// Cell `j * nx + i` holds `slots[starts[k]..starts[k + 1]]`.
    starts: Vec<u32>,
    /// The triangles of each cell, in triangle order.
    slots: Vec<Slot>,
}

impl VerticalLookup {
    /// Bins the triangles (vertex indices) of the mesh `vertices` (world XYZ). Vertical triangles and those with a
    /// vertex that is not a finite number are left out: no ray from above meets them. The cells hold about four
    /// triangles' boxes each, and there are at most 4,096 along the longer side.
    pub fn new(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Self> {
        check_triangle_indices("terrain mesh triangle", vertices.len(), triangles)?;
        let origin = vertices
            .iter()
            .map(|v| DVec2::new(v[0], v[1]))
            .filter(|p| p.is_finite())
            .reduce(DVec2::min)
            .unwrap_or(DVec2::ZERO);
        let place = |t: &[u32; 3]| upright(vertices, origin, t);

        // the grid: from how many triangles there are and how far their boxes reach
        let (count, reach) = triangles
            .par_iter()
            .filter_map(place)
            .map(|u| (1usize, u.hi))
            .reduce(
                || (0, DVec2::splat(f64::NEG_INFINITY)),
                |a, b| (a.0 + b.0, a.1.max(b.1)),
            );
        let cells = Cells::fitting(count, reach);
        let boxes: Vec<Option<CellBox>> = triangles
            .par_iter()
            .map(|t| {
                place(t).map(|u| {
                    let ((i0, j0), (i1, j1)) = (cells.of(u.lo), cells.of(u.hi));
                    [i0, j0, i1, j1].map(|c| c as u16)
                })
            })
            .collect();
        let total: u64 = boxes
            .par_iter()
            .flatten()
            .map(|&[i0, j0, i1, j1]| (u64::from(i1 - i0) + 1) * (u64::from(j1 - j0) + 1))
            .sum();
        limits::check(
            "the surface's binned triangles",
            total as f64,
            limits::MAX_BINNED_TRIANGLES,
            "slots",
        )?;

        let (starts, slots) = fill(cells, &boxes, total as usize, |t| {
            place(&triangles[t]).map(|u| u.slot)
        });
        Ok(VerticalLookup {
            origin,
            cells,
            starts,
            slots,
        })
    }

    /// The height of the highest triangle over the world XY point `p`; `None` over no triangle, and for a point
    /// that is not finite.
    pub fn height_at(&self, p: DVec2) -> Option<f64> {
        if !p.is_finite() {
            return None;
        }
        let local = p - self.origin;
        let (i, j) = self.cells.of(local);
        let k = j * self.cells.nx + i;
        let candidates = &self.slots[self.starts[k] as usize..self.starts[k + 1] as usize];
        let (x, y) = (local.x as f32, local.y as f32);
        let best = candidates
            .iter()
            .filter_map(|s| height_in(s, x, y))
            .fold(f32::NEG_INFINITY, f32::max);
        best.is_finite().then_some(f64::from(best))
    }

    /// [`VerticalLookup::height_at`] of each point, NaN over no triangle; the points are shared among threads.
    pub fn heights(&self, points: &[DVec2]) -> Vec<f64> {
        points
            .par_iter()
            .map(|&p| self.height_at(p).unwrap_or(f64::NAN))
            .collect()
    }
}

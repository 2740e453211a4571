//! The conquest grid of land parcels (thesis 3.3, Emilien 2014 ch. 3): cells of side `cell` over the land's box
//! (water, walls and `Ω` are read at the nearest land node), allocated only over the neighbourhoods the seeds can
//! reach. The road corridor is rasterized conservatively, and the free cells beside it are the road front where
//! road conquest runs; the cells round a dead end's cap are no road front.

use super::super::land::Land;
use super::super::road_index::{Projection, RoadIndex};
use super::super::Road;
use super::{ParcelSeed, NONE};
use crate::error::Result;
use crate::geom::segment_distance;
use crate::grid::{Grid, MAX_NODES};
use crate::limits;
use glam::DVec2;
use rayon::prelude::*;
use std::f64::consts::FRAC_1_SQRT_2;

/// Cell states of the conquest grid.
pub(super) const FREE: u8 = 0;
pub(super) const ROAD: u8 = 1;
pub(super) const BLOCKED: u8 = 2;

/// The ends of roads that meet no other road (nor their own road elsewhere).
fn dead_ends(roads: &[Road], index: &RoadIndex, cell: f64) -> Vec<DVec2> {
    let mut ends = Vec::new();
    let mut near = Vec::new();
    let tol = 0.1 * cell;
    for r in roads.iter().filter(|r| r.points.len() >= 2) {
        let m = r.points.len();
        for (e, own) in [
            (r.points[0], (r.points[0], r.points[1])),
            (r.points[m - 1], (r.points[m - 2], r.points[m - 1])),
        ] {
            index.candidates(e - DVec2::splat(tol), e + DVec2::splat(tol), &mut near);
            let met = near.iter().any(|&s| {
                let (a, b) = index.segments()[s as usize];
                (a, b) != own && (b, a) != own && segment_distance(e, a, b) <= tol
            });
            if !met {
                ends.push(e);
            }
        }
    }
    ends
}

/// The part of the conquest grid where parcels may grow: node (i, j) at `origin + (i, j) * cell`, one cell
/// (a square of side `cell`) around each node.
pub(super) struct Work {
    pub(super) grid: Grid,
    pub(super) state: Vec<u8>,
    /// Free cells beside the road corridor: where road conquest runs and parcels have their sources.
    pub(super) edge: Vec<bool>,
}

pub(super) const N4: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
pub(super) const N8: [(i64, i64); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

impl Work {
    /// The grid over the neighbourhoods the seeds can reach, with the road corridor rasterized conservatively: a
    /// cell is road when any of its points may lie within `half` of a centre line.
    pub(super) fn new(
        land: &Land,
        roads: &[Road],
        index: &RoadIndex,
        half: f64,
        cell: f64,
        seeds: &[ParcelSeed],
        projections: &[Projection],
    ) -> Result<Option<Work>> {
        let lg = land.grid();
        let land_max = lg.point(lg.nx - 1, lg.ny - 1);
        let gx = ((land_max.x - lg.origin.x) / cell).floor() as i64 + 1;
        let gy = ((land_max.y - lg.origin.y) / cell).floor() as i64 + 1;
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for (s, p) in seeds.iter().zip(projections) {
            let reach = s.params.budget / s.params.conquest_weight;
            let r = s.params.road_reach + 2.0 * reach + s.params.fill + half + 4.0 * cell;
            lo = lo.min(p.point - DVec2::splat(r));
            hi = hi.max(p.point + DVec2::splat(r));
        }
        let i0 = (((lo.x - lg.origin.x) / cell).floor() as i64).clamp(0, gx - 1);
        let j0 = (((lo.y - lg.origin.y) / cell).floor() as i64).clamp(0, gy - 1);
        let i1 = (((hi.x - lg.origin.x) / cell).ceil() as i64).clamp(0, gx - 1);
        let j1 = (((hi.y - lg.origin.y) / cell).ceil() as i64).clamp(0, gy - 1);
        if i1 <= i0 || j1 <= j0 {
            return Ok(None);
        }
        let (nx, ny) = ((i1 - i0 + 1) as usize, (j1 - j0 + 1) as usize);
        limits::check(
            &format!("the parcels' conquest grid of {cell} m cells (use a coarser cell or smaller budgets)"),
            nx as f64 * ny as f64,
            MAX_NODES as u64,
            "cells",
        )?;
        let origin = lg.origin + DVec2::new(i0 as f64, j0 as f64) * cell;
        let mut state: Vec<u8> = vec![FREE; nx * ny];
        state.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
            for (i, s) in row.iter_mut().enumerate() {
                let p = origin + DVec2::new(i as f64, j as f64) * cell;
                if !land.buildable(lg.nearest_clamped(p)) {
                    *s = BLOCKED;
                }
            }
        });
        let mut work = Work {
            grid: Grid {
                origin,
                cell,
                nx,
                ny,
            },
            state,
            edge: Vec::new(),
        };
        // a cell's points lie within half a diagonal of its node
        let margin = half + cell * FRAC_1_SQRT_2 * (1.0 + 1e-9);
        for &(a, b) in index.segments() {
            let (x0, y0) = work.clamped(a.min(b) - DVec2::splat(margin));
            let (x1, y1) = work.clamped(a.max(b) + DVec2::splat(margin));
            for j in y0..=y1 {
                for i in x0..=x1 {
                    if segment_distance(work.grid.point(i, j), a, b) <= margin {
                        work.state[j * nx + i] = ROAD;
                    }
                }
            }
        }
        let mut edge = vec![false; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                edge[k] = work.state[k] == FREE
                    && N4
                        .iter()
                        .any(|&(di, dj)| work.at(i as i64 + di, j as i64 + dj) == Some(ROAD));
            }
        }
        // the cells round a dead end's cap are not a road front: a parcel does not follow the road round its end
        let ends = dead_ends(roads, index, cell);
        if !ends.is_empty() {
            for (k, e) in edge.iter_mut().enumerate() {
                if *e {
                    let foot = index.nearest(work.grid.point_of(k), margin + 2.0 * cell);
                    if foot.is_some_and(|f| {
                        ends.iter()
                            .any(|q| q.distance(f.point) <= 1e-9 * (1.0 + q.abs().max_element()))
                    }) {
                        *e = false;
                    }
                }
            }
        }
        work.edge = edge;
        Ok(Some(work))
    }

    pub(super) fn inside(&self, i: i64, j: i64) -> Option<usize> {
        (i >= 0 && j >= 0 && (i as usize) < self.grid.nx && (j as usize) < self.grid.ny)
            .then(|| j as usize * self.grid.nx + i as usize)
    }

    fn at(&self, i: i64, j: i64) -> Option<u8> {
        self.inside(i, j).map(|k| self.state[k])
    }

    /// The node (i, j) nearest to `p`, clamped onto the grid.
    pub(super) fn clamped(&self, p: DVec2) -> (usize, usize) {
        let f = (p - self.grid.origin) / self.grid.cell;
        let c = |v: f64, n: usize| {
            if v.is_finite() {
                v.round().clamp(0.0, (n - 1) as f64) as usize
            } else if v > 0.0 {
                n - 1
            } else {
                0
            }
        };
        (c(f.x, self.grid.nx), c(f.y, self.grid.ny))
    }

    /// The cells within `r` of `p` (a box), as index ranges.
    pub(super) fn around(&self, p: DVec2, r: f64) -> (usize, usize, usize, usize) {
        let (x0, y0) = self.clamped(p - DVec2::splat(r));
        let (x1, y1) = self.clamped(p + DVec2::splat(r));
        (x0, y0, x1, y1)
    }

    /// The road-edge cell where a seed enters its road: the closest to `S_i` on the seed's side of the road.
    pub(super) fn source_cell(
        &self,
        index: &RoadIndex,
        p: &Projection,
        half: f64,
    ) -> Option<usize> {
        let (a, b) = index.segments()[p.segment];
        let dir = b - a;
        let (x0, y0, x1, y1) = self.around(p.point, half + 3.0 * self.grid.cell);
        let mut best: Option<(f64, usize)> = None;
        for j in y0..=y1 {
            for i in x0..=x1 {
                let k = j * self.grid.nx + i;
                if !self.edge[k] {
                    continue;
                }
                let q = self.grid.point(i, j);
                if dir.length_squared() > 0.0 && dir.perp_dot(q - p.point) * p.side <= 0.0 {
                    continue;
                }
                let d = q.distance(p.point);
                // (a road point off the grid finds nothing, not the grid's border)
                if d <= half + 3.0 * self.grid.cell && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, k));
                }
            }
        }
        best.map(|(_, k)| k)
    }

    /// Whether parcel `seed` may not enter cell `k`: road, water, wall, outside `Ω`, or another parcel's road cell.
    pub(super) fn closed_to(&self, owner: &[u32], seed: u32, k: usize) -> bool {
        self.state[k] != FREE || (self.edge[k] && owner[k] != NONE && owner[k] != seed)
    }
}

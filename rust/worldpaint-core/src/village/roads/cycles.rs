//! Road cycles (thesis 3.2.4): after the first road to `B`, the closest road node `p` ahead of `B` (in the cone
//! of half-angle `cycle_angle_degrees` around the direction in which the road arrives, within
//! `cycle_max_length`) gets a second road from `B`, kept when it is short enough and more than half of it keeps
//! `cycle_min_separation` away from the first road.

use super::grid_lines::node_polyline;
use super::search::{Ctx, Search, GOAL};
use super::{RoadConnection, RoadNetwork};
use crate::geom::{polyline_distance, polyline_length};
use glam::DVec2;

/// A cycle road is built when more than this fraction of its length is far enough from the first road.
const CYCLE_FAR_FRACTION: f64 = 0.5;
/// The direction in which a road arrives at `B` is taken over this length (m) of the road.
const ARRIVAL_LENGTH: f64 = 10.0;

/// The points through which a path between the foci `a` and `b` is at most `length` long.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ellipse {
    pub(super) a: DVec2,
    pub(super) b: DVec2,
    pub(super) length: f64,
}

impl Ellipse {
    pub(super) fn excludes(&self, q: DVec2) -> bool {
        q.distance(self.a) + q.distance(self.b) > self.length
    }
}

impl RoadNetwork {
    /// The thesis' cycle step: a second road from `B` to the closest road node ahead of it, when it is short
    /// enough and keeps away from the first road.
    pub(super) fn try_cycle(
        &mut self,
        search: &mut Search,
        ctx: &Ctx,
        b: usize,
        first: &[usize],
        first_cells: &[usize],
        connection: &mut RoadConnection,
    ) {
        let params = ctx.params;
        if params.cycle_max_length <= 0.0 {
            return;
        }
        let grid = self.grid;
        let first_line = node_polyline(&grid, first);
        let bp = grid.point_of(b);
        let Some(axis) = arrival_direction(&first_line) else {
            return;
        };
        let cos_max = params
            .cycle_angle_degrees
            .to_radians()
            .min(std::f64::consts::PI)
            .cos();
        let mut best: Option<(f64, usize)> = None;
        for &r in &self.road_nodes {
            let r = r as usize;
            if search.flags[r] & GOAL == 0 || first_cells.binary_search(&r).is_ok() {
                continue;
            }
            let d = grid.point_of(r) - bp;
            let dist = d.length();
            if dist <= 0.0 || dist > params.cycle_max_length || d.dot(axis) < cos_max * dist {
                continue;
            }
            if best.is_none_or(|(bd, _)| dist < bd) {
                best = Some((dist, r));
            }
        }
        let Some((_, p)) = best else {
            return;
        };
        let ellipse = Ellipse {
            a: bp,
            b: grid.point_of(p),
            length: params.cycle_max_length,
        };
        let Some((path, _)) = search.run(ctx, &[(p, 0.0)], b, false, Some(ellipse)) else {
            return;
        };
        let line = node_polyline(&grid, &path);
        let length = polyline_length(&line);
        if length > params.cycle_max_length
            || far_fraction(&line, &first_line, params.cycle_min_separation, grid.cell)
                <= CYCLE_FAR_FRACTION
        {
            return;
        }
        let mut cycle = RoadConnection::default();
        self.add_road(search, ctx, &path, &mut cycle);
        connection.roads.extend(cycle.roads);
        connection.steepest_grade = connection.steepest_grade.max(cycle.steepest_grade);
        connection.cycle = true;
    }
}

/// The direction (unit) in which a road `B = line[0], ...` arrives at `B`, over its last few metres.
fn arrival_direction(line: &[DVec2]) -> Option<DVec2> {
    let b = *line.first()?;
    let mut walked = 0.0;
    let mut at = b;
    for w in line.windows(2) {
        let l = w[0].distance(w[1]);
        if walked + l >= ARRIVAL_LENGTH {
            at = w[0] + (w[1] - w[0]) * ((ARRIVAL_LENGTH - walked) / l);
            break;
        }
        walked += l;
        at = w[1];
    }
    (b - at).try_normalize()
}

/// Fraction of the length of `line` farther than `separation` from `other`, sampled every half cell.
fn far_fraction(line: &[DVec2], other: &[DVec2], separation: f64, cell: f64) -> f64 {
    let (mut far, mut total) = (0.0, 0.0);
    let step = 0.5 * cell;
    for w in line.windows(2) {
        let l = w[0].distance(w[1]);
        let n = (l / step).ceil().max(1.0) as usize;
        for s in 0..n {
            let p = w[0] + (w[1] - w[0]) * ((s as f64 + 0.5) / n as f64);
            let d = polyline_distance(p, other);
            total += l / n as f64;
            if d > separation {
                far += l / n as f64;
            }
        }
    }
    if total > 0.0 {
        far / total
    } else {
        0.0
    }
}

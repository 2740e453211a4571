//! The static cost of a move (thesis 3.2.4, the cost `C(R) = Σ_j w_j g_j(R)` of GPMG10): per metre of a
//! sub-segment of grade `g`, `distance_weight + slope_weight · (g / max_grade)²`, plus `water_weight` times the
//! water fraction; a move through a node outside `Ω` is forbidden, one steeper than `max_grade` is priced with
//! [`STEEP_WEIGHT`] for the search that allows it. Costs are cached per (node, move), both ways at once.

use super::moves::{sample, sample_bool, Move, MoveTable};
use super::STEEP_WEIGHT;
use crate::grid::Grid;
use crate::village::encyclopedia::RoadParams;
use crate::village::land::Land;

/// Node surroundings, for the move costs.
pub(super) const NEAR_WATER: u8 = 1;
pub(super) const NEAR_OUTSIDE: u8 = 2;

/// The parameters the cached move costs depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CostKey {
    pub(super) distance_weight: f64,
    pub(super) slope_weight: f64,
    pub(super) max_grade: f64,
    pub(super) water_weight: f64,
    pub(super) mask_radius: u32,
}

impl CostKey {
    pub(super) fn of(p: &RoadParams) -> CostKey {
        CostKey {
            distance_weight: p.distance_weight,
            slope_weight: p.slope_weight,
            max_grade: p.max_grade,
            water_weight: p.water_weight,
            mask_radius: p.mask_radius,
        }
    }
}

/// The cached static cost of move `m` from `x` (see `Search::costs`).
pub(super) fn cached_cost(
    costs: &mut [f32],
    table: &MoveTable,
    key: &CostKey,
    land: &Land,
    near: &[u8],
    x: usize,
    m: usize,
) -> f32 {
    let m_count = table.moves.len();
    let c = costs[x * m_count + m];
    if c != 0.0 {
        return c;
    }
    let c = static_cost(land, key, &table.moves[m], x, near[x], true);
    costs[x * m_count + m] = c;
    let y = (x as isize + table.moves[m].delta) as usize;
    costs[y * m_count + table.rev[m]] = c;
    c
}

/// The cost a move may take in a search that allows steep moves or not (`None`: not allowed).
pub(super) fn usable(c: f32, steep: bool) -> Option<f32> {
    if c.is_infinite() || (c < 0.0 && !steep) {
        None
    } else {
        Some(c.abs())
    }
}

/// The cost of a move from `x` under the grade limit (positive), above it (negative), or through a node outside
/// `Ω` (infinite); see the module documentation. `near` says whether water
/// ([`NEAR_WATER`]) or nodes outside `Ω` ([`NEAR_OUTSIDE`]) may lie within the move's reach.
pub(super) fn static_cost(
    land: &Land,
    key: &CostKey,
    mv: &Move,
    x: usize,
    near: u8,
    penalise: bool,
) -> f32 {
    if near & NEAR_OUTSIDE != 0
        && mv
            .cells
            .iter()
            .any(|&d| !land.inside()[(x as isize + d) as usize])
    {
        return f32::INFINITY;
    }
    let n = mv.samples.len() - 1;
    let sub = mv.length / n as f64;
    // grade over max grade = |Δh| · to_ratio
    let to_ratio = 1.0 / (sub * key.max_grade);
    let steep_weight = if penalise {
        STEEP_WEIGHT * (key.distance_weight + key.slope_weight)
    } else {
        0.0
    };
    let mut h0 = sample(land.height(), x, &mv.samples[0]);
    let (mut slope, mut steep_cost, mut steep) = (0.0, 0.0, false);
    for s in &mv.samples[1..] {
        let h1 = sample(land.height(), x, s);
        let r = (h1 - h0).abs() * to_ratio;
        slope += r * r;
        if r > 1.0 + 1e-9 {
            steep = true;
            steep_cost += r * r;
        }
        h0 = h1;
    }
    let mut cost = key.distance_weight * mv.length
        + (key.slope_weight * slope + steep_weight * steep_cost) * sub;
    if near & NEAR_WATER != 0 && key.water_weight > 0.0 {
        // trapezoids of the bilinear water indicator
        let mut w0 = sample_bool(land.water(), x, &mv.samples[0]);
        let mut wet_length = 0.0;
        for s in &mv.samples[1..] {
            let w1 = sample_bool(land.water(), x, s);
            wet_length += 0.5 * (w0 + w1) * sub;
            w0 = w1;
        }
        cost += key.water_weight * wet_length;
    }
    let c = (cost as f32).max(f32::MIN_POSITIVE);
    if steep && penalise {
        -c
    } else {
        c
    }
}

/// Nodes with a `values` node within `radius` cells (Chebyshev): a dilation along the rows, then the columns.
pub(super) fn near(g: &Grid, values: &[bool], radius: usize) -> Vec<bool> {
    let mut rows = vec![false; g.len()];
    for j in 0..g.ny {
        let line: Vec<bool> = (0..g.nx).map(|i| values[g.index(i, j)]).collect();
        for (i, v) in dilate_line(&line, radius).into_iter().enumerate() {
            rows[g.index(i, j)] = v;
        }
    }
    let mut out = vec![false; g.len()];
    for i in 0..g.nx {
        let line: Vec<bool> = (0..g.ny).map(|j| rows[g.index(i, j)]).collect();
        for (j, v) in dilate_line(&line, radius).into_iter().enumerate() {
            out[g.index(i, j)] = v;
        }
    }
    out
}

/// The places of a line within `radius` of a set place: the nearest one on the left, then on the right.
fn dilate_line(line: &[bool], radius: usize) -> Vec<bool> {
    let mut out = vec![false; line.len()];
    let mut last: Option<usize> = None;
    for (k, &set) in line.iter().enumerate() {
        if set {
            last = Some(k);
        }
        out[k] = last.is_some_and(|l| k - l <= radius);
    }
    last = None;
    for (k, &set) in line.iter().enumerate().rev() {
        if set {
            last = Some(k);
        }
        out[k] |= last.is_some_and(|l| l - k <= radius);
    }
    out
}

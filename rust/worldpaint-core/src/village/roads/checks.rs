//! What a road network accepts (thesis 3.2.4): connection points `Ψ` snapped to an inside node, and a fingerprint
//! of the land, since the cached move costs belong to the land the network was made on.

use crate::village::land::Land;
use glam::DVec2;

/// A connection point snaps to an inside node at most this many cells away.
const CONNECTION_SNAP_CELLS: i64 = 3;

/// A fingerprint of the grid and of a sample of the land's nodes (every 31st, at most about 4,096 of them), cheap
/// enough for every call on a land of kilometres.
pub(super) fn land_mark(land: &Land) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |v: u64| {
        h ^= v;
        h = h.wrapping_mul(0x0100_0000_01b3);
    };
    let g = land.grid();
    for v in [
        g.nx as u64,
        g.ny as u64,
        g.cell.to_bits(),
        g.origin.x.to_bits(),
        g.origin.y.to_bits(),
    ] {
        eat(v);
    }
    for k in (0..g.len()).step_by((g.len() / 4096).max(31)) {
        let flags = land.inside()[k] as u64
            | (land.water()[k] as u64) << 1
            | (land.wall()[k] as u64) << 2
            | (land.fortified()[k] as u64) << 3;
        eat((land.height()[k].to_bits() as u64) << 4 | flags);
    }
    h
}

/// The inside node nearest to `p`, within [`CONNECTION_SNAP_CELLS`] cells.
pub(super) fn nearest_inside(land: &Land, p: DVec2) -> Option<usize> {
    let g = land.grid();
    let f = (p - g.origin) / g.cell;
    let (ci, cj) = (f.x.round(), f.y.round());
    let r = CONNECTION_SNAP_CELLS as f64;
    if !(ci >= -r && cj >= -r && ci <= (g.nx - 1) as f64 + r && cj <= (g.ny - 1) as f64 + r) {
        return None;
    }
    let (ci, cj) = (ci as i64, cj as i64);
    let mut best: Option<(f64, usize)> = None;
    for j in cj - CONNECTION_SNAP_CELLS..=cj + CONNECTION_SNAP_CELLS {
        for i in ci - CONNECTION_SNAP_CELLS..=ci + CONNECTION_SNAP_CELLS {
            if i < 0 || j < 0 || i >= g.nx as i64 || j >= g.ny as i64 {
                continue;
            }
            let k = g.index(i as usize, j as usize);
            let d = g.point_of(k).distance(p);
            if land.inside()[k] && d <= r * g.cell && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, k));
            }
        }
    }
    best.map(|(_, k)| k)
}

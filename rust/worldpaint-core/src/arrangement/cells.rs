//! A sparse grid of square cells listing node ids, for the growth's neighbour and edge-collision queries. Sparse
//! (a hash map of the occupied cells) because a pattern grows outwards from a seed over a region whose size says
//! nothing about where it will be; hashed with one multiply per key, as SipHash cost a sixth of a growth's time.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec2;

/// A multiplicative hasher for cell keys (Fibonacci hashing of each written integer, folded in with a rotation):
/// the keys are small integers chosen by the engine, not by an adversary.
#[derive(Default)]
pub(crate) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, n: u64) {
        self.0 = (self.0.rotate_left(5) ^ n).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }

    fn write_i64(&mut self, n: i64) {
        self.write_u64(n as u64);
    }

    fn write_usize(&mut self, n: usize) {
        self.write_u64(n as u64);
    }
}

/// A hash map keyed by cells or node ids, with [`CellHasher`].
pub(crate) type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<CellHasher>>;
/// A hash set of node ids or pairs, with [`CellHasher`].
pub(crate) type FastSet<K> = HashSet<K, BuildHasherDefault<CellHasher>>;

/// Node ids by cell.
pub(crate) struct Cells {
    cell: f64,
    map: FastMap<(i64, i64), Vec<usize>>,
}

impl Cells {
    /// An empty grid of cells of side `cell` (m, positive).
    pub(crate) fn new(cell: f64) -> Cells {
        Cells {
            cell,
            map: FastMap::default(),
        }
    }

    fn key(&self, p: DVec2) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }

    pub(crate) fn insert(&mut self, p: DVec2, id: usize) {
        let key = self.key(p);
        self.map.entry(key).or_default().push(id);
    }

    /// Moves `id` from where it was listed for `from` to the cell of `to`.
    pub(crate) fn shift(&mut self, id: usize, from: DVec2, to: DVec2) {
        let (a, b) = (self.key(from), self.key(to));
        if a != b {
            if let Some(ids) = self.map.get_mut(&a) {
                ids.retain(|&n| n != id);
            }
            self.map.entry(b).or_default().push(id);
        }
    }

    /// Whether `visit` answers true for an id listed in a cell that the box of `p` ± `radius` touches (the ids of
    /// those cells, not only those within `radius`: the caller tests the distance).
    pub(crate) fn any_near(
        &self,
        p: DVec2,
        radius: f64,
        mut visit: impl FnMut(usize) -> bool,
    ) -> bool {
        let (lo, hi) = (self.key(p - radius), self.key(p + radius));
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                if let Some(ids) = self.map.get(&(cx, cy)) {
                    if ids.iter().any(|&id| visit(id)) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

//! The boundary graph of land parcels (thesis 3.3.4, Emilien 2014 ch. 3): the cell outlines of all parcels form
//! one planar graph on the lattice of cell corners, traced into chains between junctions (points where three or
//! more parcels or the unclaimed land meet), and each parcel's outline as lattice vertices.

use super::grid::Work;
use super::NONE;
use glam::DVec2;

/// The lattice of cell corners: vertex (I, J) is the lower-left corner of cell (I, J). Directions at a vertex
/// count counter-clockwise: 0 east, 1 north, 2 west, 3 south.
pub(super) struct Lattice<'a> {
    pub(super) work: &'a Work,
    label: &'a [u32],
    pub(super) vx: usize,
}

impl<'a> Lattice<'a> {
    pub(super) fn new(work: &'a Work, label: &'a [u32]) -> Self {
        Lattice {
            work,
            label,
            vx: work.grid.nx + 1,
        }
    }

    fn lab(&self, i: i64, j: i64) -> u32 {
        self.work.inside(i, j).map_or(NONE, |k| self.label[k])
    }

    pub(super) fn vij(&self, v: u32) -> (i64, i64) {
        ((v as usize % self.vx) as i64, (v as usize / self.vx) as i64)
    }

    fn vid(&self, i: i64, j: i64) -> u32 {
        (j as usize * self.vx + i as usize) as u32
    }

    pub(super) fn pos(&self, v: u32) -> DVec2 {
        let (i, j) = self.vij(v);
        self.work.grid.origin + DVec2::new(i as f64 - 0.5, j as f64 - 0.5) * self.work.grid.cell
    }

    /// The label of the cell in the quadrant counter-clockwise after direction `d`.
    pub(super) fn quadrant(&self, v: u32, d: u8) -> u32 {
        let (i, j) = self.vij(v);
        match d {
            0 => self.lab(i, j),
            1 => self.lab(i - 1, j),
            2 => self.lab(i - 1, j - 1),
            _ => self.lab(i, j - 1),
        }
    }

    /// Whether a boundary edge leaves `v` in direction `d` (the cells on its two sides differ).
    fn has(&self, v: u32, d: u8) -> bool {
        self.quadrant(v, d) != self.quadrant(v, (d + 3) % 4)
    }

    fn degree(&self, v: u32) -> usize {
        (0..4).filter(|&d| self.has(v, d)).count()
    }

    fn step(&self, v: u32, d: u8) -> u32 {
        let (i, j) = self.vij(v);
        match d {
            0 => self.vid(i + 1, j),
            1 => self.vid(i, j + 1),
            2 => self.vid(i - 1, j),
            _ => self.vid(i, j - 1),
        }
    }

    fn edge_id(&self, v: u32, d: u8) -> usize {
        let (i, j) = self.vij(v);
        match d {
            0 => 2 * self.vid(i, j) as usize,
            1 => 2 * self.vid(i, j) as usize + 1,
            2 => 2 * self.vid(i - 1, j) as usize,
            _ => 2 * self.vid(i, j - 1) as usize + 1,
        }
    }
}

/// A maximal boundary path between junctions (or a closed loop without one).
pub(super) struct Chain {
    pub(super) ids: Vec<u32>,
    /// A loop without junction: `ids` ends where it starts and no vertex is fixed.
    pub(super) closed: bool,
    /// Direction of the first edge from `ids[0]`, and of the last edge seen from the end vertex.
    pub(super) first_dir: u8,
    pub(super) last_dir: u8,
    /// The labels on its two sides.
    pub(super) labels: [u32; 2],
}

impl Chain {
    pub(super) fn is_loop(&self) -> bool {
        self.ids.first() == self.ids.last()
    }
}

/// All chains of the boundary graph, and each parcel's outline as lattice vertices (counter-clockwise).
pub(super) fn trace(lat: &Lattice, n: usize) -> (Vec<Chain>, Vec<Vec<u32>>) {
    let work = lat.work;
    // the box of labelled cells
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    let mut first = vec![usize::MAX; n];
    let mut cells = vec![0usize; n];
    for (k, &x) in lat.label.iter().enumerate() {
        if x != NONE {
            let (i, j) = work.grid.ij(k);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
            first[x as usize] = first[x as usize].min(k);
            cells[x as usize] += 1;
        }
    }
    if i0 == usize::MAX {
        return (Vec::new(), vec![Vec::new(); n]);
    }
    let mut visited = vec![false; 2 * lat.vx * (work.grid.ny + 1)];
    let mut chains = Vec::new();
    let walk = |v: u32, d: u8, visited: &mut Vec<bool>| -> Chain {
        let mut ids = vec![v];
        let (mut cur, mut dir) = (v, d);
        loop {
            visited[lat.edge_id(cur, dir)] = true;
            let next = lat.step(cur, dir);
            ids.push(next);
            if next == v || lat.degree(next) != 2 {
                break;
            }
            let back = (dir + 2) % 4;
            dir = (0..4)
                .find(|&e| e != back && lat.has(next, e))
                .unwrap_or(back);
            cur = next;
        }
        let closed = lat.degree(v) == 2;
        Chain {
            labels: [lat.quadrant(v, d), lat.quadrant(v, (d + 3) % 4)],
            ids,
            closed,
            first_dir: d,
            last_dir: (dir + 2) % 4,
        }
    };
    let vertices =
        |pass: u8| (j0..=j1 + 1).flat_map(move |j| (i0..=i1 + 1).map(move |i| (pass, i, j)));
    for (pass, i, j) in vertices(0).chain(vertices(1)) {
        let v = lat.vid(i as i64, j as i64);
        let deg = lat.degree(v);
        // junctions first, then loops without junction
        if (pass == 0 && deg < 3) || (pass == 1 && deg != 2) {
            continue;
        }
        for d in 0..4u8 {
            if lat.has(v, d) && !visited[lat.edge_id(v, d)] {
                chains.push(walk(v, d, &mut visited));
            }
        }
    }
    // each parcel's outline, keeping the parcel on the left
    let loops = (0..n)
        .map(|x| {
            if first[x] == usize::MAX {
                return Vec::new();
            }
            let (ci, cj) = work.grid.ij(first[x]);
            let start = lat.vid(ci as i64, cj as i64);
            let (mut v, mut d) = (start, 0u8);
            let mut out = Vec::new();
            let limit = 4 * cells[x] + 8;
            loop {
                out.push(v);
                v = lat.step(v, d);
                d = if lat.quadrant(v, d) != x as u32 {
                    (d + 1) % 4
                } else if lat.quadrant(v, (d + 3) % 4) == x as u32 {
                    (d + 3) % 4
                } else {
                    d
                };
                if (v == start && d == 0) || out.len() > limit {
                    break;
                }
            }
            out
        })
        .collect();
    (chains, loops)
}

//! The network cost `T(r)` of re-use (thesis 3.2.4): from every road node to `Ψ` along the roads, a Dijkstra
//! over the road nodes, eight-connected, brought up to date whenever roads are added. The road search starts
//! from the goal nodes with their initial cost `w_ex · T(r)`.

use super::move_costs::static_cost;
use super::search::{Deeper, Search};
use super::RoadNetwork;
use crate::search::MinHeap;
use crate::village::land::Land;

impl RoadNetwork {
    /// Network cost from every road node to `Ψ` along the roads (without the re-use weight; `INFINITY` off the
    /// network or on roads not joined to `Ψ`): a Dijkstra over the road nodes, eight-connected. Roads are only
    /// ever added, so after the first time only the new road nodes and what they shorten are visited.
    ///
    /// Every entry is at depth 0, so equal costs pop by node.
    pub(super) fn exit_costs(&self, search: &mut Search, land: &Land) {
        let mut exit = std::mem::take(&mut search.exit);
        let mut heap = MinHeap::new();
        if search.exit_nodes == 0 {
            for &r in &self.road_nodes {
                exit[r as usize] = f64::INFINITY;
            }
            for &c in &self.connection_nodes {
                exit[c] = 0.0;
                heap.push(0.0, Deeper::new(0.0, c));
            }
        } else {
            for &r in &self.road_nodes[search.exit_nodes..] {
                let r = r as usize;
                for u in 0..search.table.unit.len() {
                    if let Some((y, c)) = self.road_edge(search, land, r, search.table.unit[u]) {
                        exit[r] = exit[r].min(exit[y] + c);
                    }
                }
                if exit[r].is_finite() {
                    heap.push(exit[r], Deeper::new(0.0, r));
                }
            }
        }
        while let Some(e) = heap.pop() {
            let x = e.item.state as usize;
            if e.cost > exit[x] {
                continue;
            }
            for u in 0..search.table.unit.len() {
                let Some((y, c)) = self.road_edge(search, land, x, search.table.unit[u]) else {
                    continue;
                };
                let g = e.cost + c;
                if g < exit[y] {
                    exit[y] = g;
                    heap.push(g, Deeper::new(0.0, y));
                }
            }
        }
        search.exit = exit;
        search.exit_nodes = self.road_nodes.len();
    }

    /// The road node one move `m` from road node `x`, and the cost of going there (the same both ways).
    fn road_edge(
        &self,
        search: &mut Search,
        land: &Land,
        x: usize,
        m: usize,
    ) -> Option<(usize, f64)> {
        let grid = &self.grid;
        let y = search.table.target(grid, x, grid.ij(x), m)?;
        if !self.on_road[y] {
            return None;
        }
        let c = search.cost(land, x, m);
        if c.is_infinite() {
            return None;
        }
        // a road steeper than the limit exists: it costs what its length and slope cost, no penalty
        let c = if c < 0.0 {
            let mv = &search.table.moves[m];
            static_cost(land, &search.key, mv, x, search.near[x], false)
        } else {
            c
        };
        Some((y, c as f64))
    }
}

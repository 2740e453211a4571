//! Best-first search on grids and graphs: the priority order shared by the Dijkstra and A* searches of the
//! village (road connection, thesis 3.2.4; position adaptation of façade elements, 3.4.1; the parcel searches).
//!
//! [`MinCost`] puts `std::collections::BinaryHeap`, a max-heap, in min-cost order with a total order on the
//! cost (`f64::total_cmp`, right for negative costs and NaN too, unlike ordering by `to_bits`). Equal costs pop
//! in the order of their items, smallest first, so a seeded search settles states in one order on every
//! machine. [`MinHeap`] is that heap with the wrapping done.
//!
//! Each search keeps its own record of the best cost per state (flat arrays sized to its grid or its states)
//! and skips the entries a cheaper one has replaced since ("lazy deletion"): that part differs too much between
//! them (sentinel-coded `f32` arrays, integer kernel costs, budgets) to gain from one shared loop.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A heap entry: the smallest `cost` is the greatest, so it pops first from a `BinaryHeap`; equal costs pop
/// smallest `item` first. The cost compares by `f64::total_cmp`: `-0.0` before `0.0`, NaN after `+∞`.
///
/// To pop equal costs in another order (deeper states first, say), give the item an `Ord` that says so.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MinCost<T> {
    /// The search's cost of reaching `item` (its priority).
    pub cost: f64,
    /// The state reached, or whatever the search pops.
    pub item: T,
}

impl<T> MinCost<T> {}

impl<T: Ord> Ord for MinCost<T> {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .cost
            .total_cmp(&self.cost)
            .then_with(|| other.item.cmp(&self.item))
    }
}

impl<T: Ord> PartialOrd for MinCost<T> {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Equal when neither pops before the other (consistent with [`Ord`], so `0.0` and `-0.0` differ).
impl<T: Ord> PartialEq for MinCost<T> {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl<T: Ord> Eq for MinCost<T> {}

/// A min-heap of items by cost (see [`MinCost`] for the order).
#[derive(Clone, Debug)]
pub(crate) struct MinHeap<T> {
    heap: BinaryHeap<MinCost<T>>,
}

impl<T: Ord> Default for MinHeap<T> {
    fn default() -> Self {
        MinHeap::new()
    }
}

impl<T: Ord> MinHeap<T> {
    /// An empty heap.
    pub(crate) fn new() -> MinHeap<T> {
        MinHeap {
            heap: BinaryHeap::new(),
        }
    }

    /// Adds `item` at `cost`.
    pub(crate) fn push(&mut self, cost: f64, item: T) {
        self.heap.push(MinCost { cost, item });
    }

    /// The cheapest entry (smallest item among equal costs).
    pub(crate) fn pop(&mut self) -> Option<MinCost<T>> {
        self.heap.pop()
    }

    /// Empties the heap and keeps its allocation, for the next search.
    pub(crate) fn clear(&mut self) {
        self.heap.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_the_smallest_cost_first_negative_ones_included() {
        let mut heap = MinHeap::new();
        for (k, c) in [3.0, -1.0, 0.5, -7.25, 0.0, f64::INFINITY, -0.0]
            .into_iter()
            .enumerate()
        {
            heap.push(c, k);
        }
        let order: Vec<f64> = std::iter::from_fn(|| heap.pop().map(|e| e.cost)).collect();
        assert_eq!(order, [-7.25, -1.0, -0.0, 0.0, 0.5, 3.0, f64::INFINITY]);
        assert!(order[2].is_sign_negative() && order[3].is_sign_positive());
    }

    #[test]
    fn equal_costs_pop_by_item() {
        let mut heap = MinHeap::new();
        for item in [(2u32, 1u32), (0, 9), (1, 0), (0, 3)] {
            heap.push(1.0, item);
        }
        heap.push(0.5, (9, 9));
        let order: Vec<(u32, u32)> = std::iter::from_fn(|| heap.pop().map(|e| e.item)).collect();
        assert_eq!(order, [(9, 9), (0, 3), (0, 9), (1, 0), (2, 1)]);
    }

    #[test]
    fn a_nan_cost_pops_last() {
        let mut heap = MinHeap::new();
        heap.push(f64::NAN, 0);
        heap.push(f64::INFINITY, 1);
        heap.push(1.0, 2);
        let order: Vec<i32> = std::iter::from_fn(|| heap.pop().map(|e| e.item)).collect();
        assert_eq!(order, [2, 1, 0]);
    }
}

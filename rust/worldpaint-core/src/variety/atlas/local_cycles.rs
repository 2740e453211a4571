//! Local cycles (§4.2.4): a component whose two connecting regions are identical up to a similarity T (the same
//! vertex count, matched along their chains in either direction from any start) can be repeated 1 to `max_repeat`
//! times, each copy moved by T from the one before and welded to it; each copy picks its own variant. As in the seed
//! they are allowed only on tree-like graphs and never on a terminal node; readings chosen: the repeated component
//! has exactly two regions, the one to its parent is the entry and it is not the root.

use super::{Atlas, LocalCycle, RegionChange, MAX_REPEAT, TOLERANCE};
use crate::error::{Error, Result};
use crate::variety::frame::{fit_similarity, is_identity};
use glam::{DAffine3, DVec3};

impl Atlas {
    /// Adds a local cycle on component `c` with at most `max_repeat` copies (§4.2.4).
    pub fn add_local_cycle(&mut self, c: usize, max_repeat: u32) -> Result<()> {
        self.component_checked(c)?;
        let d = &self.decomposition;
        let what = format!("local cycle on '{}'", self.name(c));
        if max_repeat == 0 || max_repeat > MAX_REPEAT {
            return Err(Error::OutOfRange {
                what: format!("maximum repetition of the {what}"),
                rule: format!("between 1 and {MAX_REPEAT}"),
                value: max_repeat as f64,
            });
        }
        if !d.is_tree_like() {
            return Err(Error::invalid(
                what,
                "local cycles are only added on tree-like graphs (seed §4.2.4), and this component graph has a cycle",
            ));
        }
        if d.degree(c) <= 1 {
            return Err(Error::invalid(
                what,
                "it is a terminal node of the graph, and terminal nodes cannot be in a local cycle (seed §4.2.4)",
            ));
        }
        if d.degree(c) != 2 {
            return Err(Error::invalid(
                what,
                format!(
                    "a repeated component needs exactly two connecting regions (its two ends), it has {}",
                    d.degree(c)
                ),
            ));
        }
        let Some((_, entry)) = d.parent(c) else {
            return Err(Error::invalid(
                what,
                "the root cannot repeat; choose another root for the decomposition",
            ));
        };
        let exit = d
            .arcs(c)
            .iter()
            .copied()
            .find(|&r| r != entry)
            .unwrap_or(entry);
        let (step, matching) = self.match_ends(entry, exit).ok_or_else(|| {
            Error::invalid(
                what.clone(),
                "its two connecting regions are not identical (the same number of vertices along the same shape, \
                 up to a move, a rotation and a uniform scale)",
            )
        })?;
        for v in &self.variants[c] {
            if v.change(entry) != RegionChange::Untouched || v.change(exit) == RegionChange::Changed
            {
                return Err(Error::invalid(
                    what,
                    format!(
                        "its copy '{}' reshapes one of its ends, so it cannot repeat",
                        v.name
                    ),
                ));
            }
        }
        self.cycles.retain(|l| l.component != c);
        self.cycles.push(LocalCycle {
            component: c,
            max_repeat,
            entry,
            exit,
            step,
            matching,
        });
        self.cycles.sort_by_key(|l| l.component);
        self.rebuild();
        Ok(())
    }

    /// The components that could repeat in a local cycle (§4.2.4: "we check if identical connecting regions exist"):
    /// on a tree-like graph, not the root, two regions, the one to the parent identical to the other up to a
    /// similarity.
    pub fn local_cycle_candidates(&self) -> Vec<usize> {
        let d = &self.decomposition;
        if !d.is_tree_like() {
            return Vec::new();
        }
        (0..d.components.len())
            .filter(|&c| d.degree(c) == 2)
            .filter(|&c| {
                d.parent(c).is_some_and(|(_, entry)| {
                    let exit = d.arcs(c).iter().copied().find(|&r| r != entry);
                    exit.is_some_and(|exit| self.match_ends(entry, exit).is_some())
                })
            })
            .collect()
    }

    /// Matches the vertices of two regions along their chains (each one chain) and fits the step between them.
    fn match_ends(&self, entry: usize, exit: usize) -> Option<(DAffine3, Vec<(u32, u32)>)> {
        let d = &self.decomposition;
        let (a, b) = (&d.regions[entry], &d.regions[exit]);
        if a.chains.len() != 1 || b.chains.len() != 1 {
            return None;
        }
        let (ca, cb) = (&a.chains[0], &b.chains[0]);
        if ca.vertices.len() != cb.vertices.len() || ca.closed != cb.closed {
            return None;
        }
        let n = ca.vertices.len();
        let pos = |v: u32| self.model.vertices[v as usize];
        let from: Vec<DVec3> = ca.vertices.iter().map(|&v| pos(v)).collect();
        let reach = from.iter().map(|p| p.length()).fold(1.0, f64::max);
        let mut best: Option<(f64, DAffine3, Vec<u32>)> = None;
        let shifts = if ca.closed { n } else { 1 };
        for reverse in [false, true] {
            for shift in 0..shifts {
                let order: Vec<u32> = (0..n)
                    .map(|k| {
                        let k = if reverse { n - 1 - k } else { k };
                        cb.vertices[(k + shift) % n]
                    })
                    .collect();
                let to: Vec<DVec3> = order.iter().map(|&v| pos(v)).collect();
                let (frame, residual) = fit_similarity(&from, &to);
                if best.as_ref().is_none_or(|b| residual < b.0) {
                    best = Some((residual, frame, order));
                }
            }
        }
        let (residual, frame, order) = best?;
        let tol = TOLERANCE * reach;
        if residual > tol || is_identity(&frame, reach, tol) || !frame.is_finite() {
            return None;
        }
        Some((frame, ca.vertices.iter().copied().zip(order).collect()))
    }
}

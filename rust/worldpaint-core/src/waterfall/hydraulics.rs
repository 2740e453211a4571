//! Flow through the hydraulic graph (thesis 4.2.2). Nodes are solved one after the other "in dependency order
//! from sources to wells", each at equilibrium (its incoming flow equals its outgoing flow).
//!
//! * Branch: the flow `γ_j` of each incoming arc `X_j` with direction `u_j` goes to the outgoing arcs `Y_k` with
//!   directions `v_k` by the normalized weights `w_jk = 1 + (u_j · v_k)`, `w̄_jk = w_jk / Σ_k w_jk`, so
//!   `γ_k = Σ_j γ_j w̄_jk`. Directions are the unit 3D vectors of the arcs' control segments at the node. An
//!   outgoing arc's strength, when the user set one, multiplies its weight; when every weight is zero (all
//!   outgoing arcs go straight back up the incoming one) the flow is split by strengths alone.
//! * Pool: "we simply distribute inflows equally to all the outgoing arcs, except when we need to take into
//!   account relative flow strength pre-set by the user for these branches": shares proportional to the
//!   strengths, 1 for an arc without one.
//! * Source: each outgoing arc carries its controller's strength, or [`WaterfallParams::source_flow`]; a pool
//!   with no inflow supplies its own strength (or the default flow) split as a pool.
//! * Well: takes what comes in.

use super::model::{Controller, WaterfallParams};
use super::network::{HydraulicGraph, HydraulicNodeKind};
use crate::error::{Error, Result};
use glam::DVec3;

/// Weights below this sum are "no preferred direction".
const NO_DIRECTION: f64 = 1e-12;

/// Sets `γ` on every arc and the inflow, outflow and depth of every node.
pub fn distribute_flow(
    graph: &mut HydraulicGraph,
    controllers: &[Controller],
    params: &WaterfallParams,
) -> Result<()> {
    for arc in &mut graph.arcs {
        arc.flow = 0.0;
    }
    let order = graph.order.clone();
    for n in order {
        let node = &graph.nodes[n];
        let outs = node.arcs_out.clone();
        let share: Vec<f64> = outs
            .iter()
            .map(|&a| graph.arcs[a].strength.unwrap_or(1.0))
            .collect();
        let inflow: f64 = node.arcs_in.iter().map(|&a| graph.arcs[a].flow).sum();
        let mut flows = vec![0.0; outs.len()];
        let supplied = match node.kind {
            HydraulicNodeKind::Source => {
                for (f, &a) in flows.iter_mut().zip(&outs) {
                    *f = graph.arcs[a].strength.unwrap_or(params.source_flow);
                }
                flows.iter().sum()
            }
            HydraulicNodeKind::Pool => {
                let total = if node.arcs_in.is_empty() {
                    node.pool
                        .and_then(|i| controllers.get(i))
                        .and_then(|c| c.strength)
                        .unwrap_or(params.source_flow)
                } else {
                    inflow
                };
                split(total, &share, &mut flows);
                total
            }
            HydraulicNodeKind::Branch | HydraulicNodeKind::Well => {
                for &j in &node.arcs_in {
                    let u = direction_in(&graph.arcs[j].points);
                    let w: Vec<f64> = outs
                        .iter()
                        .zip(&share)
                        .map(|(&k, s)| (1.0 + u.dot(direction_out(&graph.arcs[k].points))) * s)
                        .collect();
                    let gamma = graph.arcs[j].flow;
                    if w.iter().sum::<f64>() > NO_DIRECTION {
                        split(gamma, &w, &mut flows);
                    } else {
                        split(gamma, &share, &mut flows);
                    }
                }
                inflow
            }
        };
        for (&a, f) in outs.iter().zip(&flows) {
            graph.arcs[a].flow = *f;
        }
        let outflow = if outs.is_empty() {
            supplied
        } else {
            flows.iter().sum()
        };
        let node = &mut graph.nodes[n];
        node.inflow = supplied;
        node.outflow = outflow;
        node.depth = 0.5 * supplied;
        if !(supplied.is_finite() && outflow.is_finite()) {
            return Err(Error::invalid(
                format!("the flow through node {n}"),
                "is not finite",
            ));
        }
    }
    Ok(())
}

/// Adds `total · w_k / Σ w` to `flows[k]`.
fn split(total: f64, weights: &[f64], flows: &mut [f64]) {
    let sum: f64 = weights.iter().sum();
    if !(sum > 0.0) {
        return;
    }
    for (f, w) in flows.iter_mut().zip(weights) {
        *f += total * w / sum;
    }
}

/// Unit direction of the last control segment of an arc (how the water arrives).
fn direction_in(points: &[DVec3]) -> DVec3 {
    let n = points.len();
    (points[n - 1] - points[n - 2]).normalize_or_zero()
}

/// Unit direction of the first control segment of an arc (where the water leaves).
fn direction_out(points: &[DVec3]) -> DVec3 {
    (points[1] - points[0]).normalize_or_zero()
}

/// The largest imbalance `|in − out| / max(in, out)` over the nodes (sources count what they supply, wells what
/// they take; both with an arc's worth of flow on the other side). Zero for a consistent graph.
pub fn max_imbalance(graph: &HydraulicGraph) -> f64 {
    graph
        .nodes
        .iter()
        .map(|node| {
            let inflow = if node.arcs_in.is_empty() {
                node.inflow
            } else {
                node.arcs_in.iter().map(|&a| graph.arcs[a].flow).sum()
            };
            let outflow = if node.arcs_out.is_empty() {
                node.outflow
            } else {
                node.arcs_out.iter().map(|&a| graph.arcs[a].flow).sum()
            };
            let scale = inflow.abs().max(outflow.abs());
            if scale > 0.0 {
                (inflow - outflow).abs() / scale
            } else {
                0.0
            }
        })
        .fold(0.0, f64::max)
}

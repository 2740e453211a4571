//! The integration mesh (thesis 4.4.1 "Integration Mesh Generation"): "the surface meshes for all waterfall
//! elements [...] generated using the waterfall network trajectories and the widths of the elements. The meshes
//! for the contact elements are computed by extruding the width `ε` along the segment trajectories. [...]
//! Free-fall meshes are extruded from the borders of their incoming segments (e.g., pool borders) and follow the
//! free-fall element curve. Pool meshes are simply triangulated from their contours." Its contour `Ω` (Fig. 4.10
//! right) carries the constraints of 4.4.2, and its footprint seen from above the maps of 4.4.3.
//!
//! Readings:
//!
//! * a contact ribbon has three vertices across (left bank, axis, right bank) at the height of the path (the
//!   water surface; the riverbed is carved below it by [`super::deform`](fn@super::deform)); three are enough because the surface
//!   speed of 4.4.3, `δ_c (1 − ‖x − c‖/‖b − c‖)`, is linear across;
//! * widths are clamped to [`IntegrationOptions::min_width`, `max_width`]: the triangular section's width
//!   `ε = 4/(k s)` grows without bound on gentle slopes;
//! * a free-fall sheet is vertical, as wide as the contact ending at its lip (the "incoming segment") or, with
//!   none, as its own section;
//! * the footprint on the terrain's grid is the mesh's own: a node lies under a ribbon when it lies in one of
//!   its triangles, and its depth inside is the plan distance to the nearest bank edge, so that in a sharp bend
//!   the riverbed stops at the ribbon's inner bank; beyond a ribbon's end the water is closed by its last row
//!   (at sources and wells), capped by a disc (where arcs join) or left to the water it runs into (pools, lips);
//! * where ribbons meet at a branch, the arcs carrying less water stop one row inside the ribbon of the arc
//!   carrying the most instead of being cut against it exactly; the footprint keeps, per grid node, the element
//!   the node is deepest inside, so the maps and constraints see no overlap;
//! * a pool's values for foam, rocks and disturbance are those of the segments falling or flowing into it,
//!   fading linearly with the distance from where they arrive to the far side of the pool.

use super::classify::WaterfallType;
use super::model::{ControllerKind, WaterfallNetwork};
use super::network::HydraulicNodeKind;
use crate::contour::Polygons;
use crate::error::{check, Result};
use crate::polygon_mesh::{triangles_area, triangulate};
use glam::{DVec2, DVec3};

// the rasterization of the mesh onto the terrain's grid
pub use super::footprint::{waterfall_footprint, WaterfallFootprint};

/// Which kind of element a vertex, border or footprint node belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WaterPart {
    /// The ribbon of a contact segment.
    Contact = 0,
    /// The sheet of a free-fall.
    FreeFall = 1,
    /// The surface of a pool.
    Pool = 2,
}

/// How the mesh is built.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegrationOptions {
    /// Narrowest water surface (m).
    pub min_width: f64,
    /// Widest water surface (m).
    pub max_width: f64,
}

impl Default for IntegrationOptions {
    fn default() -> Self {
        IntegrationOptions {
            min_width: 1.0,
            max_width: 20.0,
        }
    }
}

impl IntegrationOptions {
    /// Checks that the widths are positive, finite and in order.
    pub fn validate(&self) -> Result<()> {
        check::positive("water min_width", self.min_width)?;
        check::within("water max_width", self.max_width, self.min_width, f64::MAX)?;
        Ok(())
    }
}

/// A piece of the contour `Ω`.
#[derive(Clone, Debug)]
pub struct Border {
    /// The kind of element it bounds.
    pub part: WaterPart,
    /// The segment (contact, free-fall) or pool controller it bounds.
    pub element: usize,
    /// World points at the water's level.
    pub points: Vec<DVec3>,
    /// Whether the last point joins the first (a pool's contour).
    pub closed: bool,
}

/// The integration mesh with its per-vertex attributes.
#[derive(Clone, Debug, Default)]
pub struct WaterMesh {
    /// Vertex positions, world XYZ (m).
    pub vertices: Vec<DVec3>,
    /// Triples of vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Plan surface velocity (m/s-like units of `δ`): along the flow, `δ` on the axis, 0 on the banks.
    pub speed: Vec<DVec2>,
    /// Table 4.1's foam of the vertex's segment type, in [0, 1].
    pub foam: Vec<f64>,
    /// Table 4.1's rocks of the vertex's segment type, in [0, 1].
    pub rocks: Vec<f64>,
    /// Table 4.1's disturbance of the vertex's segment type, in [0, 1].
    pub disturbance: Vec<f64>,
    /// The kind of element each vertex belongs to.
    pub part: Vec<WaterPart>,
    /// The segment of a contact or free-fall vertex, the pool controller of a pool vertex.
    pub element: Vec<usize>,
    /// The contour `Ω`: contact banks (closed across at sources and wells), free-fall lips, pool contours.
    pub borders: Vec<Border>,
    /// Per pool controller with a node in the graph: its contour in plan, level and depth.
    pub pools: Vec<PoolWater>,
}

/// A pool's water.
#[derive(Clone, Debug)]
pub struct PoolWater {
    /// Index of the pool controller.
    pub controller: usize,
    /// Index of the pool's node in the hydraulic graph.
    pub node: usize,
    /// The contour in plan, world XY (m).
    pub contour: Vec<DVec2>,
    /// Height of the water surface (m).
    pub level: f64,
    /// `ζ` of the pool's node (m).
    pub depth: f64,
    /// Table 4.1 values `[foam, rocks, disturbance]` of each inflow, with the plan point where it arrives.
    pub inflows: Vec<(DVec2, [f64; 3])>,
}

/// Table 4.1's `[foam, rocks, disturbance]` of a type.
pub(super) fn decoration_values(t: WaterfallType) -> [f64; 3] {
    let s = t.seed();
    [s.foam, s.rocks, s.disturbance]
}

impl WaterMesh {
    fn push(
        &mut self,
        p: DVec3,
        speed: DVec2,
        values: [f64; 3],
        part: WaterPart,
        element: usize,
    ) -> u32 {
        self.vertices.push(p);
        self.speed.push(speed);
        self.foam.push(values[0]);
        self.rocks.push(values[1]);
        self.disturbance.push(values[2]);
        self.part.push(part);
        self.element.push(element);
        (self.vertices.len() - 1) as u32
    }

    /// Water surface area (m²), the sheets of free-falls included.
    pub fn area(&self) -> f64 {
        triangles_area(&self.vertices, &self.triangles, |a, b, c| {
            0.5 * (b - a).cross(c - a).length()
        })
    }
}

/// The clamped water width of a segment.
fn width(net: &WaterfallNetwork, s: usize, o: &IntegrationOptions) -> f64 {
    net.segments[s]
        .section
        .width
        .clamp(o.min_width, o.max_width)
}

/// Unit plan normal (left of the flow) at path point `k`: the mean of the adjacent steps' directions.
fn normal_at(path: &[DVec3], k: usize) -> DVec2 {
    let dir = |a: usize, b: usize| (path[b] - path[a]).truncate().normalize_or_zero();
    let t = match (k > 0, k + 1 < path.len()) {
        (true, true) => dir(k - 1, k) + dir(k, k + 1),
        (true, false) => dir(k - 1, k),
        (false, true) => dir(k, k + 1),
        (false, false) => DVec2::ZERO,
    };
    t.normalize_or(DVec2::X).perp()
}

/// The rows of contact arc `a`'s ribbon, one per path point: left bank, axis, right bank. A row's width is the
/// mean of the segments on either side.
pub(super) fn ribbon_rows(
    net: &WaterfallNetwork,
    a: usize,
    options: &IntegrationOptions,
) -> Vec<[DVec3; 3]> {
    let path = &net.paths[a];
    let range = net.segment_ranges[a].clone();
    let n = path.len();
    if n < 2 || range.is_empty() {
        return Vec::new();
    }
    let seg_of = |k: usize| range.start + k.min(range.len() - 1);
    path.iter()
        .enumerate()
        .map(|(k, p)| {
            let s = seg_of(k);
            let w = if k > 0 && k < n - 1 {
                0.5 * (width(net, s - 1, options) + width(net, s, options))
            } else {
                width(net, s, options)
            };
            let side = (normal_at(path, k) * 0.5 * w).extend(0.0);
            [*p + side, *p, *p - side]
        })
        .collect()
}

/// The contact arc carrying the most water at graph node `n` (the lowest index among equals).
fn major_arc(net: &WaterfallNetwork, n: usize) -> Option<usize> {
    let node = &net.graph.nodes[n];
    node.arcs_in
        .iter()
        .chain(&node.arcs_out)
        .copied()
        .filter(|&a| net.graph.arcs[a].kind == ControllerKind::Contact)
        .fold(None, |best: Option<usize>, a| match best {
            Some(b) if net.graph.arcs[b].flow > net.graph.arcs[a].flow => Some(b),
            Some(b) if net.graph.arcs[b].flow == net.graph.arcs[a].flow && b < a => Some(b),
            _ => Some(a),
        })
}

/// Whether `p` lies under the four mesh triangles between two ribbon rows (left bank, axis, right bank).
pub(super) fn under_quad(p: DVec2, a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let [l0, c0, r0] = a.map(|v| v.truncate());
    let [l1, c1, r1] = b.map(|v| v.truncate());
    in_triangle(p, l0, l1, c0)
        || in_triangle(p, c0, l1, c1)
        || in_triangle(p, c0, c1, r0)
        || in_triangle(p, r0, c1, r1)
}

/// Whether `p` lies under one of a ribbon's triangles.
fn under_ribbon(rows: &[[DVec3; 3]], p: DVec2) -> bool {
    rows.windows(2).any(|w| under_quad(p, &w[0], &w[1]))
}

/// The rows of contact arc `a`'s ribbon that are drawn: where it joins an arc carrying more water, its rows whose
/// axis lies under that arc's ribbon are left out but the last, so the smaller ribbon ends just inside the larger
/// instead of lying over it.
fn drawn_rows(
    net: &WaterfallNetwork,
    a: usize,
    ribbon: &[[DVec3; 3]],
    options: &IntegrationOptions,
) -> std::ops::Range<usize> {
    let (mut lo, mut hi) = (0, ribbon.len());
    let arc = &net.graph.arcs[a];
    for (node, leaving) in [(arc.from, true), (arc.to, false)] {
        if ribbon_end(net, node, leaving) != RibbonEnd::Joined {
            continue;
        }
        let Some(major) = major_arc(net, node).filter(|&m| m != a) else {
            continue;
        };
        let larger = ribbon_rows(net, major, options);
        let under = |k: usize| under_ribbon(&larger, ribbon[k][1].truncate());
        if leaving {
            while lo + 2 < hi && under(lo + 1) {
                lo += 1;
            }
        } else {
            while hi > lo + 2 && under(hi - 2) {
                hi -= 1;
            }
        }
    }
    lo..hi
}

/// The integration mesh of a network: ribbons, sheets and pool polygons with Table 4.1's values per vertex.
pub(crate) fn integration_mesh(
    net: &WaterfallNetwork,
    options: &IntegrationOptions,
) -> Result<WaterMesh> {
    options.validate()?;
    let mut mesh = WaterMesh::default();
    for (a, arc) in net.graph.arcs.iter().enumerate() {
        if net.paths[a].len() < 2 || net.segment_ranges[a].is_empty() {
            continue;
        }
        match arc.kind {
            ControllerKind::Contact => mesh.add_ribbon(net, a, options),
            ControllerKind::FreeFall => mesh.add_sheet(net, a, options),
            ControllerKind::Pool => {}
        }
    }
    for n in 0..net.graph.nodes.len() {
        if let Some(pool) = pool_water(net, n) {
            mesh.add_pool(pool);
        }
    }
    Ok(mesh)
}

/// The water of graph node `n` when it is a pool whose controller the network holds: contour, level, depth and
/// the values of its inflows where they arrive.
fn pool_water(net: &WaterfallNetwork, n: usize) -> Option<PoolWater> {
    let node = &net.graph.nodes[n];
    let c = node.pool?;
    let ctrl = net.controllers.get(c)?;
    let contour: Vec<DVec2> = ctrl.points.iter().map(|p| p.truncate()).collect();
    let inflows: Vec<(DVec2, [f64; 3])> = node
        .arcs_in
        .iter()
        .filter_map(|&a| {
            let r = net.segment_ranges.get(a)?;
            let seg = net.segments.get(r.end.checked_sub(1)?)?;
            let end = net.paths.get(a)?.last()?.truncate();
            Some((end, decoration_values(seg.kind_of_water)))
        })
        .collect();
    Some(PoolWater {
        controller: c,
        node: n,
        contour,
        level: node.position.z,
        depth: node.depth,
        inflows,
    })
}

impl WaterMesh {
    /// The ribbon of contact arc `a`: per drawn row its banks at rest and its axis at the segment's speed along
    /// the flow, two quads between rows, and its banks as borders.
    fn add_ribbon(&mut self, net: &WaterfallNetwork, a: usize, options: &IntegrationOptions) {
        let path = &net.paths[a];
        let range = net.segment_ranges[a].clone();
        let ribbon = ribbon_rows(net, a, options);
        let drawn = drawn_rows(net, a, &ribbon, options);
        let mut rows: Vec<[u32; 3]> = Vec::with_capacity(drawn.len());
        for (k, row) in ribbon.iter().enumerate().take(drawn.end).skip(drawn.start) {
            let s = range.start + k.min(range.len() - 1);
            let seg = &net.segments[s];
            let along = -normal_at(path, k).perp();
            let values = decoration_values(seg.kind_of_water);
            let il = self.push(row[0], DVec2::ZERO, values, WaterPart::Contact, s);
            let ic = self.push(
                row[1],
                along * seg.section.speed,
                values,
                WaterPart::Contact,
                s,
            );
            let ir = self.push(row[2], DVec2::ZERO, values, WaterPart::Contact, s);
            rows.push([il, ic, ir]);
        }
        for w in rows.windows(2) {
            for c in 0..2 {
                let (a0, a1, b0, b1) = (w[0][c], w[0][c + 1], w[1][c], w[1][c + 1]);
                self.triangles.push([a0, b0, a1]);
                self.triangles.push([a1, b0, b1]);
            }
        }
        let left: Vec<DVec3> = ribbon[drawn.clone()].iter().map(|r| r[0]).collect();
        let right: Vec<DVec3> = ribbon[drawn].iter().map(|r| r[2]).collect();
        self.add_ribbon_borders(net, a, &left, &right);
    }

    /// The banks of contact arc `a`'s ribbon, closed across where the water starts from nothing (a source) or
    /// ends in nothing (a well).
    fn add_ribbon_borders(
        &mut self,
        net: &WaterfallNetwork,
        a: usize,
        left: &[DVec3],
        right: &[DVec3],
    ) {
        let graph = &net.graph;
        let arc = &graph.arcs[a];
        let first = net.segment_ranges[a].start;
        let last = net.segment_ranges[a].end - 1;
        let n = left.len();
        let bank = |element: usize, points: Vec<DVec3>| Border {
            part: WaterPart::Contact,
            element,
            points,
            closed: false,
        };
        self.borders.push(bank(first, left.to_vec()));
        self.borders.push(bank(first, right.to_vec()));
        if graph.nodes[arc.from].kind == HydraulicNodeKind::Source {
            self.borders.push(bank(first, vec![left[0], right[0]]));
        }
        if graph.nodes[arc.to].kind == HydraulicNodeKind::Well {
            self.borders
                .push(bank(last, vec![left[n - 1], right[n - 1]]));
        }
    }

    /// The vertical sheet of free-fall arc `a` along its path, its vertices at the speed of the fall, and its
    /// lip as a border.
    fn add_sheet(&mut self, net: &WaterfallNetwork, a: usize, options: &IntegrationOptions) {
        let path = &net.paths[a];
        let s = net.segment_ranges[a].start;
        let seg = &net.segments[s];
        let w = fall_width(net, a, options);
        let u = fall_direction(net, a);
        let nrm = u.perp();
        let values = decoration_values(seg.kind_of_water);
        let mut prev: Option<(u32, u32)> = None;
        for p in path {
            let l = *p + (nrm * 0.5 * w).extend(0.0);
            let r = *p - (nrm * 0.5 * w).extend(0.0);
            let il = self.push(l, u * seg.section.speed, values, WaterPart::FreeFall, s);
            let ir = self.push(r, u * seg.section.speed, values, WaterPart::FreeFall, s);
            if let Some((pl, pr)) = prev {
                self.triangles.push([pl, il, pr]);
                self.triangles.push([pr, il, ir]);
            }
            prev = Some((il, ir));
        }
        let lip = path[0];
        self.borders.push(Border {
            part: WaterPart::FreeFall,
            element: s,
            points: vec![
                lip + (nrm * 0.5 * w).extend(0.0),
                lip - (nrm * 0.5 * w).extend(0.0),
            ],
            closed: false,
        });
    }

    /// A pool's flat triangulation at its level, with values fading from its inflows, and its contour as a
    /// closed border.
    fn add_pool(&mut self, pool: PoolWater) {
        let (c, level) = (pool.controller, pool.level);
        let size = pool_radius(&pool.contour);
        let tri = triangulate(
            &Polygons::new(std::slice::from_ref(&pool.contour)),
            size / 4.0,
        );
        let base = self.vertices.len() as u32;
        for v in &tri.vertices {
            let values = pool_values(&pool, *v);
            self.push(v.extend(level), DVec2::ZERO, values, WaterPart::Pool, c);
        }
        self.triangles
            .extend(tri.triangles.iter().map(|t| t.map(|i| i + base)));
        self.borders.push(Border {
            part: WaterPart::Pool,
            element: c,
            points: pool.contour.iter().map(|p| p.extend(level)).collect(),
            closed: true,
        });
        self.pools.push(pool);
    }
}

/// Largest distance from the centroid of a contour to its points.
pub(super) fn pool_radius(contour: &[DVec2]) -> f64 {
    let c = contour.iter().copied().sum::<DVec2>() / contour.len().max(1) as f64;
    contour.iter().map(|p| p.distance(c)).fold(0.0, f64::max)
}

/// A pool's `[foam, rocks, disturbance]` at `p`: the strongest inflow's values fading over the pool's diameter.
pub(super) fn pool_values(pool: &PoolWater, p: DVec2) -> [f64; 3] {
    let reach = 2.0 * pool_radius(&pool.contour).max(1e-9);
    let mut out = [0.0; 3];
    for (at, v) in &pool.inflows {
        let f = (1.0 - p.distance(*at) / reach).clamp(0.0, 1.0);
        for c in 0..3 {
            out[c] = f64::max(out[c], v[c] * f);
        }
    }
    out
}

/// The plan direction of free-fall arc `a`: lip to foot, or the incoming contact's direction for a vertical drop.
pub(super) fn fall_direction(net: &WaterfallNetwork, a: usize) -> DVec2 {
    let path = &net.paths[a];
    let (s, e) = (path[0], path[path.len() - 1]);
    let d = (e - s).truncate();
    if d.length() > 1e-6 {
        return d.normalize();
    }
    incoming_contact(net, a)
        .and_then(|b| {
            let p = &net.paths[b];
            (p.len() >= 2).then(|| (p[p.len() - 1] - p[p.len() - 2]).truncate())
        })
        .map(|d| d.normalize_or(DVec2::X))
        .unwrap_or(DVec2::X)
}

/// A contact arc ending where free-fall arc `a` starts.
fn incoming_contact(net: &WaterfallNetwork, a: usize) -> Option<usize> {
    let from = net.graph.arcs[a].from;
    net.graph.nodes[from].arcs_in.iter().copied().find(|&b| {
        net.graph.arcs[b].kind == ControllerKind::Contact && !net.segment_ranges[b].is_empty()
    })
}

/// The width of free-fall arc `a`'s sheet.
pub(super) fn fall_width(net: &WaterfallNetwork, a: usize, o: &IntegrationOptions) -> f64 {
    match incoming_contact(net, a) {
        Some(b) => width(net, net.segment_ranges[b].end - 1, o),
        None => width(net, net.segment_ranges[a].start, o),
    }
}

/// How a ribbon ends, for the nodes beyond its first or last row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum RibbonEnd {
    /// Into a pool or over a lip: that water, or the cliff, covers what lies beyond.
    Open,
    /// Where the water starts from nothing or ends in nothing: the row is a bank.
    Closed,
    /// Where arcs join or part: a round cap, so the ribbons meeting there leave no gap.
    Joined,
}

/// How the ribbon of an arc leaving (`leaving`) or reaching graph node `n` ends there.
pub(super) fn ribbon_end(net: &WaterfallNetwork, n: usize, leaving: bool) -> RibbonEnd {
    let node = &net.graph.nodes[n];
    let falls = node
        .arcs_in
        .iter()
        .chain(&node.arcs_out)
        .any(|&a| net.graph.arcs[a].kind == ControllerKind::FreeFall);
    if node.pool.is_some() || falls {
        RibbonEnd::Open
    } else if (leaving && node.arcs_in.is_empty()) || (!leaving && node.arcs_out.is_empty()) {
        RibbonEnd::Closed
    } else {
        RibbonEnd::Joined
    }
}

/// Whether `p` lies in the triangle `abc` (either orientation, edges included).
fn in_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    let d1 = (b - a).perp_dot(p - a);
    let d2 = (c - b).perp_dot(p - b);
    let d3 = (a - c).perp_dot(p - c);
    (d1 >= 0.0 && d2 >= 0.0 && d3 >= 0.0) || (d1 <= 0.0 && d2 <= 0.0 && d3 <= 0.0)
}

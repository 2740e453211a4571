//! The structured content of an exemplar: the graphs of its graph categories and the contours of its polygon
//! categories (Section 4.2; thesis 6.2.1 and 6.3.1).
//!
//! * A graph category's paths are planarized into one [`Graph`]; its nodes inside the region are learned as a
//!   distribution, and [`Structures::graph_color`] reads the rest: the histograms of edge lengths, of the angles
//!   between edges sharing a node and of the turning angles along paths (the paper's "angles along a path",
//!   read at the planar graph's nodes of two edges), the degrees, the smallest angle, the connected components, the clearance from
//!   higher-priority instances and the polygons the graph never crosses. Statistics are taken at the nodes inside
//!   the region, over every edge that has an end inside (at its full length: the scene holds the whole graph).
//! * A polygon category's contours are filled with dense points (a jittered grid, [`crate::contour::fill_polygons`]);
//!   their spacing keeps about `POLYGON_POINTS` points inside the region, and their rdf spans the polygons' own scale.
//!   Its islands (outer contours with their lakes) whose centroid lies in the region are counted per area and their
//!   land areas kept: the synthesis matches both (module `synthesis::islands`).
//! * Later categories see graphs through their distance and polygons through their signed distance: maps whose
//!   values [`graph_map_value`] and [`polygon_map_value`] give, the same at analysis and synthesis.

use crate::contour::{fill_polygons_within, islands, Polygons};
use crate::geom::{DVec2, Region};
use crate::graph::{Graph, SegmentIndex};
use crate::palette::{GraphColor, Histogram, MapSource, PolygonColor};
use crate::scene::{Category, CategoryKind, Instance, Scene};
use std::collections::HashMap;
use std::f64::consts::PI;

/// Dense points a polygon category keeps inside the exemplar region.
const POLYGON_POINTS: f64 = 2000.0;
/// Bins of the edge-length and angle histograms.
const EDGE_BINS: usize = 24;
const ANGLE_BINS: usize = 18;
/// Vertices of a path closer than this merge into one node.
pub(crate) const SNAP: f64 = 1e-3;

/// The value of the distance map of a graph at `p`: metres, saturating at twice the color's radius (also where
/// there is no graph at all).
pub(crate) fn graph_map_value(index: &SegmentIndex, p: DVec2, max_radius: f64) -> f64 {
    index.distance(p, 2.0 * max_radius).min(2.0 * max_radius)
}

/// The value of the signed-distance map of polygons at `p`: `−d / d_max` inside (never 0: the coast belongs to
/// the outside), `d / max_radius` outside.
pub(crate) fn polygon_map_value(polygons: &Polygons, p: DVec2, max_radius: f64) -> f64 {
    polygon_value(
        polygons.side_and_signed_distance(p, 2.0 * max_radius),
        max_radius,
    )
}

fn polygon_value(side_and_distance: (bool, f64), max_radius: f64) -> f64 {
    match side_and_distance {
        (true, d) => d.min(-1e-9),
        (false, d) => d / max_radius,
    }
}

/// [`graph_map_value`] at every point (read a block of points at a time, see [`SegmentIndex::distances`]).
pub(crate) fn graph_map_values(
    index: &SegmentIndex,
    points: &[DVec2],
    max_radius: f64,
) -> Vec<f64> {
    let max = 2.0 * max_radius;
    index
        .distances(points, |_| max)
        .into_iter()
        .map(|d| d.min(max))
        .collect()
}

/// [`polygon_map_value`] at every point.
pub(crate) fn polygon_map_values(
    polygons: &Polygons,
    points: &[DVec2],
    max_radius: f64,
) -> Vec<f64> {
    polygons
        .sides_and_signed_distances(points, 2.0 * max_radius)
        .into_iter()
        .map(|sd| polygon_value(sd, max_radius))
        .collect()
}

/// The graph of every graph category and the contours of every polygon category of a scene, by category name.
pub(crate) struct Structures {
    graphs: HashMap<String, Graph>,
    polygons: HashMap<String, (Polygons, f64)>,
}

impl Structures {
    /// The structures of `scene`; polygons are filled for `region`.
    pub(crate) fn of(scene: &Scene, region: &Region) -> Structures {
        let mut graphs = HashMap::new();
        let mut polygons = HashMap::new();
        let samples = super::region_samples(region);
        for (c, category) in scene.categories.iter().enumerate() {
            match category.kind {
                CategoryKind::Graph => {
                    let paths: Vec<&[DVec2]> = scene
                        .paths
                        .iter()
                        .filter(|p| p.category == c)
                        .map(|p| p.points.as_slice())
                        .collect();
                    if !paths.is_empty() {
                        graphs.insert(category.name.clone(), Graph::from_paths(&paths, SNAP));
                    }
                }
                CategoryKind::Polygon => {
                    let contours: Vec<Vec<DVec2>> = scene
                        .contours
                        .iter()
                        .filter(|p| p.category == c)
                        .map(|p| p.points.clone())
                        .collect();
                    let polys = Polygons::new(&contours);
                    if polys.is_empty() {
                        continue;
                    }
                    let inside = samples.iter().filter(|p| polys.contains(**p)).count() as f64
                        / samples.len().max(1) as f64
                        * region.area();
                    let side = region.area().sqrt();
                    let spacing = (inside / POLYGON_POINTS)
                        .sqrt()
                        .clamp(side / 400.0, side / 20.0);
                    polygons.insert(category.name.clone(), (polys, spacing));
                }
                _ => {}
            }
        }
        Structures { graphs, polygons }
    }

    /// The graph of a graph category, planarized, when the scene has paths of it.
    pub(crate) fn graph(&self, name: &str) -> Option<&Graph> {
        self.graphs.get(name)
    }

    /// The nodes of a graph category inside the region, as instances.
    pub(crate) fn graph_nodes_inside(
        &self,
        c: usize,
        category: &Category,
        region: &Region,
    ) -> Vec<Instance> {
        let Some(g) = self.graphs.get(&category.name) else {
            return Vec::new();
        };
        let adj = g.adjacency();
        g.nodes
            .iter()
            .zip(&adj)
            .filter(|(p, n)| !n.is_empty() && region.contains(**p))
            .map(|(p, _)| Instance::at(*p, c))
            .collect()
    }

    /// The dense points of a polygon category inside the region, as instances.
    pub(crate) fn polygon_points_inside(
        &self,
        c: usize,
        category: &Category,
        region: &Region,
    ) -> Vec<Instance> {
        let Some((polys, spacing)) = self.polygons.get(&category.name) else {
            return Vec::new();
        };
        fill_polygons_within(polys, *spacing, c as u64, region.bbox())
            .into_iter()
            .filter(|p| region.contains(*p))
            .map(|p| Instance::at(p, c))
            .collect()
    }

    /// The radius of a polygon category's rdf: twice the equivalent radius of its parts inside the region.
    pub(crate) fn polygon_radius(&self, category: &Category, region: &Region) -> f64 {
        let cap = 0.25 * region.smaller_side();
        let Some((polys, spacing)) = self.polygons.get(&category.name) else {
            return cap;
        };
        let samples = super::region_samples(region);
        let inside = samples.iter().filter(|p| polys.contains(**p)).count() as f64
            / samples.len().max(1) as f64
            * region.area();
        let parts = polys
            .contours()
            .filter(|c| c.iter().any(|p| region.contains(*p)))
            .count()
            .max(1) as f64;
        (2.0 * (inside / (PI * parts)).sqrt()).clamp(4.0 * spacing, cap.max(4.0 * spacing))
    }

    /// The distance map of a graph or polygon category, when the scene has content of it.
    pub(crate) fn distance_field<'s>(
        &'s self,
        category: &Category,
        source: MapSource,
        max_radius: f64,
    ) -> Option<Box<dyn Fn(DVec2) -> f64 + 's>> {
        match source {
            MapSource::GraphDistance => {
                let g = self.graphs.get(&category.name)?;
                let index = SegmentIndex::new(g.segments());
                Some(Box::new(move |p| graph_map_value(&index, p, max_radius)))
            }
            MapSource::PolygonDistance => {
                let (polys, _) = self.polygons.get(&category.name)?;
                Some(Box::new(move |p| polygon_map_value(polys, p, max_radius)))
            }
            MapSource::Terrain => None,
        }
    }

    /// The statistics of a graph category in the region (see the module documentation); `before` lists the
    /// groups of higher priority with their points inside the region.
    pub(crate) fn graph_color(
        &self,
        category: &Category,
        region: &Region,
        before: &[(&Category, &[DVec2])],
    ) -> Option<GraphColor> {
        let g = self.graphs.get(&category.name)?;
        let held = HeldGraph::new(g, region);
        if held.nodes.is_empty() {
            return None;
        }
        let (angle, turn, min_angle, degree) = held.node_statistics();
        let total_degree: f64 = held.nodes.iter().map(|&n| held.adj[n].len() as f64).sum();
        let n_nodes = held.nodes.len() as f64;
        let components = held.components();
        let (clearance, avoids) = self.clearance_and_avoids(&held, region, before);
        Some(GraphColor {
            category: category.name.clone(),
            edge_length: held.edge_length().normalized(),
            angle: angle.normalized(),
            turn: turn.normalized(),
            degree,
            min_angle,
            edges_per_node: 0.5 * total_degree / n_nodes,
            components_per_area: components as f64 / region.area(),
            clearance,
            avoids,
        })
    }

    /// How close the graph comes to each distribution of higher priority (its smallest distance to their points),
    /// and the polygon categories of higher priority whose borders none of its edges crosses.
    fn clearance_and_avoids(
        &self,
        held: &HeldGraph,
        region: &Region,
        before: &[(&Category, &[DVec2])],
    ) -> (Vec<(String, f64)>, Vec<String>) {
        let g = held.g;
        let segments = SegmentIndex::new(
            held.edges
                .iter()
                .map(|e| (g.nodes[e[0] as usize], g.nodes[e[1] as usize]))
                .collect(),
        );
        let reach = region.bbox().1.distance(region.bbox().0);
        let mut clearance = Vec::new();
        let mut avoids = Vec::new();
        for (other, points) in before {
            match other.kind {
                CategoryKind::Distribution if !points.is_empty() => {
                    let d = points
                        .iter()
                        .map(|p| segments.distance(*p, reach))
                        .fold(f64::INFINITY, f64::min);
                    clearance.push((other.name.clone(), d));
                }
                CategoryKind::Polygon => {
                    if let Some((polys, _)) = self.polygons.get(&other.name) {
                        let border: Vec<(DVec2, DVec2)> = polys
                            .contours()
                            .flat_map(|c| (0..c.len()).map(move |i| (c[i], c[(i + 1) % c.len()])))
                            .collect();
                        let border = SegmentIndex::new(border);
                        let crosses = held.edges.iter().any(|e| {
                            border.crosses(g.nodes[e[0] as usize], g.nodes[e[1] as usize], 0.0)
                        });
                        if !crosses {
                            avoids.push(other.name.clone());
                        }
                    }
                }
                _ => {}
            }
        }
        (clearance, avoids)
    }

    /// The statistics of a polygon category: the spacing of its dense points, and its islands whose centroid
    /// lies in the region, per area and by land area, and their lakes per area.
    pub(crate) fn polygon_color(
        &self,
        category: &Category,
        region: &Region,
    ) -> Option<PolygonColor> {
        let (polys, spacing) = self.polygons.get(&category.name)?;
        let contours: Vec<Vec<DVec2>> = polys.contours().map(|c| c.to_vec()).collect();
        let counted: Vec<_> = islands(&contours)
            .into_iter()
            .filter(|i| region.contains(centroid(&contours[i.outer])))
            .collect();
        let mut island_areas: Vec<f64> = counted.iter().map(|i| i.area).collect();
        island_areas.sort_by(f64::total_cmp);
        let lakes = counted.iter().map(|i| i.lakes.len()).sum::<usize>();
        let area = region.area().max(1e-9);
        Some(PolygonColor {
            category: category.name.clone(),
            spacing: *spacing,
            islands_per_area: island_areas.len() as f64 / area,
            island_areas,
            lakes_per_area: Some(lakes as f64 / area),
        })
    }
}

/// The centroid of a closed polygon (its vertices' mean when it has no area).
pub(crate) fn centroid(points: &[DVec2]) -> DVec2 {
    let n = points.len();
    let (mut c, mut a) = (DVec2::ZERO, 0.0);
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        let w = p.perp_dot(q);
        c += (p + q) * w;
        a += w;
    }
    if a.abs() > 1e-12 {
        c / (3.0 * a)
    } else {
        points.iter().copied().sum::<DVec2>() / n.max(1) as f64
    }
}

/// The part of a graph an exemplar region holds, as the analysis reads it: its connected nodes inside, and every
/// edge with an end inside.
pub struct HeldGraph<'g> {
    g: &'g Graph,
    adj: Vec<Vec<u32>>,
    inside: Vec<bool>,
    nodes: Vec<usize>,
    edges: Vec<[u32; 2]>,
}

impl<'g> HeldGraph<'g> {
    /// The part of `g` that `region` holds.
    pub fn new(g: &'g Graph, region: &Region) -> HeldGraph<'g> {
        let adj = g.adjacency();
        let inside: Vec<bool> = g
            .nodes
            .iter()
            .zip(&adj)
            .map(|(p, n)| !n.is_empty() && region.contains(*p))
            .collect();
        let nodes: Vec<usize> = (0..g.nodes.len()).filter(|&n| inside[n]).collect();
        let edges: Vec<[u32; 2]> = g
            .edges
            .iter()
            .copied()
            .filter(|e| inside[e[0] as usize] || inside[e[1] as usize])
            .collect();
        HeldGraph {
            g,
            adj,
            inside,
            nodes,
            edges,
        }
    }

    /// The neighbours of each node of the whole graph.
    pub fn adjacency(&self) -> &[Vec<u32>] {
        &self.adj
    }

    /// Whether each node of the whole graph is held: it has an edge and lies inside the region.
    pub fn inside(&self) -> &[bool] {
        &self.inside
    }

    /// The edges with an end held.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// The histogram of the edges' lengths (up to 1.05 times the longest).
    fn edge_length(&self) -> Histogram {
        let lengths: Vec<f64> = self.edges.iter().map(|e| self.g.edge_length(*e)).collect();
        let longest = lengths.iter().copied().fold(0.0, f64::max).max(1e-9);
        let mut edge_length = Histogram::zeros(0.0, 1.05 * longest / EDGE_BINS as f64, EDGE_BINS);
        for l in &lengths {
            edge_length.add(*l, 1.0);
        }
        edge_length
    }

    /// At the nodes: the histograms of the angles between edges sharing a node and of the turning angles at
    /// nodes of two edges (`π −` their angle), the smallest angle, and the fraction of nodes of degree 1, 2, 3
    /// and 4 or more.
    fn node_statistics(&self) -> (Histogram, Histogram, f64, Vec<f64>) {
        let mut angle = Histogram::zeros(0.0, PI / ANGLE_BINS as f64, ANGLE_BINS);
        let mut turn = Histogram::zeros(0.0, PI / ANGLE_BINS as f64, ANGLE_BINS);
        let mut min_angle = PI;
        let mut degree = vec![0.0; 4];
        for &n in &self.nodes {
            let nb = &self.adj[n];
            degree[nb.len().clamp(1, 4) - 1] += 1.0;
            if let [a, b] = nb[..] {
                turn.add((PI - self.g.angle_at(n as u32, a, b)).min(PI - 1e-12), 1.0);
            }
            for (i, &a) in nb.iter().enumerate() {
                for &b in &nb[i + 1..] {
                    let t = self.g.angle_at(n as u32, a, b);
                    angle.add(t.min(PI - 1e-12), 1.0);
                    min_angle = min_angle.min(t);
                }
            }
        }
        degree
            .iter_mut()
            .for_each(|d| *d /= self.nodes.len() as f64);
        (angle, turn, min_angle, degree)
    }

    /// The connected components of the graph the region holds (edges with both ends inside), lone nodes included.
    pub fn components(&self) -> usize {
        let inside = &self.inside;
        let held = Graph {
            nodes: self.g.nodes.clone(),
            edges: self
                .g
                .edges
                .iter()
                .copied()
                .filter(|e| inside[e[0] as usize] && inside[e[1] as usize])
                .collect(),
        };
        held.components()
            + self
                .nodes
                .iter()
                .filter(|&&n| {
                    held.edges
                        .iter()
                        .all(|e| e[0] as usize != n && e[1] as usize != n)
                })
                .count()
    }
}

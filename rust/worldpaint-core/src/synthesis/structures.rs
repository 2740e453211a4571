//! The graphs and polygons a synthesis sees, by category name: those kept around (and, locked, inside) the
//! region, and what the synthesis has added so far. Later categories read them as distance maps; a graph's arcs
//! connect to the kept graph and must not cross it.

use crate::contour::Polygons;
use crate::geom::{DVec2, Region};
use crate::graph::{Graph, SegmentIndex};
use crate::scene::{CategoryKind, Scene};
use std::collections::HashMap;
use std::sync::Arc;

use crate::analysis::structure::SNAP;

/// The graph of one category: its paths, planarized, and an index of its segments.
#[derive(Clone, Default)]
pub(crate) struct GraphState {
    pub(crate) paths: Vec<Vec<DVec2>>,
    pub(crate) graph: Graph,
    pub(crate) index: Arc<SegmentIndex>,
}

impl GraphState {
    fn new(paths: Vec<Vec<DVec2>>) -> Self {
        let slices: Vec<&[DVec2]> = paths.iter().map(|p| p.as_slice()).collect();
        let graph = Graph::from_paths(&slices, SNAP);
        let index = Arc::new(SegmentIndex::new(graph.segments()));
        GraphState {
            paths,
            graph,
            index,
        }
    }
}

/// What a synthesis sees of structured content (see the module documentation).
#[derive(Default)]
pub(crate) struct StructuredContent {
    graphs: HashMap<String, GraphState>,
    polygons: HashMap<String, Arc<Polygons>>,
}

impl StructuredContent {
    /// The paths and contours of `scene` whose bounding boxes come within `reach` of the region's.
    pub(crate) fn near(scene: &Scene, region: &Region, reach: f64) -> Self {
        let (lo, hi) = region.bbox();
        let (lo, hi) = (lo - DVec2::splat(reach), hi + DVec2::splat(reach));
        let near = |points: &[DVec2]| {
            let (a, b) = points.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(a, b), p| (a.min(*p), b.max(*p)),
            );
            a.x <= hi.x && a.y <= hi.y && b.x >= lo.x && b.y >= lo.y
        };
        let mut out = StructuredContent::default();
        for (c, category) in scene.categories.iter().enumerate() {
            match category.kind {
                CategoryKind::Graph => {
                    let paths: Vec<Vec<DVec2>> = scene
                        .paths
                        .iter()
                        .filter(|p| p.category == c && near(&p.points))
                        .map(|p| p.points.clone())
                        .collect();
                    out.graphs
                        .insert(category.name.clone(), GraphState::new(paths));
                }
                CategoryKind::Polygon => {
                    let contours: Vec<Vec<DVec2>> = scene
                        .contours
                        .iter()
                        .filter(|p| p.category == c && near(&p.points))
                        .map(|p| p.points.clone())
                        .collect();
                    out.polygons
                        .insert(category.name.clone(), Arc::new(Polygons::new(&contours)));
                }
                _ => {}
            }
        }
        out
    }

    /// The segments of a graph category (empty when it has none).
    pub(crate) fn graph(&self, name: &str) -> Arc<SegmentIndex> {
        self.graphs
            .get(name)
            .map(|g| g.index.clone())
            .unwrap_or_default()
    }

    /// The kept graph of a category, planarized.
    pub(crate) fn graph_state(&self, name: &str) -> Option<&GraphState> {
        self.graphs.get(name)
    }

    /// The polygons of a polygon category (empty when it has none).
    pub(crate) fn polygons(&self, name: &str) -> Arc<Polygons> {
        self.polygons.get(name).cloned().unwrap_or_default()
    }

    /// Adds new paths to a graph category.
    pub(crate) fn add_paths(&mut self, name: &str, paths: &[Vec<DVec2>]) {
        let mut all = self
            .graphs
            .remove(name)
            .map(|g| g.paths)
            .unwrap_or_default();
        all.extend_from_slice(paths);
        self.graphs.insert(name.to_string(), GraphState::new(all));
    }

    /// Replaces the contours of a polygon category.
    pub(crate) fn set_contours(&mut self, name: &str, contours: &[Vec<DVec2>]) {
        self.polygons
            .insert(name.to_string(), Arc::new(Polygons::new(contours)));
    }
}

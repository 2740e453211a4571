//! The scene the user paints on (Section 3, "Input data"): object *categories* with a *layer* and a *type*
//! (distribution, graph, polygon, external, arrangement), a predefined *priority order* ("Scene objects are generated category
//! by category ... we set a predefined category priority order"), the instances of distribution categories, the
//! paths of graph categories, the contours of polygon categories and the terrain that carries the external maps.

use crate::terrain::Heightfield;
use glam::DVec2;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The data type of a category (Table 1 of the paper).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CategoryKind {
    /// Point objects (trees, rocks, houses): [`Instance`]s, learned as densities and rdfs.
    Distribution,
    /// Roads and rivers: [`Path`]s, learned as graphs (Section 4.2).
    Graph,
    /// Islands, lakes, fields: [`Contour`]s, learned as polygons.
    Polygon,
    /// Content the engine does not synthesize (a terrain map, say): never learned nor painted.
    External,
    /// Elements of a near-regular pattern (paving stones, roof tiles, vineyard stakes): [`Instance`]s learned as
    /// an arrangement's reference and painted by local growth (`arrangement`), never by a color's
    /// statistics.
    Arrangement,
}

/// A category of scene objects. Lower `priority` value = synthesized first (higher priority).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Category {
    /// The category's name, unique in a scene; colors and tools refer to categories by it.
    pub name: String,
    /// The layer it belongs to (e.g. "vegetation"); the engine keeps it, it does not read it.
    pub layer: String,
    /// Its data type.
    pub kind: CategoryKind,
    /// Its place in the priority order: lower values are synthesized first and condition the others.
    pub priority: i32,
}

impl Category {
    /// A category of any kind.
    pub fn new(name: &str, layer: &str, kind: CategoryKind, priority: i32) -> Self {
        Category {
            name: name.to_string(),
            layer: layer.to_string(),
            kind,
            priority,
        }
    }

    /// A distribution category.
    pub fn distribution(name: &str, layer: &str, priority: i32) -> Self {
        Category::new(name, layer, CategoryKind::Distribution, priority)
    }
}

/// One placed object: where it stands, how it is turned (about Z) and scaled, which category
/// (index into `Scene::categories`) and which prototype model of that category it shows. A *locked* instance
/// (an object the user placed by hand) is never removed by the tools; it conditions what they paint around it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Instance {
    /// World XY (m).
    pub position: DVec2,
    /// Angle about Z (radians; synthesis draws it in [0, 2π)).
    pub rotation: f64,
    /// Uniform scale of the prototype model (1 = its own size).
    pub scale: f64,
    /// Index into [`Scene::categories`].
    pub category: usize,
    /// Which of the category's prototype models it shows (0..).
    pub prototype: u32,
    /// Placed by hand: never removed by a tool.
    #[serde(default)]
    pub locked: bool,
    /// Colour variation (0: the prototype's own colour). The add-on keeps it as the point attribute `tint`, which a
    /// material reads with an Attribute node of type Instancer.
    #[serde(default)]
    pub tint: f32,
}

impl Instance {
    /// An instance with no rotation, unit scale and the first prototype.
    pub fn at(position: DVec2, category: usize) -> Self {
        Instance {
            position,
            rotation: 0.0,
            scale: 1.0,
            category,
            prototype: 0,
            locked: false,
            tint: 0.0,
        }
    }
}

/// An open polyline of a graph category (a road, a river): graphs are sets of paths that may intersect
/// (Section 4.2).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Path {
    /// Index into [`Scene::categories`] (a graph category).
    pub category: usize,
    /// The polyline's vertices, world XY (m).
    pub points: Vec<DVec2>,
    /// Drawn by hand: never removed by a tool.
    #[serde(default)]
    pub locked: bool,
}

/// A closed contour of a polygon category (an island, a lake, a field); contours of one category combine by the
/// even-odd rule, so a lake inside an island is a hole in it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Contour {
    /// Index into [`Scene::categories`] (a polygon category).
    pub category: usize,
    /// The contour's vertices, world XY (m), closed implicitly (the last joins the first).
    pub points: Vec<DVec2>,
    /// Drawn by hand: never removed by a tool.
    #[serde(default)]
    pub locked: bool,
}

/// Categories, instances, paths, contours and the terrain of a virtual world.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The categories; instances, paths and contours refer to them by index.
    pub categories: Vec<Category>,
    /// The objects of distribution categories.
    pub instances: Vec<Instance>,
    /// The polylines of graph categories.
    pub paths: Vec<Path>,
    /// The closed contours of polygon categories.
    pub contours: Vec<Contour>,
    /// Shared: the tools hand the same terrain to many syntheses without copying it.
    pub terrain: Option<Arc<Heightfield>>,
}

impl Scene {
    /// An empty scene on `terrain`.
    pub fn on(terrain: Arc<Heightfield>) -> Scene {
        Scene {
            terrain: Some(terrain),
            ..Default::default()
        }
    }

    /// The index of the category called `name`, if the scene has one.
    pub fn category_index(&self, name: &str) -> Option<usize> {
        self.categories.iter().position(|c| c.name == name)
    }

    /// Adds the category if absent (by name), returns its index.
    pub(crate) fn ensure_category(&mut self, c: &Category) -> usize {
        match self.category_index(&c.name) {
            Some(i) => i,
            None => {
                self.categories.push(c.clone());
                self.categories.len() - 1
            }
        }
    }
}

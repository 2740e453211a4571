//! The learned statistics: interaction histograms, a *color* (the paper's "distribution": "The resulting set of
//! histograms is called a distribution ... stored as one distribution in the palette, by analogy to colors in a
//! painting system", Sections 3 and 4.3) and a palette of colors, saved as versioned JSON.
//!
//! JSON envelope: `{"format": "worldpaint-palette", "version": 1, "colors": [...]}` for a palette and
//! `{"format": "worldpaint-color", "version": 1, "color": {...}}` for a single color. An unknown version gives
//! [`Error::UnsupportedVersion`], anything unreadable or invalid [`Error::Parse`]; reading never panics. Non-finite numbers
//! (an unbounded `min_distance`) are written as `null` and read back as `+∞`.

mod validate;

use crate::arrangement::ArrangementColor;
use crate::error::{Error, FileKind, Result};
use crate::geom::Region;
use crate::scene::{Category, Scene};
use serde::{Deserialize, Serialize};

/// Version of the palette JSON this build writes and reads.
pub const PALETTE_FORMAT_VERSION: u32 = 1;
const PALETTE_FORMAT: &str = "worldpaint-palette";
const COLOR_FORMAT: &str = "worldpaint-color";
/// Largest log of a scale a size histogram may span (e^±100: far beyond any model, and finite).
const MAX_LOG_SCALE: f64 = 100.0;
/// Most distance bands of a facing.
const MAX_FACING_BANDS: usize = 64;

/// A 1D histogram with bins `[start + k w, start + (k+1) w)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    /// Lower edge of bin 0, in the unit of what is binned (m for distances, radians for angles).
    pub start: f64,
    /// Width `w` of every bin, positive.
    pub bin_width: f64,
    /// One value per bin: an rdf value, or a mass (the field holding the histogram says which).
    pub values: Vec<f64>,
}

impl Histogram {
    /// `n` empty bins from `start`.
    pub fn zeros(start: f64, bin_width: f64, n: usize) -> Self {
        Histogram {
            start,
            bin_width,
            values: vec![0.0; n],
        }
    }

    /// End of the last bin.
    pub fn end(&self) -> f64 {
        self.start + self.bin_width * self.values.len() as f64
    }

    /// The bin holding `x`, `None` outside (or for a degenerate histogram / non-finite `x`).
    pub(crate) fn bin_of(&self, x: f64) -> Option<usize> {
        if !(self.bin_width > 0.0) || !x.is_finite() || !self.start.is_finite() {
            return None;
        }
        let f = (x - self.start) / self.bin_width;
        if f < 0.0 {
            return None;
        }
        let k = f.floor() as usize;
        (k < self.values.len()).then_some(k)
    }

    /// The value of the bin holding `x`, 0 outside.
    pub fn value_at(&self, x: f64) -> f64 {
        self.bin_of(x).map_or(0.0, |k| self.values[k])
    }

    /// Sum of the values.
    pub fn total(&self) -> f64 {
        self.values.iter().sum()
    }

    /// Adds `weight` to the bin holding `x`; returns whether it fell in a bin.
    pub fn add(&mut self, x: f64, weight: f64) -> bool {
        match self.bin_of(x) {
            Some(k) => {
                self.values[k] += weight;
                true
            }
            None => false,
        }
    }

    /// The same histogram with values summing to 1 (unchanged when empty).
    pub(crate) fn normalized(&self) -> Histogram {
        let t = self.total();
        let mut h = self.clone();
        if t > 0.0 {
            h.values.iter_mut().for_each(|v| *v /= t);
        }
        h
    }

    /// Total variation distance `½ ∫ |p − q|` between the normalized masses of the two histograms (any bins:
    /// both are read as piecewise-constant densities over the union of their bin edges). In [0, 1].
    pub fn total_variation(&self, other: &Histogram) -> f64 {
        let (p, q) = (self.normalized(), other.normalized());
        let pt = p.total();
        let qt = q.total();
        if pt <= 0.0 || qt <= 0.0 {
            return if pt <= 0.0 && qt <= 0.0 { 0.0 } else { 1.0 };
        }
        if p.start == q.start && p.bin_width == q.bin_width {
            let n = p.values.len().max(q.values.len());
            let at = |h: &Histogram, k: usize| h.values.get(k).copied().unwrap_or(0.0);
            return 0.5 * (0..n).map(|k| (at(&p, k) - at(&q, k)).abs()).sum::<f64>();
        }
        let mut edges: Vec<f64> = Vec::new();
        for h in [&p, &q] {
            if h.bin_width > 0.0 {
                edges.extend((0..=h.values.len()).map(|k| h.start + k as f64 * h.bin_width));
            }
        }
        edges.retain(|e| e.is_finite());
        edges.sort_by(f64::total_cmp);
        edges.dedup();
        let density = |h: &Histogram, x: f64| {
            if h.bin_width > 0.0 {
                h.value_at(x) / h.bin_width
            } else {
                0.0
            }
        };
        0.5 * edges
            .windows(2)
            .map(|w| {
                let mid = 0.5 * (w[0] + w[1]);
                (density(&p, mid) - density(&q, mid)).abs() * (w[1] - w[0])
            })
            .sum::<f64>()
    }
}

mod finite_or_null {
    use serde::{Deserialize, Deserializer, Serializer};
    pub(super) fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_some(v)
        } else {
            s.serialize_none()
        }
    }
    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

/// What a color knows about one category: how many instances, how dense, how close they come, and how they
/// are scaled, turned and which prototypes they show.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CategoryColor {
    /// The category as it was in the exemplar's scene (name, layer, kind, priority).
    pub category: Category,
    /// Instances in the exemplar region.
    pub count: usize,
    /// Per m².
    pub density: f64,
    /// Smallest same-category pair distance seen (`+∞` with fewer than two instances; `null` in JSON).
    #[serde(with = "finite_or_null")]
    pub min_distance: f64,
    /// Instance scale distribution.
    pub scale: Histogram,
    /// Instance rotation about Z in [0, 2π).
    pub rotation: Histogram,
    /// Frequency of prototype index 0..n.
    pub prototype_weights: Vec<f64>,
    /// The instances' sizes: the histogram of the natural log of their scale (mass per bin), on bins fine enough
    /// for sizes spread over an order of magnitude (a shed and a barn). The synthesis draws scales from it. Empty
    /// in colors learned before it was, whose synthesis draws scales from `scale`.
    #[serde(default = "empty_histogram")]
    pub size: Histogram,
    /// How the instances are turned to the nearest road, when they follow the roads rather than the world's axes
    /// (houses that face their street). `None` in colors learned before it was, and where the example had no road
    /// near the category or its rotations follow the world's axes better.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub facing: Option<RoadFacing>,
}

/// The orientation of a category's instances to the nearest road: the angle of an instance's local +X axis from the
/// direction towards the nearest point of the roads, counter-clockwise in [0, 2π) (0: +X towards the road, π/2 or
/// 3π/2: along it), by band of distance to that road. Beyond the last band (the reach) instances keep the
/// category's `rotation`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RoadFacing {
    /// The graph categories that are the roads (of higher priority than the category): the nearest segment of any.
    pub roads: Vec<String>,
    /// Upper edges (m) of the bands of distance to the nearest road, ascending, from 0; the last is the reach.
    pub bands: Vec<f64>,
    /// Per band, the angle from the direction towards the nearest road over [0, 2π) (mass per bin, sums to 1).
    pub angles: Vec<Histogram>,
    /// Share of the example's instances within the reach of a road.
    pub near_share: f64,
}

impl RoadFacing {
    /// The distance within which instances face the roads.
    pub fn reach(&self) -> f64 {
        self.bands.last().copied().unwrap_or(0.0)
    }

    /// The angles of the band holding the distance `d` to the nearest road (`None` at the reach and beyond).
    pub fn angles_at(&self, d: f64) -> Option<&Histogram> {
        let band = self.bands.iter().position(|edge| d < *edge)?;
        self.angles.get(band)
    }
}

/// An interaction histogram between two categories (Section 4.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Interaction {
    /// Radial distribution function, eq. (2) with the window-edge correction. Bin k covers distances
    /// [k d_r, (k+1) d_r) with d_r = `Color::bin_width`; 1 everywhere for a Poisson arrangement.
    Rdf {
        /// The rdf by distance, bins from 0.
        hist: Histogram,
    },
    /// Oriented rdf: distance × angle (angle of `other − category` relative to world X, folded to [0, π)),
    /// `values[k * angle_bins + l]`; normalized like the rdf (1 for a Poisson arrangement).
    OrientedRdf {
        /// Width of a distance bin (m); bins start at 0.
        distance_bin: f64,
        /// Angular sectors over [0, π).
        angle_bins: usize,
        /// Distance-major: `values[k * angle_bins + l]` for distance bin `k` and sector `l`.
        values: Vec<f64>,
    },
}

/// Interaction of `category` with `other` (`other` has equal or higher priority).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairInteraction {
    /// Name of the category whose instances are placed against `other`.
    pub category: String,
    /// Name of the other category (possibly `category` itself).
    pub other: String,
    /// The histogram of the pair.
    pub interaction: Interaction,
}

/// Where the values of a map come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MapSource {
    /// A named map of the terrain ("elevation", "slope", ...).
    #[default]
    Terrain,
    /// The distance (m) to the edges of the graph category the map names: the paper's distance-to-graph `h_g`.
    GraphDistance,
    /// The signed distance to the contours of the polygon category the map names (thesis 6.2.1): `−d / d_max`
    /// inside, and outside `d` in units of the color's `max_radius`.
    PolygonDistance,
}

/// Map sampling histogram `h_m` of a category on a map (mass per bin, sums to 1), with `region_hist`, the
/// histogram (same bins) of the map's values over the whole exemplar region, so synthesis can favour what the
/// exemplar preferred rather than what was merely common there. Distances to graphs and polygons are maps too.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapInteraction {
    /// Name of the category sampled.
    pub category: String,
    /// Name of the terrain map, or of the graph or polygon category whose distance is the map (see `source`).
    pub map: String,
    /// `h_m`: the map's values at the category's instances (mass per bin, sums to 1).
    pub hist: Histogram,
    /// The map's values over the whole exemplar region, same bins (mass per bin); empty when a file lacks it.
    #[serde(default = "empty_histogram")]
    pub region_hist: Histogram,
    /// Where the map's values come from.
    #[serde(default)]
    pub source: MapSource,
}

/// What a color knows of a graph category besides the distribution of its nodes (Section 4.2, thesis 6.3.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraphColor {
    /// Name of the graph category.
    pub category: String,
    /// Lengths of the edges (mass per bin).
    pub edge_length: Histogram,
    /// Angles between two edges sharing a node, in [0, π] (mass per bin): the junctions' shapes, and with
    /// them the smallest angle.
    pub angle: Histogram,
    /// Turning angles along paths, in [0, π] (0 straight on): at each node of exactly two edges, π minus the
    /// angle between them (mass per bin; [`crate::graph::Graph::turning_angles`]). Empty in colors learned
    /// before it was, which the synthesis then does not match.
    #[serde(default = "empty_histogram")]
    pub turn: Histogram,
    /// Fraction of the nodes of degree 1, 2, 3 and 4 or more.
    pub degree: Vec<f64>,
    /// The smallest angle between two edges sharing a node: no new edge makes a sharper one.
    pub min_angle: f64,
    /// Edges per node (half the mean degree).
    pub edges_per_node: f64,
    /// Connected components per m².
    pub components_per_area: f64,
    /// Per higher-priority distribution category: the smallest distance from its instances to the graph's edges,
    /// which new edges keep clear.
    pub clearance: Vec<(String, f64)>,
    /// Higher-priority polygon categories whose contours the graph's edges never cross.
    pub avoids: Vec<String>,
}

/// What a color knows of a polygon category besides the distribution of its dense points: their spacing, which
/// tracing needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PolygonColor {
    /// Name of the polygon category.
    pub category: String,
    /// Side of the grid cells of the dense points that stand for its contours (m); filling and tracing use it.
    pub spacing: f64,
    /// Islands (outer contours with their lakes, [`crate::contour::islands`]) per m² of the exemplar region,
    /// counting those whose outer contour's centroid lies in it. 0 in colors learned before, whose synthesis then
    /// keeps the traced islands as they come.
    #[serde(default)]
    pub islands_per_area: f64,
    /// The land areas (m², lakes left out) of those islands, ascending.
    #[serde(default)]
    pub island_areas: Vec<f64>,
    /// The lakes of those islands per m² of the exemplar region. `None` in colors learned before, whose synthesis
    /// then keeps the traced lakes as they come.
    #[serde(default)]
    pub lakes_per_area: Option<f64>,
}

fn empty_histogram() -> Histogram {
    Histogram::zeros(0.0, 1.0, 0)
}

/// A learned color: every histogram of an exemplar region, ready to be painted elsewhere.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Color {
    /// The name the user gave it, shown in the palette.
    pub name: String,
    /// The exemplar region.
    pub region: Region,
    /// Area of the exemplar region (m²).
    pub region_area: f64,
    /// Largest distance the rdfs cover (m), and the default radius of the region of influence.
    pub max_radius: f64,
    /// Width `d_r` of the rdfs' distance bins (m).
    pub bin_width: f64,
    /// In priority order.
    pub categories: Vec<CategoryColor>,
    /// The rdfs (and oriented rdfs) of each category with itself and with the categories of higher priority.
    pub pairs: Vec<PairInteraction>,
    /// The map-sampling histograms `h_m`: terrain maps and distances to graphs and polygons.
    pub maps: Vec<MapInteraction>,
    /// The statistics of the graph categories.
    #[serde(default)]
    pub graphs: Vec<GraphColor>,
    /// The statistics of the polygon categories.
    #[serde(default)]
    pub polygons: Vec<PolygonColor>,
    /// Exemplar points (x, y, category index into `categories`) relative to the region's bbox min, for the
    /// palette's preview picture.
    pub preview: Vec<[f64; 3]>,
    /// What the color paints by: its statistics, or an arrangement's reference grown element by element. Written
    /// as the optional `"arrangement"` field, so files of either kind read as before.
    #[serde(
        default,
        rename = "arrangement",
        with = "kind_as_arrangement",
        skip_serializing_if = "ColorKind::is_statistics"
    )]
    pub kind: ColorKind,
}

/// What a color paints by.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ColorKind {
    /// The Metropolis-Hastings synthesis of its histograms (WorldBrush).
    #[default]
    Statistics,
    /// Local growth from a reference (Ijiri et al. 2008), its categories being the reference's symbols.
    Arrangement(ArrangementColor),
}

impl ColorKind {
    /// True for a color of statistics.
    pub fn is_statistics(&self) -> bool {
        matches!(self, ColorKind::Statistics)
    }
}

/// The kind as the file's optional `"arrangement"` field: absent (or `null`) for statistics.
mod kind_as_arrangement {
    use super::{ArrangementColor, ColorKind};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<S: Serializer>(kind: &ColorKind, s: S) -> Result<S::Ok, S::Error> {
        match kind {
            ColorKind::Statistics => None::<&ArrangementColor>.serialize(s),
            ColorKind::Arrangement(pattern) => Some(pattern).serialize(s),
        }
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<ColorKind, D::Error> {
        Ok(match Option::<ArrangementColor>::deserialize(d)? {
            Some(pattern) => ColorKind::Arrangement(pattern),
            None => ColorKind::Statistics,
        })
    }
}

/// An ordered set of colors.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Palette {
    /// The colors, in the order the user sees them.
    pub colors: Vec<Color>,
}

/// Reads the envelope of a palette or color file and returns its payload field.
fn open_envelope(
    s: &str,
    kind: FileKind,
    format: &str,
    payload: &str,
) -> Result<serde_json::Value> {
    let bad = |reason: String| Error::parse(kind, reason);
    let mut value: serde_json::Value = serde_json::from_str(s).map_err(|e| bad(e.to_string()))?;
    let obj = value
        .as_object_mut()
        .ok_or_else(|| bad("the top level is not an object".into()))?;
    match obj.get("format").and_then(|f| f.as_str()) {
        Some(f) if f == format => {}
        Some(f) => return Err(bad(format!("format is '{f}', expected '{format}'"))),
        None => return Err(bad(format!("missing \"format\": \"{format}\""))),
    }
    let version = obj
        .get("version")
        .and_then(|v| v.as_u64())
        .ok_or_else(|| bad("missing or non-integer \"version\"".into()))?;
    if version != PALETTE_FORMAT_VERSION as u64 {
        return Err(Error::UnsupportedVersion {
            kind,
            found: u32::try_from(version).unwrap_or(u32::MAX),
            supported: PALETTE_FORMAT_VERSION,
        });
    }
    obj.remove(payload)
        .ok_or_else(|| bad(format!("missing \"{payload}\"")))
}

/// Writes a palette or color file.
fn write_envelope(kind: FileKind, value: serde_json::Value) -> Result<String> {
    serde_json::to_string_pretty(&value).map_err(|e| Error::parse(kind, e.to_string()))
}

impl Palette {
    /// The palette as a versioned JSON file (the envelope of the module documentation).
    pub fn to_json(&self) -> Result<String> {
        write_envelope(
            FileKind::Palette,
            serde_json::json!({
                "format": PALETTE_FORMAT,
                "version": PALETTE_FORMAT_VERSION,
                "colors": self.colors,
            }),
        )
    }

    /// Reads a palette file and validates each of its colors.
    pub fn from_json(s: &str) -> Result<Palette> {
        let kind = FileKind::Palette;
        let colors = open_envelope(s, kind, PALETTE_FORMAT, "colors")?;
        let colors: Vec<Color> =
            serde_json::from_value(colors).map_err(|e| Error::parse(kind, e.to_string()))?;
        for (k, c) in colors.iter().enumerate() {
            c.validate()
                .map_err(|e| Error::parse(kind, format!("colors[{k}]: {}", e.reason())))?;
        }
        Ok(Palette { colors })
    }
}

impl Color {
    /// The color as a versioned JSON file of its own (the envelope of the module documentation).
    pub fn to_json(&self) -> Result<String> {
        write_envelope(
            FileKind::Color,
            serde_json::json!({
                "format": COLOR_FORMAT,
                "version": PALETTE_FORMAT_VERSION,
                "color": self,
            }),
        )
    }

    /// Reads a color file and validates the color.
    pub fn from_json(s: &str) -> Result<Color> {
        let kind = FileKind::Color;
        let color = open_envelope(s, kind, COLOR_FORMAT, "color")?;
        let color: Color =
            serde_json::from_value(color).map_err(|e| Error::parse(kind, e.to_string()))?;
        color.validate().map_err(|e| e.in_file(kind))?;
        Ok(color)
    }

    /// The arrangement's reference and settings, for a color that paints by growth.
    pub fn arrangement(&self) -> Option<&ArrangementColor> {
        match &self.kind {
            ColorKind::Arrangement(pattern) => Some(pattern),
            ColorKind::Statistics => None,
        }
    }

    /// The same, to change the painting settings.
    pub fn arrangement_mut(&mut self) -> Option<&mut ArrangementColor> {
        match &mut self.kind {
            ColorKind::Arrangement(pattern) => Some(pattern),
            ColorKind::Statistics => None,
        }
    }

    /// A color with no content over `region`, named `name`: what a tool follows where there is nothing to learn.
    pub fn empty(name: &str, region: &Region) -> Color {
        Color {
            name: name.to_string(),
            region: region.clone(),
            region_area: region.area(),
            max_radius: 1.0,
            bin_width: 1.0 / 24.0,
            categories: Vec::new(),
            pairs: Vec::new(),
            maps: Vec::new(),
            graphs: Vec::new(),
            polygons: Vec::new(),
            preview: Vec::new(),
            kind: ColorKind::Statistics,
        }
    }

    /// The color without content: no categories, pairs, maps, graphs, polygons or preview; its name, region and
    /// radii kept. Blending with it scales a color's densities; compared with it, densities read 0.
    pub fn emptied(&self) -> Color {
        Color {
            region_area: self.region_area,
            max_radius: self.max_radius,
            bin_width: self.bin_width,
            ..Color::empty(&self.name, &self.region)
        }
    }

    /// An empty scene holding the color's categories, to paint the color on.
    pub fn blank_scene(&self) -> Scene {
        Scene {
            categories: self.categories.iter().map(|c| c.category.clone()).collect(),
            ..Default::default()
        }
    }

    /// The color's graph statistics of a category, by name.
    pub fn graph(&self, name: &str) -> Option<&GraphColor> {
        self.graphs.iter().find(|g| g.category == name)
    }

    /// The color's polygon statistics of a category, by name.
    pub fn polygon(&self, name: &str) -> Option<&PolygonColor> {
        self.polygons.iter().find(|p| p.category == name)
    }

    /// The color's record of a category, by name.
    pub fn category(&self, name: &str) -> Option<&CategoryColor> {
        self.categories.iter().find(|c| c.category.name == name)
    }

    /// The shortest edge the color makes of each road, river (the lower edge of the first edge-length bin it
    /// holds) or coast category (its contours' point spacing): shorter pieces are stubs it would never make.
    pub fn shortest_edges(&self) -> Vec<(String, f64)> {
        let graphs = self.graphs.iter().filter_map(|g| {
            let h = &g.edge_length;
            let first = h.values.iter().position(|v| *v > 0.0)?;
            Some((g.category.clone(), h.start + first as f64 * h.bin_width))
        });
        let polygons = self
            .polygons
            .iter()
            .map(|p| (p.category.clone(), p.spacing));
        graphs.chain(polygons).collect()
    }

    /// The color with the interactions `off` switched off: each `(category, other)` names a pair (its rdf), a map
    /// (`other` is the map's name, or the graph or polygon category whose distance it is), a graph's clearance
    /// from or avoidance of `other`, or the facing of `category` to the roads of category `other`. Switched off, `category` is synthesized as if `other` were not there.
    pub fn without_interactions(&self, off: &[(String, String)]) -> Color {
        let is_off = |a: &str, b: &str| off.iter().any(|(x, y)| x == a && y == b);
        let mut out = self.clone();
        out.pairs.retain(|p| !is_off(&p.category, &p.other));
        out.maps.retain(|m| !is_off(&m.category, &m.map));
        for c in &mut out.categories {
            let name = c.category.name.clone();
            if let Some(f) = &mut c.facing {
                f.roads.retain(|road| !is_off(&name, road));
                if f.roads.is_empty() {
                    c.facing = None;
                }
            }
        }
        for g in &mut out.graphs {
            let name = g.category.clone();
            g.clearance.retain(|(other, _)| !is_off(&name, other));
            g.avoids.retain(|other| !is_off(&name, other));
        }
        out
    }
}

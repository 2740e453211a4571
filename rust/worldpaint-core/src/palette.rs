//! The learned statistics: interaction histograms, a *color* (the paper's "distribution": "The resulting set of
//! histograms is called a distribution ... stored as one distribution in the palette, by analogy to colors in a
//! painting system", Sections 3 and 4.3) and a palette of colors, saved as versioned JSON.
//!
//! JSON envelope: `{"format": "worldpaint-palette", "version": 1, "colors": [...]}` for a palette and
//! `{"format": "worldpaint-color", "version": 1, "color": {...}}` for a single color. An unknown version gives
//! [`Error::UnsupportedVersion`], anything unreadable [`Error::Json`]; reading never panics. Non-finite numbers
//! (an unbounded `min_distance`) are written as `null` and read back as `+∞`.

use crate::error::{Error, Result};
use crate::geom::Region;
use crate::scene::{Category, Scene};
use serde::{Deserialize, Serialize};

/// Version of the palette JSON this build writes and reads.
pub const PALETTE_FORMAT_VERSION: u32 = 1;
const PALETTE_FORMAT: &str = "worldpaint-palette";
const COLOR_FORMAT: &str = "worldpaint-color";

/// A 1D histogram with bins `[start + k w, start + (k+1) w)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    pub start: f64,
    pub bin_width: f64,
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
    pub fn bin_of(&self, x: f64) -> Option<usize> {
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
    pub fn normalized(&self) -> Histogram {
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
    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_some(v)
        } else {
            s.serialize_none()
        }
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

/// What a color knows about one category: how many instances, how dense, how close they come, and how they
/// are scaled, turned and which prototypes they show.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CategoryColor {
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
}

/// An interaction histogram between two categories (Section 4.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Interaction {
    /// Radial distribution function, eq. (2) with the window-edge correction. Bin k covers distances
    /// [k d_r, (k+1) d_r) with d_r = `Color::bin_width`; 1 everywhere for a Poisson arrangement.
    Rdf { hist: Histogram },
    /// Oriented rdf: distance × angle (angle of `other − category` relative to world X, folded to [0, π)),
    /// `values[k * angle_bins + l]`; normalized like the rdf (1 for a Poisson arrangement).
    OrientedRdf {
        distance_bin: f64,
        angle_bins: usize,
        values: Vec<f64>,
    },
}

/// Interaction of `category` with `other` (`other` has equal or higher priority).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairInteraction {
    pub category: String,
    pub other: String,
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
    pub category: String,
    pub map: String,
    pub hist: Histogram,
    #[serde(default = "empty_histogram")]
    pub region_hist: Histogram,
    #[serde(default)]
    pub source: MapSource,
}

/// What a color knows of a graph category besides the distribution of its nodes (Section 4.2, thesis 6.3.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GraphColor {
    pub category: String,
    /// Lengths of the edges (mass per bin).
    pub edge_length: Histogram,
    /// Angles between two edges sharing a node, in [0, π] (mass per bin).
    pub angle: Histogram,
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
    pub category: String,
    pub spacing: f64,
}

fn empty_histogram() -> Histogram {
    Histogram::zeros(0.0, 1.0, 0)
}

/// A learned color: every histogram of an exemplar region, ready to be painted elsewhere.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Color {
    pub name: String,
    /// The exemplar region.
    pub region: Region,
    pub region_area: f64,
    pub max_radius: f64,
    pub bin_width: f64,
    /// In priority order.
    pub categories: Vec<CategoryColor>,
    pub pairs: Vec<PairInteraction>,
    pub maps: Vec<MapInteraction>,
    #[serde(default)]
    pub graphs: Vec<GraphColor>,
    #[serde(default)]
    pub polygons: Vec<PolygonColor>,
    /// Exemplar points (x, y, category index into `categories`) relative to the region's bbox min, for the
    /// palette's preview picture.
    pub preview: Vec<[f64; 3]>,
}

/// An ordered set of colors.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Palette {
    pub colors: Vec<Color>,
}

fn to_json_error(e: serde_json::Error) -> Error {
    Error::Json(e.to_string())
}

/// Reads the envelope of a palette or color file and returns its payload field.
fn open_envelope(s: &str, format: &str, payload: &str) -> Result<serde_json::Value> {
    let mut value: serde_json::Value = serde_json::from_str(s).map_err(to_json_error)?;
    let obj = value
        .as_object_mut()
        .ok_or_else(|| Error::Json("top level is not an object".into()))?;
    match obj.get("format").and_then(|f| f.as_str()) {
        Some(f) if f == format => {}
        Some(f) => return Err(Error::Json(format!("format is '{f}', expected '{format}'"))),
        None => return Err(Error::Json(format!("missing \"format\": \"{format}\""))),
    }
    let version = obj
        .get("version")
        .and_then(|v| v.as_u64())
        .ok_or_else(|| Error::Json("missing or non-integer \"version\"".into()))?;
    if version != PALETTE_FORMAT_VERSION as u64 {
        return Err(Error::UnsupportedVersion {
            found: u32::try_from(version).unwrap_or(u32::MAX),
            supported: PALETTE_FORMAT_VERSION,
        });
    }
    obj.remove(payload)
        .ok_or_else(|| Error::Json(format!("missing \"{payload}\"")))
}

impl Palette {
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(&serde_json::json!({
            "format": PALETTE_FORMAT,
            "version": PALETTE_FORMAT_VERSION,
            "colors": self.colors,
        }))
        .map_err(to_json_error)
    }

    pub fn from_json(s: &str) -> Result<Palette> {
        let colors = open_envelope(s, PALETTE_FORMAT, "colors")?;
        let colors: Vec<Color> = serde_json::from_value(colors).map_err(to_json_error)?;
        for c in &colors {
            c.validate()?;
        }
        Ok(Palette { colors })
    }
}

impl Color {
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string_pretty(&serde_json::json!({
            "format": COLOR_FORMAT,
            "version": PALETTE_FORMAT_VERSION,
            "color": self,
        }))
        .map_err(to_json_error)
    }

    pub fn from_json(s: &str) -> Result<Color> {
        let color = open_envelope(s, COLOR_FORMAT, "color")?;
        let color: Color = serde_json::from_value(color).map_err(to_json_error)?;
        color.validate()?;
        Ok(color)
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

    /// The color with the interactions `off` switched off: each `(category, other)` names a pair (its rdf), a map
    /// (`other` is the map's name, or the graph or polygon category whose distance it is), or a graph's clearance
    /// from or avoidance of `other`. Switched off, `category` is synthesized as if `other` were not there.
    pub fn without_interactions(&self, off: &[(String, String)]) -> Color {
        let is_off = |a: &str, b: &str| off.iter().any(|(x, y)| x == a && y == b);
        let mut out = self.clone();
        out.pairs.retain(|p| !is_off(&p.category, &p.other));
        out.maps.retain(|m| !is_off(&m.category, &m.map));
        for g in &mut out.graphs {
            let name = g.category.clone();
            g.clearance.retain(|(other, _)| !is_off(&name, other));
            g.avoids.retain(|other| !is_off(&name, other));
        }
        out
    }

    /// Checks what synthesis relies on (as read from a file it may be anything): positive finite radii,
    /// histogram shapes, known category names.
    pub fn validate(&self) -> Result<()> {
        self.validate_scales()?;
        self.validate_categories()?;
        self.validate_pairs()?;
        self.validate_maps()?;
        self.validate_graphs()?;
        self.validate_polygons()
    }

    /// A validation error naming the color.
    fn invalid<T>(&self, m: String) -> Result<T> {
        Err(Error::Json(format!("color '{}': {m}", self.name)))
    }

    /// A histogram has valid bins (or no values) and finite, non-negative values.
    fn check_hist(&self, h: &Histogram, what: &str) -> Result<()> {
        if !(h.bin_width.is_finite() && h.bin_width > 0.0 && h.start.is_finite())
            && !h.values.is_empty()
        {
            return Err(Error::Json(format!(
                "color '{}': {what} histogram has bad bins",
                self.name
            )));
        }
        if h.values.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(Error::Json(format!(
                "color '{}': {what} histogram has negative or non-finite values",
                self.name
            )));
        }
        Ok(())
    }

    /// The rdf's radius and bin width, and the region's area.
    fn validate_scales(&self) -> Result<()> {
        if !(self.max_radius.is_finite() && self.max_radius > 0.0) {
            return self.invalid(format!("max_radius {} is not positive", self.max_radius));
        }
        if !(self.bin_width.is_finite() && self.bin_width > 0.0) {
            return self.invalid(format!("bin_width {} is not positive", self.bin_width));
        }
        if !(self.region_area.is_finite() && self.region_area >= 0.0) {
            return self.invalid("region_area is not valid".into());
        }
        Ok(())
    }

    fn validate_categories(&self) -> Result<()> {
        for c in &self.categories {
            if !(c.density.is_finite() && c.density >= 0.0) {
                return self.invalid(format!(
                    "category '{}' density is not valid",
                    c.category.name
                ));
            }
            self.check_hist(&c.scale, "scale")?;
            self.check_hist(&c.rotation, "rotation")?;
            if c.prototype_weights
                .iter()
                .any(|w| !w.is_finite() || *w < 0.0)
            {
                return self.invalid(format!("category '{}' prototype weights", c.category.name));
            }
        }
        Ok(())
    }

    fn validate_pairs(&self) -> Result<()> {
        for p in &self.pairs {
            if self.category(&p.category).is_none() || self.category(&p.other).is_none() {
                return self.invalid(format!(
                    "pair {}-{} names an unknown category",
                    p.category, p.other
                ));
            }
            match &p.interaction {
                Interaction::Rdf { hist } => self.check_hist(hist, "rdf")?,
                Interaction::OrientedRdf {
                    distance_bin,
                    angle_bins,
                    values,
                } => {
                    if !(distance_bin.is_finite() && *distance_bin > 0.0)
                        || *angle_bins == 0
                        || values.len() % angle_bins != 0
                        || values.iter().any(|v| !v.is_finite() || *v < 0.0)
                    {
                        return self.invalid(format!("oriented rdf {}-{}", p.category, p.other));
                    }
                }
            }
        }
        Ok(())
    }

    fn validate_maps(&self) -> Result<()> {
        for m in &self.maps {
            if self.category(&m.category).is_none() {
                return self.invalid(format!(
                    "map histogram names unknown category {}",
                    m.category
                ));
            }
            self.check_hist(&m.hist, "map")?;
            self.check_hist(&m.region_hist, "map region")?;
            if m.source != MapSource::Terrain && self.category(&m.map).is_none() {
                return self.invalid(format!(
                    "distance map of {} names unknown category {}",
                    m.category, m.map
                ));
            }
        }
        Ok(())
    }

    fn validate_graphs(&self) -> Result<()> {
        for g in &self.graphs {
            if self.category(&g.category).is_none() {
                return self.invalid(format!(
                    "graph statistics name unknown category {}",
                    g.category
                ));
            }
            self.check_hist(&g.edge_length, "edge length")?;
            self.check_hist(&g.angle, "angle")?;
            let finite = [g.min_angle, g.edges_per_node, g.components_per_area]
                .iter()
                .all(|v| v.is_finite() && *v >= 0.0);
            if !finite || g.degree.iter().any(|v| !v.is_finite() || *v < 0.0) {
                return self.invalid(format!("graph statistics of {} are not valid", g.category));
            }
        }
        Ok(())
    }

    fn validate_polygons(&self) -> Result<()> {
        for p in &self.polygons {
            if self.category(&p.category).is_none() || !(p.spacing.is_finite() && p.spacing > 0.0) {
                return self.invalid(format!(
                    "polygon statistics of {} are not valid",
                    p.category
                ));
            }
        }
        Ok(())
    }
}

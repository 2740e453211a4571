//! Brushes (Section 5.3, Fig. 12–13; thesis 6.5.1): "the region for synthesizing evolves along the brush path".
//!
//! A [`BrushStroke`] follows the brush: each time the brush has travelled `spacing × radius` along its path it makes a
//! *dab* at the brush centre. Dab `k` paints the disc `φ_k` without the discs of the earlier dabs of the stroke
//! — "we remove all existing objects in `φ_k` except those objects in `φ_i`, `i < k`. Then we synthesize new
//! objects in `φ_k` while considering the region of influence `I_k = X_k ∪ {φ_i, i ≤ k}`" — so the stroke
//! grows seamlessly: what earlier dabs painted stays and conditions the next ones like any content around them,
//! and the leading edge of a dab, where nothing stands yet, is a free border whose missing neighbours the synthesis
//! integrates (so no arc of instances marks it; measured on a 40-dab stroke, the density across each dab step stays
//! within 7 % of the color's).
//!
//! **Alpha** (thesis 6.5.1: "interpolate between the existing color with the brush color, with an alpha
//! coefficient that varies along the brush radius"): with an opacity below 1 or a falloff, the color under the
//! brush (learned from the scene as it was before the stroke, over the dab's disc) is interpolated with the brush
//! color at `α(r) = opacity · falloff(r / R)` by the optimal-transport interpolation of [`crate::interpolate`],
//! in `ALPHA_RINGS` rings from the centre out, each painted conditioned on the rings inside it. A ring repaints
//! what earlier dabs covered only with rings farther from their centres, so every place ends with the alpha of
//! the brush centre's closest pass, as a stroke across it would paint it. Over bare ground the color under the
//! brush is empty and alpha thins the brush color's densities.
//!
//! **Spray** (Ijiri et al. 2008, §5.3): an arrangement color's dab grows its pattern into the disc from the
//! elements around and in it, which stay; other content in the disc is cleared. Opacity and falloff do not apply.
//!
//! **Eraser** (thesis 6.5.1, "simply removes all objects within the circular region"): the same stroke in
//! erase mode removes the unlocked instances (of the chosen categories) within the radius of the brush path. A
//! road, river or coast category chosen by name is cut too: the parts of its paths and contours under the brush
//! go, and so do the pieces left beside the cut that are shorter than the category's shortest edge before the
//! stroke (stubs no synthesis of it would make).

use super::{color_of_region, empty_color, Clearing, ToolEdit, Working};
use crate::error::{check, Error, Result};
use crate::geom::{segment_distance, DVec2, Region};
use crate::interpolate::interpolate_colors;
use crate::palette::Color;
use crate::scene::Scene;
use crate::synthesis::{mix_seed, SynthesisOptions};

/// Rings in which an alpha brush blends the color under it with its own.
pub(crate) const ALPHA_RINGS: usize = 3;
/// Dabs whose new area is below this fraction of the disc paint nothing (the brush has hardly moved).
const MIN_NEW_AREA: f64 = 1e-3;

/// How the brush's alpha falls off from its centre (`x` = distance / radius).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Falloff {
    /// The same alpha over the whole disc.
    Constant,
    /// `1 − x`.
    Linear,
    /// `1 − (3x² − 2x³)`, Blender's smooth brush curve.
    Smooth,
}

impl Falloff {
    pub(crate) fn weight(self, x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        match self {
            Falloff::Constant => 1.0,
            Falloff::Linear => 1.0 - x,
            Falloff::Smooth => 1.0 - x * x * (3.0 - 2.0 * x),
        }
    }
}

/// What the brush does.
#[derive(Clone, Debug)]
pub enum BrushMode {
    /// Paints a color.
    Paint(Box<Color>),
    /// Removes unlocked instances of these categories (all when `None`), and cuts the paths and contours of the
    /// graph and polygon categories named.
    Erase(Option<Vec<String>>),
}

/// Brush settings.
#[derive(Clone, Debug)]
pub struct BrushOptions {
    /// Radius of the brush disc (m).
    pub radius: f64,
    /// A new dab each time the brush has travelled this fraction of its radius.
    pub spacing: f64,
    /// Alpha at the brush centre, in (0, 1].
    pub opacity: f64,
    /// How the alpha falls off from the centre to the rim.
    pub falloff: Falloff,
    /// Seed, region of influence and proposals of each dab's synthesis (dab `k` uses a seed derived from
    /// `seed` and `k`).
    pub synthesis: SynthesisOptions,
}

impl Default for BrushOptions {
    fn default() -> Self {
        BrushOptions {
            radius: 20.0,
            spacing: 0.5,
            opacity: 1.0,
            falloff: Falloff::Constant,
            synthesis: SynthesisOptions::default(),
        }
    }
}

/// One brush stroke over a scene (see the module documentation).
pub struct BrushStroke {
    work: Working,
    /// The scene before the stroke (kept only for an alpha brush, to read the color under the brush).
    before: Option<Scene>,
    mode: BrushMode,
    opts: BrushOptions,
    dabs: Vec<DVec2>,
    last: Option<DVec2>,
    /// Path length since the last dab.
    travelled: f64,
    /// The shortest edge of each category's paths and contours before the stroke (0 without any): the eraser
    /// removes pieces shorter than it.
    shortest_edges: Vec<f64>,
}

impl BrushStroke {
    /// Starts a stroke on `scene` (no dab yet); fails on a radius or spacing that is not positive, an opacity
    /// outside (0, 1] or an invalid color.
    pub fn new(scene: &Scene, mode: BrushMode, opts: BrushOptions) -> Result<BrushStroke> {
        check::positive("brush radius", opts.radius)?;
        check::positive("brush spacing", opts.spacing)?;
        if !(opts.opacity > 0.0 && opts.opacity <= 1.0) {
            return Err(Error::OutOfRange {
                what: "brush opacity".into(),
                rule: "in (0, 1]".into(),
                value: opts.opacity,
            });
        }
        if let BrushMode::Paint(color) = &mode {
            color.validate()?;
        }
        let alpha = opts.opacity < 1.0 || opts.falloff != Falloff::Constant;
        let before = (alpha && matches!(mode, BrushMode::Paint(_))).then(|| scene.clone());
        Ok(BrushStroke {
            work: Working::new(scene),
            before,
            mode,
            opts,
            dabs: Vec::new(),
            last: None,
            travelled: 0.0,
            shortest_edges: shortest_edges(scene),
        })
    }

    /// Sets the length below which the eraser removes what it leaves of a road, river or coast category: the
    /// shortest edge of the color that made it ([`Color::shortest_edges`]); by default, the shortest edge of the
    /// category's paths and contours in the scene, the ends of open paths left out (they may be earlier cuts).
    pub fn set_shortest_edge(&mut self, category: &str, length: f64) -> Result<()> {
        check::non_negative("shortest edge", length)?;
        let index = self.work.scene.category_index(category).ok_or_else(|| {
            Error::invalid("the scene", format!("has no category named '{category}'"))
        })?;
        self.shortest_edges[index] = length;
        Ok(())
    }

    /// The scene as the stroke has left it so far.
    pub fn scene(&self) -> &Scene {
        &self.work.scene
    }

    /// What the stroke has done so far, relative to the scene it started on.
    pub fn edit(&self) -> ToolEdit {
        self.work.edit()
    }

    /// Centres of the dabs made so far.
    pub fn dabs(&self) -> &[DVec2] {
        &self.dabs
    }

    /// Moves the brush to `p` and paints (or erases) along the way; returns the number of dabs made.
    pub fn move_to(&mut self, p: DVec2) -> Result<usize> {
        self.follow(&[p], &|_| true)
    }

    /// Follows the brush along `path`, calling `progress` with the fraction of the path's dabs done (false
    /// cancels with [`Error::Cancelled`]); returns the number of dabs made.
    pub fn follow(
        &mut self,
        path: &[DVec2],
        progress: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<usize> {
        if path.iter().any(|p| !p.is_finite()) {
            return Err(Error::invalid("brush path", "has non-finite points"));
        }
        if let BrushMode::Erase(categories) = &self.mode {
            let categories = categories.clone();
            for &p in path {
                let a = self.last.unwrap_or(p);
                self.erase_segment(a, p, categories.as_deref());
                self.last = Some(p);
                self.dabs.push(p);
            }
            return Ok(path.len());
        }
        let centres = self.dab_centres(path);
        for (k, c) in centres.iter().enumerate() {
            self.paint_dab(*c, &|f| progress((k as f64 + f) / centres.len() as f64))?;
        }
        Ok(centres.len())
    }

    /// Advances the path state along `path`: where dabs fall (every `spacing × radius`, the first at once).
    fn dab_centres(&mut self, path: &[DVec2]) -> Vec<DVec2> {
        let step = self.opts.spacing * self.opts.radius;
        let mut out = Vec::new();
        for &p in path {
            let Some(mut at) = self.last else {
                out.push(p);
                self.last = Some(p);
                continue;
            };
            let mut remaining = at.distance(p);
            while remaining > 0.0 {
                let need = step - self.travelled;
                if need > remaining {
                    self.travelled += remaining;
                    break;
                }
                at += (p - at) * (need / remaining);
                remaining -= need;
                self.travelled = 0.0;
                out.push(at);
            }
            self.last = Some(p);
        }
        out
    }

    fn erase_segment(&mut self, a: DVec2, b: DVec2, categories: Option<&[String]>) {
        let r = self.opts.radius;
        let names = &self.work.scene.categories;
        let wanted: Option<Vec<bool>> = categories.map(|only| {
            names
                .iter()
                .map(|c| only.iter().any(|n| n == &c.name))
                .collect()
        });
        self.work.remove_where(|i| {
            wanted
                .as_ref()
                .is_none_or(|w| w.get(i.category).copied().unwrap_or(false))
                && segment_distance(i.position, a, b) <= r
        });
        if let Some(wanted) = wanted.filter(|w| w.iter().any(|&x| x)) {
            let shortest = &self.shortest_edges;
            let of = |c: usize| {
                (wanted.get(c).copied().unwrap_or(false))
                    .then(|| shortest.get(c).copied().unwrap_or(0.0))
            };
            self.work.cut_structures(&capsule(a, b, r), &of);
        }
    }

    /// One dab of a painting stroke at `centre` (see the module documentation).
    fn paint_dab(&mut self, centre: DVec2, progress: &(dyn Fn(f64) -> bool + Sync)) -> Result<()> {
        let BrushMode::Paint(color) = &self.mode else {
            return Ok(());
        };
        let r = self.opts.radius;
        let k = self.dabs.len();
        if !color.kind.is_statistics() {
            // the spray tool grows the pattern into the disc's gaps; a pattern has no alpha
            self.dabs.push(centre);
            let mut dab_opts = self.opts.synthesis.clone();
            dab_opts.seed = mix_seed(self.opts.synthesis.seed, k as u64 + 1);
            dab_opts.guides.start = Some(centre);
            let disc = Region::Circle {
                center: centre,
                radius: r,
            };
            let color = color.clone();
            self.work
                .fill(Clearing::KeepingPattern, &color, &disc, &dab_opts, progress)?;
            return Ok(());
        }
        let earlier: Vec<DVec2> = self
            .dabs
            .iter()
            .copied()
            .filter(|c| c.distance(centre) < 2.0 * r)
            .collect();
        self.dabs.push(centre);
        let disc = |c: DVec2, radius: f64| Region::Circle { center: c, radius };
        let full_area = std::f64::consts::PI * r * r;
        let rings = if self.opts.falloff == Falloff::Constant {
            1
        } else {
            ALPHA_RINGS
        };
        let under = match &self.before {
            Some(before) => Some(
                color_of_region(before, &disc(centre, r), "under the brush")?
                    .unwrap_or_else(|| empty_color(color, &disc(centre, r))),
            ),
            None => None,
        };
        let mut dab_opts = self.opts.synthesis.clone();
        dab_opts.seed = mix_seed(self.opts.synthesis.seed, k as u64 + 1);
        for j in 0..rings {
            let (inner, outer) = (
                r * j as f64 / rings as f64,
                r * (j + 1) as f64 / rings as f64,
            );
            // ring j repaints what no earlier dab covered with a ring as central as this one
            let mut without: Vec<Region> = earlier.iter().map(|c| disc(*c, outer)).collect();
            if inner > 0.0 {
                without.push(disc(centre, inner));
            }
            let region = if without.is_empty() {
                disc(centre, outer)
            } else {
                Region::Clipped {
                    within: vec![disc(centre, outer)],
                    without,
                }
            };
            if region.area() < MIN_NEW_AREA * full_area {
                continue;
            }
            let blended;
            let ring_color = match &under {
                None => color,
                Some(under) => {
                    let x = 0.5 * (inner + outer) / r;
                    let alpha = (self.opts.opacity * self.opts.falloff.weight(x)).clamp(0.0, 1.0);
                    blended = interpolate_colors(under, color, alpha, &color.name)?;
                    &blended
                }
            };
            let mut ring_opts = dab_opts.clone();
            ring_opts.seed = mix_seed(dab_opts.seed, j as u64);
            let f0 = j as f64 / rings as f64;
            self.work
                .fill(Clearing::All, ring_color, &region, &ring_opts, &|f| {
                    progress(f0 + f / rings as f64)
                })?;
        }
        Ok(())
    }
}

/// Sides of the half-discs that end the eraser's capsule.
const CAPSULE_ARC_SIDES: usize = 12;

/// The region within `r` of the segment `a`–`b` (a disc when they coincide), as a polygon around it: its straight
/// sides on the outline, its arcs' corners within 1 % of `r` outside it.
fn capsule(a: DVec2, b: DVec2, r: f64) -> Region {
    let along = (b - a).try_normalize().unwrap_or(DVec2::X);
    let normal = along.perp();
    // each half-disc circumscribed: its sides touch the circle (the first and last along the straight sides, at
    // `r`), so all within `r` of the segment is inside
    let step = std::f64::consts::PI / CAPSULE_ARC_SIDES as f64;
    let r = r / (0.5 * step).cos();
    let mut points = Vec::with_capacity(2 * CAPSULE_ARC_SIDES);
    for (centre, start) in [(b, -normal), (a, normal)] {
        for k in 0..CAPSULE_ARC_SIDES {
            let t = step * (k as f64 + 0.5);
            // half a turn from `start`, counter-clockwise through the segment's outward direction
            let dir = start * t.cos() + start.perp() * t.sin();
            points.push(centre + dir * r);
        }
    }
    Region::Polygon { points }
}

/// The shortest edge of each category's paths and contours in `scene` (0 for a category without any); the end
/// edges of an open path of more than two edges are left out: a cut may have shortened them.
fn shortest_edges(scene: &Scene) -> Vec<f64> {
    let mut out = vec![f64::INFINITY; scene.categories.len()];
    let lines = scene
        .paths
        .iter()
        .map(|p| (p.category, &p.points, false))
        .chain(scene.contours.iter().map(|c| (c.category, &c.points, true)));
    for (category, points, closed) in lines {
        let Some(slot) = out.get_mut(category) else {
            continue;
        };
        let mut edges: Vec<f64> = points.windows(2).map(|w| w[0].distance(w[1])).collect();
        match (points.first(), points.last()) {
            (Some(first), Some(last)) if closed => edges.push(first.distance(*last)),
            _ if edges.len() > 2 => {
                edges.pop();
                edges.remove(0);
            }
            _ => {}
        }
        for length in edges.into_iter().filter(|l| *l > 0.0) {
            *slot = slot.min(length);
        }
    }
    out.into_iter()
        .map(|l| if l.is_finite() { l } else { 0.0 })
        .collect()
}

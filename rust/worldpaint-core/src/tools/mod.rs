//! The painting tools of Section 5 (and thesis ch. 6.4–6.5) as operations over a scene: paste (§5.1), brush
//! strokes with alpha and the eraser ([`brush`], §5.3 and thesis 6.5.1), move ([`moving`], §5.4),
//! seam-carving stretch ([`stretch`], §5.5), gradients ([`gradient`], §5.2) and blur ([`blur`], thesis 6.5.2).
//!
//! Every tool returns an [`Edit`]: which of the scene's instances it removed and which it added, so a caller
//! holding the scene elsewhere (Blender's point clouds) applies exactly that. Locked instances (placed by hand)
//! are never removed; inside a painted region they condition the synthesis like the region of influence does.
//! A tool that paints several regions in turn (a stroke's dabs, a gradient's bands, a blur's cells) paints each
//! conditioned on everything around it, including what its earlier steps painted: "each of them taking into
//! account the previously synthesized regions" (Section 5.3).

pub mod blur;
pub mod brush;
pub mod gradient;
pub mod moving;
pub mod stretch;

use crate::analysis::{learn_color, AnalysisOptions};
use crate::error::{Error, Result};
use crate::geom::{DVec2, Region};
use crate::palette::Color;
use crate::scene::{Category, Instance, Scene};
use crate::synthesis::{synthesize_keeping, SynthesisOptions};

/// What a tool did: the scene's instances it removed (indices, ascending) and the instances it added, whose
/// `category` indexes `categories` (the scene's categories, then any the tool's colors brought).
#[derive(Clone, Debug, Default)]
pub struct Edit {
    pub categories: Vec<Category>,
    pub removed: Vec<usize>,
    pub added: Vec<Instance>,
}

impl Edit {
    /// The scene after the edit.
    pub fn applied_to(&self, scene: &Scene) -> Scene {
        let mut gone = vec![false; scene.instances.len()];
        for &i in &self.removed {
            gone[i] = true;
        }
        let mut instances: Vec<Instance> = scene
            .instances
            .iter()
            .zip(&gone)
            .filter(|(_, g)| !**g)
            .map(|(i, _)| *i)
            .collect();
        instances.extend_from_slice(&self.added);
        Scene {
            categories: self.categories.clone(),
            instances,
            terrain: scene.terrain.clone(),
            ..Default::default()
        }
    }
}

/// A scene being edited by a tool: the current instances, each remembering which original instance it is.
pub(crate) struct Working {
    pub(crate) scene: Scene,
    /// Per current instance: its index in the original scene (`None` for an added one).
    origin: Vec<Option<usize>>,
    n_original: usize,
}

impl Working {
    pub(crate) fn new(scene: &Scene) -> Self {
        Working {
            scene: scene.clone(),
            origin: (0..scene.instances.len()).map(Some).collect(),
            n_original: scene.instances.len(),
        }
    }

    /// Removes the unlocked instances for which `pred` holds; returns them.
    pub(crate) fn remove_where(&mut self, pred: impl Fn(&Instance) -> bool) -> Vec<Instance> {
        let n = self.scene.instances.len();
        let mut removed = Vec::new();
        let mut instances = Vec::with_capacity(n);
        let mut origin = Vec::with_capacity(n);
        for (i, o) in self.scene.instances.drain(..).zip(self.origin.drain(..)) {
            if !i.locked && pred(&i) {
                removed.push(i);
            } else {
                instances.push(i);
                origin.push(o);
            }
        }
        self.scene.instances = instances;
        self.origin = origin;
        removed
    }

    /// Adds instances whose categories index `categories` (an extension of the scene's list).
    pub(crate) fn add(&mut self, categories: Vec<Category>, instances: Vec<Instance>) {
        if categories.len() > self.scene.categories.len() {
            self.scene.categories = categories;
        }
        self.origin
            .extend(std::iter::repeat_n(None, instances.len()));
        self.scene.instances.extend(instances);
    }

    /// Applies an edit computed on the current scene (its `removed` index the current instances).
    pub(crate) fn apply(&mut self, edit: &Edit) {
        let mut gone = vec![false; self.scene.instances.len()];
        for &k in &edit.removed {
            gone[k] = true;
        }
        let mut k = 0;
        self.origin.retain(|_| {
            k += 1;
            !gone[k - 1]
        });
        k = 0;
        self.scene.instances.retain(|_| {
            k += 1;
            !gone[k - 1]
        });
        self.add(edit.categories.clone(), edit.added.clone());
    }

    /// Removes the unlocked content inside `region` and synthesizes `color` there, conditioned on the rest.
    pub(crate) fn paint(
        &mut self,
        color: &Color,
        region: &Region,
        opts: &SynthesisOptions,
        progress: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<usize> {
        self.remove_where(|i| region.contains(i.position));
        let result = synthesize_keeping(&self.scene, color, region, opts, progress, &|_| true)?;
        let n = result.instances.len();
        self.add(result.categories, result.instances);
        Ok(n)
    }

    /// The edit from the original scene to the current one.
    pub(crate) fn edit(&self) -> Edit {
        let mut present = vec![false; self.n_original];
        let mut added = Vec::new();
        for (i, o) in self.scene.instances.iter().zip(&self.origin) {
            match o {
                Some(k) => present[*k] = true,
                None => added.push(*i),
            }
        }
        Edit {
            categories: self.scene.categories.clone(),
            removed: (0..self.n_original).filter(|&k| !present[k]).collect(),
            added,
        }
    }
}

/// Paste (Section 5.1): removes the unlocked instances inside `region` and synthesizes the color there,
/// consistent with the content around it.
pub fn paste(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<Edit> {
    region.validate()?;
    let mut work = Working::new(scene);
    work.paint(color, region, opts, progress)?;
    Ok(work.edit())
}

/// The color of the content of `region` (every distribution category, with the slope preference when the terrain
/// has a slope map), or `None` when the region holds no distribution instance: the statistics a tool reads off
/// the scene itself (the pipette, the colors around a blur, the color under an alpha brush).
pub fn color_of_region(scene: &Scene, region: &Region, name: &str) -> Result<Option<Color>> {
    let maps = match scene.terrain.as_deref() {
        Some(t) if t.maps.contains_key("slope") => vec!["slope".to_string()],
        _ => Vec::new(),
    };
    let opts = AnalysisOptions {
        maps,
        ..Default::default()
    };
    match learn_color(scene, region, name, &opts) {
        Ok(c) => Ok(Some(c)),
        Err(Error::EmptyExemplar(_)) => Ok(None),
        Err(e) => Err(e),
    }
}

/// About how many points a painted preview shows.
const PREVIEW_POINTS: f64 = 4_000.0;

/// The color with a preview that shows an arrangement painted with it (terrain maps aside): for colors no
/// exemplar showed, such as interpolations. A large region is previewed by a square patch at its centre, scaled to
/// the region's frame, so the preview stays quick to paint and to draw.
pub fn with_painted_preview(mut color: Color) -> Result<Color> {
    let mut plain = color.clone();
    plain.maps.clear();
    let canvas = Scene {
        categories: color
            .categories
            .iter()
            .map(|c| c.category.clone())
            .collect(),
        ..Default::default()
    };
    let (lo, hi) = color.region.bbox();
    let density: f64 = color.categories.iter().map(|c| c.density).sum();
    let side = (PREVIEW_POINTS / density.max(1e-12)).sqrt();
    let (region, scale) = if density * color.region.area() <= PREVIEW_POINTS {
        (color.region.clone(), DVec2::ONE)
    } else {
        let centre = 0.5 * (lo + hi);
        let patch = Region::Rect {
            min: centre - DVec2::splat(0.5 * side),
            max: centre + DVec2::splat(0.5 * side),
        };
        (patch, (hi - lo) / side)
    };
    let painted = crate::synthesis::synthesize(&canvas, &plain, &region, &Default::default())?;
    let (origin, _) = region.bbox();
    color.preview = painted
        .instances
        .iter()
        .map(|i| {
            let p = (i.position - origin) * scale;
            [p.x, p.y, i.category as f64]
        })
        .collect();
    Ok(color)
}

/// A color with no content, for blending with "nothing" (an empty neighbourhood, a brush over bare ground):
/// interpolating it with a color scales that color's densities and keeps its other statistics.
pub(crate) fn empty_color(like: &Color, region: &Region) -> Color {
    Color {
        name: "empty".into(),
        region: region.clone(),
        region_area: region.area(),
        max_radius: like.max_radius,
        bin_width: like.bin_width,
        categories: Vec::new(),
        pairs: Vec::new(),
        maps: Vec::new(),
        graphs: Vec::new(),
        polygons: Vec::new(),
        preview: Vec::new(),
    }
}

/// Checks a seed-independent option: a positive finite number.
pub(crate) fn positive(value: f64, what: &str) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidInput(format!(
            "{what} {value} must be positive"
        )))
    }
}

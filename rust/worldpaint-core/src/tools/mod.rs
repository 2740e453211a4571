//! The painting tools of Section 5 (and thesis ch. 6.4–6.5) as operations over a scene: paste (§5.1), brush
//! strokes with alpha and the eraser ([`brush`], §5.3 and thesis 6.5.1), move ([`moving`], §5.4),
//! seam-carving stretch ([`stretch`], §5.5), gradients ([`gradient`], §5.2) and blur ([`blur`], thesis 6.5.2).
//!
//! Every tool returns a [`ToolEdit`]: which of the scene's instances it removed and which it added, so a caller
//! holding the scene elsewhere (Blender's point clouds) applies exactly that. Locked instances (placed by hand)
//! are never removed; inside a painted region they condition the synthesis like the region of influence does.
//! A tool that paints several regions in turn (a stroke's dabs, a gradient's bands, a blur's cells) paints each
//! conditioned on everything around it, including what its earlier steps painted: "each of them taking into
//! account the previously synthesized regions" (Section 5.3).

pub(crate) mod blur;
pub(crate) mod brush;
pub(crate) mod gradient;
pub(crate) mod moving;
pub(crate) mod stretch;

use crate::analysis::{learn_color, AnalysisOptions};
use crate::contour::cut;
use crate::error::{Error, Result};
use crate::geom::{polyline_length, DVec2, PreparedRegion, Region, RegionQueries};
use crate::paint::{synthesize, synthesize_keeping};
use crate::palette::Color;
use crate::scene::{Category, Contour, Instance, Path, Scene};
use crate::synthesis::{add_unseen, PaintRequest, SynthesisOptions};

/// What a tool did: the scene's instances, paths and contours it removed (indices, ascending) and those it added,
/// whose `category` indexes `categories` (the scene's categories, then any the tool's colors brought). A path or
/// contour a tool cuts is removed, and its pieces outside the painted region come back among the added ones.
#[derive(Clone, Debug, Default)]
pub struct ToolEdit {
    /// The scene's categories, then any the tool's colors brought; the added content indexes these.
    pub categories: Vec<Category>,
    /// Indices of the scene's instances removed, ascending.
    pub removed: Vec<usize>,
    /// The instances added.
    pub added: Vec<Instance>,
    /// Indices of the scene's paths removed, ascending.
    pub removed_paths: Vec<usize>,
    /// The paths added: new ones and the pieces of cut ones.
    pub added_paths: Vec<Path>,
    /// Indices of the scene's contours removed, ascending.
    pub removed_contours: Vec<usize>,
    /// The contours added: new ones and the pieces of cut ones.
    pub added_contours: Vec<Contour>,
    /// Per map, the largest share of a painted region where the map read values the color's example never
    /// showed ([`crate::synthesis::SynthesisResult::unseen_maps`]).
    pub unseen_maps: Vec<(String, f64)>,
}

/// The scene with its arrangements' elements held as if locked (same indices, so an edit of it is one of `scene`):
/// the tools that repaint a region from the colors around it (blur, stretch) leave a pattern as it is.
pub(crate) fn holding_arrangements(scene: &Scene) -> std::borrow::Cow<'_, Scene> {
    let pattern: Vec<bool> = scene
        .categories
        .iter()
        .map(|c| c.kind == crate::scene::CategoryKind::Arrangement)
        .collect();
    if !pattern.contains(&true) {
        return std::borrow::Cow::Borrowed(scene);
    }
    let mut held = scene.clone();
    for i in &mut held.instances {
        if pattern.get(i.category).copied().unwrap_or(false) {
            i.locked = true;
        }
    }
    std::borrow::Cow::Owned(held)
}

/// `items` less the indices `removed`, then `added`.
fn replaced<T: Clone>(items: &[T], removed: &[usize], added: &[T]) -> Vec<T> {
    let mut gone = vec![false; items.len()];
    for &i in removed {
        gone[i] = true;
    }
    let mut out: Vec<T> = items
        .iter()
        .zip(&gone)
        .filter(|(_, g)| !**g)
        .map(|(i, _)| i.clone())
        .collect();
    out.extend_from_slice(added);
    out
}

impl ToolEdit {
    /// The scene after the edit.
    pub fn applied_to(&self, scene: &Scene) -> Scene {
        Scene {
            categories: self.categories.clone(),
            instances: replaced(&scene.instances, &self.removed, &self.added),
            paths: replaced(&scene.paths, &self.removed_paths, &self.added_paths),
            contours: replaced(
                &scene.contours,
                &self.removed_contours,
                &self.added_contours,
            ),
            terrain: scene.terrain.clone(),
        }
    }
}

/// How a tool's region is cleared before a color fills it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clearing {
    /// All its unlocked content goes.
    All,
    /// Its unlocked content goes but the elements of the arrangement being painted, which growth continues.
    KeepingPattern,
    /// The tool has cleared it already, as it wants.
    Done,
}

/// Which original item each current item of a list being edited is (`None` for an added one).
#[derive(Clone, Debug)]
struct Origins {
    origin: Vec<Option<usize>>,
    n_original: usize,
}

impl Origins {
    fn new(n: usize) -> Self {
        Origins {
            origin: (0..n).map(Some).collect(),
            n_original: n,
        }
    }

    /// Keeps the items for which `keep` holds (in `items` and here); returns the others.
    fn retain<T>(&mut self, items: &mut Vec<T>, mut keep: impl FnMut(&T) -> bool) -> Vec<T> {
        let mut removed = Vec::new();
        let mut kept = Vec::with_capacity(items.len());
        let mut origin = Vec::with_capacity(items.len());
        for (i, o) in items.drain(..).zip(self.origin.drain(..)) {
            if keep(&i) {
                kept.push(i);
                origin.push(o);
            } else {
                removed.push(i);
            }
        }
        *items = kept;
        self.origin = origin;
        removed
    }

    /// Keeps the items whose current index is not flagged in `gone`.
    fn remove_flagged<T>(&mut self, items: &mut Vec<T>, gone: &[bool]) {
        let mut k = 0;
        self.retain(items, |_| {
            k += 1;
            !gone.get(k - 1).copied().unwrap_or(false)
        });
    }

    /// Replaces each item for which `replace` gives new items (none removes it) by those, after the kept ones;
    /// `None` keeps it as it is.
    fn replace<T>(&mut self, items: &mut Vec<T>, mut replace: impl FnMut(&T) -> Option<Vec<T>>) {
        let mut pieces = Vec::new();
        self.retain(items, |item| match replace(item) {
            None => true,
            Some(new) => {
                pieces.extend(new);
                false
            }
        });
        self.push(items, pieces);
    }

    fn push<T>(&mut self, items: &mut Vec<T>, added: impl IntoIterator<Item = T>) {
        for i in added {
            items.push(i);
            self.origin.push(None);
        }
    }

    /// The original indices gone and the items added, from the original list to `items`.
    fn diff<T: Clone>(&self, items: &[T]) -> (Vec<usize>, Vec<T>) {
        let mut present = vec![false; self.n_original];
        let mut added = Vec::new();
        for (i, o) in items.iter().zip(&self.origin) {
            match o {
                Some(k) => present[*k] = true,
                None => added.push(i.clone()),
            }
        }
        (
            (0..self.n_original).filter(|&k| !present[k]).collect(),
            added,
        )
    }
}

/// Flags of the indices `removed` among `n`.
fn flags(n: usize, removed: &[usize]) -> Vec<bool> {
    let mut gone = vec![false; n];
    for &k in removed {
        if k < n {
            gone[k] = true;
        }
    }
    gone
}

/// A scene being edited by a tool: the current content, each item remembering which original one it is.
pub(crate) struct Working {
    pub(crate) scene: Scene,
    instances: Origins,
    paths: Origins,
    contours: Origins,
    unseen_maps: Vec<(String, f64)>,
}

impl Working {
    pub(crate) fn new(scene: &Scene) -> Self {
        Working {
            scene: scene.clone(),
            instances: Origins::new(scene.instances.len()),
            paths: Origins::new(scene.paths.len()),
            contours: Origins::new(scene.contours.len()),
            unseen_maps: Vec::new(),
        }
    }

    /// Removes the unlocked instances for which `pred` holds; returns them.
    pub(crate) fn remove_where(&mut self, pred: impl Fn(&Instance) -> bool) -> Vec<Instance> {
        self.instances
            .retain(&mut self.scene.instances, |i| i.locked || !pred(i))
    }

    /// Removes the unlocked instances inside `region`; returns them. Its large polygons are indexed once for all
    /// the instances: a drawn outline can have a million vertices.
    pub(crate) fn remove_inside(&mut self, region: &Region) -> Vec<Instance> {
        let region = PreparedRegion::new(region);
        self.remove_where(|i| region.contains(i.position))
    }

    /// Removes the unlocked content inside `region`: instances, and the parts of paths and contours in it (their
    /// parts outside stay, as new pieces).
    pub(crate) fn clear(&mut self, region: &Region) {
        self.remove_inside(region);
        self.clear_structures(region);
    }

    /// Removes the unlocked parts of paths and contours inside `region` (their parts outside stay, as new pieces).
    /// Its large polygons are indexed once for all their segments and points.
    pub(crate) fn clear_structures(&mut self, region: &Region) {
        self.cut_structures(region, &|_| Some(0.0));
    }

    /// Removes the unlocked parts inside `region` of the paths and contours whose category `shortest` gives a
    /// length for, and the pieces left outside shorter than that length (stubs); the other pieces stay.
    pub(crate) fn cut_structures(
        &mut self,
        region: &Region,
        shortest: &dyn Fn(usize) -> Option<f64>,
    ) {
        let region = &PreparedRegion::new(region);
        let long_enough = |category: usize, points: &[DVec2]| {
            shortest(category).is_some_and(|l| polyline_length(points) >= l)
        };
        self.paths.replace(&mut self.scene.paths, |p: &Path| {
            if p.locked || shortest(p.category).is_none() {
                return None;
            }
            let (inside, outside) = region.clip_polyline(&p.points);
            (!inside.is_empty()).then(|| {
                outside
                    .into_iter()
                    .filter(|o| o.len() >= 2 && long_enough(p.category, o))
                    .map(|points| Path {
                        points,
                        ..p.clone()
                    })
                    .collect()
            })
        });
        self.contours
            .replace(&mut self.scene.contours, |c: &Contour| {
                if c.locked || shortest(c.category).is_none() {
                    return None;
                }
                let rest = cut(&c.points, region)?;
                Some(
                    rest.into_iter()
                        .filter(|points| long_enough(c.category, points))
                        .map(|points| Contour {
                            points,
                            ..c.clone()
                        })
                        .collect(),
                )
            });
    }

    /// Replaces each unlocked path and contour by what `reshape` makes of its points (`true` for a contour); `None`
    /// keeps it as it is. A result too short to be a path (2 points) or a contour (3) removes it.
    pub(crate) fn reshape_structures(
        &mut self,
        reshape: impl Fn(&[DVec2], bool) -> Option<Vec<DVec2>>,
    ) {
        self.paths.replace(&mut self.scene.paths, |p: &Path| {
            let new = (!p.locked).then(|| reshape(&p.points, false)).flatten()?;
            Some(Vec::from_iter((new.len() >= 2).then(|| Path {
                points: new,
                ..p.clone()
            })))
        });
        self.contours
            .replace(&mut self.scene.contours, |c: &Contour| {
                let new = (!c.locked).then(|| reshape(&c.points, true)).flatten()?;
                Some(Vec::from_iter((new.len() >= 3).then(|| Contour {
                    points: new,
                    ..c.clone()
                })))
            });
    }

    /// Adds instances whose categories index `categories` (an extension of the scene's list).
    pub(crate) fn add(&mut self, categories: Vec<Category>, instances: Vec<Instance>) {
        if categories.len() > self.scene.categories.len() {
            self.scene.categories = categories;
        }
        self.instances.push(&mut self.scene.instances, instances);
    }

    /// Applies an edit computed on the current scene (its removed indices index the current content).
    pub(crate) fn apply(&mut self, edit: &ToolEdit) {
        let gone = flags(self.scene.instances.len(), &edit.removed);
        self.instances
            .remove_flagged(&mut self.scene.instances, &gone);
        let gone = flags(self.scene.paths.len(), &edit.removed_paths);
        self.paths.remove_flagged(&mut self.scene.paths, &gone);
        let gone = flags(self.scene.contours.len(), &edit.removed_contours);
        self.contours
            .remove_flagged(&mut self.scene.contours, &gone);
        self.add(edit.categories.clone(), edit.added.clone());
        self.paths
            .push(&mut self.scene.paths, edit.added_paths.iter().cloned());
        self.contours.push(
            &mut self.scene.contours,
            edit.added_contours.iter().cloned(),
        );
    }

    /// Clears `region` as `clearing` says and synthesizes `color` there, conditioned on the rest; returns the count
    /// of new instances.
    pub(crate) fn fill(
        &mut self,
        clearing: Clearing,
        color: &Color,
        region: &Region,
        opts: &SynthesisOptions,
        progress: &(dyn Fn(f64) -> bool + Sync),
    ) -> Result<usize> {
        match clearing {
            Clearing::All => self.clear(region),
            Clearing::KeepingPattern => self.clear_around_pattern(color, region),
            Clearing::Done => {}
        }
        let result = synthesize_keeping(PaintRequest {
            scene: &self.scene,
            color,
            region,
            opts,
            progress,
            keep: &|_| true,
        })?;
        let n = result.instances.len();
        for (name, share) in result.unseen_maps {
            add_unseen(&mut self.unseen_maps, name, share);
        }
        let gone = flags(self.scene.contours.len(), &result.replaced_contours);
        self.contours
            .remove_flagged(&mut self.scene.contours, &gone);
        self.add(result.categories, result.instances);
        self.paths.push(&mut self.scene.paths, result.paths);
        self.contours
            .push(&mut self.scene.contours, result.contours);
        Ok(n)
    }

    /// Clears the unlocked content of `region` but the elements of the arrangement `color` there, which its
    /// growth continues (the spray tool, seed §5.3).
    fn clear_around_pattern(&mut self, color: &Color, region: &Region) {
        let own: Vec<bool> = self
            .scene
            .categories
            .iter()
            .map(|c| color.category(&c.name).is_some())
            .collect();
        let prepared = PreparedRegion::new(region);
        self.remove_where(|i| {
            !own.get(i.category).copied().unwrap_or(false) && prepared.contains(i.position)
        });
        self.clear_structures(region);
    }

    /// The edit from the original scene to the current one.
    pub(crate) fn edit(&self) -> ToolEdit {
        let (removed, added) = self.instances.diff(&self.scene.instances);
        let (removed_paths, added_paths) = self.paths.diff(&self.scene.paths);
        let (removed_contours, added_contours) = self.contours.diff(&self.scene.contours);
        ToolEdit {
            categories: self.scene.categories.clone(),
            removed,
            added,
            removed_paths,
            added_paths,
            removed_contours,
            added_contours,
            unseen_maps: self.unseen_maps.clone(),
        }
    }
}

/// Paste (Section 5.1): removes the unlocked content inside `region` (instances, and the parts of paths and
/// contours in it) and synthesizes the color there, consistent with the content around it: new roads end on the
/// roads cut at the border, new islands merge with the coasts around.
pub fn paste(
    scene: &Scene,
    color: &Color,
    region: &Region,
    opts: &SynthesisOptions,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<ToolEdit> {
    region.validate()?;
    let mut work = Working::new(scene);
    work.fill(Clearing::All, color, region, opts, progress)?;
    Ok(work.edit())
}

/// Clear Region: removes the unlocked content inside `region` (instances, and the parts of paths and contours in
/// it; the parts outside stay), of every category or only of `category`.
pub fn clear_region(scene: &Scene, region: &Region, category: Option<&str>) -> Result<ToolEdit> {
    region.validate()?;
    let only = match category {
        None => None,
        Some(name) => Some(scene.category_index(name).ok_or_else(|| {
            Error::invalid("the scene", format!("has no category named '{name}'"))
        })?),
    };
    // content of the other categories is held as if locked: same indices, so the edit is one of `scene`
    let mut held = scene.clone();
    if let Some(c) = only {
        held.instances
            .iter_mut()
            .filter(|i| i.category != c)
            .for_each(|i| i.locked = true);
        held.paths
            .iter_mut()
            .filter(|p| p.category != c)
            .for_each(|p| p.locked = true);
        held.contours
            .iter_mut()
            .filter(|k| k.category != c)
            .for_each(|k| k.locked = true);
    }
    let mut work = Working::new(&held);
    work.clear(region);
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
        local: true,
        ..Default::default()
    };
    match learn_color(scene, region, name, &opts) {
        Ok(c) => Ok(Some(c)),
        Err(Error::EmptyExemplar { .. }) => Ok(None),
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
    let canvas = color.blank_scene();
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
    let painted = synthesize(&canvas, &plain, &region, &Default::default())?;
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
        ..like.emptied()
    }
}

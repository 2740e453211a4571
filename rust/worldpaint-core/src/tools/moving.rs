//! Move (Section 5.4, Fig. 14): the content of a region moves by an offset and adapts to its new place — the
//! terrain there and the content around it — by a displacement Metropolis-Hastings (set by
//! [`AdaptOptions`]), which keeps what still fits exactly where the move put it.
//!
//! The moved content replaces the unlocked content of the destination (as a moved selection covers what lies
//! under it in a painting program); the part of the source it leaves is left empty. Instances the move would put
//! off the terrain stay where they were (counted in [`Moved::stayed`]): moving them would delete them. Locked content stays where it
//! is, in the source and in the destination, and conditions the adaptation. A drag recomputes the move from the
//! original scene at each step with the same seed, so each intermediate result is the same function of the
//! offset and nothing flickers. The unlocked parts of paths and contours inside the source move rigidly too (cut
//! at the source's border: a moved road ends where the cut was), they replace the unlocked parts in the destination,
//! and the moved instances adapt to the roads and coasts where they land.

use super::{color_of_region, ToolEdit, Working};
use crate::contour::split;
use crate::error::{Error, Result};
use crate::geom::{DVec2, PreparedRegion, Region, RegionQueries};
use crate::palette::Color;
use crate::scene::{CategoryKind, Contour, Instance, Path, Scene};
use crate::synthesis::{adapt, AdaptOptions};

/// What a move did, with its counts.
#[derive(Clone, Debug)]
pub struct Moved {
    /// The change to the scene: the unlocked instances of the source and of the destination removed, the moved
    /// ones (where they settled) and the births added; paths and contours moved likewise.
    pub edit: ToolEdit,
    /// Instances carried from the source.
    pub moved: usize,
    /// Of those, the ones that had to leave the place the move put them.
    pub displaced: usize,
    /// Of those, the ones that found no place and were replaced by births.
    pub reborn: usize,
    /// Births that found no allowed place (the count could not be kept).
    pub lost: usize,
    /// Instances the move would have put off the terrain: they stay where they were.
    pub stayed: usize,
}

/// Moves the unlocked content of `source` by `offset`, adapting it with `color`'s statistics, or with those of
/// the moved content itself when `color` is `None` (see the module documentation).
pub fn move_region(
    scene: &Scene,
    color: Option<&Color>,
    source: &Region,
    offset: DVec2,
    opts: &AdaptOptions,
) -> Result<Moved> {
    source.validate()?;
    if !offset.is_finite() {
        return Err(Error::invalid(
            "move offset",
            format!("({}, {}) is not finite", offset.x, offset.y),
        ));
    }
    let destination = source.translated(offset);
    let inside = PreparedRegion::new(source);
    let moving: Vec<usize> = (0..scene.instances.len())
        .filter(|&k| !scene.instances[k].locked && inside.contains(scene.instances[k].position))
        .collect();
    let structures = move_structures(scene, source, &destination, offset);
    let learned;
    let color = match color {
        Some(c) => c,
        None => {
            // only an arrangement's elements move: rigidly, with no statistics to follow
            learned = color_of_region(scene, source, "moved")?
                .unwrap_or_else(|| Color::empty("moved", source));
            &learned
        }
    };
    let mut moved = move_instances(
        scene,
        &structures.scene,
        color,
        &destination,
        &moving,
        offset,
        opts,
    )?;
    let edit = structures.edit();
    moved.edit.removed_paths = edit.removed_paths;
    moved.edit.added_paths = edit.added_paths;
    moved.edit.removed_contours = edit.removed_contours;
    moved.edit.added_contours = edit.added_contours;
    Ok(moved)
}

/// The scene with its unlocked paths and contours moved (instances as they were): the parts inside `source` cut
/// out and carried by `offset`, the parts under `destination` removed.
fn move_structures(scene: &Scene, source: &Region, destination: &Region, offset: DVec2) -> Working {
    let outline = &PreparedRegion::new(source);
    let carried_paths: Vec<Path> = scene
        .paths
        .iter()
        .filter(|p| !p.locked)
        .flat_map(|p| {
            let inside = outline.clip_polyline(&p.points).0;
            inside
                .into_iter()
                .filter(|q| q.len() >= 2)
                .map(move |points| Path {
                    points: points.into_iter().map(|q| q + offset).collect(),
                    ..p.clone()
                })
        })
        .collect();
    let carried_contours: Vec<Contour> = scene
        .contours
        .iter()
        .filter(|c| !c.locked)
        .flat_map(|c| {
            let parts = split(&c.points, outline)
                .map(|(inside, _)| inside)
                .unwrap_or_default();
            parts.into_iter().map(move |points| Contour {
                points: points.into_iter().map(|q| q + offset).collect(),
                ..c.clone()
            })
        })
        .collect();
    let mut work = Working::new(scene);
    work.clear_structures(source);
    work.clear_structures(destination);
    work.paths.push(&mut work.scene.paths, carried_paths);
    work.contours
        .push(&mut work.scene.contours, carried_contours);
    work
}

/// The instances `indices` of the scene moved by `offset`.
fn shifted(scene: &Scene, indices: &[usize], offset: DVec2) -> Vec<Instance> {
    indices
        .iter()
        .map(|&k| Instance {
            position: scene.instances[k].position + offset,
            ..scene.instances[k]
        })
        .collect()
}

/// Which of the scene's instances a move removes: the unlocked ones at the `destination` and the `moved` ones,
/// but not those that `stayed` where they were.
fn removed_by_move<'a>(
    scene: &Scene,
    destination: &Region,
    stayed: &[usize],
    moved: impl Iterator<Item = &'a usize>,
) -> Vec<bool> {
    let at_destination = PreparedRegion::new(destination);
    let mut removed: Vec<bool> = scene
        .instances
        .iter()
        .map(|i| !i.locked && at_destination.contains(i.position))
        .collect();
    for &k in stayed {
        removed[k] = false;
    }
    for &k in moved {
        removed[k] = true;
    }
    removed
}

/// A move of only an arrangement's elements (`carried` rigidly; none when empty), which adapts nothing.
fn carried_only(
    scene: &Scene,
    removed: Vec<usize>,
    carried: Vec<Instance>,
    stayed: usize,
) -> Moved {
    Moved {
        moved: carried.len(),
        edit: ToolEdit {
            categories: scene.categories.clone(),
            removed,
            added: carried,
            ..Default::default()
        },
        displaced: 0,
        reborn: 0,
        lost: 0,
        stayed,
    }
}

/// Moves the instances `moving` (indices into the scene) by `offset` into `destination`, where they replace the
/// unlocked instances, and adapts them to the instances left and to the paths and contours of `landing` (the
/// scene as it will be around them).
pub(crate) fn move_instances(
    scene: &Scene,
    landing: &Scene,
    color: &Color,
    destination: &Region,
    moving: &[usize],
    offset: DVec2,
    opts: &AdaptOptions,
) -> Result<Moved> {
    // what would land off the terrain stays: moving it would delete it
    let (moving, stayed): (Vec<usize>, Vec<usize>) = moving.iter().partition(|&&k| {
        let to = scene.instances[k].position + offset;
        scene.terrain.as_deref().is_none_or(|t| t.contains(to))
    });
    // an arrangement's elements keep their pattern: they move rigidly and condition the others
    let (rigid, moving): (Vec<usize>, Vec<usize>) = moving.into_iter().partition(|&k| {
        scene
            .categories
            .get(scene.instances[k].category)
            .is_some_and(|c| c.kind == CategoryKind::Arrangement)
    });
    let carried = shifted(scene, &rigid, offset);
    let landing_area = match scene.terrain.as_deref() {
        Some(t) => t.clip(destination),
        None => Some(destination.clone()),
    };
    let Some(destination) = landing_area.filter(|_| !moving.is_empty() || !rigid.is_empty()) else {
        return Ok(carried_only(scene, Vec::new(), Vec::new(), stayed.len()));
    };
    let destination = &destination;
    let removed = removed_by_move(scene, destination, &stayed, moving.iter().chain(&rigid));
    let removed_list: Vec<usize> = (0..removed.len()).filter(|&k| removed[k]).collect();
    if moving.is_empty() {
        return Ok(carried_only(scene, removed_list, carried, stayed.len()));
    }
    let fixed = Scene {
        categories: scene.categories.clone(),
        instances: scene
            .instances
            .iter()
            .zip(&removed)
            .filter(|(_, r)| !**r)
            .map(|(i, _)| *i)
            .chain(carried.iter().copied())
            .collect(),
        paths: landing.paths.clone(),
        contours: landing.contours.clone(),
        terrain: scene.terrain.clone(),
    };
    let anchors = shifted(scene, &moving, offset);
    let adapted = adapt(&fixed, color, destination, &anchors, opts)?;
    let mut added: Vec<Instance> = carried;
    added.extend(
        anchors
            .iter()
            .zip(&adapted.positions)
            .filter_map(|(i, p)| p.map(|position| Instance { position, ..*i })),
    );
    let reborn = adapted.positions.iter().filter(|p| p.is_none()).count();
    let lost = reborn.saturating_sub(adapted.births.len());
    added.extend_from_slice(&adapted.births);
    Ok(Moved {
        edit: ToolEdit {
            categories: adapted.categories,
            removed: removed_list,
            added,
            ..Default::default()
        },
        moved: moving.len() + rigid.len(),
        displaced: adapted.displaced,
        reborn,
        lost,
        stayed: stayed.len(),
    })
}

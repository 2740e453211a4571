//! Terrain deformation to the sketch (thesis §5.3.3) and the lowering of protruding silhouettes (§5.4).
//!
//! **Deformation.** For every point `p` of the strokes' 3D curves, `δ = z − H(x, y)` is a displacement
//! constraint on the terrain's grid; the constraints are diffused by the multigrid solver of `terrain_edit` into
//! the displacement map `M`, and `H′ = H + M`. Diffusing differences keeps the terrain's fine detail. The
//! displacement fades to zero at [`SketchDeformOptions::reach`] from the constraints, so the terrain farther away is
//! unchanged (the thesis diffuses over the whole grid; an edit that moves a far corner of the map would surprise an
//! artist). Each grid node the curve fixes takes the curve's height, or the lower height that puts the node itself on
//! the stroke where it stands in front of the curve (a node half a cell nearer the camera than the curve, at the
//! curve's height, would rise above the stroke), and where the curve crosses a cell through its middle, the corner
//! in front of it is fixed too (see `constrain_on_stroke`); between the breaks of a curve that jumps from one
//! silhouette to another, nothing is fixed.
//!
//! **Lowering protruding silhouettes.** "Mountain silhouette `s` hides a user-specified silhouette `g` if `s` is closer
//! to the camera than `g` and the projection `s_p` of `s` on the sketching plane has a higher altitude than `g_p`"; it
//! is lowered "uniformly by an offset `h`", the largest height difference between it and the silhouettes it hides, and
//! its lowered points become new constraints. The thesis deforms the terrain again from the original with all
//! constraints; we diffuse the strokes' constraints once, and in each round only the change the new constraints still
//! ask for, around them alone (every node fixed before held where it is, the change fading within eight times its size,
//! each group of nearby silhouettes in its own window of the grid): the same constraints are met, in a fraction of the
//! time of a whole-grid solve per round. Rounds go on until nothing protrudes, or a round hides no fewer columns than
//! the one before (what still protrudes is held by a stroke's own curve, as where a stroke ends on another).
//! Silhouettes are found column by column: in each image column a stroke covers (sampled
//! [`SketchDeformOptions::columns`] across the image), the highest ray that meets the terrain nearer than the stroke's
//! curve is cast ([`Sight::silhouette_above`]); if it passes above the stroke, the grazed point belongs to a protruding
//! silhouette. Runs of protruding columns are one silhouette each. We count as "closer to the camera" also the terrain
//! just behind the curve, within the deformation's reach, in the columns where the stroke is the highest one drawn:
//! when a feature is lowered onto a stroke, the ground behind it, lowered less, would otherwise rise above the stroke
//! and no silhouette would be seen where the user drew one. Terrain farther behind, or behind a stroke with another
//! stroke drawn above it, is background the user may see.

use super::curves::projected;
use super::matching::{on_stroke, StrokeCurve};
use super::view::{Camera, Sight};
use crate::distance::distance_transform;
use crate::error::{Error, Result};
use crate::terrain::Heightfield;
use crate::terrain_edit::{diffuse, displaced, rasterize, Constraints, DiffusionOptions};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::time::Instant;

/// How the terrain is deformed and how protruding silhouettes are lowered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SketchDeformOptions {
    /// Distance (m) from the constraints at which the displacement has faded to zero; `None`: eight times the
    /// largest displacement asked for, at least 16 cells (the deformed slopes then stay below about 1 in 8 beside
    /// the curves), but at most half the distance from the eye to the nearest curve (at least 4 cells), so that
    /// the ground the artist stands on does not move.
    pub reach: Option<f64>,
    /// Image columns sampled across the whole frame when looking for protruding silhouettes.
    pub columns: usize,
    /// How far (image heights) a protruding silhouette may rise above a stroke before it is lowered, and how far
    /// below the stroke it is lowered to.
    pub clearance: f64,
    /// Most deformations (the first one and the ones after each lowering).
    pub max_rounds: usize,
}

impl Default for SketchDeformOptions {
    /// 512 columns, a clearance of 0.2 % of the image height (a pixel of a 512-pixel-high view), 6 rounds (the
    /// thesis: "a single iteration is usually sufficient").
    fn default() -> Self {
        SketchDeformOptions {
            reach: None,
            columns: 512,
            clearance: 0.002,
            max_rounds: 6,
        }
    }
}

/// A stroke and the 3D curve the terrain is deformed to for it.
#[derive(Clone, Debug)]
pub struct StrokeTarget {
    /// The stroke, as a function of image `x`.
    pub stroke: StrokeCurve,
    /// The curve (on the stroke when seen from the camera).
    pub curve: Vec<DVec3>,
    /// Indices `k` where the curve jumps between points `k − 1` and `k`: the segment between them is no constraint.
    pub breaks: Vec<usize>,
}

impl StrokeTarget {
    /// The curve's pieces between its breaks.
    pub fn pieces(&self) -> impl Iterator<Item = &[DVec3]> {
        let mut bounds: Vec<usize> = self
            .breaks
            .iter()
            .copied()
            .filter(|&b| b > 0 && b < self.curve.len())
            .collect();
        bounds.sort_unstable();
        bounds.dedup();
        let starts = std::iter::once(0).chain(bounds.clone());
        let ends = bounds.into_iter().chain(std::iter::once(self.curve.len()));
        starts.zip(ends).map(|(a, b)| &self.curve[a..b])
    }
}

/// The deformed terrain and how it was reached.
#[derive(Clone, Debug)]
pub struct Deformation {
    /// `H′ = H + M`.
    pub terrain: Heightfield,
    /// `M`, row-major on the terrain's grid.
    pub displacement: Vec<f64>,
    /// The protruding silhouettes found, as lowered (world points), over all rounds.
    pub lowered: Vec<Vec<DVec3>>,
    /// Deformations run.
    pub rounds: usize,
    /// Image columns where a silhouette still rises above a stroke after the last round.
    pub hidden_columns: usize,
    /// The reach used (m).
    pub reach: f64,
    /// Seconds of the first deformation, and of the lowering after it (finding protruding silhouettes, deforming
    /// again).
    pub seconds: (f64, f64),
}

/// Grid nodes in front of a curve's sample within this many cells of it are fixed: the corners of a cell the curve
/// crosses through its middle (0.71 cells away), not those of the cells beside it (a cell or more).
const NODE_REACH: f64 = 0.75;

/// Fixes the grid nodes along `curve` (a stroke's curve, between breaks), each at the height of its nearest sample
/// of the curve, or lower, at the height that puts the node itself on `stroke` seen from `camera`, where it stands
/// nearer the camera than the curve (at the curve's height it would rise above the stroke). The curve is sampled half
/// a cell apart; the node of each sample (within half a cell of it) is fixed, and so is every node in front of it
/// within [`NODE_REACH`] cells: a curve crossing a cell on the diagonal also fixes the corner in front of it, where
/// fixing only the nearest nodes left the other two corners at their lower height and the silhouette sagged between
/// them by up to half the lift (the corner behind is left free: fixed, it lifted the ground behind the curve above
/// the stroke). Nodes already fixed keep their value. Returns the number of nodes fixed.
fn constrain_on_stroke(
    constraints: &mut Constraints,
    terrain: &Heightfield,
    camera: &Camera,
    stroke: &StrokeCurve,
    curve: &[DVec3],
) -> Result<usize> {
    let cell = terrain.cell;
    // per node (row, column): the distance to its nearest sample and that sample's height
    let mut nearest: std::collections::BTreeMap<(usize, usize), (f64, f64)> = Default::default();
    let mut visit = |p: DVec3| {
        if !p.is_finite() {
            return;
        }
        let f = (p.truncate() - terrain.origin) / cell;
        let depth = (p - camera.eye).dot(camera.forward);
        for j in (f.y - NODE_REACH).ceil() as i64..=(f.y + NODE_REACH).floor() as i64 {
            for i in (f.x - NODE_REACH).ceil() as i64..=(f.x + NODE_REACH).floor() as i64 {
                if i < 0 || j < 0 || i as usize >= terrain.nx || j as usize >= terrain.ny {
                    continue;
                }
                let d = f.distance(DVec2::new(i as f64, j as f64));
                let node = terrain.origin + DVec2::new(i as f64, j as f64) * cell;
                let in_front = (node.extend(p.z) - camera.eye).dot(camera.forward) <= depth;
                if d <= 0.5 || (d <= NODE_REACH && in_front) {
                    let e = nearest
                        .entry((j as usize, i as usize))
                        .or_insert((f64::INFINITY, 0.0));
                    if d < e.0 {
                        *e = (d, p.z);
                    }
                }
            }
        }
    };
    if let Some(&first) = curve.first() {
        visit(first);
    }
    for w in curve.windows(2) {
        let (a, b) = (w[0], w[1]);
        let steps = ((a.truncate().distance(b.truncate()) / (0.5 * cell)).ceil() as usize)
            .clamp(1, 10_000_000);
        for k in 1..=steps {
            visit(a.lerp(b, k as f64 / steps as f64));
        }
    }
    let mut fixed = 0;
    for ((j, i), (_, z)) in nearest {
        let node = terrain.origin + DVec2::new(i as f64, j as f64) * cell;
        // on the stroke where the node is in front of the curve; no higher than the curve where it is behind it
        let height = on_stroke(camera, stroke, node.extend(z)).map_or(z, |p| p.z.min(z));
        if constraints.set_if_free(i, j, height - terrain.heights[j * terrain.nx + i] as f64)? {
            fixed += 1;
        }
    }
    Ok(fixed)
}

/// The depth of a curve at image `x`, from its projected points (sorted by `x`).
fn depth_at(points: &[(DVec2, f64)], x: f64) -> Option<f64> {
    let k = points.partition_point(|p| p.0.x < x);
    if k == 0 || k == points.len() {
        return points
            .iter()
            .find(|p| (p.0.x - x).abs() < 1e-12)
            .map(|p| p.1);
    }
    let (a, b) = (points[k - 1], points[k]);
    let t = if b.0.x > a.0.x {
        (x - a.0.x) / (b.0.x - a.0.x)
    } else {
        0.0
    };
    Some(a.1 + (b.1 - a.1) * t)
}

/// Strokes searched for protruding silhouettes between two questions whether to stop.
const STROKES_BETWEEN_STOPS: usize = 4;

/// One image column of a stroke where terrain rises above it: the grazed point and how much it must drop (m).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Protrusion {
    column: usize,
    point: DVec3,
    drop: f64,
}

/// Deforms `terrain` so that the targets' curves lie on it, then lowers what hides them, round after round;
/// `progress` hears the share of [`SketchDeformOptions::max_rounds`] done after each round, and cancels
/// ([`Error::Cancelled`]) by returning `false`.
pub fn deform_to_targets(
    terrain: &Heightfield,
    camera: &Camera,
    targets: &[StrokeTarget],
    options: &SketchDeformOptions,
    progress: &dyn Fn(f64) -> bool,
) -> Result<Deformation> {
    let reach = options
        .reach
        .unwrap_or_else(|| default_reach(terrain, camera, targets));
    let start = Instant::now();
    let mut constraints = Constraints::for_terrain(terrain);
    // the strokes' curves first, so that a lowered silhouette crossing one never overrides it
    for target in targets {
        for piece in target.pieces().filter(|p| !p.is_empty()) {
            constrain_on_stroke(&mut constraints, terrain, camera, &target.stroke, piece)?;
        }
    }
    let mut displacement = diffuse(
        &constraints,
        &DiffusionOptions {
            falloff: Some(reach),
            ..DiffusionOptions::default()
        },
    )?
    .displacement;
    // the terrain as the rounds leave it (heights only: its maps are made once, at the end)
    let mut shown = terrain.clone();
    add_displacement(
        terrain,
        &displacement,
        &mut shown,
        (0, 0, terrain.nx, terrain.ny),
    );
    let first = start.elapsed().as_secs_f64();
    let rounds = options.max_rounds.max(1);
    let mut lowered: Vec<Vec<DVec3>> = Vec::new();
    let mut round = 1;
    let mut last_hidden = usize::MAX;
    loop {
        let done_before = (round - 1) as f64 / rounds as f64;
        let found = protruding(&shown, camera, targets, reach, options, &|| {
            progress(done_before)
        })?;
        let hidden: usize = found.iter().map(Vec::len).sum();
        if !progress(round as f64 / rounds as f64) {
            return Err(Error::Cancelled);
        }
        // a round whose lowering hid no fewer columns is the last: what still protrudes is held by a stroke's
        // curve (as where a stroke ends on another), and another round would lower the same ground again
        let mut done = hidden == 0 || round >= rounds || hidden >= last_hidden;
        if !done {
            let runs: Vec<Vec<DVec3>> = found
                .iter()
                .map(|run| {
                    // "uniformly lower s by an offset h": the largest drop any of its columns needs
                    let h = run.iter().map(|p| p.drop).fold(0.0, f64::max);
                    run.iter().map(|p| p.point - DVec3::Z * h).collect()
                })
                .collect();
            let mut fresh = Vec::with_capacity(runs.len());
            for run in runs.iter().filter(|c| c.len() >= 2) {
                fresh.push(rasterize::polyline_nodes(
                    &mut constraints,
                    terrain,
                    run,
                    |_, z| z,
                )?);
            }
            lowered.extend(runs);
            if fresh.iter().all(Vec::is_empty) {
                // the ground to lower is all held already
                done = true;
            } else {
                lower(
                    &constraints,
                    &fresh,
                    &mut displacement,
                    reach,
                    terrain,
                    &mut shown,
                )?;
                round += 1;
            }
        }
        if done {
            let terrain = displaced(terrain, &displacement)?;
            return Ok(Deformation {
                terrain,
                displacement,
                lowered,
                rounds: round,
                hidden_columns: hidden,
                reach,
                seconds: (first, start.elapsed().as_secs_f64() - first),
            });
        }
        last_hidden = hidden;
    }
}

/// How far the displacement fades by default: eight times the largest change the curves ask for, at least 16 cells,
/// but fading before the ground under the eye (the viewpoint stays where it is), and at least 4 cells.
fn default_reach(terrain: &Heightfield, camera: &Camera, targets: &[StrokeTarget]) -> f64 {
    let curves: Vec<&[DVec3]> = targets
        .iter()
        .map(|t| t.curve.as_slice())
        .filter(|c| !c.is_empty())
        .collect();
    let largest = curves
        .iter()
        .flat_map(|c| c.iter())
        .filter_map(|p| terrain.height_at(p.truncate()).map(|h| (p.z - h).abs()))
        .fold(0.0, f64::max);
    // the viewpoint stays where it is: by default the displacement fades before the ground under the eye
    let to_eye = curves
        .iter()
        .flat_map(|c| c.iter())
        .map(|p| p.truncate().distance(camera.eye.truncate()))
        .fold(f64::INFINITY, f64::min);
    (8.0 * largest)
        .max(16.0 * terrain.cell)
        .min(0.5 * to_eye)
        .max(4.0 * terrain.cell)
}

/// Nodes `i0..i1 × j0..j1` of the grid, as `(i0, j0, i1, j1)`.
type Window = (usize, usize, usize, usize);

/// Writes `H + M` into the heights of `shown` over the nodes `i0..i1 × j0..j1`.
fn add_displacement(
    terrain: &Heightfield,
    displacement: &[f64],
    shown: &mut Heightfield,
    (i0, j0, i1, j1): Window,
) {
    let nx = terrain.nx;
    for j in j0..j1 {
        let row = j * nx + i0..j * nx + i1;
        for ((out, h), d) in shown.heights[row.clone()]
            .iter_mut()
            .zip(&terrain.heights[row.clone()])
            .zip(&displacement[row])
        {
            *out = (*h as f64 + d) as f32;
        }
    }
}

/// One round's lowering: the nodes `fresh` (per protruding silhouette, the ones its lowered curve fixed, now fixed
/// in `constraints`) are brought to their new height by a displacement diffused around them alone, every node fixed
/// before held where it is, fading to zero within eight times the largest change asked for (at least 16 cells, at
/// most `reach`). Silhouettes whose fading disks are apart are diffused apart, each in a window of the grid around
/// it; `displacement` and `shown` are updated there.
fn lower(
    constraints: &Constraints,
    fresh: &[Vec<(usize, usize)>],
    displacement: &mut [f64],
    reach: f64,
    terrain: &Heightfield,
    shown: &mut Heightfield,
) -> Result<()> {
    let (nx, ny, cell) = (terrain.nx, terrain.ny, terrain.cell);
    // what each fresh node must still come down (or go up) by
    let change = |&(i, j): &(usize, usize)| -> f64 {
        constraints.get(i, j).unwrap_or(0.0) - displacement[j * nx + i]
    };
    let largest = fresh
        .iter()
        .flatten()
        .map(|n| change(n).abs())
        .fold(0.0, f64::max);
    let fade = (8.0 * largest).max(16.0 * cell).min(reach);
    let margin = (fade / cell).ceil() as usize + 2;
    let windows = merged_windows(fresh, margin, (nx, ny));
    let corrections: Vec<(Window, Vec<f64>)> = windows
        .par_iter()
        .map(|((i0, j0, i1, j1), members)| {
            let (w, h) = (i1 - i0, j1 - j0);
            let mut is_fresh = vec![false; w * h];
            for &k in members {
                for &(i, j) in &fresh[k] {
                    is_fresh[(j - j0) * w + (i - i0)] = true;
                }
            }
            let distance = distance_transform(w, h, cell, &is_fresh);
            let mut local = Constraints::new(w, h, cell)?;
            for lj in 0..h {
                for li in 0..w {
                    let k = lj * w + li;
                    let (i, j) = (i0 + li, j0 + lj);
                    if is_fresh[k] {
                        local.set(li, lj, change(&(i, j)))?;
                    } else if constraints.get(i, j).is_some() || distance[k] as f64 > fade {
                        local.set(li, lj, 0.0)?;
                    }
                }
            }
            let solved = diffuse(&local, &DiffusionOptions::default())?;
            Ok(((*i0, *j0, *i1, *j1), solved.displacement))
        })
        .collect::<Result<_>>()?;
    for ((i0, j0, i1, j1), correction) in corrections {
        let w = i1 - i0;
        for j in j0..j1 {
            let row = &mut displacement[j * nx + i0..j * nx + i1];
            for (d, e) in row
                .iter_mut()
                .zip(&correction[(j - j0) * w..(j - j0 + 1) * w])
            {
                *d += e;
            }
        }
        add_displacement(terrain, displacement, shown, (i0, j0, i1, j1));
    }
    Ok(())
}

/// The windows of the grid a round's lowering is diffused in: each silhouette's `fresh` nodes with `margin` nodes
/// around them (within the `nx × ny` grid), merged while they overlap; each with the silhouettes it holds.
fn merged_windows(
    fresh: &[Vec<(usize, usize)>],
    margin: usize,
    (nx, ny): (usize, usize),
) -> Vec<(Window, Vec<usize>)> {
    let mut windows: Vec<(Window, Vec<usize>)> = fresh
        .iter()
        .enumerate()
        .filter(|(_, nodes)| !nodes.is_empty())
        .map(|(k, nodes)| {
            let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
            for &(i, j) in nodes {
                i0 = i0.min(i);
                j0 = j0.min(j);
                i1 = i1.max(i);
                j1 = j1.max(j);
            }
            let bounds = (
                i0.saturating_sub(margin),
                j0.saturating_sub(margin),
                (i1 + margin + 1).min(nx),
                (j1 + margin + 1).min(ny),
            );
            (bounds, vec![k])
        })
        .collect();
    loop {
        let overlapping = (0..windows.len()).find_map(|a| {
            (a + 1..windows.len())
                .find(|&b| {
                    let (p, q) = (windows[a].0, windows[b].0);
                    p.0 < q.2 && q.0 < p.2 && p.1 < q.3 && q.1 < p.3
                })
                .map(|b| (a, b))
        });
        let Some((a, b)) = overlapping else {
            break;
        };
        let (q, members) = windows.swap_remove(b);
        let p = &mut windows[a];
        p.0 = (
            p.0 .0.min(q.0),
            p.0 .1.min(q.1),
            p.0 .2.max(q.2),
            p.0 .3.max(q.3),
        );
        p.1.extend(members);
    }
    windows
}

/// The protruding silhouettes over the strokes: per stroke, runs of consecutive columns where terrain that may not
/// hide the stroke rises above it.
fn protruding(
    deformed: &Heightfield,
    camera: &Camera,
    targets: &[StrokeTarget],
    reach: f64,
    options: &SketchDeformOptions,
    go_on: &dyn Fn() -> bool,
) -> Result<Vec<Vec<Protrusion>>> {
    let sight = Sight::new(deformed);
    let columns = options.columns.max(2);
    let projections: Vec<Vec<(DVec2, f64)>> = targets
        .iter()
        .map(|t| {
            let mut p = projected(camera, &t.curve);
            p.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
            p
        })
        .collect();
    let mut per_stroke: Vec<Vec<Vec<Protrusion>>> = Vec::with_capacity(targets.len());
    // a few strokes at a time, asking between them whether to stop (each stroke casts some rays per column)
    for chunk in (0..targets.len())
        .collect::<Vec<_>>()
        .chunks(STROKES_BETWEEN_STOPS)
    {
        if !go_on() {
            return Err(Error::Cancelled);
        }
        per_stroke.par_extend(chunk.par_iter().map(|&s| {
            let target = &targets[s];
            let (x0, x1) = target.stroke.x_range();
            let first = (x0 * columns as f64).ceil().max(0.0) as usize;
            let last = (x1 * columns as f64).floor().min(columns as f64) as usize;
            let mut runs: Vec<Vec<Protrusion>> = Vec::new();
            for column in first..=last {
                let x = column as f64 / columns as f64;
                let (Some(y), Some(depth)) = (target.stroke.y_at(x), depth_at(&projections[s], x))
                else {
                    continue;
                };
                let drawn_above = targets
                    .iter()
                    .enumerate()
                    .any(|(r, t)| r != s && t.stroke.y_at(x).is_some_and(|yr| yr > y));
                let max_depth = if drawn_above {
                    depth - 2.0 * deformed.cell
                } else {
                    depth + reach
                };
                // the stroke's own curve grazes at the stroke: only what rises clear above it protrudes
                let Some((_, point)) =
                    sight.silhouette_above(camera, x, y + options.clearance, max_depth)
                else {
                    continue;
                };
                let target_y = StrokeCurve::new(&super::SketchStroke {
                    points: vec![
                        DVec2::new(x - 1.0, y - options.clearance),
                        DVec2::new(x + 1.0, y - options.clearance),
                    ],
                });
                let Some(down) = on_stroke(camera, &target_y, point) else {
                    continue;
                };
                let p = Protrusion {
                    column,
                    point,
                    drop: (point.z - down.z).max(0.0),
                };
                match runs.last_mut() {
                    Some(run) if run.last().is_some_and(|l| l.column + 1 == column) => run.push(p),
                    _ => runs.push(vec![p]),
                }
            }
            runs
        }));
    }
    Ok(per_stroke.into_iter().flatten().collect())
}

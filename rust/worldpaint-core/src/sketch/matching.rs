//! Stroke–feature matching (thesis §5.3.2): which terrain feature each stroke deforms.
//!
//! **Priority lists.** Every feature is projected on the image and cut into pieces whose projection runs one way in
//! `x` (a silhouette's projection is a function of `x`; a ridge seen at an angle may turn back on itself, and only a
//! piece that does not can follow a stroke). A piece is a candidate for stroke `s` when "the `x` interval that
//! [it covers] matches the one of stroke `s`": our reading is that it covers at least
//! [`MatchingOptions::min_cover`] of the stroke's `x` extent. The piece is restricted to the stroke's `x` extent,
//! extended at its ends along its horizontal direction on the ground until its projection covers the whole stroke,
//! and each point `q` is raised or lowered to `q′` so that its projection lies on the stroke:
//!
//! > q′.z = q.z + k ‖q_p − q_p^s‖ · ‖q − eye‖ / ‖q_p − eye‖
//!
//! which is exact for a level camera, where vertical lines project to image columns. For a pitched camera a vertical
//! move also shifts `x`; the height is then solved by a few Newton steps on "projection on the stroke", which is
//! the same formula's intent (see [`on_stroke`]).
//!
//! Besides the features, each stroke's list holds **the skyline under it** (see [`super::skyline`]): the highest
//! visible silhouette of each of its image columns, which seen from the ground is seldom one feature. Where other
//! strokes share its columns, the list also holds the skyline left to them there: pushed behind the strokes in front
//! of it, pulled in front of the strokes behind it drawn above it, so that a stroke ending on another does not take
//! from it the skyline both are drawn over.
//!
//! **Cost.** `E(f, s) = w_dis E_dis + w_def E_def + w_e E_e`, all weights 1 as in the thesis, with:
//! * `E_dis`: the mean image distance `|f_p.y − s.y|` along the piece's projection, in image heights;
//! * `E_def`: the deformation `f′` needs, divided by the terrain's relief (highest minus lowest point), so that it is
//!   as dimensionless as `E_dis` (the thesis adds them with unit weights without saying their units). At each point
//!   of `f′` the change is `|f′.z − h|` plus the lowering it forces in front of it (how far the terrain nearer the
//!   camera would have to come down not to rise above the stroke, §5.4: a feature behind a higher ridge costs that
//!   ridge's lowering too). `E_def` is the mean of the two, the thesis's mean along `f′` and the largest change: the
//!   deformation spreads as far as its largest change (the reach is eight times it), and a candidate that lifts
//!   one stretch far more than the rest makes a spike the mean alone hardly sees (on real terrain it chose a slope
//!   0.55–1 km from the camera raised by 165 m over the skyline's own ridge raised by at most 100 m);
//! * `E_e = l(f′) / l(f)`: 1 for a piece that covers the stroke, more for one extended to cover it.
//!
//! The thesis writes the two integrals without absolute values; a signed mean would let a feature half above and half
//! below its stroke cost nothing, so the distances are taken absolute.
//!
//! **Assignment.** Strokes are processed front to back. A feature serves one stroke at most ("a feature curve
//! assigned to a stroke is no longer considered for subsequent strokes"); the skyline may serve several, each over
//! its own columns. A stroke's candidate is dropped when it
//! would hide the curve chosen for a stroke in front of it: somewhere in their common `x` range it lies nearer the
//! camera, or less than a few cells behind it. The margin is ours: a crest is often detected twice, as a ridge and
//! as the silhouette along it, and without it two strokes took the same crest and one was lost. A stroke left
//! without candidates costs [`EMPTY_LIST_COST`], so that an assignment where every stroke has a feature wins
//! whenever one exists; it is then embedded in 3D between its neighbours in depth (see `super::curves`). The
//! minimum is found by branch and bound: a partial assignment is cut when its cost plus the cheapest remaining
//! candidate of every later stroke (a lower bound that ignores the constraints) reaches the best complete cost
//! found. With many strokes whose candidates exclude one another the bound is weak and the search grows
//! exponentially (20 random strokes: 128 s), so it visits at most [`MAX_ASSIGNMENT_NODES`] partial assignments and
//! keeps the best found by then (the first is the greedy one: front to back, each stroke's cheapest candidate
//! allowed); [`Assignment::complete`] says whether the minimum was proven. It asks every [`STOP_CHECK_NODES`]
//! nodes whether to stop.

use super::skyline::SilhouetteColumns;
use super::view::{Camera, Sight};
use super::{Feature, FeatureKind, SketchStroke};
use crate::error::{Error, Result};
use glam::{DVec2, DVec3};

/// Cost of a stroke that no feature can serve: far above any feature's cost.
pub(crate) const EMPTY_LIST_COST: f64 = 1.0e6;
/// Partial assignments the branch and bound may visit before it keeps the best found.
pub const MAX_ASSIGNMENT_NODES: usize = 20_000;
/// Partial assignments between two questions whether to stop.
pub(crate) const STOP_CHECK_NODES: usize = 1_024;
/// Newton steps that put a point's projection on its stroke.
const NEWTON_STEPS: usize = 6;
/// Largest share of the image width one terrain cell may span at a candidate's depth: nearer, the stroke's shape
/// is finer than the terrain's grid can follow (measured on SRTM at 30 m: a ridge 300 m away, a cell spanning 9 % of
/// the view, left silhouettes several metres off the stroke however much was lowered).
const MAX_CELL_SPAN: f64 = 0.03;
/// Image widths beyond a stroke's end within which a point still counts as under the stroke's end.
const END_SLACK: f64 = 1e-3;
/// Cells a stroke's curve must lie behind the curve of a stroke in front of it; terrain nearer than a candidate by
/// more than this is in front of it.
pub(crate) const SEPARATION_CELLS: f64 = 3.0;

/// The weights of the cost and what makes a candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MatchingOptions {
    /// `w_dis`: weight of the image distance between feature and stroke.
    pub w_dis: f64,
    /// `w_def`: weight of the deformation.
    pub w_def: f64,
    /// `w_e`: weight of the extension.
    pub w_e: f64,
    /// Least share of a stroke's `x` extent a feature piece's projection must cover to be a candidate.
    pub min_cover: f64,
    /// Candidates kept per stroke, cheapest first (bounds the branch and bound's width).
    pub max_candidates: usize,
    /// Image columns across the frame in which the visible silhouettes are read: the skyline under a stroke, and
    /// the terrain a candidate forces down in front of it.
    pub columns: usize,
}

impl Default for MatchingOptions {
    /// The thesis's unit weights; a piece must cover a quarter of the stroke (so that the extension, penalised by
    /// `E_e`, stays shorter than three times the feature); eight candidates per stroke; 512 columns (those the
    /// lowering of protruding silhouettes samples by default).
    fn default() -> Self {
        MatchingOptions {
            w_dis: 1.0,
            w_def: 1.0,
            w_e: 1.0,
            min_cover: 0.25,
            max_candidates: 8,
            columns: 512,
        }
    }
}

/// A stroke as a function of image `x`: its points sorted left to right.
#[derive(Clone, Debug)]
pub struct StrokeCurve {
    points: Vec<DVec2>,
}

impl StrokeCurve {
    /// The curve of an oriented stroke (points with increasing `x`; see `super::ordering`). Points that do not
    /// advance in `x` are dropped.
    pub fn new(stroke: &SketchStroke) -> StrokeCurve {
        let mut points: Vec<DVec2> = Vec::with_capacity(stroke.points.len());
        let mut sorted = stroke.points.clone();
        if sorted.len() > 1 && sorted[0].x > sorted[sorted.len() - 1].x {
            sorted.reverse();
        }
        for p in sorted {
            if points.last().is_none_or(|l: &DVec2| p.x > l.x) {
                points.push(p);
            }
        }
        StrokeCurve { points }
    }

    /// Leftmost and rightmost `x`.
    pub fn x_range(&self) -> (f64, f64) {
        match (self.points.first(), self.points.last()) {
            (Some(a), Some(b)) => (a.x, b.x),
            _ => (0.0, 0.0),
        }
    }

    /// The stroke's `y` at `x`; `None` outside its extent.
    pub fn y_at(&self, x: f64) -> Option<f64> {
        let k = self.points.partition_point(|p| p.x < x);
        if k == 0 {
            return (self.points.first()?.x == x).then(|| self.points[0].y);
        }
        let b = *self.points.get(k)?;
        let a = self.points[k - 1];
        Some(a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x))
    }

    /// The stroke's points.
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }
}

/// A piece of a feature whose projection runs left to right.
#[derive(Clone, Debug)]
pub(crate) struct FeaturePiece {
    /// The feature it comes from (index in the features given).
    pub feature: usize,
    /// That feature's kind.
    pub kind: FeatureKind,
    /// World points, left to right in the image.
    pub points: Vec<DVec3>,
    /// Their image coordinates.
    pub image: Vec<DVec2>,
}

/// Cuts every feature into pieces whose projection runs one way in `x`, turned to run left to right; points behind
/// the eye end a piece.
pub(crate) fn feature_pieces(camera: &Camera, features: &[Feature]) -> Vec<FeaturePiece> {
    let mut pieces = Vec::new();
    for (f, feature) in features.iter().enumerate() {
        let mut run: Vec<(DVec3, DVec2)> = Vec::new();
        let mut direction = 0.0f64;
        let flush = |run: &mut Vec<(DVec3, DVec2)>, pieces: &mut Vec<FeaturePiece>| {
            if run.len() >= 2 {
                if run[0].1.x > run[run.len() - 1].1.x {
                    run.reverse();
                }
                pieces.push(FeaturePiece {
                    feature: f,
                    kind: feature.kind,
                    points: run.iter().map(|r| r.0).collect(),
                    image: run.iter().map(|r| r.1).collect(),
                });
            }
            run.clear();
        };
        for &p in &feature.points {
            let Some((image, _)) = camera.project(p) else {
                flush(&mut run, &mut pieces);
                direction = 0.0;
                continue;
            };
            if let Some(&(_, last)) = run.last() {
                let dx = image.x - last.x;
                if dx == 0.0 {
                    continue;
                }
                if direction != 0.0 && dx.signum() != direction {
                    // the turning point starts the next piece too
                    let turn = run[run.len() - 1];
                    flush(&mut run, &mut pieces);
                    run.push(turn);
                }
                direction = dx.signum();
            }
            run.push((p, image));
        }
        flush(&mut run, &mut pieces);
    }
    pieces
}

/// A feature piece deformed to follow a stroke: a candidate of the stroke's priority list.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// The feature (index in the features given); `None` for the skyline under the stroke.
    pub feature: Option<usize>,
    /// `f′`: the deformed curve, left to right in the image, its projection on the stroke.
    pub curve: Vec<DVec3>,
    /// Indices `k` where `curve` jumps between points `k − 1` and `k` (from one silhouette of the skyline to
    /// another, at another depth): the segment between them is no part of it.
    pub breaks: Vec<usize>,
    /// Depth along the camera's forward axis of each point of `curve`.
    pub depths: Vec<f64>,
    /// Image `x` of each point of `curve`.
    pub xs: Vec<f64>,
    /// `E(f, s)`.
    pub cost: f64,
    /// `E_dis`, `E_def`, `E_e`.
    pub terms: [f64; 3],
    /// The largest height change (m) of a point of `curve`, or of the terrain it forces down in front of it.
    pub largest_change: f64,
}

impl Candidate {
    /// Depth of the curve at image `x` (linear between its points); `None` outside its extent.
    pub fn depth_at(&self, x: f64) -> Option<f64> {
        let k = self.xs.partition_point(|&v| v < x);
        if k == 0 {
            return (self.xs.first() == Some(&x)).then(|| self.depths[0]);
        }
        let b = *self.xs.get(k)?;
        let a = self.xs[k - 1];
        let t = if b > a { (x - a) / (b - a) } else { 0.0 };
        Some(self.depths[k - 1] + (self.depths[k] - self.depths[k - 1]) * t)
    }

    /// Whether this curve would hide `front`'s, or run into it: somewhere in their common `x` range it lies less
    /// than `separation` (m) behind it.
    pub fn hides(&self, front: &Candidate, separation: f64) -> bool {
        let (Some(&a0), Some(&a1), Some(&b0), Some(&b1)) = (
            self.xs.first(),
            self.xs.last(),
            front.xs.first(),
            front.xs.last(),
        ) else {
            return false;
        };
        let (lo, hi) = (a0.max(b0), a1.min(b1));
        if !(hi > lo) {
            return false;
        }
        self.xs
            .iter()
            .chain(front.xs.iter())
            .filter(|&&x| x >= lo && x <= hi)
            .any(|&x| match (self.depth_at(x), front.depth_at(x)) {
                (Some(d), Some(e)) => d < e + separation,
                _ => false,
            })
    }
}

/// The height that puts the projection of the point above `q`'s ground position on the stroke (Newton steps on
/// the image distance, starting from `q.z`); `None` if the stroke does not reach the point's image column or the
/// point leaves the view.
pub(crate) fn on_stroke(camera: &Camera, stroke: &StrokeCurve, q: DVec3) -> Option<DVec3> {
    let gap = |z: f64| -> Option<f64> {
        let (image, _) = camera.project(DVec3::new(q.x, q.y, z))?;
        // a point a hair beyond the stroke's end (where an extension stopped) takes the end's height
        let (x0, x1) = stroke.x_range();
        let x = if image.x < x0 && image.x > x0 - END_SLACK {
            x0
        } else if image.x > x1 && image.x < x1 + END_SLACK {
            x1
        } else {
            image.x
        };
        Some(image.y - stroke.y_at(x)?)
    };
    let mut z = q.z;
    let (_, depth) = camera.project(q)?;
    // a metre of height moves the projection by about this much of the image at this depth
    let dz = (1e-3 * depth).max(1e-3);
    for _ in 0..NEWTON_STEPS {
        let g = gap(z)?;
        let slope = (gap(z + dz)? - g) / dz;
        if !(slope.abs() > 1e-12) {
            return None;
        }
        z -= g / slope;
    }
    (gap(z)?.abs() < 1e-6).then(|| DVec3::new(q.x, q.y, z))
}

fn polyline_length<T: Copy>(points: &[T], distance: impl Fn(T, T) -> f64) -> f64 {
    points.windows(2).map(|w| distance(w[0], w[1])).sum()
}

/// Mean of `value` along a polyline, weighted by the length of the segments around each point.
fn mean_along(lengths: &[f64], values: &[f64]) -> f64 {
    let n = values.len();
    if n == 0 {
        return 0.0;
    }
    if n == 1 || lengths.iter().sum::<f64>() <= 0.0 {
        return values.iter().sum::<f64>() / n as f64;
    }
    let (mut sum, mut weight) = (0.0, 0.0);
    for k in 0..n {
        let w = 0.5
            * (if k > 0 { lengths[k - 1] } else { 0.0 } + lengths.get(k).copied().unwrap_or(0.0));
        sum += w * values[k];
        weight += w;
    }
    sum / weight
}

/// The part of `piece` inside the image `x` range `[x0, x1]`, with points interpolated at the bounds.
fn restrict(piece: &FeaturePiece, x0: f64, x1: f64) -> Vec<(DVec3, DVec2)> {
    let mut out = Vec::new();
    let pts: Vec<(DVec3, DVec2)> = piece
        .points
        .iter()
        .copied()
        .zip(piece.image.iter().copied())
        .collect();
    for w in pts.windows(2) {
        let ((p, a), (q, b)) = (w[0], w[1]);
        if b.x < x0 || a.x > x1 {
            continue;
        }
        let at = |x: f64| {
            let t = ((x - a.x) / (b.x - a.x)).clamp(0.0, 1.0);
            (p.lerp(q, t), a.lerp(b, t))
        };
        let start = if a.x < x0 { at(x0) } else { (p, a) };
        let end = if b.x > x1 { at(x1) } else { (q, b) };
        if out
            .last()
            .is_none_or(|l: &(DVec3, DVec2)| l.1.x < start.1.x)
        {
            out.push(start);
        }
        if end.1.x > start.1.x {
            out.push(end);
        }
    }
    out
}

/// Ground points that extend `from` outwards along `direction` (horizontal, unit) until their projection passes
/// image `x = target` (going left if `leftwards`); `None` if the extension leaves the terrain or turns away.
fn extension(
    sight: &Sight,
    camera: &Camera,
    from: DVec3,
    direction: DVec2,
    target: f64,
    leftwards: bool,
) -> Option<Vec<DVec3>> {
    let terrain = sight.terrain;
    let step = terrain.cell;
    let (lo, hi) = terrain.bbox();
    let max_steps = ((hi - lo).length() / step).ceil() as usize + 1;
    let passed = |x: f64| if leftwards { x <= target } else { x >= target };
    let mut out = Vec::new();
    let mut last_x = camera.project(from)?.0.x;
    for k in 1..=max_steps {
        let xy = from.truncate() + direction * (step * k as f64);
        let z = terrain.height_at(xy)?;
        let p = DVec3::new(xy.x, xy.y, z);
        let x = camera.project(p)?.0.x;
        if (x - last_x) * if leftwards { -1.0 } else { 1.0 } <= 0.0 {
            return None;
        }
        if passed(x) {
            // the last point where the projection reaches the stroke's end
            let before = out.last().copied().unwrap_or(from);
            let t = ((target - last_x) / (x - last_x)).clamp(0.0, 1.0);
            let xy = before.truncate().lerp(xy, t);
            out.push(DVec3::new(xy.x, xy.y, terrain.height_at(xy)?));
            return Some(out);
        }
        out.push(p);
        last_x = x;
    }
    None
}

/// What every candidate of one sketch is measured against: the terrain seen from the camera, its relief, and the
/// visible silhouettes column by column.
pub(crate) struct MatchingContext<'a> {
    /// The terrain as the camera sees it.
    pub sight: &'a Sight<'a>,
    /// The camera.
    pub camera: &'a Camera,
    /// Highest minus lowest terrain point (m): the scale of `E_def`.
    pub relief: f64,
    /// The visible silhouettes per image column.
    pub columns: SilhouetteColumns,
    /// How far (m) in front of a candidate terrain counts as in front of it: the separation the assignment keeps
    /// between two strokes' curves.
    pub separation: f64,
}

impl<'a> MatchingContext<'a> {
    /// The context of `pieces` (all the features' pieces) seen from `camera`, with `options.columns` columns.
    pub(crate) fn new(
        sight: &'a Sight<'a>,
        camera: &'a Camera,
        pieces: &[FeaturePiece],
        options: &MatchingOptions,
    ) -> MatchingContext<'a> {
        MatchingContext {
            sight,
            camera,
            relief: relief(sight),
            columns: SilhouetteColumns::new(camera, pieces, options.columns),
            separation: SEPARATION_CELLS * sight.terrain.cell,
        }
    }
}

/// The candidate `f′` of `piece` for `stroke`, with its cost; `None` if the piece does not cover enough of the
/// stroke or cannot be deformed or extended onto it.
pub(crate) fn candidate(
    context: &MatchingContext,
    stroke: &StrokeCurve,
    piece: &FeaturePiece,
    options: &MatchingOptions,
) -> Option<Candidate> {
    let (sight, camera) = (context.sight, context.camera);
    let (x0, x1) = stroke.x_range();
    let (p0, p1) = (piece.image.first()?.x, piece.image.last()?.x);
    let cover = (p1.min(x1) - p0.max(x0)) / (x1 - x0);
    if !(cover >= options.min_cover) {
        return None;
    }
    let part = restrict(piece, x0, x1);
    if part.len() < 2 {
        return None;
    }
    let image: Vec<DVec2> = part.iter().map(|r| r.1).collect();
    // the ground curve, extended to cover the stroke
    let original: Vec<DVec3> = part.iter().map(|r| r.0).collect();
    let mut ground = original.clone();
    let horizontal = |a: DVec3, b: DVec3| (b - a).truncate().try_normalize();
    if image[0].x > x0 + 1e-9 {
        let dir = horizontal(original[1], original[0])?;
        let mut left = extension(sight, camera, original[0], dir, x0, true)?;
        left.reverse();
        left.extend(ground);
        ground = left;
    }
    if image[image.len() - 1].x < x1 - 1e-9 {
        let n = original.len();
        let dir = horizontal(original[n - 2], original[n - 1])?;
        ground.extend(extension(sight, camera, original[n - 1], dir, x1, false)?);
    }
    let length = polyline_length(&original, DVec3::distance);
    deformed_onto(
        context,
        stroke,
        Some(piece.feature),
        &image,
        &ground,
        &[],
        length,
        options,
    )
}

/// The skyline under `stroke` (see [`super::skyline`]) as a candidate, with its cost, each column's point moved
/// `offset(x)` metres along the column; `None` where fewer than [`MatchingOptions::min_cover`] of the stroke's
/// columns have a visible silhouette.
pub(crate) fn skyline_candidate(
    context: &MatchingContext,
    stroke: &StrokeCurve,
    offset: &dyn Fn(f64) -> f64,
    options: &MatchingOptions,
) -> Option<Candidate> {
    let sky = context
        .columns
        .skyline(context.camera, context.sight.terrain, stroke, offset)?;
    let (x0, x1) = stroke.x_range();
    let covered = sky.image.len() as f64 / ((x1 - x0) * (options.columns.max(2) - 1) as f64 + 1.0);
    if !(covered >= options.min_cover) {
        return None;
    }
    let length = pieces_length(&sky.points, &sky.breaks);
    deformed_onto(
        context,
        stroke,
        None,
        &sky.image,
        &sky.points,
        &sky.breaks,
        length,
        options,
    )
}

/// The strokes that share image columns with a stroke: those nearer the camera, and those farther.
#[derive(Clone, Debug, Default)]
pub(crate) struct Neighbours<'a> {
    /// Strokes in front of it.
    pub in_front: Vec<&'a StrokeCurve>,
    /// Strokes behind it.
    pub behind: Vec<&'a StrokeCurve>,
}

impl<'a> Neighbours<'a> {
    /// The strokes of `curves` that share columns with stroke `s`, `front_to_back` their depth order.
    pub(crate) fn of(
        s: usize,
        curves: &'a [StrokeCurve],
        front_to_back: &[usize],
    ) -> Neighbours<'a> {
        let Some(stroke) = curves.get(s) else {
            return Neighbours::default();
        };
        let (x0, x1) = stroke.x_range();
        let sharing = |&r: &usize| {
            let (a, b) = curves.get(r)?.x_range();
            (r != s && a < x1 && b > x0).then(|| &curves[r])
        };
        let k = front_to_back
            .iter()
            .position(|&r| r == s)
            .unwrap_or(front_to_back.len());
        Neighbours {
            in_front: front_to_back[..k].iter().filter_map(sharing).collect(),
            behind: front_to_back
                .get(k + 1..)
                .unwrap_or(&[])
                .iter()
                .filter_map(sharing)
                .collect(),
        }
    }
}

/// The skyline candidates of `stroke`: the skyline as it is, and where strokes share its columns, the skyline
/// left to them there: pushed behind the strokes in front of it, pulled in front of the strokes behind it drawn
/// above it (a cell more than the separation the assignment asks for).
fn skyline_candidates(
    context: &MatchingContext,
    stroke: &StrokeCurve,
    neighbours: &Neighbours,
    options: &MatchingOptions,
) -> Vec<Candidate> {
    let shift = context.separation + context.sight.terrain.cell;
    let behind_front = |x: f64| {
        if neighbours.in_front.iter().any(|r| r.y_at(x).is_some()) {
            shift
        } else {
            0.0
        }
    };
    let before_back = |x: f64| {
        let y = stroke.y_at(x).unwrap_or(f64::INFINITY);
        if neighbours
            .behind
            .iter()
            .any(|r| r.y_at(x).is_some_and(|yr| yr > y))
        {
            -shift
        } else {
            0.0
        }
    };
    let mut offsets: Vec<&dyn Fn(f64) -> f64> = vec![&|_| 0.0];
    if !neighbours.in_front.is_empty() {
        offsets.push(&behind_front);
    }
    if !neighbours.behind.is_empty() {
        offsets.push(&before_back);
    }
    offsets
        .into_iter()
        .filter_map(|offset| skyline_candidate(context, stroke, offset, options))
        .collect()
}

/// The length of a polyline broken at `breaks` (the segments ending at those indices left out).
fn pieces_length(points: &[DVec3], breaks: &[usize]) -> f64 {
    points
        .windows(2)
        .enumerate()
        .filter(|(k, _)| !breaks.contains(&(k + 1)))
        .map(|(_, w)| w[0].distance(w[1]))
        .sum()
}

/// The candidate that moves `ground` (broken at `breaks`) vertically onto `stroke`, from `feature`, whose
/// projection as it is was `image` and whose length before any extension was `length`.
#[allow(clippy::too_many_arguments)]
fn deformed_onto(
    context: &MatchingContext,
    stroke: &StrokeCurve,
    feature: Option<usize>,
    image: &[DVec2],
    ground: &[DVec3],
    breaks: &[usize],
    length: f64,
    options: &MatchingOptions,
) -> Option<Candidate> {
    let (sight, camera) = (context.sight, context.camera);
    // E_dis along the projection of the feature as it is
    let image_lengths: Vec<f64> = image.windows(2).map(|w| w[0].distance(w[1])).collect();
    let gaps: Vec<f64> = image
        .iter()
        .map(|p| stroke.y_at(p.x).map_or(0.0, |y| (p.y - y).abs()))
        .collect();
    let e_dis = mean_along(&image_lengths, &gaps);
    // f′: each point moved vertically onto the stroke (points projecting just outside it are dropped)
    let mut curve = Vec::with_capacity(ground.len());
    let mut kept_breaks = Vec::new();
    let mut changes = Vec::with_capacity(ground.len());
    let mut projected = Vec::with_capacity(ground.len());
    let mut pending_break = false;
    for (k, &q) in ground.iter().enumerate() {
        pending_break |= breaks.contains(&k);
        let Some(p) = on_stroke(camera, stroke, q) else {
            continue;
        };
        let (image, depth) = camera.project(p)?;
        let h = sight.terrain.height_at(q.truncate()).unwrap_or(q.z);
        // the point's own change, and the lowering it forces on the terrain in front of it
        let lowering =
            context
                .columns
                .lowering_in_front(image.x, image.y, depth, context.separation);
        changes.push((p.z - h).abs() + lowering);
        if pending_break && !curve.is_empty() {
            kept_breaks.push(curve.len());
        }
        pending_break = false;
        curve.push(p);
        projected.push((image, depth));
    }
    if curve.len() < 2 {
        return None;
    }
    let lengths: Vec<f64> = curve
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            if kept_breaks.contains(&(k + 1)) {
                0.0
            } else {
                w[0].distance(w[1])
            }
        })
        .collect();
    let largest_change = changes.iter().copied().fold(0.0, f64::max);
    let e_def = 0.5 * (mean_along(&lengths, &changes) + largest_change) / context.relief.max(1e-9);
    let e_e = pieces_length(&curve, &kept_breaks) / length.max(1e-9);
    // a terrain cell seen this near spans more of the image than the terrain can bend a silhouette within
    let depth = projected.iter().map(|p| p.1).sum::<f64>() / projected.len() as f64;
    let width = camera.frame_max.x - camera.frame_min.x;
    if sight.terrain.cell / (depth * width) > MAX_CELL_SPAN {
        return None;
    }
    let cost = options.w_dis * e_dis + options.w_def * e_def + options.w_e * e_e;
    cost.is_finite().then(|| Candidate {
        feature,
        xs: projected.iter().map(|p| p.0.x).collect(),
        depths: projected.iter().map(|p| p.1).collect(),
        curve,
        breaks: kept_breaks,
        cost,
        terms: [e_dis, e_def, e_e],
        largest_change,
    })
}

/// The priority list of `stroke`: its candidates among `pieces` and the skyline under it (as it is, and left to
/// its `neighbours` where they share its columns), cheapest first, at most [`MatchingOptions::max_candidates`], one
/// per feature (its cheapest piece).
pub(crate) fn priority_list(
    context: &MatchingContext,
    stroke: &StrokeCurve,
    neighbours: &Neighbours,
    pieces: &[FeaturePiece],
    options: &MatchingOptions,
) -> Vec<Candidate> {
    let mut list: Vec<Candidate> = pieces
        .iter()
        .filter_map(|piece| candidate(context, stroke, piece, options))
        .chain(skyline_candidates(context, stroke, neighbours, options))
        .collect();
    list.sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.feature.cmp(&b.feature)));
    let mut seen = std::collections::BTreeSet::new();
    list.retain(|c| c.feature.is_none() || seen.insert(c.feature));
    list.truncate(options.max_candidates);
    list
}

/// Highest minus lowest terrain point.
fn relief(sight: &Sight) -> f64 {
    let (lo, hi) = sight
        .terrain
        .heights
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h as f64), hi.max(h as f64))
        });
    hi - lo
}

/// The features chosen for the strokes.
#[derive(Clone, Debug, PartialEq)]
pub struct Assignment {
    /// Per stroke of the priority lists given, the index of its chosen candidate in its list, or `None` when no
    /// candidate could serve it.
    pub chosen: Vec<Option<usize>>,
    /// The total cost (each stroke without a candidate counting [`EMPTY_LIST_COST`]).
    pub cost: f64,
    /// Search nodes visited (partial assignments extended).
    pub nodes: usize,
    /// Whether the search finished: `false` when it stopped at [`MAX_ASSIGNMENT_NODES`] with the best found then.
    pub complete: bool,
}

/// The assignment of least total cost, by branch and bound: `lists[s]` is stroke `s`'s priority list and
/// `front_to_back` the strokes' depth order (see the module documentation for the rules); `stop` is asked every
/// [`STOP_CHECK_NODES`] nodes whether to give up ([`Error::Cancelled`]).
pub(crate) fn assign_until(
    front_to_back: &[usize],
    lists: &[Vec<Candidate>],
    separation: f64,
    stop: &dyn Fn() -> bool,
) -> Result<Assignment> {
    match search(front_to_back, lists, separation, true, stop) {
        (_, true) => Err(Error::Cancelled),
        (a, false) => Ok(a),
    }
}

struct Search<'a> {
    order: &'a [usize],
    lists: &'a [Vec<Candidate>],
    /// Cheapest possible cost of the strokes from position `k` on.
    remaining: Vec<f64>,
    separation: f64,
    bound: bool,
    stop: &'a dyn Fn() -> bool,
    /// Set once the search must end: stopped, or out of nodes.
    halted: bool,
    cancelled: bool,
    current: Vec<Option<usize>>,
    best: Assignment,
}

/// The assignment, and whether `stop` cancelled the search.
fn search(
    front_to_back: &[usize],
    lists: &[Vec<Candidate>],
    separation: f64,
    bound: bool,
    stop: &dyn Fn() -> bool,
) -> (Assignment, bool) {
    let n = front_to_back.len();
    let mut remaining = vec![0.0; n + 1];
    for k in (0..n).rev() {
        let list = lists
            .get(front_to_back[k])
            .map(Vec::as_slice)
            .unwrap_or(&[]);
        let cheapest = list.iter().map(|c| c.cost).fold(EMPTY_LIST_COST, f64::min);
        remaining[k] = remaining[k + 1] + cheapest;
    }
    let mut s = Search {
        order: front_to_back,
        lists,
        remaining,
        separation,
        bound,
        stop,
        halted: false,
        cancelled: false,
        current: vec![None; lists.len()],
        best: Assignment {
            chosen: vec![None; lists.len()],
            cost: f64::INFINITY,
            nodes: 0,
            complete: true,
        },
    };
    s.extend(0, 0.0);
    let nodes = s.best.nodes;
    let complete = !s.halted;
    let mut best = s.best;
    if !best.cost.is_finite() {
        best.cost = n as f64 * EMPTY_LIST_COST;
    }
    best.nodes = nodes;
    best.complete = complete;
    (best, s.cancelled)
}

impl Search<'_> {
    /// Assigns the stroke at depth position `k`, the ones in front being assigned in `self.current` at `cost`.
    fn extend(&mut self, k: usize, cost: f64) {
        if self.halted {
            return;
        }
        self.best.nodes += 1;
        if self.best.nodes.is_multiple_of(STOP_CHECK_NODES) && (self.stop)() {
            self.halted = true;
            self.cancelled = true;
            return;
        }
        // out of nodes once an assignment is known (the first descent reaches one in a node per stroke)
        if self.bound && self.best.nodes > MAX_ASSIGNMENT_NODES && self.best.cost.is_finite() {
            self.halted = true;
            return;
        }
        if k == self.order.len() {
            if cost < self.best.cost {
                let nodes = self.best.nodes;
                self.best = Assignment {
                    chosen: self.current.clone(),
                    cost,
                    nodes,
                    complete: true,
                };
            }
            return;
        }
        if self.bound && cost + self.remaining[k] >= self.best.cost {
            return;
        }
        let stroke = self.order[k];
        let list = self.lists.get(stroke).map(Vec::as_slice).unwrap_or(&[]);
        for (c, cand) in list.iter().enumerate() {
            if !self.allowed(k, cand) {
                continue;
            }
            if self.bound && cost + cand.cost + self.remaining[k + 1] >= self.best.cost {
                // the list is sorted: no later candidate can do better
                break;
            }
            self.current[stroke] = Some(c);
            self.extend(k + 1, cost + cand.cost);
            self.current[stroke] = None;
        }
        // no candidate (or none taken): the stroke is embedded, at a high cost
        self.extend(k + 1, cost + EMPTY_LIST_COST);
    }

    /// Whether `cand` may serve the stroke at depth position `k`: its feature is not used by a stroke in front, and
    /// it hides none of their curves.
    fn allowed(&self, k: usize, cand: &Candidate) -> bool {
        self.order[..k].iter().all(|&front| {
            match self.current[front].and_then(|c| self.lists[front].get(c)) {
                Some(chosen) => {
                    (chosen.feature.is_none() || chosen.feature != cand.feature)
                        && !cand.hides(chosen, self.separation)
                }
                None => true,
            }
        })
    }
}

#[cfg(test)]
mod tests;

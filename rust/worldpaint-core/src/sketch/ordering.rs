//! Stroke ordering by depth (thesis §5.2, step 1 of §5.1): the silhouette strokes of a sketch are ordered from front
//! to back, so that the features later matched to them do not hide one another.
//!
//! The thesis's rules, and the reading taken of each:
//!
//! - *"The terrain being a heightfield, the projection of each stroke onto the horizon (x-axis of the viewing plane)
//!   is injective."* A stroke drawn back over itself is accepted, not refused: it is replaced by its **upper
//!   envelope** (for each `x` of its points, the highest `y` the drawn polyline reaches there), since the sky side of
//!   what was drawn is what a silhouette shows. A stroke whose points all share one `x` has no width and is refused.
//! - *"Strokes are always oriented clockwise. Hence, stroke tangents are independent of the direction in which the
//!   stroke was sketched."* A silhouette is the upper boundary of the land below it; walked clockwise around that
//!   land, its top runs **left to right**, land on the right hand and sky on the left. Every stroke is oriented so
//!   that `x` strictly increases ([`StrokeOrder::oriented`]); one drawn right to left is reversed.
//! - *"An extremity q_s of stroke s is a T-junction if its closest distance to another stroke r is smaller than a
//!   given threshold."* The threshold is [`OrderingOptions::junction_distance`], in frame widths (the image's `y` is
//!   scaled by the frame's aspect so that distances are the same in every direction). When several strokes are that
//!   close, the closest one is `r`. An extremity on or past the frame's left or right edge (`x ≤ 0` or `x ≥ 1`) is
//!   where the frame cut the silhouette, not a junction: draw across the edge to say so.
//! - *"q_s is labeled 'occluded-by' r if the oriented angle, measured counterclockwise, between the tangent t_s of s
//!   at q_s and the tangent t_r of r at q_s, ∠(t_s, t_r) < π. Otherwise s is in front of r."* and its footnote
//!   *"When labeling a starting point q_s as T-junction, we flip its tangent."* `t_s` is the chord over
//!   [`OrderingOptions::tangent_length`] of `s` ending at `q_s` (so it points out of `s` at its end, and once flipped
//!   out of `s` at its start too); `t_r` is the oriented chord of the same length of `r` centred on the point of `r`
//!   closest to `q_s`. Chords, rather than the last segment, keep the hand's tremor out of the angle. The angle is in
//!   `[0, 2π)`: "occluded by" exactly when `t_s × t_r > 0`, or when the tangents are parallel and point the same way
//!   (angle 0). So a stroke whose end comes down onto `r` from above is behind `r` (it disappears behind it), and
//!   one whose end rises onto `r` from below, inside `r`'s mountain, is in front of it.
//! - *"If a stroke s has no T-junction, then it is behind a stroke r either if the projection of s completely contains
//!   the projection of r or if the smallest height value of s's endpoints is larger than the smallest height value of
//!   r's endpoints."* These cues order every pair the T-junctions leave unordered (a stroke without T-junction is
//!   the case where all its pairs are). Containment is tried first and decides when it holds either way; only then
//!   the lowest endpoints are compared. Projections and endpoints are taken inside the frame (a stroke drawn past an
//!   edge is cut there), so that two silhouettes drawn across the whole frame compare by height, not by how far past
//!   the edges the hand went.
//! - *"While scanning the sketch from left to right, we insert each stroke in a sorting structure, at a relative
//!   depth position determined by the cues above."* The sweep visits the extremities in increasing `x` and labels the
//!   T-junctions; the strokes are then inserted, in the order of their left extremities, into a front-to-back list.
//!   A stroke goes after every listed stroke the labels put in front of it, directly or through other strokes, and
//!   before every listed stroke they put behind it; between those bounds it moves back past each stroke the cues
//!   put in front of it. The result is a topological order of the "in front of" relation of the labels.
//! - Two strokes may each have an extremity near the other: one ends on the other, and the other's extremity only
//!   comes within the threshold of it (a peak drawn just above the end of a ridge that disappears behind it). Read
//!   as two junctions, their labels may contradict. They are **one junction**, that of the stroke that ends on the
//!   other: of two junctions between the same strokes, each onto the other, whose labels put different strokes in
//!   front, the nearer one is kept (on a tie the more confident, then the first of the sweep) and the other is no
//!   junction.
//! - Labels can still contradict one another (a cycle through three strokes or more: a hand-drawn impossible figure).
//!   They are then taken in order of confidence, `|sin ∠(t_s, t_r)|` (a label whose tangents are nearly parallel is
//!   the least sure), then closer junctions first, then in the sweep's order: a label that would close a cycle with
//!   those already taken is left out of the order and reported as [`Junction::overruled`].
//!
//! Everything is deterministic: ties are broken by `x`, then by the strokes' indices.

use super::SketchStroke;
use crate::error::{check, Error, Result};
use crate::limits;
use glam::DVec2;

/// Strokes one sketch may hold (a sketch has a handful; a thousand is far past any drawing).
const MAX_STROKES: u64 = 1_000;
/// Points of one sketch, all strokes together.
const MAX_SKETCH_POINTS: u64 = 200_000;
/// Segment evaluations of the upper envelope of one stroke drawn back over itself (a hand's small returns cost a
/// few per point; a second of work is about 10⁸).
const MAX_ENVELOPE_WORK: u64 = 50_000_000;

/// How strokes are ordered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrderingOptions {
    /// An extremity closer than this to another stroke is a T-junction (frame widths). The thesis gives no value;
    /// the default, 0.02, is about 38 px on a 1920 px wide frame. It was read off the tests' scenes (Fig. 5.3 and
    /// 5.8 rebuilt from mountains at known depths): there the occluded strokes end on their occluders (within 0.004
    /// with a simulated hand tremor of ±0.003 in `y`), while the free ends inside the frame lie 0.079 to 0.26 from
    /// every other stroke; 0.02 leaves a factor of four or more on either side.
    pub junction_distance: f64,
    /// Length of the chords that give the tangents at a junction (frame widths): 0.03 by default, longer than a
    /// hand's tremor, shorter than a silhouette's bends.
    pub tangent_length: f64,
    /// Width of the camera frame over its height (Blender's render resolution x over y), so that distances are
    /// measured alike across and up the image; 1 by default.
    pub aspect: f64,
}

impl Default for OrderingOptions {
    fn default() -> Self {
        OrderingOptions {
            junction_distance: 0.02,
            tangent_length: 0.03,
            aspect: 1.0,
        }
    }
}

/// What a T-junction says about the stroke that ends there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Relation {
    /// The stroke disappears behind the other one: it is behind it.
    OccludedBy,
    /// The stroke ends on the other one from inside its mountain: it is in front of it.
    InFrontOf,
}

/// A T-junction: an extremity of one stroke that lies on another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Junction {
    /// The stroke whose extremity it is (index into the input).
    pub stroke: usize,
    /// Whether it is the stroke's starting (left) extremity, once oriented; otherwise its ending (right) one.
    pub at_start: bool,
    /// The stroke it lies on.
    pub onto: usize,
    /// The extremity, in image coordinates.
    pub point: DVec2,
    /// Its distance to `onto` (frame widths).
    pub distance: f64,
    /// `stroke` seen from `onto`.
    pub relation: Relation,
    /// Whether the label contradicts more confident ones (a cycle) and was left out of the order.
    pub overruled: bool,
}

impl Junction {
    /// The stroke this label puts in front and the one it puts behind.
    pub fn front_back(&self) -> (usize, usize) {
        match self.relation {
            Relation::OccludedBy => (self.onto, self.stroke),
            Relation::InFrontOf => (self.stroke, self.onto),
        }
    }
}

/// The strokes of a sketch ordered in depth.
#[derive(Clone, Debug, PartialEq)]
pub struct StrokeOrder {
    /// Indices of the input strokes, the closest to the camera first.
    pub front_to_back: Vec<usize>,
    /// The input strokes oriented left to right (`x` strictly increasing; upper envelope of a stroke drawn back over
    /// itself), in input order.
    pub oriented: Vec<SketchStroke>,
    /// The T-junctions found, in the sweep's order (increasing `x`).
    pub junctions: Vec<Junction>,
}

impl StrokeOrder {
    /// The depth rank of each input stroke: 0 for the front-most.
    pub fn rank(&self) -> Vec<usize> {
        let mut rank = vec![0; self.front_to_back.len()];
        for (k, &s) in self.front_to_back.iter().enumerate() {
            if let Some(r) = rank.get_mut(s) {
                *r = k;
            }
        }
        rank
    }
}

/// Orders the silhouette `strokes` of a sketch front to back by the sweep of thesis §5.2 (see the module
/// documentation for the rules and their reading). Refuses, naming the stroke, one that is empty, has a point that
/// is not finite, has fewer than two distinct points or no width; refuses past the engine's limits a sketch of more
/// than 1,000 strokes or 200,000 points, or a long stroke scribbled back and forth across the frame.
pub(crate) fn order_strokes(
    strokes: &[SketchStroke],
    options: &OrderingOptions,
) -> Result<StrokeOrder> {
    check::positive(
        "stroke ordering junction distance",
        options.junction_distance,
    )?;
    check::positive("stroke ordering tangent length", options.tangent_length)?;
    check::positive("stroke ordering frame aspect", options.aspect)?;
    limits::check(
        "sketch strokes",
        strokes.len() as f64,
        MAX_STROKES,
        "strokes",
    )?;
    let points: usize = strokes.iter().map(|s| s.points.len()).sum();
    limits::check("sketch points", points as f64, MAX_SKETCH_POINTS, "points")?;
    let oriented = strokes
        .iter()
        .enumerate()
        .map(|(k, s)| orient(k, s).map(|points| SketchStroke { points }))
        .collect::<Result<Vec<_>>>()?;
    let lines: Vec<Line> = oriented
        .iter()
        .map(|s| Line::new(&s.points, options.aspect))
        .collect();
    let (junctions, confidence) = sweep(&oriented, &lines, options);
    let (mut junctions, confidence) = one_junction_per_contradiction(junctions, confidence);
    let front = resolve(strokes.len(), &mut junctions, &confidence);
    let cues: Vec<Cue> = oriented.iter().map(|s| Cue::new(&s.points)).collect();
    let front_to_back = insert(&oriented, &front, &cues);
    Ok(StrokeOrder {
        front_to_back,
        oriented,
        junctions,
    })
}

/// Checks stroke `k` and orients it left to right (see the module documentation).
fn orient(k: usize, stroke: &SketchStroke) -> Result<Vec<DVec2>> {
    let what = || format!("sketch stroke {k}");
    if stroke.points.is_empty() {
        return Err(Error::invalid(what(), "is empty"));
    }
    if let Some((i, p)) = stroke
        .points
        .iter()
        .enumerate()
        .find(|(_, p)| !p.is_finite())
    {
        return Err(Error::invalid(
            what(),
            format!("point {i} ({p}) is not finite"),
        ));
    }
    let mut points = stroke.points.clone();
    points.dedup();
    if points.len() < 2 {
        return Err(Error::invalid(what(), "has fewer than 2 distinct points"));
    }
    let points = if points.windows(2).all(|w| w[1].x > w[0].x) {
        points
    } else if points.windows(2).all(|w| w[1].x < w[0].x) {
        points.reverse();
        points
    } else {
        upper_envelope(k, &points)?
    };
    if points.len() < 2 {
        return Err(Error::invalid(
            what(),
            "has no width: all its points have the same x, and a silhouette spans some width",
        ));
    }
    Ok(points)
}

/// The upper envelope of the polyline through `points` (stroke `k`), at the `x` of each of them, left to right.
/// Each segment is evaluated at the `x` it spans: refused past [`MAX_ENVELOPE_WORK`] evaluations (a long stroke
/// scribbled back and forth across the whole frame), before any is made.
fn upper_envelope(k: usize, points: &[DVec2]) -> Result<Vec<DVec2>> {
    let mut xs: Vec<f64> = points.iter().map(|p| p.x).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let spans: Vec<(DVec2, DVec2, usize, usize)> = points
        .windows(2)
        .map(|w| {
            let (a, b) = if w[0].x <= w[1].x {
                (w[0], w[1])
            } else {
                (w[1], w[0])
            };
            let lo = xs.partition_point(|&x| x < a.x);
            (a, b, lo, xs.partition_point(|&x| x <= b.x).max(lo))
        })
        .collect();
    let work: usize = spans.iter().map(|&(_, _, lo, hi)| hi - lo).sum();
    limits::check(
        &format!("sketch stroke {k} drawn back over itself"),
        work as f64,
        MAX_ENVELOPE_WORK,
        "segment evaluations",
    )?;
    let mut ys = vec![f64::NEG_INFINITY; xs.len()];
    for (a, b, lo, hi) in spans {
        for (x, y) in xs[lo..hi].iter().zip(&mut ys[lo..hi]) {
            let on = if b.x > a.x {
                a.y + (b.y - a.y) * ((x - a.x) / (b.x - a.x))
            } else {
                a.y.max(b.y)
            };
            *y = y.max(on);
        }
    }
    Ok(xs
        .into_iter()
        .zip(ys)
        .map(|(x, y)| DVec2::new(x, y))
        .collect())
}

/// An oriented stroke in frame widths (image `y` divided by the aspect), with its arc length at each point.
struct Line {
    points: Vec<DVec2>,
    arc: Vec<f64>,
    min: DVec2,
    max: DVec2,
}

impl Line {
    fn new(image: &[DVec2], aspect: f64) -> Line {
        let points: Vec<DVec2> = image
            .iter()
            .map(|p| DVec2::new(p.x, p.y / aspect))
            .collect();
        let mut arc = Vec::with_capacity(points.len());
        let mut total = 0.0;
        for (k, p) in points.iter().enumerate() {
            if k > 0 {
                total += p.distance(points[k - 1]);
            }
            arc.push(total);
        }
        let min = points.iter().fold(DVec2::INFINITY, |m, &p| m.min(p));
        let max = points.iter().fold(DVec2::NEG_INFINITY, |m, &p| m.max(p));
        Line {
            points,
            arc,
            min,
            max,
        }
    }

    fn length(&self) -> f64 {
        self.arc.last().copied().unwrap_or(0.0)
    }

    /// The point at arc length `s`, clamped to the line.
    fn at(&self, s: f64) -> DVec2 {
        let n = self.points.len();
        if n < 2 {
            return self.points.first().copied().unwrap_or(DVec2::ZERO);
        }
        let i = self.arc.partition_point(|&a| a <= s).clamp(1, n - 1);
        let (a0, a1) = (self.arc[i - 1], self.arc[i]);
        let t = if a1 > a0 {
            ((s - a0) / (a1 - a0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.points[i - 1].lerp(self.points[i], t)
    }

    /// The distance from `q` to the line and the arc length of the closest point (the first one on ties).
    fn closest(&self, q: DVec2) -> (f64, f64) {
        let mut best = (f64::INFINITY, 0.0);
        for (i, w) in self.points.windows(2).enumerate() {
            let d = w[1] - w[0];
            let len2 = d.length_squared();
            let t = if len2 > 0.0 {
                ((q - w[0]).dot(d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let dist = q.distance(w[0] + d * t);
            if dist < best.0 {
                best = (dist, self.arc[i] + t * len2.sqrt());
            }
        }
        best
    }

    /// The distance from `q` to the line's bounding box.
    fn box_distance(&self, q: DVec2) -> f64 {
        (q - q.clamp(self.min, self.max)).length()
    }

    /// The unit direction from the point at arc length `a` to the one at `b`.
    fn chord(&self, a: f64, b: f64) -> DVec2 {
        (self.at(b) - self.at(a)).normalize_or_zero()
    }
}

/// The sweep: the extremities in increasing `x`, each labelled if it is a T-junction; with each label's confidence.
fn sweep(
    oriented: &[SketchStroke],
    lines: &[Line],
    options: &OrderingOptions,
) -> (Vec<Junction>, Vec<f64>) {
    let mut events: Vec<(DVec2, usize, bool)> = Vec::with_capacity(2 * oriented.len());
    for (s, stroke) in oriented.iter().enumerate() {
        if let (Some(&first), Some(&last)) = (stroke.points.first(), stroke.points.last()) {
            events.push((first, s, true));
            events.push((last, s, false));
        }
    }
    events.sort_by(|a, b| {
        a.0.x
            .total_cmp(&b.0.x)
            .then(a.1.cmp(&b.1))
            .then(b.2.cmp(&a.2))
    });
    let (threshold, window) = (options.junction_distance, options.tangent_length);
    let mut junctions = Vec::new();
    let mut confidence = Vec::new();
    for (point, s, at_start) in events {
        if point.x <= 0.0 || point.x >= 1.0 {
            continue; // the frame cut the silhouette here
        }
        let line = &lines[s];
        let q = if at_start {
            line.at(0.0)
        } else {
            line.at(line.length())
        };
        let mut best: Option<(f64, usize, f64)> = None;
        for (r, other) in lines.iter().enumerate() {
            if r == s || other.box_distance(q) >= threshold {
                continue;
            }
            let (d, a) = other.closest(q);
            if d < threshold && best.is_none_or(|b| d < b.0) {
                best = Some((d, r, a));
            }
        }
        let Some((distance, onto, a)) = best else {
            continue;
        };
        // tangents pointing out of s at q (flipped at the start), and along r at its closest point
        let t_s = if at_start {
            line.chord(window, 0.0)
        } else {
            line.chord(line.length() - window, line.length())
        };
        let t_r = lines[onto].chord(a - 0.5 * window, a + 0.5 * window);
        let (cross, dot) = (t_s.perp_dot(t_r), t_s.dot(t_r));
        let relation = if cross > 0.0 || (cross == 0.0 && dot > 0.0) {
            Relation::OccludedBy
        } else {
            Relation::InFrontOf
        };
        junctions.push(Junction {
            stroke: s,
            at_start,
            onto,
            point,
            distance,
            relation,
            overruled: false,
        });
        confidence.push(cross.abs());
    }
    (junctions, confidence)
}

/// Of two junctions between the same strokes, each ending on the other, whose labels contradict (each puts a
/// different stroke in front), keeps the one of the stroke that ends on the other: the nearer one (on a tie, the more
/// confident one, then the first of the sweep). The other extremity only came near the stroke that ends on it.
fn one_junction_per_contradiction(
    junctions: Vec<Junction>,
    confidence: Vec<f64>,
) -> (Vec<Junction>, Vec<f64>) {
    let mut nearest_first: Vec<usize> = (0..junctions.len()).collect();
    nearest_first.sort_by(|&a, &b| {
        junctions[a]
            .distance
            .total_cmp(&junctions[b].distance)
            .then(confidence[b].total_cmp(&confidence[a]))
            .then(a.cmp(&b))
    });
    let mut kept = vec![false; junctions.len()];
    for k in nearest_first {
        let j = &junctions[k];
        kept[k] = !(0..junctions.len()).any(|o| {
            let other = &junctions[o];
            kept[o]
                && other.stroke == j.onto
                && other.onto == j.stroke
                && other.front_back() != j.front_back()
        });
    }
    junctions
        .into_iter()
        .zip(confidence)
        .zip(kept)
        .filter(|(_, keep)| *keep)
        .map(|(pair, _)| pair)
        .unzip()
}

/// Keeps the labels, most confident first, that close no cycle with those kept before; marks the others overruled.
/// Returns the transitive "in front of" relation of the kept labels: `front[a][b]` when `a` must be before `b`.
fn resolve(n: usize, junctions: &mut [Junction], confidence: &[f64]) -> Vec<Vec<bool>> {
    let mut order: Vec<usize> = (0..junctions.len()).collect();
    order.sort_by(|&a, &b| {
        let conf = |k: usize| confidence.get(k).copied().unwrap_or(0.0);
        conf(b)
            .total_cmp(&conf(a))
            .then(junctions[a].distance.total_cmp(&junctions[b].distance))
            .then(a.cmp(&b))
    });
    let mut edges: Vec<Vec<usize>> = vec![Vec::new(); n];
    for k in order {
        let (f, b) = junctions[k].front_back();
        if reachable(&edges, b)[f] {
            junctions[k].overruled = true;
        } else if !edges[f].contains(&b) {
            edges[f].push(b);
        }
    }
    (0..n).map(|a| reachable(&edges, a)).collect()
}

/// The strokes reachable from `from` along `edges` (not `from` itself unless on a cycle, which `resolve` prevents).
fn reachable(edges: &[Vec<usize>], from: usize) -> Vec<bool> {
    let mut seen = vec![false; edges.len()];
    let mut stack: Vec<usize> = edges[from].clone();
    while let Some(v) = stack.pop() {
        if !seen[v] {
            seen[v] = true;
            stack.extend(edges[v].iter().copied().filter(|&w| !seen[w]));
        }
    }
    seen
}

/// What the cues of strokes without T-junction read: the stroke's `x` extent and its lowest endpoint inside the frame.
struct Cue {
    x0: f64,
    x1: f64,
    low: f64,
}

impl Cue {
    fn new(points: &[DVec2]) -> Cue {
        let (first, last) = match (points.first(), points.last()) {
            (Some(&f), Some(&l)) => (f, l),
            _ => (DVec2::ZERO, DVec2::ZERO),
        };
        let (x0, x1) = (first.x.max(0.0), last.x.min(1.0));
        if x0 < x1 {
            let low = height_at(points, x0).min(height_at(points, x1));
            Cue { x0, x1, low }
        } else {
            // entirely outside the frame: read as drawn
            Cue {
                x0: first.x,
                x1: last.x,
                low: first.y.min(last.y),
            }
        }
    }

    /// Whether `self`'s projection strictly contains `other`'s.
    fn contains(&self, other: &Cue) -> bool {
        self.x0 <= other.x0 && self.x1 >= other.x1 && (self.x0 < other.x0 || self.x1 > other.x1)
    }

    /// Whether the cues put `self` behind `other`: containment first, then the lowest endpoints.
    fn behind(&self, other: &Cue) -> bool {
        if self.contains(other) {
            true
        } else if other.contains(self) {
            false
        } else {
            self.low > other.low
        }
    }
}

/// The height of the `x`-monotone polyline `points` at `x` inside its extent.
fn height_at(points: &[DVec2], x: f64) -> f64 {
    let i = points
        .partition_point(|p| p.x <= x)
        .clamp(1, points.len().max(2) - 1);
    match (points.get(i - 1), points.get(i)) {
        (Some(a), Some(b)) if b.x > a.x => {
            a.y + (b.y - a.y) * ((x - a.x) / (b.x - a.x)).clamp(0.0, 1.0)
        }
        (Some(a), _) => a.y,
        _ => 0.0,
    }
}

/// Inserts the strokes, by increasing left extremity, into the front-to-back list (see the module documentation).
fn insert(oriented: &[SketchStroke], front: &[Vec<bool>], cues: &[Cue]) -> Vec<usize> {
    let left = |s: usize| oriented[s].points.first().map_or(0.0, |p| p.x);
    let mut sweep: Vec<usize> = (0..oriented.len()).collect();
    sweep.sort_by(|&a, &b| left(a).total_cmp(&left(b)).then(a.cmp(&b)));
    let mut list: Vec<usize> = Vec::with_capacity(oriented.len());
    for s in sweep {
        let lo = list.iter().rposition(|&a| front[a][s]).map_or(0, |p| p + 1);
        let hi = list
            .iter()
            .position(|&b| front[s][b])
            .unwrap_or(list.len())
            .max(lo);
        let mut pos = lo;
        while pos < hi && cues[s].behind(&cues[list[pos]]) {
            pos += 1;
        }
        list.insert(pos, s);
    }
    list
}

#[cfg(test)]
mod tests;

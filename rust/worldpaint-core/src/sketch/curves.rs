//! The 3D curves a sketch deforms the terrain to (thesis §5.3.2, "Stroke in World Space" and "Completing Selected
//! 3D Features"): a stroke with a matched feature uses the feature deformed onto it, `f′`; a stroke no feature could
//! serve is embedded in 3D between the strokes just in front of and just behind it; and each curve is extended at
//! both ends along its tangent until it meets the terrain, so that a silhouette does not start abruptly in mid-air
//! when seen from elsewhere.

use super::matching::StrokeCurve;
use super::view::{Camera, Sight};
use glam::{DVec2, DVec3};

/// How far an embedded stroke is placed behind the farthest stroke, or in front of the nearest one, as a share of
/// that stroke's depth: our choice (the thesis says "behind" and "in front", not how far).
pub(crate) const EMBED_MARGIN: f64 = 0.25;

/// The depth at which the stroke at depth position `k` (of `mean_depths.len()`, front to back) is embedded: halfway
/// between the nearest strokes in front of and behind it that have a curve (`mean_depths[k]` their mean depth along
/// the camera's forward axis), behind the farthest or in front of the nearest one when it has no neighbour on one
/// side, at `fallback` when no stroke has a curve.
pub(crate) fn embedding_depth(k: usize, mean_depths: &[Option<f64>], fallback: f64) -> f64 {
    let front = mean_depths[..k].iter().rev().find_map(|d| *d);
    let back = mean_depths
        .get(k + 1..)
        .and_then(|rest| rest.iter().find_map(|d| *d));
    match (front, back) {
        (Some(f), Some(b)) => 0.5 * (f + b),
        (Some(f), None) => f * (1.0 + EMBED_MARGIN),
        (None, Some(b)) => b * (1.0 - EMBED_MARGIN),
        (None, None) => fallback,
    }
}

/// The stroke placed at `depth` along the camera's forward axis: each point where its ray reaches that depth.
pub(crate) fn embed(camera: &Camera, stroke: &StrokeCurve, depth: f64) -> Vec<DVec3> {
    stroke
        .points()
        .iter()
        .map(|&p| {
            let dir = camera.ray(p);
            camera.eye + dir * (depth / dir.dot(camera.forward))
        })
        .collect()
}

/// The depth an embedded stroke takes when no stroke has a feature: that of the terrain it is drawn over (the
/// visible silhouette in its middle column), else of the terrain's centre.
pub(crate) fn fallback_depth(sight: &Sight, camera: &Camera, stroke: &StrokeCurve) -> f64 {
    let (x0, x1) = stroke.x_range();
    let x = 0.5 * (x0 + x1);
    let grazed = sight
        .column_silhouette(camera, x, -1.0, stroke.y_at(x).unwrap_or(1.0))
        .map(|(_, p)| (p - camera.eye).dot(camera.forward));
    let (lo, hi) = sight.terrain.bbox();
    let centre = 0.5 * (lo + hi);
    let centre = (centre.extend(0.0) - camera.eye)
        .truncate()
        .dot(camera.forward.truncate());
    grazed
        .filter(|d| *d > 0.0)
        .unwrap_or(centre.max(sight.terrain.cell))
}

/// Length (in terrain cells) of the end of a curve whose chord gives its tangent there.
const TANGENT_CELLS: f64 = 3.0;

/// `curve` (broken at `breaks`, see [`super::matching::Candidate::breaks`]) extended at both ends along its tangent
/// (the chord over its last `TANGENT_CELLS` cells, within its end piece) until it meets the terrain, stepping half
/// a cell, for at most `max_length` metres; an end whose tangent does not lead down to the surface within that
/// length, or that would pass higher above the ground than the end itself (flying over a valley behind a ridge
/// rather than coming down to it), stays as it is. Returns the curve and the number of points put before its first.
pub(crate) fn complete(
    sight: &Sight,
    curve: &[DVec3],
    breaks: &[usize],
    max_length: f64,
) -> (Vec<DVec3>, usize) {
    let n = curve.len();
    if n < 2 {
        return (curve.to_vec(), 0);
    }
    let cell = sight.terrain.cell;
    let end = |piece: &mut dyn Iterator<Item = &DVec3>| -> Vec<DVec3> {
        let Some(&tip) = piece.next() else {
            return Vec::new();
        };
        let mut inner = tip;
        for &p in piece {
            inner = p;
            if p.distance(tip) >= TANGENT_CELLS * cell {
                break;
            }
        }
        let (Some(dir), Some(ground)) = (
            (tip - inner).try_normalize(),
            sight.terrain.height_at(tip.truncate()),
        ) else {
            return Vec::new();
        };
        let clearance = tip.z - ground;
        let step = 0.5 * cell;
        let steps = (max_length / step).floor() as usize;
        let mut out = Vec::new();
        for k in 1..=steps {
            let p = tip + dir * (step * k as f64);
            let Some(h) = sight.terrain.height_at(p.truncate()) else {
                return Vec::new();
            };
            if p.z <= h {
                out.push(DVec3::new(p.x, p.y, h));
                return out;
            }
            if p.z - h > clearance {
                return Vec::new();
            }
            out.push(p);
        }
        Vec::new()
    };
    // the end pieces: up to the first break, from the last one
    let first_piece = breaks.iter().copied().min().unwrap_or(n).min(n);
    let last_piece = breaks.iter().copied().max().unwrap_or(0).min(n);
    let mut start = end(&mut curve[..first_piece].iter());
    start.reverse();
    let finish = end(&mut curve[last_piece..].iter().rev());
    let before = start.len();
    let done = start.iter().chain(curve).chain(&finish).copied().collect();
    (done, before)
}

/// Image coordinates of a curve's points, with their depths; points behind the eye are left out.
pub(crate) fn projected(camera: &Camera, curve: &[DVec3]) -> Vec<(DVec2, f64)> {
    curve.iter().filter_map(|&p| camera.project(p)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sketch::SketchStroke;
    use crate::terrain::Heightfield;

    #[test]
    fn an_embedded_stroke_sits_between_its_neighbours_and_projects_onto_itself() {
        assert_eq!(
            embedding_depth(1, &[Some(100.0), None, Some(300.0)], 50.0),
            200.0
        );
        assert_eq!(
            embedding_depth(2, &[Some(100.0), Some(200.0), None], 50.0),
            250.0
        );
        assert_eq!(embedding_depth(0, &[None, Some(200.0)], 50.0), 150.0);
        assert_eq!(embedding_depth(0, &[None], 50.0), 50.0);
        let camera = Camera::looking_at(
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::new(0.0, 100.0, 10.0),
            60.0,
            1.5,
        )
        .expect("a camera");
        let stroke = StrokeCurve::new(&SketchStroke {
            points: vec![
                DVec2::new(0.2, 0.6),
                DVec2::new(0.5, 0.7),
                DVec2::new(0.8, 0.55),
            ],
        });
        for (p, s) in embed(&camera, &stroke, 120.0).iter().zip(stroke.points()) {
            let (image, depth) = camera.project(*p).expect("in front");
            assert!(image.distance(*s) < 1e-9 && (depth - 120.0).abs() < 1e-9);
        }
    }

    #[test]
    fn completion_runs_down_the_tangent_to_the_ground() {
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, 101, 101, vec![0.0; 101 * 101])
            .expect("a valid grid");
        let sight = Sight::new(&terrain);
        // a curve rising from x = 40 to the top at 50 and falling to 60, 10 m up at its ends
        let curve: Vec<DVec3> = (0..=20)
            .map(|k| DVec3::new(40.0 + k as f64, 50.0, 20.0 - (k as f64 - 10.0).abs()))
            .collect();
        let (done, before) = complete(&sight, &curve, &[], 50.0);
        assert_eq!(done[before], curve[0]);
        let (first, last) = (done[0], done[done.len() - 1]);
        assert!(
            first.z.abs() < 1e-9 && last.z.abs() < 1e-9,
            "ends on the ground: {first} {last}"
        );
        assert!(
            (first.x - 30.0).abs() < 0.6 && (last.x - 70.0).abs() < 0.6,
            "along the slopes: {first} {last}"
        );
        // a rising end cannot reach the ground: it stays
        let rising: Vec<DVec3> = (0..=10)
            .map(|k| DVec3::new(40.0 + k as f64, 50.0, 5.0 + k as f64))
            .collect();
        assert_eq!(complete(&sight, &rising, &[], 50.0).0.last(), rising.last());
    }
}

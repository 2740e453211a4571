//! The visible silhouettes image column by image column (our addition to thesis §5.3.2): the skyline under a stroke,
//! a candidate of its priority list, and how much terrain a candidate would have to lower in front of it.
//!
//! **The skyline.** The thesis matches a stroke to one terrain feature. Seen from the ground, the skyline is rarely
//! one feature: it is made of the tops of ridges at different depths, each silhouette curve ending where a farther
//! one rises behind it (the silhouette detector cannot link them: they share no edge). A stroke drawn a little
//! above the skyline then found no feature that follows it; the one chosen was the feature that covered the
//! stroke best, often a slope much nearer, raised by more than the skyline's own ridges would have needed, and the
//! real skyline then disappeared behind it. So each stroke also gets the **skyline under it** as a candidate: in
//! each image column the stroke covers, the highest point of the visible silhouettes there (the skyline, where the
//! terrain's own edge does not stand above them), moved vertically onto the stroke like any feature. Where two
//! neighbouring columns take their point from different silhouette curves, the curve is broken
//! ([`Skyline::breaks`]): the two pieces lie at different depths, and a constraint joining them would raise a wall
//! along the line of sight across the valley between them.
//!
//! **Lowering in front.** A candidate lying behind terrain that rises above the stroke forces that terrain to be
//! lowered (§5.4) as surely as it forces its own points onto the stroke. The highest terrain nearer than a point in
//! an image column is a visible silhouette (anything in front of it would be higher still), so the silhouettes
//! crossing the column tell how far it rises above the stroke: `Δy` image heights at depth `d` are
//! `Δy · d · h` metres, `h` the frame's height one metre ahead.

use super::matching::{FeaturePiece, StrokeCurve};
use super::view::Camera;
use super::FeatureKind;
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};

/// A visible silhouette crossing an image column.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Crossing {
    /// Image `y`.
    y: f64,
    /// Depth along the camera's forward axis (m).
    depth: f64,
    /// The world point (on the silhouette's segment, interpolated at the column).
    point: DVec3,
    /// The feature piece it lies on.
    piece: usize,
}

/// The visible silhouettes crossing each of `n` image columns across the frame.
#[derive(Clone, Debug)]
pub(crate) struct SilhouetteColumns {
    crossings: Vec<Vec<Crossing>>,
    image_height: f64,
}

/// The skyline under a stroke, as a candidate curve before it is moved onto the stroke.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Skyline {
    /// Its points, one per image column, left to right.
    pub points: Vec<DVec3>,
    /// Their image coordinates.
    pub image: Vec<DVec2>,
    /// Indices `k` where the curve jumps from one silhouette to another between points `k − 1` and `k`.
    pub breaks: Vec<usize>,
}

impl SilhouetteColumns {
    /// The crossings of the silhouette pieces among `pieces` with `columns` image columns across the frame
    /// (column `c` at `x = c / (columns − 1)`).
    pub(crate) fn new(
        camera: &Camera,
        pieces: &[FeaturePiece],
        columns: usize,
    ) -> SilhouetteColumns {
        let n = columns.max(2);
        let mut crossings = vec![Vec::new(); n];
        let last = (n - 1) as f64;
        for (p, piece) in pieces.iter().enumerate() {
            if piece.kind != FeatureKind::Silhouette {
                continue;
            }
            for (k, w) in piece.image.windows(2).enumerate() {
                let (a, b) = (w[0], w[1]);
                if !(b.x > a.x) {
                    continue;
                }
                // the columns in [a.x, b.x), and the last point's own column at the piece's end
                let first = (a.x * last).ceil().max(0.0);
                let end = if k + 2 == piece.image.len() {
                    (b.x * last).floor()
                } else {
                    (b.x * last).ceil() - 1.0
                };
                let end = end.min(last);
                let mut c = first;
                while c <= end {
                    let x = c / last;
                    let t = ((x - a.x) / (b.x - a.x)).clamp(0.0, 1.0);
                    let point = piece.points[k].lerp(piece.points[k + 1], t);
                    if let Some((image, depth)) = camera.project(point) {
                        crossings[c as usize].push(Crossing {
                            y: image.y,
                            depth,
                            point,
                            piece: p,
                        });
                    }
                    c += 1.0;
                }
            }
        }
        SilhouetteColumns {
            crossings,
            image_height: camera.image_height(),
        }
    }

    fn column(&self, x: f64) -> Option<&[Crossing]> {
        let last = (self.crossings.len() - 1) as f64;
        let c = (x * last).round();
        if !(0.0..=last).contains(&c) {
            return None;
        }
        self.crossings.get(c as usize).map(Vec::as_slice)
    }

    /// The height (m) by which the terrain nearer than `depth` minus `separation` in image column `x` would have to
    /// be lowered so that none of it rises above image height `y`.
    pub(crate) fn lowering_in_front(&self, x: f64, y: f64, depth: f64, separation: f64) -> f64 {
        self.column(x).map_or(0.0, |crossings| {
            crossings
                .iter()
                .filter(|c| c.depth < depth - separation && c.y > y)
                .map(|c| (c.y - y) * c.depth * self.image_height)
                .fold(0.0, f64::max)
        })
    }

    /// The skyline under `stroke`: the highest crossing of every column the stroke covers, broken where it passes
    /// from one silhouette piece to another or a column has none; `None` if fewer than two columns have one. Where
    /// `offset(x)` is not zero, the point of column `x` is the ground that many metres farther along the column
    /// (nearer where it is negative): the skyline there is left to another stroke.
    pub(crate) fn skyline(
        &self,
        camera: &Camera,
        terrain: &Heightfield,
        stroke: &StrokeCurve,
        offset: &dyn Fn(f64) -> f64,
    ) -> Option<Skyline> {
        let (x0, x1) = stroke.x_range();
        let last = (self.crossings.len() - 1) as f64;
        let (first, end) = ((x0 * last).ceil().max(0.0), (x1 * last).floor().min(last));
        let mut sky = Skyline {
            points: Vec::new(),
            image: Vec::new(),
            breaks: Vec::new(),
        };
        // the silhouette piece of the previous column's point, and the side it was moved to
        let mut previous: Option<(usize, i8)> = None;
        let mut gap = false;
        let mut c = first;
        while c <= end {
            let x = c / last;
            let top = self.crossings[c as usize]
                .iter()
                .max_by(|a, b| a.y.total_cmp(&b.y));
            let shift = offset(x);
            let point = top.and_then(|top| {
                let side = (shift > 0.0) as i8 - (shift < 0.0) as i8;
                let at = if side == 0 {
                    Some((top.point, top.y))
                } else {
                    ground_along(camera, terrain, x, top, shift)
                };
                at.map(|p| (p, (top.piece, side)))
            });
            match point {
                Some(((point, y), piece)) => {
                    if !sky.points.is_empty() && (gap || previous != Some(piece)) {
                        sky.breaks.push(sky.points.len());
                    }
                    sky.points.push(point);
                    sky.image.push(DVec2::new(x, y));
                    previous = Some(piece);
                    gap = false;
                }
                None => gap = true,
            }
            c += 1.0;
        }
        (sky.points.len() >= 2).then_some(sky)
    }
}

/// The ground `shift` metres farther than `top` along image column `x` (on the ray through it, then dropped onto
/// the terrain), with its image `y`; `None` off the terrain or behind the eye.
fn ground_along(
    camera: &Camera,
    terrain: &Heightfield,
    x: f64,
    top: &Crossing,
    shift: f64,
) -> Option<(DVec3, f64)> {
    let dir = camera.ray(DVec2::new(x, top.y));
    let along = dir.dot(camera.forward);
    let depth = top.depth + shift;
    if !(along > 1e-9 && depth > 0.0) {
        return None;
    }
    let p = camera.eye + dir * (depth / along);
    let ground = p.truncate().extend(terrain.height_at(p.truncate())?);
    Some((ground, camera.project(ground)?.0.y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sketch::matching::feature_pieces;
    use crate::sketch::{Feature, SketchStroke};

    fn camera() -> Camera {
        Camera::looking_at(
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::new(0.0, 100.0, 10.0),
            60.0,
            1.5,
        )
        .expect("a camera")
    }

    /// A silhouette along X from `x0` to `x1` at `y` metres ahead, `z` high.
    fn crest(x0: f64, x1: f64, y: f64, z: f64) -> Feature {
        Feature {
            kind: FeatureKind::Silhouette,
            points: (0..=20)
                .map(|k| DVec3::new(x0 + (x1 - x0) * k as f64 / 20.0, y, z))
                .collect(),
        }
    }

    #[test]
    fn the_skyline_takes_the_highest_silhouette_of_each_column_and_breaks_between_them() {
        let camera = camera();
        // a near low crest across the view, a far high one over its left half only, and a ridge (not a silhouette)
        // higher than both
        let mut high = crest(-300.0, 0.0, 600.0, 60.0);
        high.kind = FeatureKind::Ridge;
        high.points.iter_mut().for_each(|p| p.z = 200.0);
        let features = [
            crest(-100.0, 100.0, 100.0, 15.0),
            crest(-400.0, 0.0, 500.0, 60.0),
            high,
        ];
        let pieces = feature_pieces(&camera, &features);
        let columns = SilhouetteColumns::new(&camera, &pieces, 101);
        let stroke = StrokeCurve::new(&SketchStroke {
            points: vec![DVec2::new(0.2, 0.8), DVec2::new(0.8, 0.8)],
        });
        let flat = Heightfield::new(
            DVec2::new(-1000.0, 0.0),
            10.0,
            201,
            201,
            vec![0.0; 201 * 201],
        )
        .expect("a grid");
        let sky = columns
            .skyline(&camera, &flat, &stroke, &|_| 0.0)
            .expect("a skyline");
        assert_eq!(sky.points.len(), 61);
        assert_eq!(sky.breaks, vec![31], "one jump, at the far crest's end");
        assert!(sky.points[..31].iter().all(|p| (p.y - 500.0).abs() < 1e-9));
        assert!(sky.points[31..].iter().all(|p| (p.y - 100.0).abs() < 1e-9));
        for (p, image) in sky.points.iter().zip(&sky.image) {
            let (seen, _) = camera.project(*p).expect("in front");
            assert!((seen - *image).length() < 1e-9);
        }
        // the near crest stands 5 m above the eye: 5 m at 100 m is this much of the image, and a stroke drawn
        // 0.01 lower forces it down by that much more
        let y = camera
            .project(DVec3::new(50.0, 100.0, 15.0))
            .expect("in front")
            .0
            .y;
        let x = 0.75;
        let drop = columns.lowering_in_front(x, y - 0.01, 300.0, 6.0);
        assert!(
            (drop - 0.01 * 100.0 * camera.image_height()).abs() < 1e-6,
            "{drop}"
        );
        assert_eq!(
            columns.lowering_in_front(x, y - 0.01, 90.0, 6.0),
            0.0,
            "behind the candidate"
        );
        assert_eq!(
            columns.lowering_in_front(x, y + 0.01, 300.0, 6.0),
            0.0,
            "below the stroke"
        );
    }
}

//! What an Apply Sketch is checked for before any work, so that a sketch no camera could show is refused with the
//! figure instead of deforming the terrain by kilometres (the thesis assumes a sensible view and says nothing of
//! these bounds; the readings here are ours):
//!
//! * every stroke point lies in the camera frame (`x` and `y` from 0 to 1, see [`super`]), with a slack of
//!   [`FRAME_SLACK`] for a stroke drawn past the frame's edge;
//! * the camera's field of view lies within Blender's camera range ([`MIN_FOV_DEGREES`] to [`MAX_FOV_DEGREES`],
//!   across the frame's wider side);
//! * the eye is above the ground under it, and no farther from the terrain's box than
//!   [`SketchLimits::max_camera_distance`] (by default the terrain's horizontal diagonal);
//! * the camera sees some terrain: one of the rays cast through a grid of [`SEEN_COLUMNS`] image columns and nine
//!   rows meets it;
//! * the matching's work (strokes × candidates × image columns) is within [`MAX_MATCHING_WORK`];
//! * no height change asked for, or made, is larger than [`SketchLimits::max_change`] (by default the terrain's
//!   relief, or a quarter of its shorter side on flatter ground).

use super::view::{Camera, Sight};
use super::SketchStroke;
use crate::error::{Error, Result};
use crate::limits;
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};

/// How far (share of the frame) a stroke point may lie past the frame's edge: a stroke drawn over the view may stray
/// a little beyond it.
pub(crate) const FRAME_SLACK: f64 = 0.05;
/// Narrowest field of view of a Blender camera (`Camera.angle`'s minimum, 0.367°).
pub(crate) const MIN_FOV_DEGREES: f64 = 0.367;
/// Widest field of view of a Blender camera (`Camera.angle`'s maximum, 172.847°).
pub(crate) const MAX_FOV_DEGREES: f64 = 172.847;
/// Image columns across the frame of which one must meet the terrain.
pub(crate) const SEEN_COLUMNS: usize = 64;
/// Rows (intervals between the rays cast, bottom to top) of each of those columns.
const SEEN_ROWS: usize = 8;
/// Stroke × candidate × image column evaluations the matching may be asked for (about 2 s of it): 100 strokes
/// across the whole frame among 1,170 feature pieces, at 512 columns.
pub const MAX_MATCHING_WORK: u64 = 60_000_000;

/// The bounds of a sketch's view and change.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SketchLimits {
    /// Farthest (m) the eye may be from the terrain's box; `None`: the terrain's horizontal diagonal.
    pub max_camera_distance: Option<f64>,
    /// Largest height change (m) the sketch may ask for or make; `None`: the terrain's relief, at least a quarter of
    /// its shorter side.
    pub max_change: Option<f64>,
}

impl SketchLimits {
    /// The largest height change allowed on `terrain`.
    pub fn change_bound(&self, terrain: &Heightfield) -> f64 {
        self.max_change.unwrap_or_else(|| {
            let (lo, hi) = terrain
                .heights
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
                    (lo.min(h as f64), hi.max(h as f64))
                });
            let side = (terrain.nx.min(terrain.ny) - 1) as f64 * terrain.cell;
            (hi - lo).max(0.25 * side)
        })
    }
}

/// Refuses a stroke point that is not finite or lies out of the camera frame, naming the stroke and the point.
pub(crate) fn check_strokes(strokes: &[SketchStroke]) -> Result<()> {
    let (lo, hi) = (-FRAME_SLACK, 1.0 + FRAME_SLACK);
    for (s, stroke) in strokes.iter().enumerate() {
        for (k, p) in stroke.points.iter().enumerate() {
            let what = format!("stroke {s}, point {k}");
            if !p.is_finite() {
                return Err(Error::invalid(
                    what,
                    format!("({}, {}) is not finite", p.x, p.y),
                ));
            }
            if !(p.x >= lo && p.x <= hi && p.y >= lo && p.y <= hi) {
                return Err(Error::invalid(
                    what,
                    format!(
                        "({:.4}, {:.4}) lies out of the camera frame (x and y from 0 to 1: strokes are drawn in the \
                         frame, not in pixels)",
                        p.x, p.y
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The camera's field of view across the frame's wider side, in degrees.
pub(crate) fn field_of_view(camera: &Camera) -> f64 {
    let across = |lo: f64, hi: f64| (hi.atan() - lo.atan()).to_degrees();
    across(camera.frame_min.x, camera.frame_max.x)
        .max(across(camera.frame_min.y, camera.frame_max.y))
}

/// Refuses a camera Blender could not have, one under the ground or too far from the terrain, and one that sees no
/// terrain.
pub(crate) fn check_camera(camera: &Camera, sight: &Sight, limits: &SketchLimits) -> Result<()> {
    let terrain = sight.terrain;
    let fov = field_of_view(camera);
    if !(MIN_FOV_DEGREES..=MAX_FOV_DEGREES).contains(&fov) {
        return Err(Error::invalid(
            "the camera's field of view",
            format!("{fov:.3}° is outside a Blender camera's range ({MIN_FOV_DEGREES}° to {MAX_FOV_DEGREES}°)"),
        ));
    }
    let eye = camera.eye;
    if let Some(ground) = terrain.height_at(eye.truncate()) {
        if eye.z <= ground {
            return Err(Error::invalid(
                "the camera",
                format!(
                    "its eye is {:.1} m under the ground (at {:.1} m, the ground at {ground:.1} m): it must look \
                     from above the terrain",
                    ground - eye.z,
                    eye.z
                ),
            ));
        }
    }
    let (lo, hi) = terrain
        .heights
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h as f64), hi.max(h as f64))
        });
    let size = DVec2::new((terrain.nx - 1) as f64, (terrain.ny - 1) as f64) * terrain.cell;
    let low = terrain.origin.extend(lo);
    let high = (terrain.origin + size).extend(hi);
    let distance = eye.distance(eye.clamp(low, high));
    let bound = limits.max_camera_distance.unwrap_or(size.length());
    if !(distance <= bound) {
        return Err(Error::invalid(
            "the camera",
            format!("its eye is {distance:.0} m from the terrain, farther than the bound of {bound:.0} m"),
        ));
    }
    let sees = (0..SEEN_COLUMNS).any(|k| {
        let x = (k as f64 + 0.5) / SEEN_COLUMNS as f64;
        (0..=SEEN_ROWS).any(|r| {
            let y = r as f64 / SEEN_ROWS as f64;
            sight.blocked_within(eye, camera.ray(DVec2::new(x, y)), f64::INFINITY)
        })
    });
    if !sees {
        return Err(Error::invalid(
            "the camera",
            "it sees no terrain in its frame (it looks at the sky, or away from the terrain): turn it towards the \
             ground",
        ));
    }
    Ok(())
}

/// Refuses a matching of `strokes` among `pieces` feature pieces (and their skyline candidates) at `columns` image
/// columns past [`MAX_MATCHING_WORK`].
pub(crate) fn check_matching_work(
    strokes: &[SketchStroke],
    pieces: usize,
    columns: usize,
) -> Result<()> {
    let columns_covered: f64 = strokes
        .iter()
        .map(|s| {
            let (lo, hi) = s
                .points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.x), hi.max(p.x))
                });
            ((hi - lo).max(0.0) * columns as f64).ceil() + 1.0
        })
        .sum();
    // every piece and the three skyline candidates, in each column a stroke covers
    let work = columns_covered * (pieces as f64 + 3.0);
    limits::check(
        "the sketch's matching",
        work,
        MAX_MATCHING_WORK,
        "candidate columns",
    )
}

/// Refuses a change of `largest` metres at `at` past the bound of `limits` on `terrain`; `what` says what changes.
pub(crate) fn check_change(
    what: &str,
    largest: f64,
    at: DVec3,
    terrain: &Heightfield,
    limits: &SketchLimits,
) -> Result<()> {
    let bound = limits.change_bound(terrain);
    if largest <= bound {
        return Ok(());
    }
    let rule = if limits.max_change.is_some() {
        "the bound set"
    } else {
        "the terrain's relief"
    };
    Err(Error::invalid(
        what,
        format!(
            "would change the terrain by {largest:.1} m (at x {:.1}, y {:.1}), more than {rule} of {bound:.1} m: \
             draw the strokes nearer the skyline, or allow a larger change",
            at.x, at.y
        ),
    ))
}

//! The first-person view: a perspective camera that maps world points to image coordinates and back to rays, and
//! rays cast on the heightfield (what the camera sees, and the terrain's visible silhouette in each image column).

use crate::error::{check, Error, Result};
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// A perspective camera: its eye, an orthonormal frame (`forward` the viewing direction, `up` the image's up) and
/// the image frame on the plane one metre in front of the eye, in units of `right` and `up` (Blender's
/// `Camera.view_frame` divided by its depth, so lens shift and sensor fit are kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye (world, m).
    pub eye: DVec3,
    /// Image right, unit.
    pub right: DVec3,
    /// Image up, unit, orthogonal to `right` and `forward`.
    pub up: DVec3,
    /// Viewing direction, unit.
    pub forward: DVec3,
    /// Bottom-left corner of the frame at one metre: `(x, y)` along `right` and `up`.
    pub frame_min: DVec2,
    /// Top-right corner of the frame at one metre.
    pub frame_max: DVec2,
}

impl Camera {
    /// A camera at `eye` looking along `forward`, with `up` the image's up once made orthogonal to `forward`, and
    /// the frame at one metre from `frame_min` to `frame_max`.
    pub fn new(
        eye: DVec3,
        forward: DVec3,
        up: DVec3,
        frame_min: DVec2,
        frame_max: DVec2,
    ) -> Result<Camera> {
        for (name, v) in [("eye", eye), ("forward", forward), ("up", up)] {
            if !v.is_finite() {
                return Err(Error::invalid(format!("camera {name}"), "is not finite"));
            }
        }
        if !(frame_min.is_finite() && frame_max.is_finite())
            || !(frame_max.x > frame_min.x && frame_max.y > frame_min.y)
        {
            return Err(Error::invalid(
                "camera frame",
                format!("{frame_min} to {frame_max} is empty"),
            ));
        }
        let forward = forward
            .try_normalize()
            .ok_or_else(|| Error::invalid("camera forward", "is zero"))?;
        let right = forward
            .cross(up)
            .try_normalize()
            .ok_or_else(|| Error::invalid("camera up", "is parallel to its forward direction"))?;
        Ok(Camera {
            eye,
            right,
            up: right.cross(forward),
            forward,
            frame_min,
            frame_max,
        })
    }

    /// A level-horizon camera (image up in the vertical plane of `forward`) looking from `eye` at `target`, with a
    /// horizontal field of view of `fov_degrees` and a frame `aspect` times wider than tall: for tests and scripts.
    pub fn looking_at(eye: DVec3, target: DVec3, fov_degrees: f64, aspect: f64) -> Result<Camera> {
        check::positive("camera field of view", fov_degrees)?;
        check::positive("camera aspect", aspect)?;
        if fov_degrees >= 179.0 {
            return Err(Error::invalid(
                "camera field of view",
                format!("{fov_degrees}° is not below 179°"),
            ));
        }
        let half = (0.5 * fov_degrees).to_radians().tan();
        let frame = DVec2::new(half, half / aspect);
        Camera::new(eye, target - eye, DVec3::Z, -frame, frame)
    }

    /// Image coordinates of `p` and its depth along `forward` (m); `None` for a point behind or at the eye.
    pub fn project(&self, p: DVec3) -> Option<(DVec2, f64)> {
        let v = p - self.eye;
        let depth = v.dot(self.forward);
        if !(depth > 1e-9) {
            return None;
        }
        let plane = DVec2::new(v.dot(self.right), v.dot(self.up)) / depth;
        Some((
            (plane - self.frame_min) / (self.frame_max - self.frame_min),
            depth,
        ))
    }

    /// The unit direction of the ray from the eye through image point `image`.
    pub fn ray(&self, image: DVec2) -> DVec3 {
        let plane = self.frame_min + image * (self.frame_max - self.frame_min);
        (self.forward + plane.x * self.right + plane.y * self.up).normalize()
    }

    /// Image `y` per metre of `up` at one metre: converts image heights to angles' tangents.
    pub fn image_height(&self) -> f64 {
        self.frame_max.y - self.frame_min.y
    }
}

/// A terrain as the camera sees it: the heightfield, its highest point, which bounds every ray march, and the
/// highest point of each block of cells, over which a march leaps where the ray passes above it.
#[derive(Clone, Debug)]
pub struct Sight<'a> {
    /// The terrain.
    pub terrain: &'a Heightfield,
    top: f64,
    /// Blocks across X and Y.
    blocks: (usize, usize),
    /// The highest sample of each block of `BLOCK × BLOCK` cells (its border samples included), row-major.
    block_top: Vec<f32>,
}

/// Side of the blocks (cells) whose highest sample lets a march leap over them: on a rough terrain most of a ray's
/// way passes well above the ground, and a block is crossed in one step rather than sixteen.
const BLOCK: usize = 8;

/// Bisection steps that refine a ray's hit after the march brackets it.
const HIT_REFINEMENT: usize = 20;
/// March step along a ray, in terrain cells of horizontal travel: half a cell never steps over a bilinear bump.
const MARCH_STEP: f64 = 0.5;
/// Image rows the column search first steps down by, before bisecting to the silhouette.
const COLUMN_ROWS: usize = 64;
/// Bisection steps of the column search: 2⁻¹⁸ of the searched height, far below a pixel.
const COLUMN_REFINEMENT: usize = 18;
/// First step (image heights) of the search above a point of a column, and the bisection steps after it: the
/// silhouette is then placed within 2⁻¹² of the last step, far below a pixel.
const ABOVE_FIRST_STEP: f64 = 1.0 / 512.0;
const ABOVE_REFINEMENT: usize = 12;

impl<'a> Sight<'a> {
    /// The terrain prepared for ray casting.
    pub fn new(terrain: &'a Heightfield) -> Sight<'a> {
        let t = terrain;
        let blocks = (
            t.nx.saturating_sub(2) / BLOCK + 1,
            t.ny.saturating_sub(2) / BLOCK + 1,
        );
        let block_top: Vec<f32> = (0..blocks.1)
            .into_par_iter()
            .flat_map_iter(|by| {
                (0..blocks.0).map(move |bx| {
                    let (i1, j1) = ((bx + 1) * BLOCK, (by + 1) * BLOCK);
                    (by * BLOCK..=j1.min(t.ny.saturating_sub(1)))
                        .flat_map(|j| {
                            (bx * BLOCK..=i1.min(t.nx.saturating_sub(1)))
                                .filter_map(move |i| t.heights.get(j * t.nx + i).copied())
                        })
                        .fold(f32::NEG_INFINITY, f32::max)
                })
            })
            .collect();
        let top = block_top
            .iter()
            .fold(f64::NEG_INFINITY, |m, &h| m.max(h as f64));
        Sight {
            terrain,
            top,
            blocks,
            block_top,
        }
    }

    /// Marches `origin + dir·t` from `t0` (excluded) to `t1` (included), calling `probe(before, t)` at points at
    /// most `step` apart, until it returns `Some`. Blocks of cells whose highest sample the ray passes above from
    /// where it enters them to where it leaves are leapt over: the ray meets nothing in them.
    fn march<R>(
        &self,
        origin: DVec3,
        dir: DVec3,
        (t0, t1): (f64, f64),
        step: f64,
        mut probe: impl FnMut(f64, f64) -> Option<R>,
    ) -> Option<R> {
        let block = BLOCK as f64 * self.terrain.cell;
        let corner = self.terrain.origin;
        let (o, v) = ((origin.truncate() - corner) / block, dir.truncate() / block);
        let mut t = t0;
        while t < t1 {
            // the block the ray is entering at `t` (of two on a border, the one ahead) and where it leaves it
            let f = o + v * t;
            let index = |f: f64, v: f64, n: usize| {
                let k = if v < 0.0 { f.ceil() - 1.0 } else { f.floor() };
                (k.max(0.0) as usize).min(n - 1)
            };
            let (bx, by) = (
                index(f.x, v.x, self.blocks.0),
                index(f.y, v.y, self.blocks.1),
            );
            let mut exit = t1;
            for (o, v, b) in [(o.x, v.x, bx), (o.y, v.y, by)] {
                if v > 1e-15 {
                    exit = exit.min(((b + 1) as f64 - o) / v);
                } else if v < -1e-15 {
                    exit = exit.min((b as f64 - o) / v);
                }
            }
            let exit = exit.max(t);
            let under = self.block_top[by * self.blocks.0 + bx] as f64;
            if exit > t && origin.z + dir.z * t > under && origin.z + dir.z * exit > under {
                t = exit;
                continue;
            }
            // through the block (or the step, if the ray lies on a block's border) a step at a time
            let end = if exit > t { exit } else { (t + step).min(t1) };
            while t < end {
                let next = (t + step).min(end);
                if let Some(r) = probe(t, next) {
                    return Some(r);
                }
                t = next;
            }
        }
        None
    }

    /// Where the ray from `origin` along the unit `dir` first meets the terrain's (bilinear) surface: the distance
    /// along the ray and the point; `None` if it leaves the terrain's box first.
    pub fn hit(&self, origin: DVec3, dir: DVec3) -> Option<(f64, DVec3)> {
        self.hit_within(origin, dir, f64::INFINITY)
    }

    /// [`Sight::hit`] looking no farther than `t_max` along the ray: what stands in front of a point at that
    /// distance (the march stops there, which is what makes occlusion tests cheap).
    pub fn hit_within(&self, origin: DVec3, dir: DVec3, t_max: f64) -> Option<(f64, DVec3)> {
        let (mut lo, mut hi) = self.bracket(origin, dir, t_max)?;
        if lo < hi {
            for _ in 0..HIT_REFINEMENT {
                let mid = 0.5 * (lo + hi);
                match self.above(origin, dir, mid) {
                    Some(v) if v > 0.0 => lo = mid,
                    _ => hi = mid,
                }
            }
        }
        Some((hi, origin + dir * hi))
    }

    /// Whether the ray from `origin` along the unit `dir` meets the terrain no farther than `t_max`: what
    /// [`Sight::hit_within`] finds, without placing the hit.
    pub fn blocked_within(&self, origin: DVec3, dir: DVec3, t_max: f64) -> bool {
        self.bracket(origin, dir, t_max).is_some()
    }

    /// How far above the terrain the ray is at `t`; `None` off the grid.
    fn above(&self, origin: DVec3, dir: DVec3, t: f64) -> Option<f64> {
        let p = origin + dir * t;
        self.terrain.height_at(p.truncate()).map(|h| p.z - h)
    }

    /// The march's step `(before, at)` where the ray first comes down to the surface (`before` = `at` if it starts
    /// there): it is above it at `before` and not at `at`.
    fn bracket(&self, origin: DVec3, dir: DVec3, t_max: f64) -> Option<(f64, f64)> {
        let (t0, t1) = self.span(origin, dir)?;
        let t1 = t1.min(t_max);
        if !(t0 <= t1) {
            return None;
        }
        if self.above(origin, dir, t0)? <= 0.0 {
            return Some((t0, t0));
        }
        let horizontal = dir.truncate().length().max(0.05);
        let step = MARCH_STEP * self.terrain.cell / horizontal;
        // `Some(None)`: the march left the grid
        self.march(origin, dir, (t0, t1), step, |t, next| {
            match self.above(origin, dir, next) {
                None => Some(None),
                Some(d) => (d <= 0.0).then_some(Some((t, next))),
            }
        })
        .flatten()
    }

    /// The part `[t0, t1]` of the ray inside the terrain's box (its XY extent, below its highest point).
    fn span(&self, origin: DVec3, dir: DVec3) -> Option<(f64, f64)> {
        let (lo, hi) = self.terrain.bbox();
        let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
        for (o, d, a, b) in [(origin.x, dir.x, lo.x, hi.x), (origin.y, dir.y, lo.y, hi.y)] {
            if d.abs() < 1e-12 {
                if o < a || o > b {
                    return None;
                }
                continue;
            }
            let (ta, tb) = ((a - o) / d, (b - o) / d);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        if dir.z.abs() > 1e-12 {
            let t_top = (self.top - origin.z) / dir.z;
            if dir.z > 0.0 {
                t1 = t1.min(t_top);
            } else {
                t0 = t0.max(t_top);
            }
        } else if origin.z > self.top {
            return None;
        }
        // a hair inside the box, so that the heights there are defined
        let pad = 1e-9 * (1.0 + t1.abs().min(1e12));
        (t0 + pad <= t1 - pad).then_some((t0 + pad, t1 - pad))
    }

    /// The terrain's visible silhouette in image column `x`: the image `y` of the highest ray of the column that
    /// meets the terrain (searched between `y_min` and `y_max`), and the point it grazes; `None` if no ray of the
    /// column between them meets the terrain. If the ray at `y_max` already meets it, that is returned.
    pub fn column_silhouette(
        &self,
        camera: &Camera,
        x: f64,
        y_min: f64,
        y_max: f64,
    ) -> Option<(f64, DVec3)> {
        let cast = |y: f64| {
            self.hit(camera.eye, camera.ray(DVec2::new(x, y)))
                .map(|(_, p)| p)
        };
        if let Some(p) = cast(y_max) {
            return Some((y_max, p));
        }
        // a lower ray of the column passes below a higher one everywhere, so once one meets the terrain every
        // lower one does: step down to the first hit, then bisect the step
        let row = (y_max - y_min) / COLUMN_ROWS as f64;
        let (mut miss, mut hit) = (y_max, None);
        for k in 1..=COLUMN_ROWS {
            let y = y_max - row * k as f64;
            if let Some(p) = cast(y) {
                hit = Some((y, p));
                break;
            }
            miss = y;
        }
        let (mut lo, mut point) = hit?;
        for _ in 0..COLUMN_REFINEMENT {
            let mid = 0.5 * (lo + miss);
            match cast(mid) {
                Some(p) => {
                    lo = mid;
                    point = p;
                }
                None => miss = mid,
            }
        }
        Some((lo, point))
    }

    /// The highest ray of image column `x`, at or above `y`, that meets the terrain nearer than `max_depth` (along
    /// the camera's forward axis), and the point it grazes; `None` if the ray at `y` meets nothing that near. The
    /// search steps up from `y` by doubling steps, then bisects: a few dozen rays, each marched no farther than
    /// `max_depth`.
    pub fn silhouette_above(
        &self,
        camera: &Camera,
        x: f64,
        y: f64,
        max_depth: f64,
    ) -> Option<(f64, DVec3)> {
        let cast = |y: f64| {
            let dir = camera.ray(DVec2::new(x, y));
            let t_max = max_depth / dir.dot(camera.forward).max(1e-9);
            self.hit_within(camera.eye, dir, t_max).map(|(_, p)| p)
        };
        let mut point = cast(y)?;
        let (mut lo, mut step) = (y, ABOVE_FIRST_STEP);
        let mut hi = loop {
            let next = lo + step;
            match cast(next) {
                Some(p) if step < 1.0 => {
                    lo = next;
                    point = p;
                    step *= 2.0;
                }
                Some(p) => return Some((next, p)),
                None => break next,
            }
        };
        for _ in 0..ABOVE_REFINEMENT {
            let mid = 0.5 * (lo + hi);
            match cast(mid) {
                Some(p) => {
                    lo = mid;
                    point = p;
                }
                None => hi = mid,
            }
        }
        Some((lo, point))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(slope: f64) -> Heightfield {
        let n = 101;
        let heights = (0..n * n)
            .map(|k| (slope * (k / n) as f64) as f32)
            .collect();
        Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("a valid grid")
    }

    /// What the eye sees over a rough terrain is what a march a tenth as long per step, with no leap over any
    /// block, sees: the leaps skip no ground, and the hits are placed where the fine march places them.
    #[test]
    fn the_camera_sees_over_rough_ground_what_a_fine_march_sees() {
        let terrain = crate::exemplar::rough_terrain(2.0 * 127.0, 2.0, 5);
        let ground = |x: f64, y: f64| {
            let p = DVec2::new(x, y) * 254.0;
            p.extend(terrain.height_at(p).expect("on the terrain"))
        };
        let eye = ground(0.1, 0.1) + DVec3::Z * 12.0;
        let camera = Camera::looking_at(eye, ground(0.8, 0.7), 60.0, 1.5).expect("a camera");
        let sight = Sight::new(&terrain);
        let fine = |dir: DVec3| {
            let step = 0.05 * terrain.cell / dir.truncate().length().max(0.05);
            let mut t = 0.0;
            while t < 1e4 {
                let p = eye + dir * t;
                match terrain.height_at(p.truncate()) {
                    Some(h) if p.z <= h => return Some(t),
                    None if t > 0.0 => return None,
                    _ => t += step,
                }
            }
            None
        };
        let (mut rays, mut hits, mut disagree) = (0, 0, 0);
        for i in 0..60 {
            for j in 0..40 {
                let dir = camera.ray(DVec2::new((i as f64 + 0.5) / 60.0, (j as f64 + 0.5) / 40.0));
                let ours = sight.hit(eye, dir).map(|(t, _)| t);
                rays += 1;
                hits += usize::from(ours.is_some());
                // the fine march places a hit within its step after the surface
                let agree = match (ours, fine(dir)) {
                    (Some(a), Some(b)) => (a - b).abs() <= 0.1 * terrain.cell,
                    (None, None) => true,
                    _ => false,
                };
                disagree += usize::from(!agree);
                assert_eq!(
                    sight.blocked_within(eye, dir, f64::INFINITY),
                    ours.is_some(),
                    "ray {i}, {j}"
                );
            }
        }
        assert!(
            hits > rays / 3 && hits < rays,
            "{hits} of {rays} rays meet the ground"
        );
        // a half-cell march may miss what grazes a crest by less than its step: a few rays in a thousand
        assert!(
            disagree * 200 <= rays,
            "{disagree} of {rays} rays differ from the fine march"
        );
    }

    #[test]
    fn projection_and_rays_agree() {
        let cam = Camera::looking_at(
            DVec3::new(0.0, -50.0, 10.0),
            DVec3::new(20.0, 50.0, 0.0),
            60.0,
            1.5,
        )
        .expect("a camera");
        let p = DVec3::new(10.0, 30.0, 3.0);
        let (image, depth) = cam.project(p).expect("in front");
        let dir = cam.ray(image);
        let back = cam.eye + dir * (depth / dir.dot(cam.forward));
        assert!(back.distance(p) < 1e-9, "{back} vs {p}");
        assert!(
            cam.project(DVec3::new(0.0, -60.0, 10.0)).is_none(),
            "behind the eye"
        );
        let centre = cam
            .project(cam.eye + cam.forward * 7.0)
            .expect("in front")
            .0;
        assert!(centre.distance(DVec2::splat(0.5)) < 1e-12);
    }

    #[test]
    fn a_ray_meets_a_slope_where_the_plane_equation_says() {
        let terrain = plane(0.2);
        let sight = Sight::new(&terrain);
        let origin = DVec3::new(50.0, -10.0, 15.0);
        let dir = DVec3::new(0.0, 1.0, -0.1).normalize();
        let (_, p) = sight.hit(origin, dir).expect("a hit");
        // z = 15 - 0.1 (y + 10) and z = 0.2 y: y = 14 / 0.3
        assert!((p.y - 14.0 / 0.3).abs() < 1e-3, "{p}");
        assert!((p.z - 0.2 * p.y).abs() < 1e-3);
        assert!(
            sight
                .hit(origin, DVec3::new(0.0, 1.0, 0.3).normalize())
                .is_none(),
            "rising above the top"
        );
        assert!(
            sight.hit(origin, DVec3::new(0.0, -1.0, 0.0)).is_none(),
            "away from the terrain"
        );
    }

    #[test]
    fn the_column_silhouette_of_a_ridge_is_its_crest() {
        // a ridge along X at y = 60, 30 m high, on flat ground
        let n = 121;
        let heights = (0..n * n)
            .map(|k| {
                let y = (k / n) as f64;
                (30.0 * (-((y - 60.0) / 8.0).powi(2)).exp()) as f32
            })
            .collect();
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("a valid grid");
        let sight = Sight::new(&terrain);
        let cam = Camera::looking_at(
            DVec3::new(60.0, -40.0, 5.0),
            DVec3::new(60.0, 60.0, 5.0),
            50.0,
            1.0,
        )
        .expect("a camera");
        let (y, p) = sight
            .column_silhouette(&cam, 0.5, 0.0, 1.0)
            .expect("the ridge is seen");
        // the grazing point is the crest seen from the eye: the tangent from the eye touches the ridge's near side
        let (image, _) = cam.project(p).expect("in front");
        assert!((image.y - y).abs() < 1e-4, "{} vs {y}", image.y);
        assert!(p.y > 45.0 && p.y <= 60.5 && p.z > 20.0, "{p}");
        // nothing in the column above the crest meets the terrain
        assert!(sight
            .hit(cam.eye, cam.ray(DVec2::new(0.5, y + 0.01)))
            .is_none());
    }
}

//! The terrain's visible silhouettes from the camera: the edges of the triangulated grid between a front and a
//! back face that the eye sees, linked into curves (see the parent module for the readings).

use super::chains::chains;
use super::{polyline_length, FeatureOptions};
use crate::error::Result;
use crate::sketch::{Camera, Feature, FeatureKind, Sight};
use crate::terrain::Heightfield;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// How far above a sample (in cells) the visibility test aims: above the surface, not into it.
const AIM_ABOVE: f64 = 1e-3;

/// The terrain's visible silhouette curves seen from `camera`, each a polyline of grid samples in order along it.
pub fn silhouettes(
    sight: &Sight,
    camera: &Camera,
    options: &FeatureOptions,
) -> Result<Vec<Feature>> {
    options.check()?;
    super::check_terrain(sight.terrain)?;
    if !(camera.eye.is_finite() && camera.forward.is_finite() && camera.right.is_finite()) {
        return Err(crate::error::Error::invalid("camera", "is not finite"));
    }
    let mesh = Mesh::new(sight, camera);
    let (nx, ny) = (mesh.t.nx, mesh.t.ny);
    let facing: Vec<Vec<[bool; 2]>> = (0..ny - 1)
        .into_par_iter()
        .map(|j| (0..nx - 1).map(|i| mesh.facing(i, j)).collect())
        .collect();
    let candidates: Vec<(u32, u32)> = (0..ny)
        .into_par_iter()
        .map(|j| mesh.row_edges(j, &facing, options.frustum_margin))
        .collect::<Vec<_>>()
        .concat();
    // an edge is seen when both its ends are, so that every point of a curve is: one ray per sample
    let mut ends: Vec<u32> = candidates.iter().flat_map(|&(a, b)| [a, b]).collect();
    ends.sort_unstable();
    ends.dedup();
    let seen: Vec<bool> = ends
        .par_iter()
        .map(|&v| mesh.seen(mesh.vertex(v) + DVec3::Z * (AIM_ABOVE * mesh.t.cell)))
        .collect();
    let is_seen = |v: u32| ends.binary_search(&v).is_ok_and(|k| seen[k]);
    let edges: Vec<(u32, u32)> = candidates
        .into_iter()
        .filter(|&(a, b)| is_seen(a) && is_seen(b))
        .collect();
    let min_length = options.min_silhouette_length * mesh.t.cell;
    Ok(chains(&edges)
        .into_iter()
        .map(|line| Feature {
            kind: FeatureKind::Silhouette,
            points: line.iter().map(|&v| mesh.vertex(v)).collect(),
        })
        .filter(|f| f.points.len() >= 2 && polyline_length(&f.points) >= min_length)
        .collect())
}

/// The triangulated grid seen from the eye. Cell `(i, j)` is split along its diagonal from `(i, j)` to
/// `(i + 1, j + 1)` into the lower face `(i, j), (i + 1, j), (i + 1, j + 1)` and the upper face
/// `(i, j), (i + 1, j + 1), (i, j + 1)`, both counter-clockwise from above.
struct Mesh<'a> {
    t: &'a Heightfield,
    camera: &'a Camera,
    /// The terrain as the eye sees it, for the visibility test.
    sight: &'a Sight<'a>,
}

impl<'a> Mesh<'a> {
    fn new(sight: &'a Sight<'a>, camera: &'a Camera) -> Mesh<'a> {
        Mesh {
            t: sight.terrain,
            camera,
            sight,
        }
    }

    fn h(&self, i: usize, j: usize) -> f64 {
        self.t.heights[j * self.t.nx + i] as f64
    }

    fn point(&self, i: usize, j: usize) -> DVec3 {
        let xy = self.t.origin + DVec2::new(i as f64, j as f64) * self.t.cell;
        xy.extend(self.h(i, j))
    }

    fn vertex(&self, v: u32) -> DVec3 {
        let v = v as usize;
        self.point(v % self.t.nx, v / self.t.nx)
    }

    fn id(&self, i: usize, j: usize) -> u32 {
        (j * self.t.nx + i) as u32
    }

    /// Whether the lower and the upper face of cell `(i, j)` face the eye (the eye above their plane).
    fn facing(&self, i: usize, j: usize) -> [bool; 2] {
        let (a, b, c, d) = (
            self.h(i, j),
            self.h(i + 1, j),
            self.h(i + 1, j + 1),
            self.h(i, j + 1),
        );
        let to_eye = self.camera.eye - self.point(i, j);
        let cell = self.t.cell;
        [
            DVec3::new(a - b, b - c, cell).dot(to_eye) > 0.0,
            DVec3::new(d - c, a - d, cell).dot(to_eye) > 0.0,
        ]
    }

    /// The visible silhouette edges starting on grid row `j`: the horizontal ones along it, and the vertical and
    /// diagonal ones up to row `j + 1`.
    fn row_edges(&self, j: usize, facing: &[Vec<[bool; 2]>], margin: f64) -> Vec<(u32, u32)> {
        let (nx, ny) = (self.t.nx, self.t.ny);
        let mut out = Vec::new();
        // each edge: its ends, then (facing, third vertex) of its two faces
        let mut test = |p: (usize, usize), q: (usize, usize), f: [(bool, (usize, usize)); 2]| {
            if f[0].0 == f[1].0 {
                return;
            }
            let front = if f[0].0 { f[0].1 } else { f[1].1 };
            if self.is_silhouette(p, q, front, margin) {
                out.push((self.id(p.0, p.1), self.id(q.0, q.1)));
            }
        };
        for i in 0..nx {
            if i + 1 < nx && j >= 1 && j + 1 < ny {
                // horizontal: the lower face of the cell above, the upper face of the cell below
                test(
                    (i, j),
                    (i + 1, j),
                    [
                        (facing[j][i][0], (i + 1, j + 1)),
                        (facing[j - 1][i][1], (i, j - 1)),
                    ],
                );
            }
            if j + 1 < ny && i >= 1 && i + 1 < nx {
                // vertical: the upper face of the cell to the right, the lower face of the cell to the left
                test(
                    (i, j),
                    (i, j + 1),
                    [
                        (facing[j][i][1], (i + 1, j + 1)),
                        (facing[j][i - 1][0], (i - 1, j)),
                    ],
                );
            }
            if j + 1 < ny && i + 1 < nx {
                // the diagonal between the cell's two faces
                test(
                    (i, j),
                    (i + 1, j + 1),
                    [(facing[j][i][0], (i + 1, j)), (facing[j][i][1], (i, j + 1))],
                );
            }
        }
        out
    }

    /// Whether the edge `p q` between a front and a back face, with `front` the third vertex of its front face,
    /// may be a visible silhouette: the front face on the eye's side (the back face behind the edge, not a hidden
    /// fold in front of it) and the midpoint in the frame. Whether the eye sees it is tested on its ends.
    fn is_silhouette(
        &self,
        p: (usize, usize),
        q: (usize, usize),
        front: (usize, usize),
        margin: f64,
    ) -> bool {
        let (a, b, f) = (
            self.point(p.0, p.1),
            self.point(q.0, q.1),
            self.point(front.0, front.1),
        );
        let along = (b - a).truncate();
        let side_eye = along.perp_dot(self.camera.eye.truncate() - a.truncate());
        let side_front = along.perp_dot(f.truncate() - a.truncate());
        if !(side_eye * side_front > 0.0) {
            return false;
        }
        let mid = 0.5 * (a + b);
        let Some((image, _)) = self.camera.project(mid) else {
            return false;
        };
        image.x >= -margin
            && image.x <= 1.0 + margin
            && image.y >= -margin
            && image.y <= 1.0 + margin
    }

    /// Whether the segment from the eye to `target` stays above the terrain's bilinear surface, up to one cell
    /// (of horizontal travel) before `target`.
    fn seen(&self, target: DVec3) -> bool {
        let eye = self.camera.eye;
        let d = target - eye;
        let horizontal = d.truncate().length();
        if horizontal <= self.t.cell {
            return true;
        }
        let length = d.length();
        let reach = length * (1.0 - self.t.cell / horizontal);
        !self.sight.blocked_within(eye, d / length, reach)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two ridges along X on flat ground: a near one at y = 60 (20 m) and a far one at y = 110, 15 m high at its
    /// ends and 40 m in its middle (x = 80), seen from (80, −30, 8) looking north.
    fn two_ridges() -> (Heightfield, Camera) {
        let n = 161;
        let heights = (0..n * n)
            .map(|k| {
                let (x, y) = ((k % n) as f64, (k / n) as f64);
                let near = 20.0 * (-((y - 60.0) / 8.0).powi(2)).exp();
                let top = 15.0 + 25.0 * (-((x - 80.0) / 25.0).powi(2)).exp();
                let far = top * (-((y - 110.0) / 8.0).powi(2)).exp();
                near.max(far) as f32
            })
            .collect();
        let terrain = Heightfield::new(DVec2::ZERO, 1.0, n, n, heights).expect("a valid grid");
        let camera = Camera::looking_at(
            DVec3::new(80.0, -30.0, 8.0),
            DVec3::new(80.0, 100.0, 10.0),
            60.0,
            1.5,
        )
        .expect("a camera");
        (terrain, camera)
    }

    #[test]
    fn both_ridges_show_their_crests_where_they_are_seen() {
        let (terrain, camera) = two_ridges();
        let sight = Sight::new(&terrain);
        let found = silhouettes(&sight, &camera, &FeatureOptions::default()).expect("valid");
        let points: Vec<DVec3> = found
            .iter()
            .flat_map(|f| f.points.iter().copied())
            .collect();
        // every silhouette lies on a crest's near side: the eye is lower than both tops
        let near: Vec<&DVec3> = points
            .iter()
            .filter(|p| (p.y - 60.0).abs() <= 6.0)
            .collect();
        let far: Vec<&DVec3> = points
            .iter()
            .filter(|p| (p.y - 110.0).abs() <= 6.0)
            .collect();
        assert_eq!(near.len() + far.len(), points.len(), "{found:?}");
        assert!(
            near.len() >= 100 && far.len() >= 20,
            "{} {}",
            near.len(),
            far.len()
        );
        // the far ridge rises above the near one only within about 22 m of its middle
        assert!(far.iter().all(|p| (p.x - 80.0).abs() < 25.0), "{far:?}");
        assert!(far.iter().any(|p| (p.x - 80.0).abs() < 2.0));
        // none is hidden: the ray from the eye meets the terrain no earlier than a cell before it
        for p in &points {
            let target = *p + DVec3::Z * 1e-3;
            let (dir, distance) = (
                (target - camera.eye).normalize(),
                target.distance(camera.eye),
            );
            let slack = 1.5 / dir.truncate().length();
            if let Some((t, _)) = sight.hit(camera.eye, dir) {
                assert!(t >= distance - slack, "{p} hidden at {t} of {distance}");
            }
        }
        // the topmost silhouette of each image column is the terrain's visible outline there
        let projected: Vec<Vec<DVec2>> = found
            .iter()
            .map(|f| {
                f.points
                    .iter()
                    .filter_map(|&p| camera.project(p))
                    .map(|(i, _)| i)
                    .collect()
            })
            .collect();
        let (mut columns, mut covered, mut agree) = (0, 0, 0);
        for k in 5..=95 {
            let x = k as f64 / 100.0;
            let Some((top, _)) = sight.column_silhouette(&camera, x, 0.0, 1.0) else {
                continue;
            };
            columns += 1;
            let highest = projected
                .iter()
                .flat_map(|l| l.windows(2))
                .filter(|w| (w[0].x - x) * (w[1].x - x) <= 0.0 && w[0].x != w[1].x)
                .map(|w| w[0].y + (w[1].y - w[0].y) * (x - w[0].x) / (w[1].x - w[0].x))
                .fold(f64::NEG_INFINITY, f64::max);
            if highest.is_finite() {
                covered += 1;
                // within a thousandth of the frame but where the far ridge comes out from behind the near one:
                // there its first edge, whose end is hidden, is left out (a cell, 0.6 % of the frame away)
                assert!(
                    (highest - top).abs() < 0.01,
                    "column {x}: {highest} vs {top}"
                );
                agree += usize::from((highest - top).abs() < 0.001);
            }
        }
        assert!(columns >= 80 && covered == columns, "{covered}/{columns}");
        assert!(agree + 2 >= columns, "{agree}/{columns}");
    }

    #[test]
    fn nothing_outside_the_frame_and_nothing_from_behind() {
        let (terrain, _) = two_ridges();
        let sight = Sight::new(&terrain);
        // looking away from the terrain, then at it from high above
        let away = Camera::looking_at(
            DVec3::new(80.0, -30.0, 8.0),
            DVec3::new(80.0, -100.0, 8.0),
            60.0,
            1.5,
        )
        .expect("a camera");
        let options = FeatureOptions::default();
        assert!(silhouettes(&sight, &away, &options)
            .expect("valid")
            .is_empty());
        let above = Camera::looking_at(
            DVec3::new(80.0, 80.0, 500.0),
            DVec3::new(80.0, 81.0, 0.0),
            40.0,
            1.0,
        )
        .expect("a camera");
        // from straight above no face turns its back: no silhouette
        assert!(silhouettes(&sight, &above, &options)
            .expect("valid")
            .is_empty());
    }
}

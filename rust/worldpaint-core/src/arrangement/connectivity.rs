//! The reference arrangement's connectivity (seed §4): "we extract the connectivity by Delaunay triangulation … we
//! remove skewed triangles which have angles greater than 2/3π and we keep only edges which are a part of at least one
//! un-skewed triangle … We do not use elements around the boundary of the reference arrangement, since they do not have
//! enough neighborhood elements." The user "can flip an edge by clicking it" (Fig. 3): [`ReferenceArrangement::flip`].
//!
//! Readings: a triangle is skewed when its largest angle is over 2π/3; an element is a *boundary* element when the
//! kept triangles around it do not close a full fan (it lies on the hull, or next to a removed triangle).

use glam::DVec2;
use spade::{DelaunayTriangulation, Point2, Triangulation};

use super::lattice::Lattice;
use super::Element;
use crate::error::{Error, Result};

/// The largest angle a kept triangle may have (seed §4: 2π/3).
pub(crate) const MAX_TRIANGLE_ANGLE: f64 = 2.0 * std::f64::consts::FRAC_PI_3;

/// The most elements a reference arrangement may hold (it is placed by hand: a few hundred at most in practice).
pub(crate) const MAX_REFERENCE_ELEMENTS: usize = 100_000;

/// A reference arrangement analysed into its connectivity: each element's ring of neighbours, counter-clockwise.
#[derive(Clone, Debug)]
pub struct ReferenceArrangement {
    elements: Vec<Element>,
    /// Kept (un-skewed) triangles, counter-clockwise.
    triangles: Vec<[usize; 3]>,
    rings: Vec<Vec<usize>>,
    boundary: Vec<bool>,
    shortest_edge: f64,
    mean_edge: f64,
    longest_edge: f64,
    lattice: Option<Lattice>,
}

impl ReferenceArrangement {
    /// Analyses `elements` (each element's index is its *sub-id*): Delaunay triangulation, skewed triangles removed,
    /// rings and boundary flags. Errors on fewer than 3 elements, a non-finite value, two elements at one place, or
    /// a reference whose every element lies on its boundary (nothing to grow from).
    pub fn new(elements: Vec<Element>) -> Result<ReferenceArrangement> {
        if elements.len() < 3 {
            return Err(Error::invalid(
                "reference arrangement",
                format!("needs at least 3 elements, got {}", elements.len()),
            ));
        }
        crate::error::check::at_most_items(
            "reference arrangement",
            elements.len(),
            MAX_REFERENCE_ELEMENTS,
        )?;
        for (i, e) in elements.iter().enumerate() {
            if !(e.position.is_finite() && e.rotation.is_finite() && e.scale.is_finite()) {
                return Err(Error::invalid(
                    "reference arrangement",
                    format!(
                        "element {i} has a non-finite position, rotation or scale ({}, {}, {}, {})",
                        e.position.x, e.position.y, e.rotation, e.scale
                    ),
                ));
            }
        }
        let mut tri: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
        for (i, e) in elements.iter().enumerate() {
            tri.insert(Point2::new(e.position.x, e.position.y))
                .map_err(|err| {
                    Error::invalid(
                        "reference arrangement",
                        format!("element {i} cannot be triangulated: {err:?}"),
                    )
                })?;
            if tri.num_vertices() != i + 1 {
                return Err(Error::invalid(
                    "reference arrangement",
                    format!("element {i} lies at the same place as an earlier element"),
                ));
            }
        }
        let mut triangles = Vec::new();
        for face in tri.inner_faces() {
            let v = face.vertices().map(|v| v.fix().index());
            let p = v.map(|i| elements[i].position);
            if largest_angle(p) <= MAX_TRIANGLE_ANGLE {
                triangles.push(counter_clockwise(v, p));
            }
        }
        let mut reference = ReferenceArrangement {
            elements,
            triangles,
            rings: Vec::new(),
            boundary: Vec::new(),
            shortest_edge: 0.0,
            mean_edge: 0.0,
            longest_edge: 0.0,
            lattice: None,
        };
        reference.rebuild()?;
        Ok(reference)
    }

    /// Flips the edge between elements `a` and `b` (seed Fig. 3): the two kept triangles that share it become the two
    /// triangles on the other diagonal of their quadrilateral. Errors if `a`–`b` is not an edge between two kept
    /// triangles, or if the quadrilateral is not convex (the flipped edge would cross others).
    pub fn flip(&mut self, a: usize, b: usize) -> Result<()> {
        let n = self.elements.len();
        if a >= n || b >= n || a == b {
            return Err(Error::invalid(
                "edge flip",
                format!(
                    "elements {a} and {b} are not two elements of the reference ({n} elements)"
                ),
            ));
        }
        let sharing: Vec<usize> = (0..self.triangles.len())
            .filter(|&t| self.triangles[t].contains(&a) && self.triangles[t].contains(&b))
            .collect();
        let [t0, t1] = sharing[..] else {
            return Err(Error::invalid(
                "edge flip",
                format!("{a}–{b} is not an edge shared by two kept triangles"),
            ));
        };
        let other = |t: usize| {
            self.triangles[t]
                .iter()
                .copied()
                .find(|&v| v != a && v != b)
                .unwrap_or(a)
        };
        let (c, d) = (other(t0), other(t1));
        let p = |i: usize| self.elements[i].position;
        if !segments_cross(p(a), p(b), p(c), p(d)) {
            return Err(Error::invalid(
                "edge flip",
                format!("the quadrilateral around {a}–{b} is not convex: {c}–{d} would cross other edges"),
            ));
        }
        let new0 = [c, d, a];
        let new1 = [d, c, b];
        self.triangles[t0] = counter_clockwise(new0, new0.map(p));
        self.triangles[t1] = counter_clockwise(new1, new1.map(p));
        self.rebuild()
    }

    /// Rings, boundary flags and edge lengths from the kept triangles.
    fn rebuild(&mut self) -> Result<()> {
        let n = self.elements.len();
        let mut rings: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut fans = vec![0usize; n];
        for t in &self.triangles {
            for k in 0..3 {
                let (i, j) = (t[k], t[(k + 1) % 3]);
                if !rings[i].contains(&j) {
                    rings[i].push(j);
                }
                if !rings[j].contains(&i) {
                    rings[j].push(i);
                }
                fans[t[k]] += 1;
            }
        }
        let mut lengths = Vec::new();
        for (i, ring) in rings.iter_mut().enumerate() {
            let c = self.elements[i].position;
            ring.sort_by(|&x, &y| {
                let ax = (self.elements[x].position - c).to_angle();
                let ay = (self.elements[y].position - c).to_angle();
                ax.total_cmp(&ay).then(x.cmp(&y))
            });
            for &j in ring.iter().filter(|&&j| j > i) {
                lengths.push(self.elements[j].position.distance(c));
            }
        }
        // Interior: the kept triangles around an element close a fan, one triangle per consecutive ring pair.
        let boundary: Vec<bool> = (0..n)
            .map(|i| {
                let ring = &rings[i];
                ring.len() < 3
                    || fans[i] != ring.len()
                    || (0..ring.len()).any(|k| {
                        let (x, y) = (ring[k], ring[(k + 1) % ring.len()]);
                        !self.has_triangle(i, x, y)
                    })
            })
            .collect();
        if boundary.iter().all(|&b| b) {
            return Err(Error::invalid(
                "reference arrangement",
                format!(
                    "every one of its {n} elements lies on its boundary ({} triangles kept of angle at most 2π/3): \
                     place more elements around the middle",
                    self.triangles.len()
                ),
            ));
        }
        self.shortest_edge = lengths.iter().copied().fold(f64::INFINITY, f64::min);
        self.mean_edge = lengths.iter().sum::<f64>() / lengths.len().max(1) as f64;
        self.longest_edge = lengths.iter().copied().fold(0.0, f64::max);
        let offsets: Vec<DVec2> = (0..n)
            .filter(|&i| !boundary[i])
            .flat_map(|i| {
                let p = self.elements[i].position;
                rings[i].iter().map(move |&j| (j, p))
            })
            .map(|(j, p)| self.elements[j].position - p)
            .collect();
        self.lattice = Lattice::estimate(&offsets, self.shortest_edge);
        self.rings = rings;
        self.boundary = boundary;
        Ok(())
    }

    fn has_triangle(&self, i: usize, x: usize, y: usize) -> bool {
        self.triangles
            .iter()
            .any(|t| t.contains(&i) && t.contains(&x) && t.contains(&y))
    }

    /// The elements, indexed by sub-id.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Element `i`'s neighbours, counter-clockwise by angle from the +x axis.
    pub fn ring(&self, i: usize) -> &[usize] {
        &self.rings[i]
    }

    /// Whether element `i` lies on the reference's boundary (not used as a reference in growth).
    pub fn is_boundary(&self, i: usize) -> bool {
        self.boundary[i]
    }

    /// The kept triangles, counter-clockwise.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// The edges of the connectivity, each once as `(i, j)` with `i < j`, in order.
    pub fn edges(&self) -> Vec<(usize, usize)> {
        let mut edges = Vec::new();
        for (i, ring) in self.rings.iter().enumerate() {
            edges.extend(ring.iter().filter(|&&j| j > i).map(|&j| (i, j)));
        }
        edges
    }

    /// The lattice the reference was placed on, when it is near-regular (see `super::lattice`).
    pub fn lattice(&self) -> Option<&Lattice> {
        self.lattice.as_ref()
    }

    /// The shortest edge of the connectivity (m).
    pub fn shortest_edge(&self) -> f64 {
        self.shortest_edge
    }

    /// The mean edge length `l` of the connectivity (m).
    pub fn mean_edge(&self) -> f64 {
        self.mean_edge
    }

    /// The longest edge of the connectivity (m).
    pub fn longest_edge(&self) -> f64 {
        self.longest_edge
    }

    /// r_short: half the shortest reference edge (seed §5.4); no two grown elements are closer.
    pub fn r_short(&self) -> f64 {
        0.5 * self.shortest_edge
    }
}

/// The largest interior angle of a triangle.
pub(crate) fn largest_angle(p: [DVec2; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            a.angle_to(b).abs()
        })
        .fold(0.0, f64::max)
}

fn counter_clockwise(v: [usize; 3], p: [DVec2; 3]) -> [usize; 3] {
    if (p[1] - p[0]).perp_dot(p[2] - p[0]) >= 0.0 {
        v
    } else {
        [v[0], v[2], v[1]]
    }
}

/// Whether the open segments `a`–`b` and `c`–`d` cross (touching at an end point does not count).
pub(crate) fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let o1 = (b - a).perp_dot(c - a);
    let o2 = (b - a).perp_dot(d - a);
    let o3 = (d - c).perp_dot(a - c);
    let o4 = (d - c).perp_dot(b - c);
    o1 * o2 < 0.0 && o3 * o4 < 0.0
}

//! Houses on slopes by an open shape grammar: thesis section 3.4 (Emilien 2014), "Geometry Generation".
//!
//! As in 3.4.2, the floors and the roof come first, from the footprint, then the façade elements (doors and
//! windows) by an *open shape grammar* (3.4.1): a grammar whose rules depend on external constraints, here the
//! terrain line along each wall and the openings already built. Algorithm 2 states such a rule in words: while an
//! untried parameter set `λ` is left in the ordered list `Λ`, try to build `B(λ)`; `B(λ)` checks the external
//! constraints of `λ`, and if they hold it creates the element and the rule succeeds; otherwise that attempt
//! fails and the next `λ` is tried; when `Λ` is exhausted the rule falls back to `C`.
//!
//! Two adaptations give the ordered parameter sets (in the `grammar` submodule):
//! * *position*: an element starts at its most plausible place (a window centred in its bay with its sill on the
//!   storey's floor line; the door centred on the front wall of the ground storey) and, while invalid, moves over
//!   a lattice of the wall surface in order of the cost `c(p) + K(dx, dy)` kept in a priority queue, `K` favouring
//!   horizontal moves (Fig. 3.13), until a position is valid or 400 positions failed;
//! * *shape*: when every position fails, the next shape of a priority list is tried (tall window, square window,
//!   small high window, half window; door, narrow door, low door), and when none fits the bay stays plain wall
//!   (Algorithm 3).
//!
//! The door rule tries, in order, the front wall and then the side and back walls, and on each wall the storeys
//! from the lowest: on a slope its lowest storey may be buried on the uphill side and the door moves up a storey
//! or round the corner (Fig. 3.12, 3.17). A door reachable by a few steps is preferred to one high above the
//! terrain; steps are built under a door that stands above the terrain.
//!
//! Levels: the ground floor is the median of the terrain heights at the four corners plus a plinth, so the house
//! is neither perched on its lowest corner nor buried under its highest; it is raised further only where the
//! terrain would otherwise come within 1.2 m of the eaves (a low house across a steep slope). Uphill the terrain
//! cuts into the walls, which the grammar adapts to; downhill a foundation reaches from the floor to below the
//! lowest terrain along the walls. The mesh is made of closed solids (foundation, one prism per storey, roof and
//! attic, steps), each wound counter-clockwise seen from outside, plus one quad per opening standing
//! 3 cm in front of its wall.
//!
//! A footprint that is not a convex quad with sides of 0.5–500 m and corners of at least 15°, a storey height
//! outside 1–20 m, or a terrain that is not finite around the house give an empty mesh and report. Clockwise
//! corners are taken in the other order, the front side kept.

mod geometry;
mod grammar;

pub(crate) use grammar::Ground;

use crate::geom::polygon_signed_area;
use crate::village::encyclopedia::{BuildingKind, RoofStyle};
use crate::village::{HouseFootprint, HouseMaterial, HouseMesh};
use geometry::{block, offset, roof, MeshBuilder, RoofParams};
use glam::DVec2;
use grammar::{Rect, Shape, Site, Wall};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Ground floor above the median terrain height at the corners (m).
const PLINTH: f64 = 0.2;
/// Height of wall (m) the terrain leaves clear at every corner, below the eaves: the floor is raised above the
/// median where a short house on a steep slope would otherwise be buried to its roof.
const CLEAR_WALL: f64 = 1.2;
/// The foundation stands out of the walls by this much (m).
const PLINTH_OUTSET: f64 = 0.05;
/// The foundation and steps go this far below the lowest terrain they stand on (m), so no gap shows.
const FOUNDATION_DEPTH: f64 = 0.15;
/// Spacing of the terrain samples along the foundation outline (m).
const FOUNDATION_SAMPLE: f64 = 0.25;
/// A footprint with a shorter side (m) or a sharper corner (degrees) is degenerate; one with a longer side (m) is
/// no house (and would cost terrain samples in proportion).
const MIN_SIDE: f64 = 0.5;
const MAX_SIDE: f64 = 500.0;
const MIN_CORNER_DEGREES: f64 = 15.0;
/// Storeys and storey heights (m) a house is built with, at most and at least.
const MAX_STOREYS: u32 = 24;
const STOREY_HEIGHT: [f64; 2] = [1.0, 20.0];
/// Length of wall given to one room (bay), roughly (m).
const BAY: f64 = 4.0;
/// Openings keep this far from the corners of the house and from the ends of their bay (m).
const CORNER_MARGIN: f64 = 0.4;
const BAY_MARGIN: f64 = 0.15;
/// Lowest sill of a window, and free wall kept above windows and doors, under the next floor (m).
const MIN_SILL: f64 = 0.3;
const LINTEL: f64 = 0.25;
const DOOR_LINTEL: f64 = 0.2;
/// A door whose sill stands higher than this above the terrain (m) is tried only when no lower one fits.
const DOOR_REACH: f64 = 1.0;
/// Steps: built below a sill higher than `STAIR_FROM` above the terrain; rise, run, widening on each side (m).
const STAIR_FROM: f64 = 0.3;
const RISE: f64 = 0.18;
const RUN: f64 = 0.3;
const STAIR_SIDE: f64 = 0.15;
const MAX_STEPS: usize = 16;
/// Order in which the door rule tries the walls: front, the two sides, back.
const DOOR_WALLS: [usize; 4] = [0, 1, 3, 2];

/// What the grammar built on a house.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct HouseReport {
    /// Doors built.
    pub doors: usize,
    /// Windows built.
    pub windows: usize,
    /// Elements placed away from their first position (a door on another wall or storey counts).
    pub moved: usize,
    /// Elements built with a fallback shape of their priority list.
    pub reshaped: usize,
    /// Rooms: the bays of every wall of every storey.
    pub rooms: usize,
    /// Rooms left with neither a door nor a window.
    pub rooms_without_opening: usize,
}

/// Door or window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum OpeningKind {
    /// A door (material [`HouseMaterial::Door`]).
    Door,
    /// A window (material [`HouseMaterial::Window`]).
    Window,
}

/// One façade element as the grammar placed it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedOpening {
    /// Door or window.
    pub kind: OpeningKind,
    /// The footprint side `corners[wall]..corners[wall + 1]` it is on (0: the front).
    pub wall: usize,
    /// The storey it is on (0: the ground storey).
    pub storey: u32,
    /// The bay (room) of the wall it opens, counted from `corners[wall]`; for a door, the bay of its centre.
    pub bay: usize,
    /// Name of the shape built (e.g. "tall window", "narrow door").
    pub shape: &'static str,
    /// Built with a fallback shape.
    pub reshaped: bool,
    /// Placed away from its first position.
    pub moved: bool,
    /// First position of the shape built: centre along the wall from `corners[wall]`, and sill above the storey
    /// floor (m).
    pub first: DVec2,
    /// Where it went, in the same terms as `first` (m).
    pub at: DVec2,
    /// Width of the shape built (m).
    pub width: f64,
    /// Height of the shape built (m).
    pub height: f64,
}

/// The house of `kind` on `footprint`: floors and roof first, then doors and windows by the open shape grammar,
/// against the ground `ground(xy) -> z`.
pub fn build_house(
    footprint: &HouseFootprint,
    kind: &BuildingKind,
    storeys: u32,
    ground: &Ground,
    seed: u64,
) -> (HouseMesh, HouseReport) {
    let (mesh, report, _) = house_layout(footprint, kind, storeys, ground, seed);
    (mesh, report)
}

/// Openings (door/window faces) with any vertex below the ground line on their wall (the geometric check a user
/// would make on the mesh).
pub fn openings_below_ground(mesh: &HouseMesh, ground: &Ground) -> usize {
    mesh.faces
        .iter()
        .zip(&mesh.materials)
        .filter(|(_, m)| matches!(m, HouseMaterial::Door | HouseMaterial::Window))
        .filter(|(face, _)| {
            face.iter().any(|&i| {
                mesh.vertices
                    .get(i as usize)
                    .is_some_and(|v| v[2] < ground(DVec2::new(v[0], v[1])))
            })
        })
        .count()
}

/// What is drawn per house: the roof's pitch and overhang, and the priority lists of shapes.
struct Style {
    roof: RoofParams,
    windows: Vec<Shape>,
    doors: Vec<Shape>,
}

impl Style {
    fn draw(kind: &BuildingKind, rng: &mut ChaCha8Rng) -> Style {
        let (pitch_degrees, overhang) = match kind.roof {
            RoofStyle::Gable => (rng.random_range(30.0..42.0), rng.random_range(0.3..0.5)),
            RoofStyle::Hip => (rng.random_range(25.0..35.0), rng.random_range(0.3..0.5)),
            RoofStyle::Flat => (0.0, 0.08),
        };
        let roof = RoofParams {
            style: kind.roof,
            pitch: f64::to_radians(pitch_degrees).tan(),
            overhang,
            thickness: 0.15,
        };
        // Window heights follow the storey height; widths stay those of a house.
        let s = (kind.storey_height / 2.8).clamp(0.85, 2.0);
        let shape = |name, width, height: f64, sill: f64| Shape {
            name,
            width,
            height: height * s,
            sill: sill * s,
        };
        // The fallbacks keep the lintel line of the first shape: they rise as they shrink, away from the ground.
        let small = shape("small high window", 0.6, 0.6, 1.6);
        let half = shape("half window", 0.9, 0.4, 1.8);
        let windows = if rng.random_bool(0.7) {
            vec![
                shape("tall window", 0.9, 1.3, 0.9),
                shape("square window", 0.8, 0.8, 1.4),
                small,
                half,
            ]
        } else {
            let lower = |w: Shape| Shape {
                sill: w.sill - 0.4 * s,
                ..w
            };
            vec![
                shape("square window", 0.8, 0.8, 1.0),
                lower(small),
                lower(half),
            ]
        };
        let door = |name, width, height| Shape {
            name,
            width,
            height,
            sill: 0.0,
        };
        let mut doors = vec![
            door("door", 1.0, 2.1),
            door("narrow door", 0.85, 1.95),
            door("low door", 0.75, 1.7),
        ];
        if kind.religious {
            doors.insert(0, door("portal", 1.6, 2.8));
        }
        Style {
            roof,
            windows,
            doors,
        }
    }
}

/// The footprint counter-clockwise with its front side first, or `None` when it is not a proper convex quad.
fn normalized(c: &[DVec2; 4]) -> Option<[DVec2; 4]> {
    if c.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let area = polygon_signed_area(c);
    let f = if area > 0.0 {
        *c
    } else if area < 0.0 {
        // Reversed, the front side keeps its two corners.
        [c[1], c[0], c[3], c[2]]
    } else {
        return None;
    };
    let max_turn = (180.0 - MIN_CORNER_DEGREES).to_radians();
    for i in 0..4 {
        let e0 = f[i] - f[(i + 3) % 4];
        let e1 = f[(i + 1) % 4] - f[i];
        let turn = e0.perp_dot(e1).atan2(e0.dot(e1));
        let side = e1.length();
        if !(MIN_SIDE..=MAX_SIDE).contains(&side) || !(turn > 0.0 && turn <= max_turn) {
            return None;
        }
    }
    Some(f)
}

/// The number of bays (rooms) of a wall.
fn bays(len: f64) -> usize {
    ((len / BAY).round() as usize).max(1)
}

/// [`build_house`], with the list of doors and windows as placed.
pub fn house_layout(
    footprint: &HouseFootprint,
    kind: &BuildingKind,
    storeys: u32,
    ground: &Ground,
    seed: u64,
) -> (HouseMesh, HouseReport, Vec<PlacedOpening>) {
    let empty = || {
        (
            HouseMesh {
                seed: footprint.seed,
                ..HouseMesh::default()
            },
            HouseReport::default(),
            Vec::new(),
        )
    };
    let h = kind.storey_height;
    if !(STOREY_HEIGHT[0]..=STOREY_HEIGHT[1]).contains(&h) {
        return empty();
    }
    let Some(f) = normalized(&footprint.corners) else {
        return empty();
    };
    let n = storeys.clamp(1, MAX_STOREYS);
    let mut corner_ground = f.map(ground);
    if corner_ground.iter().any(|g| !g.is_finite()) {
        return empty();
    }
    corner_ground.sort_by(f64::total_cmp);
    let median = 0.5 * (corner_ground[1] + corner_ground[2]);
    let base = (median + PLINTH).max(corner_ground[3] - (n as f64 * h - CLEAR_WALL));
    let Some(walls) = (0..4)
        .map(|i| Wall::new(f[i], f[(i + 1) % 4], ground))
        .collect::<Option<Vec<Wall>>>()
    else {
        return empty();
    };
    let plinth = offset(&f, PLINTH_OUTSET);
    let Some(low) = lowest_along(&plinth, ground) else {
        return empty();
    };

    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let style = Style::draw(kind, &mut rng);
    let floor = |k: u32| base + k as f64 * h;

    // Floors and roof.
    let mut b = MeshBuilder::default();
    b.prism(
        &plinth,
        low.min(base) - FOUNDATION_DEPTH,
        base,
        HouseMaterial::Foundation,
    );
    for k in 0..n {
        b.prism(&f, floor(k), floor(k + 1), HouseMaterial::Wall);
    }
    roof(&mut b, &f, floor(n), &style.roof);

    // Façade elements: the door, then the windows, each wall of each storey knowing what is already on it.
    let slot = |w: usize, k: u32| w * n as usize + k as usize;
    let mut placed: Vec<Vec<Rect>> = vec![Vec::new(); 4 * n as usize];
    let mut openings: Vec<PlacedOpening> = Vec::new();
    if let Some(door) = place_door(&walls, ground, &floor, h, n, &style.doors, &placed) {
        let r = Rect::of(&style.doors[door.shape], door.at);
        placed[slot(door.wall, door.storey)].push(r);
        if let Some(lowest) = stairs(&mut b, &walls[door.wall], ground, &r, floor(door.storey)) {
            // Keep the windows of the storeys below out from behind the steps.
            for k in 0..door.storey {
                placed[slot(door.wall, k)].push(Rect {
                    u0: r.u0 - STAIR_SIDE,
                    u1: r.u1 + STAIR_SIDE,
                    v0: lowest - floor(k),
                    v1: h,
                });
            }
        }
        openings.push(door.opening(&walls, &style.doors));
    }
    let mut report = HouseReport::default();
    let storeys = Storeys {
        n,
        height: h,
        floor: &floor,
    };
    place_windows(
        &walls,
        ground,
        &storeys,
        &style.windows,
        &mut placed,
        &mut openings,
        &mut report,
    );
    open_faces(&mut b, &walls, &floor, &openings, &mut report);
    (b.finish(footprint.seed), report, openings)
}

/// The storeys of a house: how many, their height, and the height of each one's floor.
struct Storeys<'a> {
    n: u32,
    height: f64,
    floor: &'a dyn Fn(u32) -> f64,
}

/// A window in each bay of each wall of each storey where one fits beside what is already placed (the door, its
/// steps); counts the rooms, and those left with no opening.
fn place_windows(
    walls: &[Wall],
    ground: &Ground,
    storeys: &Storeys,
    windows: &[Shape],
    placed: &mut [Vec<Rect>],
    openings: &mut Vec<PlacedOpening>,
    report: &mut HouseReport,
) {
    let (n, floor) = (storeys.n, storeys.floor);
    for k in 0..n {
        for (w, wall) in walls.iter().enumerate() {
            let nb = bays(wall.len);
            let bay_len = wall.len / nb as f64;
            for j in 0..nb {
                let (s0, s1) = (j as f64 * bay_len, (j + 1) as f64 * bay_len);
                let site = Site {
                    wall,
                    ground,
                    floor: floor(k),
                    placed: &placed[w * n as usize + k as usize],
                    u_lo: (s0 + BAY_MARGIN).max(CORNER_MARGIN),
                    u_hi: (s1 - BAY_MARGIN).min(wall.len - CORNER_MARGIN),
                    v_lo: MIN_SILL,
                    v_hi: storeys.height - LINTEL,
                    vertical: true,
                    reach: None,
                };
                let window = site.place(windows, 0.5 * (s0 + s1));
                let has_door = openings.iter().any(|o| {
                    o.kind == OpeningKind::Door && o.wall == w && o.storey == k && o.bay == j
                });
                report.rooms += 1;
                match window {
                    Some(p) => {
                        let s = &windows[p.shape];
                        placed[w * n as usize + k as usize].push(Rect::of(s, p.at));
                        openings.push(PlacedOpening {
                            kind: OpeningKind::Window,
                            wall: w,
                            storey: k,
                            bay: j,
                            shape: s.name,
                            reshaped: p.shape > 0,
                            moved: p.at != p.first,
                            first: p.first,
                            at: p.at,
                            width: s.width,
                            height: s.height,
                        });
                    }
                    None if !has_door => report.rooms_without_opening += 1,
                    None => {}
                }
            }
        }
    }
}

/// The doors' and windows' faces on their walls, counted in the report.
fn open_faces(
    b: &mut MeshBuilder,
    walls: &[Wall],
    floor: &dyn Fn(u32) -> f64,
    openings: &[PlacedOpening],
    report: &mut HouseReport,
) {
    for o in openings {
        let wall = &walls[o.wall];
        let z = floor(o.storey);
        let p = |u: f64, v: f64| wall.at(u).extend(z + v);
        let (u0, u1) = (o.at.x - 0.5 * o.width, o.at.x + 0.5 * o.width);
        let (v0, v1) = (o.at.y, o.at.y + o.height);
        let material = match o.kind {
            OpeningKind::Door => HouseMaterial::Door,
            OpeningKind::Window => HouseMaterial::Window,
        };
        b.face(&[p(u0, v0), p(u1, v0), p(u1, v1), p(u0, v1)], material);
        match o.kind {
            OpeningKind::Door => report.doors += 1,
            OpeningKind::Window => report.windows += 1,
        }
        report.moved += usize::from(o.moved);
        report.reshaped += usize::from(o.reshaped);
    }
}

/// The lowest terrain along the closed outline `poly`, or `None` where the terrain is not finite.
fn lowest_along(poly: &[DVec2], ground: &Ground) -> Option<f64> {
    let mut low = f64::INFINITY;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let steps = ((a.distance(b) / FOUNDATION_SAMPLE).ceil() as usize).max(1);
        for i in 0..steps {
            let g = ground(a.lerp(b, i as f64 / steps as f64));
            if !g.is_finite() {
                return None;
            }
            low = low.min(g);
        }
    }
    Some(low)
}

/// The door as the grammar placed it.
struct Door {
    wall: usize,
    storey: u32,
    shape: usize,
    first: DVec2,
    at: DVec2,
}

impl Door {
    fn opening(&self, walls: &[Wall], shapes: &[Shape]) -> PlacedOpening {
        let s = &shapes[self.shape];
        let len = walls[self.wall].len;
        let nb = bays(len);
        PlacedOpening {
            kind: OpeningKind::Door,
            wall: self.wall,
            storey: self.storey,
            bay: ((self.at.x / (len / nb as f64)) as usize).min(nb - 1),
            shape: s.name,
            reshaped: self.shape > 0,
            // Its first position is the middle of the front wall on the ground storey.
            moved: self.wall != DOOR_WALLS[0] || self.storey != 0 || self.at != self.first,
            first: self.first,
            at: self.at,
            width: s.width,
            height: s.height,
        }
    }
}

/// The door rule: walls in the order of [`DOOR_WALLS`], storeys from the lowest, shapes in priority order, each
/// by position adaptation along the storey's floor line from the middle of the wall. A door within reach of the
/// terrain is looked for first, then any door clear of the terrain.
fn place_door(
    walls: &[Wall],
    ground: &Ground,
    floor: &dyn Fn(u32) -> f64,
    h: f64,
    n: u32,
    shapes: &[Shape],
    placed: &[Vec<Rect>],
) -> Option<Door> {
    for reach in [Some(DOOR_REACH), None] {
        for w in DOOR_WALLS {
            let wall = &walls[w];
            for k in 0..n {
                let site = Site {
                    wall,
                    ground,
                    floor: floor(k),
                    placed: &placed[w * n as usize + k as usize],
                    u_lo: CORNER_MARGIN,
                    u_hi: wall.len - CORNER_MARGIN,
                    v_lo: 0.0,
                    v_hi: h - DOOR_LINTEL,
                    vertical: false,
                    reach,
                };
                if let Some(p) = site.place(shapes, 0.5 * wall.len) {
                    return Some(Door {
                        wall: w,
                        storey: k,
                        shape: p.shape,
                        first: p.first,
                        at: p.at,
                    });
                }
            }
        }
    }
    None
}

/// Steps down from the sill of the door `r` of the storey at `floor` to the terrain in front of it; returns the
/// lowest tread height when steps were built.
fn stairs(b: &mut MeshBuilder, wall: &Wall, ground: &Ground, r: &Rect, floor: f64) -> Option<f64> {
    let sill = floor + r.v0;
    let centre = ground(wall.at(0.5 * (r.u0 + r.u1)));
    if !(sill - centre >= STAIR_FROM) {
        return None;
    }
    let (u0, u1) = (r.u0 - STAIR_SIDE, r.u1 + STAIR_SIDE);
    let mut lowest = None;
    for i in 0..MAX_STEPS {
        let tread = sill - (i + 1) as f64 * RISE;
        let (d0, d1) = (i as f64 * RUN, (i + 1) as f64 * RUN);
        let p = |u: f64, d: f64| wall.a + wall.dir * u + wall.normal * d;
        // Counter-clockwise: the wall runs along `dir` with the outside on its right.
        let corners = [p(u0, d0), p(u0, d1), p(u1, d1), p(u1, d0)];
        let g = corners.map(ground);
        let middle = ground(p(0.5 * (u0 + u1), 0.5 * (d0 + d1)));
        // Down until the steps meet the terrain under their middle; across a slope one end of a tread may sink
        // into it, as steps do.
        if g.iter().any(|z| !z.is_finite()) || !(tread > middle + 0.05) {
            break;
        }
        let lo = g.iter().fold(f64::INFINITY, |lo, &z| lo.min(z));
        block(b, &corners, lo - FOUNDATION_DEPTH, tread);
        lowest = Some(lo - FOUNDATION_DEPTH);
    }
    lowest
}

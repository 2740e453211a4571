//! Element arrangement by example (Ijiri et al. 2008): a pattern grown from a small hand-placed lattice keeps the
//! lattice's rings, edge lengths and edge directions, never crowds two elements, and relaxes towards the reference.
//! Run with `--nocapture` to see the figures.

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use worldpaint_core::{
    grow_arrangement, relax_arrangement, Arrangement, Element, GrowthOptions, ReferenceArrangement,
    Region, RotationMode,
};

const SIDE: usize = 7;
const JITTER: f64 = 0.03;

fn lattice(hexagonal: bool, seed: u64) -> Vec<Element> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut elements = Vec::new();
    for row in 0..SIDE {
        for col in 0..SIDE {
            let (x, y) = if hexagonal {
                (
                    col as f64 + 0.5 * (row % 2) as f64,
                    row as f64 * 3f64.sqrt() / 2.0,
                )
            } else {
                (col as f64, row as f64)
            };
            let jitter = DVec2::new(
                rng.random_range(-JITTER..JITTER),
                rng.random_range(-JITTER..JITTER),
            );
            elements.push(Element {
                position: DVec2::new(x, y) + jitter,
                symbol: 0,
                rotation: 0.0,
                scale: 1.0,
            });
        }
    }
    elements
}

const BINS: usize = 12;

/// Relaxation during growth, every this many elements.
const RELAX_EVERY: usize = 50;

/// Edge directions modulo π, in 15° bins centred on multiples of 15°.
fn angle_histogram(edges: &[(usize, usize)], position: impl Fn(usize) -> DVec2) -> Vec<f64> {
    let mut hist = [0.0; BINS];
    let width = std::f64::consts::PI / BINS as f64;
    for &(a, b) in edges {
        let d = position(b) - position(a);
        let angle = (d.y.atan2(d.x) + 0.5 * width).rem_euclid(std::f64::consts::PI);
        hist[((angle / width) as usize).min(BINS - 1)] += 1.0;
    }
    let total: f64 = hist.iter().sum();
    hist.iter().map(|h| h / total.max(1.0)).collect()
}

fn mean_length(edges: &[(usize, usize)], position: impl Fn(usize) -> DVec2) -> f64 {
    edges
        .iter()
        .map(|&(a, b)| position(a).distance(position(b)))
        .sum::<f64>()
        / edges.len() as f64
}

struct Figures {
    ring_fraction: f64,
    interior: usize,
    length_ratio: f64,
    angle_tv: f64,
    closest: f64,
}

fn figures(reference: &ReferenceArrangement, grown: &Arrangement) -> Figures {
    let neighbours = grown.neighbours();
    let origin = grown.elements[0].position;
    let reach = grown
        .elements
        .iter()
        .map(|e| e.position.distance(origin))
        .fold(0.0, f64::max);
    let interior: Vec<usize> = (0..grown.elements.len())
        .filter(|&i| grown.elements[i].position.distance(origin) < 0.8 * reach)
        .collect();
    let same = interior
        .iter()
        .filter(|&&i| neighbours[i].len() == reference.ring(grown.sub_ids[i]).len())
        .count();
    let ref_edges = reference.edges();
    let ref_pos = |i: usize| reference.elements()[i].position;
    let pos = |i: usize| grown.elements[i].position;
    let (h_ref, h_grown) = (
        angle_histogram(&ref_edges, ref_pos),
        angle_histogram(&grown.edges, pos),
    );
    let angle_tv = 0.5
        * h_ref
            .iter()
            .zip(&h_grown)
            .map(|(a, b)| (a - b).abs())
            .sum::<f64>();
    let mut closest = f64::INFINITY;
    for i in 0..grown.elements.len() {
        for j in i + 1..grown.elements.len() {
            closest = closest.min(pos(i).distance(pos(j)));
        }
    }
    Figures {
        ring_fraction: same as f64 / interior.len().max(1) as f64,
        interior: interior.len(),
        length_ratio: mean_length(&grown.edges, pos) / mean_length(&ref_edges, ref_pos),
        angle_tv,
        closest,
    }
}

/// The lattice's connectivity as a user leaves it: on the square lattice, whose Delaunay diagonals fall either way
/// with the jitter, every diagonal flipped to run the same way (seed Fig. 3).
fn reference_of(hexagonal: bool) -> ReferenceArrangement {
    let mut reference =
        ReferenceArrangement::new(lattice(hexagonal, 7)).expect("a lattice is a valid reference");
    if !hexagonal {
        let backward: Vec<(usize, usize)> = reference
            .edges()
            .into_iter()
            .filter(|&(a, b)| b - a == SIDE - 1 && a % SIDE != 0)
            .collect();
        for (a, b) in backward {
            reference.flip(a, b).expect("a diagonal flips");
        }
    }
    reference
}

fn grown_from(
    reference: ReferenceArrangement,
    rotation: RotationMode,
) -> (ReferenceArrangement, Arrangement) {
    grown_with(reference, rotation, RELAX_EVERY)
}

fn grown_with(
    reference: ReferenceArrangement,
    rotation: RotationMode,
    relax_every: usize,
) -> (ReferenceArrangement, Arrangement) {
    let region = Region::Rect {
        min: DVec2::splat(-100.0),
        max: DVec2::splat(100.0),
    };
    let options = GrowthOptions {
        rotation,
        max_elements: 2_000,
        seed: 11,
        relax_every,
        ..GrowthOptions::default()
    };
    let grown = grow_arrangement(&reference, &region, DVec2::ZERO, &options).expect("growth runs");
    (reference, grown)
}

fn grown_lattice(hexagonal: bool, rotation: RotationMode) -> (ReferenceArrangement, Arrangement) {
    grown_from(reference_of(hexagonal), rotation)
}

fn check_lattice(name: &str, hexagonal: bool) {
    let (reference, mut grown) = grown_lattice(hexagonal, RotationMode::None);
    assert_eq!(
        grown.elements.len(),
        2_000,
        "{name}: the pattern reaches 2,000 elements"
    );
    let f = figures(&reference, &grown);
    println!(
        "{name}: {} elements, {} interior; same ring size as their reference element {:.1} %; mean edge length \
         ratio {:.4}; edge-angle TV {:.3}; closest pair {:.3} (r_short {:.3})",
        grown.elements.len(),
        f.interior,
        100.0 * f.ring_fraction,
        f.length_ratio,
        f.angle_tv,
        f.closest,
        reference.r_short()
    );
    assert!(f.ring_fraction >= 0.95, "{name}: ring sizes kept");
    assert!(
        (f.length_ratio - 1.0).abs() <= 0.03,
        "{name}: mean edge length kept"
    );
    assert!(f.angle_tv <= 0.1, "{name}: edge directions kept");
    assert!(
        f.closest >= reference.r_short(),
        "{name}: no two elements closer than r_short"
    );

    let relaxation = relax_arrangement(&mut grown).expect("relaxation solves");
    println!(
        "{name}: a last relaxation, eq. (5) error {:.4} -> {:.4} m² (factor {:.3}), {} elements fixed",
        relaxation.error_before,
        relaxation.error_after,
        relaxation.error_before / relaxation.error_after.max(1e-300),
        relaxation.fixed
    );
    // grown on the lattice the reference was placed on, every ring already holds its reference offsets
    assert!(
        relaxation.error_before <= 1e-9 * grown.elements.len() as f64,
        "{name}: nothing left to relax"
    );
    assert!(
        relaxation.error_after <= relaxation.error_before + 1e-9,
        "{name}: relaxation does not raise the error"
    );
}

#[test]
fn a_square_lattice_grows_into_a_square_lattice() {
    let automatic =
        ReferenceArrangement::new(lattice(false, 7)).expect("a lattice is a valid reference");
    let (automatic, grown) = grown_from(automatic, RotationMode::None);
    let f = figures(&automatic, &grown);
    println!(
        "square lattice, Delaunay diagonals as they fall (no flips): same ring size {:.1} %; mean edge length \
         ratio {:.4}; edge-angle TV {:.3}",
        100.0 * f.ring_fraction,
        f.length_ratio,
        f.angle_tv
    );
    check_lattice("square lattice", false);
}

#[test]
fn a_hexagonal_lattice_grows_into_a_hexagonal_lattice() {
    check_lattice("hexagonal lattice", true);
}

#[test]
fn relaxation_lowers_the_ring_error_of_a_pattern_grown_without_it() {
    // an irregular reference (a lattice's rings all agree, and there is nothing to relax): a Poisson-disk scatter
    for seed in [3, 5] {
        let square = Region::Rect {
            min: DVec2::ZERO,
            max: DVec2::splat(8.0),
        };
        let points = worldpaint_core::hard_core_points(&square, 1.0, 0.75, seed);
        let reference = ReferenceArrangement::new(
            points
                .iter()
                .map(|&position| Element {
                    position,
                    symbol: 0,
                    rotation: 0.0,
                    scale: 1.0,
                })
                .collect(),
        )
        .expect("a valid reference");
        let (_, mut grown) = grown_with(reference, RotationMode::None, 0);
        let first = grown.elements[0].position;
        let relaxation = relax_arrangement(&mut grown).expect("relaxation solves");
        let factor = relaxation.error_before / relaxation.error_after.max(1e-300);
        println!(
            "irregular reference {seed} grown without relaxation: eq. (5) error {:.3} -> {:.3} m², lowered by a \
             factor {factor:.2}",
            relaxation.error_before, relaxation.error_after
        );
        assert!(
            factor > 1.3,
            "relaxation lowers the error by a quarter or more"
        );
        assert_eq!(
            grown.elements[0].position, first,
            "the initial element stays"
        );
    }
}

#[test]
fn growth_stops_at_the_region_and_relaxation_keeps_its_edge_fixed() {
    let reference = ReferenceArrangement::new(lattice(true, 3)).expect("valid reference");
    let region = Region::Circle {
        center: DVec2::ZERO,
        radius: 6.0,
    };
    let options = GrowthOptions {
        max_elements: 2_000,
        ..GrowthOptions::default()
    };
    let mut grown =
        grow_arrangement(&reference, &region, DVec2::ZERO, &options).expect("growth runs");
    let outside = grown
        .elements
        .iter()
        .filter(|e| !region.contains(e.position))
        .count();
    let at_edge = grown.at_region_boundary.iter().filter(|&&b| b).count();
    println!(
        "disc of radius 6: {} elements, {outside} outside, {at_edge} stopped by the region",
        grown.elements.len()
    );
    assert_eq!(outside, 0);
    assert!(grown.elements.len() > 100 && grown.elements.len() < 2_000);
    assert!(at_edge > 10);
    let before = grown.clone();
    relax_arrangement(&mut grown).expect("relaxation solves");
    for i in 0..grown.elements.len() {
        if i == 0 || grown.at_region_boundary[i] {
            assert_eq!(grown.elements[i].position, before.elements[i].position);
        }
    }
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(|| {
            let (reference, mut grown) = grown_lattice(true, RotationMode::BestFit);
            let f = figures(&reference, &grown);
            println!(
                "hexagonal lattice, best-fit rotation, {threads} thread(s): same ring size {:.1} %; mean edge \
                 length ratio {:.4}; edge-angle TV {:.3}",
                100.0 * f.ring_fraction,
                f.length_ratio,
                f.angle_tv
            );
            assert!(f.ring_fraction >= 0.95 && (f.length_ratio - 1.0).abs() <= 0.03 && f.angle_tv <= 0.1);
            relax_arrangement(&mut grown).expect("relaxation solves");
            grown
                .elements
                .iter()
                .map(|e| {
                    (
                        e.position.x.to_bits(),
                        e.position.y.to_bits(),
                        e.rotation.to_bits(),
                    )
                })
                .collect::<Vec<_>>()
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn an_edge_flip_swaps_the_diagonal_of_two_triangles() {
    let mut reference = ReferenceArrangement::new(lattice(false, 5)).expect("valid reference");
    let (a, b) = reference
        .edges()
        .into_iter()
        .find(|&(a, b)| {
            let d = reference.elements()[a].position - reference.elements()[b].position;
            d.length() > 1.3 && !reference.is_boundary(a) && !reference.is_boundary(b)
        })
        .expect("a jittered square lattice has diagonals");
    let before = reference.edges().len();
    reference.flip(a, b).expect("a diagonal flips");
    assert!(!reference.edges().contains(&(a, b)));
    assert_eq!(reference.edges().len(), before);
    let err = reference.flip(a, b).expect_err("no longer an edge");
    println!("flip of a missing edge: {err}");
}

#[test]
fn bad_references_are_refused_with_clear_messages() {
    let element = |x: f64, y: f64| Element {
        position: DVec2::new(x, y),
        symbol: 0,
        rotation: 0.0,
        scale: 1.0,
    };
    let cases: Vec<(&str, Vec<Element>, &str)> = vec![
        ("empty", vec![], "at least 3"),
        (
            "two elements",
            vec![element(0.0, 0.0), element(1.0, 0.0)],
            "at least 3",
        ),
        (
            "NaN",
            vec![element(0.0, 0.0), element(1.0, 0.0), element(f64::NAN, 1.0)],
            "non-finite",
        ),
        (
            "duplicate",
            vec![element(0.0, 0.0), element(1.0, 0.0), element(0.0, 0.0)],
            "same place",
        ),
        (
            "flat",
            (0..6)
                .map(|i| element(i as f64, 0.01 * (i * i) as f64))
                .collect(),
            "boundary",
        ),
    ];
    for (name, elements, words) in cases {
        let err = ReferenceArrangement::new(elements).expect_err(name);
        println!("{name}: {err}");
        assert!(err.to_string().contains(words), "{name}: {err}");
    }
    let reference = ReferenceArrangement::new(lattice(false, 1)).expect("valid reference");
    let region = Region::Circle {
        center: DVec2::ZERO,
        radius: 5.0,
    };
    let err = grow_arrangement(
        &reference,
        &region,
        DVec2::new(9.0, 0.0),
        &GrowthOptions::default(),
    )
    .expect_err("start outside");
    println!("start outside: {err}");
    let err = grow_arrangement(
        &reference,
        &region,
        DVec2::new(f64::NAN, 0.0),
        &GrowthOptions::default(),
    )
    .expect_err("NaN start");
    println!("NaN start: {err}");
    let mut broken = Arrangement {
        elements: vec![element(0.0, 0.0)],
        ..Arrangement::default()
    };
    let err = relax_arrangement(&mut broken).expect_err("inconsistent lists");
    println!("inconsistent arrangement: {err}");
}

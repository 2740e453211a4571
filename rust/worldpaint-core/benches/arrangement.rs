//! Benchmark of element arrangement by example (Ijiri et al. 2008) against the painting tools' needs:
//!
//! * `arrangement/grow_1000`: 1,000 elements grown from a jittered hexagonal lattice with relaxation every 50
//!   elements and a last relaxation of the whole pattern (goal ≤ 50 ms; the seed reports about 5 s for 1,000
//!   elements with relaxation, under a second without);
//! * `arrangement/grow_100000`: 100,000 elements, relaxation every 50 (goal ≤ 5 s);
//! * `arrangement/spray_dab_20000`: one spray dab (a disc of radius 4 m) at the edge of a hole in a pattern of about
//!   20,000 elements: the scene's elements within the disc + 3 mean edges picked out, then `grow_around` them
//!   (goal ≤ 30 ms).
//!
//! `cargo bench -p worldpaint-core --bench arrangement`

mod timing;

use criterion::Criterion;
use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::{Duration, Instant};
use worldpaint_core::{
    grow_arrangement, grow_arrangement_around, relax_arrangement, Element, GrowthOptions,
    ReferenceArrangement, Region, RotationMode,
};

fn hexagonal_reference() -> ReferenceArrangement {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut elements = Vec::new();
    for row in 0..7 {
        for col in 0..7 {
            let p = DVec2::new(
                col as f64 + 0.5 * (row % 2) as f64,
                row as f64 * 3f64.sqrt() / 2.0,
            );
            let jitter = DVec2::new(rng.random_range(-0.03..0.03), rng.random_range(-0.03..0.03));
            elements.push(Element {
                position: p + jitter,
                symbol: 0,
                rotation: 0.0,
                scale: 1.0,
            });
        }
    }
    match ReferenceArrangement::new(elements) {
        Ok(r) => r,
        Err(e) => panic!("the benchmark reference: {e}"),
    }
}

fn options(max_elements: usize) -> GrowthOptions {
    GrowthOptions {
        rotation: RotationMode::None,
        max_elements,
        seed: 11,
        relax_every: 50,
        ..GrowthOptions::default()
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let reference = hexagonal_reference();
    let square = |half: f64| Region::Rect {
        min: DVec2::splat(-half),
        max: DVec2::splat(half),
    };

    let mut g = timing::flat_group(&mut c, "arrangement", 20, Duration::from_secs(10));
    let small = square(100.0);
    let grow_1000_s = timing::median(&mut g, "grow_1000", || {
        let t0 = Instant::now();
        let grown =
            grow_arrangement(&reference, &small, DVec2::ZERO, &options(1_000)).map(|mut a| {
                let _ = relax_arrangement(&mut a);
                a
            });
        black_box(grown.ok());
        t0.elapsed()
    });
    g.finish();

    // a pattern of about 20,000 elements around a hole of radius 6 m, and a dab at the hole's edge
    let hole = Region::Circle {
        center: DVec2::new(20.0, 0.0),
        radius: 6.0,
    };
    let holed = Region::Clipped {
        within: vec![square(66.0)],
        without: vec![hole],
    };
    let scene = match grow_arrangement(
        &reference,
        &holed,
        DVec2::ZERO,
        &options(worldpaint_core::MAX_INSTANCES as usize),
    ) {
        Ok(a) => a.elements,
        Err(e) => panic!("the benchmark pattern: {e}"),
    };
    let (center, radius) = (DVec2::new(16.0, 1.0), 4.0);
    let dab = Region::Circle { center, radius };
    let reach = radius + 3.0 * reference.mean_edge();
    let mut new_in_dab = 0;
    let mut g = timing::flat_group(&mut c, "arrangement", 30, Duration::from_secs(10));
    let dab_s = timing::median(&mut g, "spray_dab_20000", || {
        let t0 = Instant::now();
        let nearby: Vec<Element> = scene
            .iter()
            .filter(|e| e.position.distance(center) <= reach)
            .copied()
            .collect();
        let grown = grow_arrangement_around(
            &reference,
            &dab,
            &nearby,
            Some(center),
            &options(worldpaint_core::MAX_INSTANCES as usize),
            &|_| true,
        );
        let dt = t0.elapsed();
        if let Ok(a) = &grown {
            new_in_dab = a.elements.len() - nearby.len();
        }
        black_box(grown.ok());
        dt
    });
    g.finish();

    let mut g = timing::flat_group(&mut c, "arrangement", 10, Duration::from_secs(40));
    let large = square(200.0);
    let grow_100000_s = timing::median(&mut g, "grow_100000", || {
        let t0 = Instant::now();
        black_box(grow_arrangement(&reference, &large, DVec2::ZERO, &options(100_000)).ok());
        t0.elapsed()
    });
    g.finish();
    c.final_summary();

    println!();
    println!("== arrangement summary ==");
    println!(
        "1,000 elements with relaxation: {:.1} ms (goal ≤ 50 ms; the seed: about 5 s)",
        1e3 * grow_1000_s
    );
    println!(
        "100,000 elements, relaxation every 50: {:.2} s (goal ≤ 5 s)",
        grow_100000_s
    );
    println!(
        "spray dab among {} elements ({} new): {:.1} ms (goal ≤ 30 ms)",
        scene.len(),
        new_in_dab,
        1e3 * dab_s
    );
}

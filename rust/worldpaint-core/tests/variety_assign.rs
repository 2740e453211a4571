//! Painting with variants: a forest of 100,000 trees over 1 km² with a 729-variant tree shows no variant more than
//! twice inside any 50 m window, and what was painted before keeps its variants. Run with `--nocapture` for the
//! figures.

use glam::DVec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;
use worldpaint_core::assign_variants;

const SIDE: f64 = 1_000.0;
const WINDOW: f64 = 50.0;

fn forest(n: usize, seed: u64) -> Vec<DVec2> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| DVec2::new(rng.random_range(0.0..SIDE), rng.random_range(0.0..SIDE)))
        .collect()
}

/// The largest count of one variant inside a `WINDOW` square, over squares every 10 m.
fn worst_window(points: &[DVec2], variants: &[u32]) -> u32 {
    let step = 10.0;
    let mut counts: HashMap<(i64, i64, u32), u32> = HashMap::new();
    let per = (WINDOW / step) as i64;
    for (p, &v) in points.iter().zip(variants) {
        let (cx, cy) = ((p.x / step).floor() as i64, (p.y / step).floor() as i64);
        // the windows whose lower corner cell lies within `per` cells below and left
        for wx in cx - per + 1..=cx {
            for wy in cy - per + 1..=cy {
                *counts.entry((wx, wy, v)).or_default() += 1;
            }
        }
    }
    counts.values().copied().max().unwrap_or(0)
}

#[test]
fn a_forest_painted_with_729_variants_repeats_none_more_than_twice_in_a_50_m_window() {
    let points = forest(100_000, 1);
    let free = vec![None; points.len()];
    let variants = assign_variants(&points, &free, 729, WINDOW, 7).unwrap();
    let worst = worst_window(&points, &variants);
    let naive: Vec<u32> = {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        (0..points.len())
            .map(|_| rng.random_range(0..729))
            .collect()
    };
    println!(
        "100,000 trees, 729 variants: at most {worst} of one variant in a 50 m window (uniform random picks: {})",
        worst_window(&points, &naive)
    );
    assert!(worst <= 2);
    assert_eq!(
        variants,
        assign_variants(&points, &free, 729, WINDOW, 7).unwrap()
    );
}

#[test]
fn painted_instances_keep_their_variants_and_new_ones_avoid_them() {
    let points = forest(2_000, 2);
    let mut fixed = vec![None; points.len()];
    for (k, f) in fixed.iter_mut().enumerate().take(1_000) {
        *f = Some((k % 5) as u32);
    }
    let variants = assign_variants(&points, &fixed, 5_000, WINDOW, 3).unwrap();
    assert!((0..1_000).all(|k| variants[k] == (k % 5) as u32));
    assert!(
        variants[1_000..].iter().all(|&v| v >= 5),
        "new instances avoid the variants around them"
    );
    assert!(assign_variants(&points, &fixed[..3], 5, WINDOW, 3).is_err());
    assert!(assign_variants(&points, &fixed, 0, WINDOW, 3).is_err());
}

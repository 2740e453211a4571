//! Which variant each painted instance shows (issue 20's "paint with variants"): the seed makes thousands of
//! models so that "no two trees are the same"; painted, that only holds if nearby instances pick different ones.
//!
//! Reading chosen: the instances are visited in an order drawn by the seeded generator; each takes the variant
//! used least among the instances already assigned within `window` metres of it (ties: the first such variant
//! from a start drawn by the generator, so the choice is uniform among them). Instances whose variant is given
//! (already painted) keep it and count. With V variants and n instances within a window, no variant shows more
//! than ⌈n / V⌉ + 1 times in one, and none repeats until V are used.

use glam::DVec2;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashMap;

use crate::error::{check, Error, Result};
use crate::limits;

/// The variant (0..`count`) of each point: `fixed[i]` where given, else chosen as the module documentation says.
pub fn assign_variants(
    positions: &[DVec2],
    fixed: &[Option<u32>],
    count: u32,
    window: f64,
    seed: u64,
) -> Result<Vec<u32>> {
    if fixed.len() != positions.len() {
        return Err(Error::invalid(
            "variant assignment",
            format!(
                "{} points but {} given variants",
                positions.len(),
                fixed.len()
            ),
        ));
    }
    if count == 0 {
        return Err(Error::invalid(
            "variant assignment",
            "needs at least one variant",
        ));
    }
    check::positive("variant window", window)?;
    limits::check(
        "variant assignment",
        positions.len() as f64,
        limits::MAX_INSTANCES,
        "instances",
    )?;
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::invalid(format!("point {k}"), "is not finite"));
    }
    let cell_of = |p: DVec2| ((p.x / window).floor() as i64, (p.y / window).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    let mut out: Vec<Option<u32>> = fixed.iter().map(|f| f.map(|v| v % count)).collect();
    for (i, p) in positions.iter().enumerate() {
        if out[i].is_some() {
            grid.entry(cell_of(*p)).or_default().push(i);
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut order: Vec<usize> = (0..positions.len()).filter(|&i| out[i].is_none()).collect();
    order.shuffle(&mut rng);
    let mut used = vec![0u32; count as usize];
    let mut touched: Vec<u32> = Vec::new();
    for i in order {
        let p = positions[i];
        let (cx, cy) = cell_of(p);
        for gx in cx - 1..=cx + 1 {
            for gy in cy - 1..=cy + 1 {
                for &j in grid.get(&(gx, gy)).map(Vec::as_slice).unwrap_or(&[]) {
                    if positions[j].distance_squared(p) <= window * window {
                        if let Some(v) = out[j] {
                            if used[v as usize] == 0 {
                                touched.push(v);
                            }
                            used[v as usize] += 1;
                        }
                    }
                }
            }
        }
        let start = rng.random_range(0..count);
        let mut best = (u32::MAX, start);
        for k in 0..count {
            let v = (start + k) % count;
            if used[v as usize] < best.0 {
                best = (used[v as usize], v);
                if best.0 == 0 {
                    break;
                }
            }
        }
        for v in touched.drain(..) {
            used[v as usize] = 0;
        }
        out[i] = Some(best.1);
        grid.entry((cx, cy)).or_default().push(i);
    }
    Ok(out.into_iter().map(|v| v.unwrap_or(0)).collect())
}

//! The product model of eq. (1) for small counts (see "Small counts" in the module documentation of
//! [`super`]): relocations and shifts at a fixed count, accepted with `f(X')/f(X)` (times the Hastings ratio of a
//! relocation whose birth is drawn from the map-weighted intensity, see [`super::births`]).

use super::births::{birth_in, BirthIntensity};
use super::gaussian;
use super::target::{Target, FIXED_ID};
use crate::error::{Error, Result};
use crate::geom::{DVec2, PreparedRegion, RegionQueries};
use crate::spatial::GridEntry;
use rand::Rng;

/// The birth / death / shift chain of one category; returns the final points.
#[allow(clippy::too_many_arguments)]
pub(super) fn run_chain<R: Rng>(
    mut target: Target,
    region: &PreparedRegion,
    expected: f64,
    self_tag: u32,
    max_radius: f64,
    iterations_per_instance: f64,
    births: Option<&BirthIntensity>,
    rng: &mut R,
    progress: &dyn Fn(f64) -> bool,
) -> Result<Vec<DVec2>> {
    let (lo, hi) = region.bbox();
    let births = births.map(|b| b.over(lo, hi));
    let mut own: Vec<DVec2> = Vec::new();
    let insert = |target: &mut Target, own: &mut Vec<DVec2>, p: DVec2| {
        target.grid.insert(GridEntry {
            position: p,
            tag: self_tag,
            id: own.len() as u32,
        });
        own.push(p);
    };
    // the count: the expected count, rounded stochastically (see "The count" in the module documentation)
    let want = expected.floor() as usize + usize::from(rng.random::<f64>() < expected.fract());
    // start from dart throwing among allowed positions
    for _ in 0..(4 * want + 100) {
        if own.len() >= want {
            break;
        }
        let Some(p) = birth_in(region, births.as_ref(), rng) else {
            break;
        };
        if target.energy(p, FIXED_ID) > f64::NEG_INFINITY {
            insert(&mut target, &mut own, p);
        }
    }
    let total = (iterations_per_instance * expected.max(1.0)).ceil() as usize;
    let sweep = (expected.ceil() as usize).max(64);
    let shift_sigma = max_radius / 8.0;
    let mut done = 0usize;
    while done < total {
        let end = (done + sweep).min(total);
        for _ in done..end {
            if own.len() < want {
                // a hard core left the start short: keep trying allowed births
                if let Some(p) = birth_in(region, births.as_ref(), rng) {
                    if target.energy(p, FIXED_ID) > f64::NEG_INFINITY {
                        insert(&mut target, &mut own, p);
                    }
                }
                continue;
            }
            if own.is_empty() {
                break;
            }
            let k = rng.random_range(0..own.len());
            let p = own[k];
            let (q, hastings) = if rng.random::<f64>() < 0.5 {
                // relocation: the death of p and the birth of q in one move, q drawn from the map-weighted
                // intensity g (or uniformly): f(X')/f(X) · g(p)/g(q)
                match birth_in(region, births.as_ref(), rng) {
                    Some(q) => (
                        q,
                        births
                            .as_ref()
                            .map_or(0.0, |b| b.log_weight(p) - b.log_weight(q)),
                    ),
                    None => continue,
                }
            } else {
                // shift: a small Gaussian step (symmetric)
                (p + gaussian(rng) * shift_sigma, 0.0)
            };
            if !region.contains(q) {
                continue;
            }
            let e_new = target.energy(q, k as u32);
            if e_new == f64::NEG_INFINITY {
                continue;
            }
            let e_old = target.energy(p, k as u32);
            if rng.random::<f64>().ln() < e_new - e_old + hastings {
                target.grid.remove(p, k as u32);
                target.grid.insert(GridEntry {
                    position: q,
                    tag: self_tag,
                    id: k as u32,
                });
                own[k] = q;
            }
        }
        done = end;
        if !progress(done as f64 / total as f64) {
            return Err(Error::Cancelled);
        }
    }
    Ok(own)
}

//! Squares of a search grid ranked by how many points they hold, for picking the densest windows of real data.

use worldpaint_core::{DVec2, Region};

/// The squares of `side` whose corners lie on a `step` grid inside `lo..hi`, each with the number of `points` it
/// holds, most first (ties in grid order). Counted with a summed-area table of the points per cell.
pub fn squares_by_count(
    points: &[DVec2],
    lo: DVec2,
    hi: DVec2,
    side: f64,
    step: f64,
) -> Vec<(DVec2, usize)> {
    let cells = |extent: f64| (extent / step).floor().max(0.0) as usize;
    let (nx, ny) = (cells(hi.x - lo.x), cells(hi.y - lo.y));
    let k = (side / step).round() as usize;
    if nx < k || ny < k {
        return Vec::new();
    }
    let mut sat = vec![0usize; (nx + 1) * (ny + 1)];
    for p in points {
        let f = (*p - lo) / step;
        if f.x >= 0.0 && f.y >= 0.0 && (f.x as usize) < nx && (f.y as usize) < ny {
            sat[(f.y as usize + 1) * (nx + 1) + f.x as usize + 1] += 1;
        }
    }
    for j in 1..=ny {
        for i in 1..=nx {
            let at = j * (nx + 1) + i;
            sat[at] += sat[at - 1] + sat[at - nx - 1] - sat[at - nx - 2];
        }
    }
    let at = |i: usize, j: usize| sat[j * (nx + 1) + i];
    let mut squares: Vec<(DVec2, usize)> = (0..=ny - k)
        .flat_map(|j| (0..=nx - k).map(move |i| (i, j)))
        .map(|(i, j)| {
            (
                lo + DVec2::new(i as f64, j as f64) * step,
                at(i + k, j + k) + at(i, j) - at(i + k, j) - at(i, j + k),
            )
        })
        .collect();
    squares.sort_by_key(|s| std::cmp::Reverse(s.1));
    squares
}

/// The square of `side` whose lower corner is `min`.
pub fn square(min: DVec2, side: f64) -> Region {
    Region::Rect {
        min,
        max: min + DVec2::splat(side),
    }
}

/// The `points` inside `window`, in their order.
pub fn points_in(points: &[DVec2], window: &Region) -> Vec<DVec2> {
    points
        .iter()
        .copied()
        .filter(|p| window.contains(*p))
        .collect()
}

/// The mean of the `points` in the square of `side` at `min` (its own centre when it holds none): a square
/// centred there covers the village itself rather than a window of the search grid.
pub fn centre_of_points_in(points: &[DVec2], min: DVec2, side: f64) -> DVec2 {
    let window = square(min, side);
    let (sum, n) = points
        .iter()
        .filter(|p| window.contains(**p))
        .fold((DVec2::ZERO, 0.0), |(s, n), p| (s + *p, n + 1.0));
    if n > 0.0 {
        sum / n
    } else {
        min + DVec2::splat(0.5 * side)
    }
}

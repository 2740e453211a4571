//! The Laplace solver behind the diffusion: every free cell equals the mean of its 4-neighbours inside the grid
//! (zero flux across the grid's border), fixed cells keep their value.
//!
//! Multigrid in correction form: red-black Gauss-Seidel smoothing, the residual restricted by full weighting
//! (the transpose of bilinear prolongation), the error equation solved on the coarser grid with the error held at
//! 0 on coarse cells whose footprint holds a fixed fine cell, the correction prolonged bilinearly. Any grid size
//! coarsens as `n → n / 2 + 1` (coarse node `I` on fine node `2I`). The first guess comes from nested iteration
//! (the same problem solved on the coarser grids and prolonged). A coarse grid sees a one-cell constraint curve
//! as a thicker one, which alone slows plain V-cycles to a factor of about 0.5–0.7 per cycle; the V-cycle (made
//! symmetric) therefore preconditions conjugate gradients, which brings the residual down by about 10× per
//! iteration.
//!
//! Each level stores its two colours apart (cell `(i, j)` of colour `(i + j) % 2` at `[colour][j·h + i/2]`), so a
//! colour's half-sweep writes one array while reading only the other: rows update in parallel, safely, and the
//! result does not depend on the number of threads.

use rayon::prelude::*;

/// Pre- and post-smoothing sweeps per V-cycle.
const SWEEPS: usize = 2;
/// A level this small (in either direction) is the coarsest.
const COARSEST: usize = 4;
/// Fewest cells a parallel task gets: the coarse levels are small, and splitting them costs more than it saves.
const TASK_CELLS: usize = 16_384;

/// Fewest rows of `h` cells a parallel task gets.
fn rows_per_task(h: usize) -> usize {
    (TASK_CELLS / h.max(1)).max(1)
}

/// The float type of the grid hierarchy: the V-cycle is a preconditioner, so single precision (half the memory
/// traffic of the bandwidth-bound sweeps) is enough; the conjugate-gradient iteration itself runs in `f64`.
type P = f32;

/// What the row kernels need of a float type.
trait Real:
    Copy
    + Send
    + Sync
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::AddAssign
{
    const ZERO: Self;
    fn of(x: f64) -> Self;
    fn wide(self) -> f64;
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    #[inline]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline]
    fn wide(self) -> f64 {
        self as f64
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    #[inline]
    fn of(x: f64) -> Self {
        x
    }
    #[inline]
    fn wide(self) -> f64 {
        self
    }
}

/// The problem on one grid in red-black layout.
struct Level {
    nx: usize,
    ny: usize,
    /// Row stride of each colour array: (nx + 1) / 2.
    h: usize,
    free: [Vec<bool>; 2],
    /// The unknown: the displacement on the finest level, the correction on coarser ones.
    u: [Vec<P>; 2],
    /// Right-hand side (0 on the finest level).
    f: [Vec<P>; 2],
    /// Residual scratch.
    r: [Vec<P>; 2],
}

impl Level {
    fn new(nx: usize, ny: usize) -> Level {
        let h = nx.div_ceil(2);
        let zeros = || [vec![0.0; h * ny], vec![0.0; h * ny]];
        Level {
            nx,
            ny,
            h,
            free: [vec![false; h * ny], vec![false; h * ny]],
            u: zeros(),
            f: zeros(),
            r: zeros(),
        }
    }
}

/// Cells of colour `c` in row `j` of a grid `nx` wide, and the column of the first one.
#[inline]
fn row_cells(nx: usize, j: usize, c: usize) -> (usize, usize) {
    let off = (j + c) & 1;
    ((nx + 1 - off) / 2, off)
}

/// One half-sweep of Gauss-Seidel over the cells of colour `c`: each free cell becomes the mean of its
/// neighbours (plus the right-hand side over the neighbour count).
fn relax_colour(l: &mut Level, c: usize) {
    let (nx, ny, h) = (l.nx, l.ny, l.h);
    let [u0, u1] = &mut l.u;
    let (mine, other): (&mut Vec<P>, &Vec<P>) = if c == 0 { (u0, u1) } else { (u1, u0) };
    let other = other.as_slice();
    mine.par_chunks_mut(h)
        .zip(l.free[c].par_chunks(h))
        .zip(l.f[c].par_chunks(h))
        .enumerate()
        .with_min_len(rows_per_task(h))
        .for_each(|(j, ((row, free), f))| {
            let (n, off) = row_cells(nx, j, c);
            let same = &other[j * h..(j + 1) * h];
            let up = (j > 0).then(|| &other[(j - 1) * h..j * h]);
            let down = (j + 1 < ny).then(|| &other[(j + 1) * h..(j + 2) * h]);
            let (ka, kb) = interior(nx, n, off, up.is_some() && down.is_some());
            if let (Some(up), Some(down)) = (up, down) {
                // the bulk of the row: four neighbours, no branch but the fixed-cell select
                let (left, right) = (&same[ka + off - 1..kb + off - 1], &same[ka + off..kb + off]);
                for ((((((u, f), free), l), r), a), b) in row[ka..kb]
                    .iter_mut()
                    .zip(&f[ka..kb])
                    .zip(&free[ka..kb])
                    .zip(left)
                    .zip(right)
                    .zip(&up[ka..kb])
                    .zip(&down[ka..kb])
                {
                    let v = 0.25 * (l + r + a + b + f);
                    *u = if *free { v } else { *u };
                }
            }
            for k in (0..ka).chain(kb..n) {
                if free[k] {
                    let (s, d) = neighbour_sum(same, up, down, nx, k, off);
                    row[k] = (s + f[k]) / d;
                }
            }
        });
}

/// The cells `ka..kb` of a row (`n` cells of a colour, the first in column `off`) that have all four neighbours;
/// an empty range on the first and last rows (`inner` false).
#[inline]
fn interior(nx: usize, n: usize, off: usize, inner: bool) -> (usize, usize) {
    let ka = 1 - off;
    if !inner || nx < 3 {
        return (ka, ka);
    }
    // columns 1..=nx−2: 2k + off ≤ nx − 2
    let kb = ((nx - 2 - off) / 2 + 1).min(n);
    (ka, kb.max(ka))
}

/// Sum and count of the in-grid neighbours of cell `k` (column `2k + off`) of a row, read from the other colour.
#[inline]
fn neighbour_sum<T: Real>(
    same: &[T],
    up: Option<&[T]>,
    down: Option<&[T]>,
    nx: usize,
    k: usize,
    off: usize,
) -> (T, T) {
    let i = 2 * k + off;
    let (mut s, mut d) = (T::ZERO, T::ZERO);
    if i > 0 {
        s += same[k + off - 1];
        d += T::of(1.0);
    }
    if i + 1 < nx {
        s += same[k + off];
        d += T::of(1.0);
    }
    if let Some(up) = up {
        s += up[k];
        d += T::of(1.0);
    }
    if let Some(down) = down {
        s += down[k];
        d += T::of(1.0);
    }
    (s, d)
}

/// Red then black half-sweeps.
fn relax(l: &mut Level, sweeps: usize) {
    for _ in 0..sweeps {
        relax_colour(l, 0);
        relax_colour(l, 1);
    }
}

/// Black then red: the adjoint of [`relax`], so the V-cycle is symmetric (a preconditioner for conjugate
/// gradients).
fn relax_back(l: &mut Level, sweeps: usize) {
    for _ in 0..sweeps {
        relax_colour(l, 1);
        relax_colour(l, 0);
    }
}

/// Fills `r` with the residual `f + Σ neighbours − deg·u` (0 on fixed cells) and returns the largest
/// `|residual| / deg`: how far a free cell is from the mean of its neighbours.
fn residual(l: &mut Level) -> f64 {
    let Level {
        nx,
        ny,
        h,
        free,
        u,
        f,
        r,
    } = l;
    stencil(*nx, *ny, *h, free, u, Some(f), r).0
}

/// `out = f + Σ neighbours of x − deg·x` on free cells (0 elsewhere); returns the largest `|out| / deg` and
/// `Σ x·out` (summed row by row in a fixed order, the same whatever the thread count).
fn stencil<T: Real>(
    nx: usize,
    ny: usize,
    h: usize,
    free: &[Vec<bool>; 2],
    x: &[Vec<T>; 2],
    f: Option<&[Vec<T>; 2]>,
    out: &mut [Vec<T>; 2],
) -> (f64, f64) {
    let (mut worst, mut total) = (0.0f64, 0.0);
    let zeros = vec![T::ZERO; h];
    for c in 0..2 {
        let other = x[1 - c].as_slice();
        let mine = x[c].as_slice();
        let fc = f.map(|f| f[c].as_slice());
        let rows: Vec<(f64, f64)> = out[c]
            .par_chunks_mut(h)
            .zip(free[c].par_chunks(h))
            .enumerate()
            .with_min_len(rows_per_task(h))
            .map(|(j, (orow, free))| {
                let (n, off) = row_cells(nx, j, c);
                let same = &other[j * h..(j + 1) * h];
                let up = (j > 0).then(|| &other[(j - 1) * h..j * h]);
                let down = (j + 1 < ny).then(|| &other[(j + 1) * h..(j + 2) * h]);
                let xr = &mine[j * h..(j + 1) * h];
                let fr = fc.map_or(zeros.as_slice(), |f| &f[j * h..(j + 1) * h]);
                let (mut worst, mut sum) = (0.0f64, 0.0);
                let (ka, kb) = interior(nx, n, off, up.is_some() && down.is_some());
                if let (Some(up), Some(down)) = (up, down) {
                    let (left, right) =
                        (&same[ka + off - 1..kb + off - 1], &same[ka + off..kb + off]);
                    for (((((((o, f), free), x), l), r), a), b) in orow[ka..kb]
                        .iter_mut()
                        .zip(&fr[ka..kb])
                        .zip(&free[ka..kb])
                        .zip(&xr[ka..kb])
                        .zip(left)
                        .zip(right)
                        .zip(&up[ka..kb])
                        .zip(&down[ka..kb])
                    {
                        let v = *f + *l + *r + *a + *b - T::of(4.0) * *x;
                        let v = if *free { v } else { T::ZERO };
                        *o = v;
                        let (x, v) = (x.wide(), v.wide());
                        sum += x * v;
                        worst = worst.max(0.25 * v.abs());
                    }
                }
                for k in (0..ka).chain(kb..n) {
                    if !free[k] {
                        orow[k] = T::ZERO;
                        continue;
                    }
                    let (s, d) = neighbour_sum(same, up, down, nx, k, off);
                    let v = fr[k] + s - d * xr[k];
                    orow[k] = v;
                    let (v, d) = (v.wide(), d.wide());
                    sum += xr[k].wide() * v;
                    worst = worst.max(v.abs() / d);
                }
                (worst, sum)
            })
            .collect();
        for (w, sum) in rows {
            worst = worst.max(w);
            total += sum;
        }
    }
    (worst, total)
}

/// `Σ a·b` over both colours, summed row by row in a fixed order (the same whatever the thread count).
fn dot(h: usize, a: &[Vec<f64>; 2], b: &[Vec<f64>; 2]) -> f64 {
    let mut total = 0.0;
    for c in 0..2 {
        let rows: Vec<f64> = a[c]
            .par_chunks(h)
            .zip(b[c].par_chunks(h))
            .with_min_len(rows_per_task(h))
            .map(|(x, y)| x.iter().zip(y).map(|(x, y)| x * y).sum::<f64>())
            .collect();
        total += rows.iter().sum::<f64>();
    }
    total
}

/// `r += alpha·q` over both colours; returns the largest `|r| / deg` over the cells (the residual's measure: `r`
/// is 0 on fixed cells).
fn update_residual(
    nx: usize,
    ny: usize,
    h: usize,
    alpha: f64,
    q: &[Vec<f64>; 2],
    r: &mut [Vec<f64>; 2],
) -> f64 {
    let mut worst = 0.0f64;
    for c in 0..2 {
        let w = r[c]
            .par_chunks_mut(h)
            .zip(q[c].par_chunks(h))
            .enumerate()
            .with_min_len(rows_per_task(h))
            .map(|(j, (r, q))| {
                let (n, off) = row_cells(nx, j, c);
                let edge_rows = f64::from(u8::from(j == 0)) + f64::from(u8::from(j + 1 == ny));
                let mut worst = 0.0f64;
                for (k, (r, q)) in r[..n].iter_mut().zip(&q[..n]).enumerate() {
                    *r += alpha * q;
                    let i = 2 * k + off;
                    let d = 4.0
                        - edge_rows
                        - f64::from(u8::from(i == 0))
                        - f64::from(u8::from(i + 1 == nx));
                    worst = worst.max(r.abs() / d.max(1.0));
                }
                worst
            })
            .reduce(|| 0.0, f64::max);
        worst = worst.max(w);
    }
    worst
}

/// `y += alpha·x` over both colours.
fn axpy(alpha: f64, x: &[Vec<f64>; 2], y: &mut [Vec<f64>; 2]) {
    for c in 0..2 {
        y[c].par_iter_mut()
            .zip(x[c].par_iter())
            .with_min_len(TASK_CELLS)
            .for_each(|(y, x)| *y += alpha * x);
    }
}

/// Adds `w ×` row `j` of a colour-split grid `nx` wide into the row-major `out`.
fn add_row(v: &[Vec<P>; 2], h: usize, nx: usize, j: usize, w: P, out: &mut [P]) {
    // even columns are colour j % 2, odd ones the other
    let (even, odd) = (&v[j & 1][j * h..], &v[1 - (j & 1)][j * h..]);
    for (m, pair) in out[..nx].chunks_mut(2).enumerate() {
        pair[0] += w * even[m];
        if let Some(o) = pair.get_mut(1) {
            *o += w * odd[m];
        }
    }
}

/// Restricts the residual of `fine` into the right-hand side of `coarse` (weights 1/4, 1/2, 1 summing to 4: the
/// transpose of bilinear prolongation, which also carries the h² scaling of the unscaled operator) and zeroes
/// `coarse.u`.
fn restrict(fine: &Level, coarse: &mut Level) {
    let (fnx, fny, fh) = (fine.nx, fine.ny, fine.h);
    let (cnx, ch) = (coarse.nx, coarse.h);
    let [f0, f1] = &mut coarse.f;
    let [u0, u1] = &mut coarse.u;
    f0.par_chunks_mut(ch)
        .zip(f1.par_chunks_mut(ch))
        .zip(u0.par_chunks_mut(ch))
        .zip(u1.par_chunks_mut(ch))
        .enumerate()
        .with_min_len(rows_per_task(ch))
        .for_each_init(
            // one spare zero: on an even-sized fine grid the last coarse node lies one node beyond it
            || vec![0.0 as P; fnx + 1],
            |g, (jc, (((f0, f1), u0), u1))| {
                // the fine rows 2J − 1, 2J, 2J + 1 weighted 1/2, 1, 1/2
                g.fill(0.0);
                let fj = 2 * jc;
                if fj < fny {
                    add_row(&fine.r, fh, fnx, fj, 1.0, g);
                }
                if fj >= 1 && fj - 1 < fny {
                    add_row(&fine.r, fh, fnx, fj - 1, 0.5, g);
                }
                if fj + 1 < fny {
                    add_row(&fine.r, fh, fnx, fj + 1, 0.5, g);
                }
                u0.fill(0.0);
                u1.fill(0.0);
                for (c, frow) in [(0, f0), (1, f1)] {
                    let free = &coarse.free[c][jc * ch..(jc + 1) * ch];
                    let (n, off) = row_cells(cnx, jc, c);
                    for k in 0..n {
                        if !free[k] {
                            frow[k] = 0.0;
                            continue;
                        }
                        let fi = 2 * (2 * k + off);
                        let mut s = g[fi];
                        if fi >= 1 {
                            s += 0.5 * g[fi - 1];
                        }
                        if fi + 1 < fnx {
                            s += 0.5 * g[fi + 1];
                        }
                        frow[k] = s;
                    }
                }
            },
        );
}

/// Adds the bilinear prolongation of `coarse.u` to the free cells of `fine.u`.
fn prolong_add(coarse: &Level, fine: &mut Level) {
    let (fnx, fh) = (fine.nx, fine.h);
    let (cnx, ch) = (coarse.nx, coarse.h);
    let [u0, u1] = &mut fine.u;
    u0.par_chunks_mut(fh)
        .zip(u1.par_chunks_mut(fh))
        .enumerate()
        .with_min_len(rows_per_task(fh))
        .for_each_init(
            || vec![0.0 as P; cnx + 1],
            |buf, (j, (u0, u1))| {
                // the coarse correction interpolated to this row's height, row-major
                buf.fill(0.0);
                if j % 2 == 0 {
                    add_row(&coarse.u, ch, cnx, j / 2, 1.0, buf);
                } else {
                    add_row(&coarse.u, ch, cnx, j / 2, 0.5, buf);
                    add_row(&coarse.u, ch, cnx, j / 2 + 1, 0.5, buf);
                }
                for (c, urow) in [(0, u0), (1, u1)] {
                    let free = &fine.free[c][j * fh..(j + 1) * fh];
                    let (n, off) = row_cells(fnx, j, c);
                    // within a colour and row the columns 2k + off all have the parity of off
                    if off == 0 {
                        for ((u, free), e) in urow[..n].iter_mut().zip(&free[..n]).zip(&buf[..n]) {
                            if *free {
                                *u += e;
                            }
                        }
                    } else {
                        for (((u, free), a), b) in urow[..n]
                            .iter_mut()
                            .zip(&free[..n])
                            .zip(&buf[..n])
                            .zip(&buf[1..=n])
                        {
                            if *free {
                                *u += 0.5 * (a + b);
                            }
                        }
                    }
                }
            },
        );
}

/// Replaces the free cells of `fine.u` with the bilinear prolongation of `coarse.u` (nested iteration's guess).
fn prolong_replace(coarse: &Level, fine: &mut Level) {
    for c in 0..2 {
        for (u, free) in fine.u[c].iter_mut().zip(&fine.free[c]) {
            if *free {
                *u = 0.0;
            }
        }
    }
    prolong_add(coarse, fine);
}

fn vcycle(levels: &mut [Level]) {
    let Some((fine, rest)) = levels.split_first_mut() else {
        return;
    };
    if rest.is_empty() {
        solve_coarsest(fine);
        return;
    }
    relax(fine, SWEEPS);
    residual(fine);
    restrict(fine, &mut rest[0]);
    vcycle(rest);
    prolong_add(&rest[0], fine);
    relax_back(fine, SWEEPS);
}

/// Gauss-Seidel until the coarsest grid's residual stops mattering (it has at most a few hundred cells unless the
/// grid is very elongated, where the sweep count is capped and the V-cycles finish the work).
fn solve_coarsest(l: &mut Level) {
    let sweeps = (2 * (l.nx + l.ny)).clamp(10, 1000);
    relax(l, sweeps);
    relax_back(l, sweeps);
}

/// What a solve did.
pub(crate) struct Solved {
    pub u: Vec<f64>,
    pub cycles: usize,
    pub residual: f64,
}

/// The grid sizes of the hierarchy, finest first.
fn sizes(nx: usize, ny: usize) -> Vec<(usize, usize)> {
    let mut out = vec![(nx, ny)];
    let (mut x, mut y) = (nx, ny);
    while x > COARSEST && y > COARSEST {
        x = x / 2 + 1;
        y = y / 2 + 1;
        out.push((x, y));
    }
    out
}

/// The level of a row-major grid of fixed values (NaN marks a free cell).
fn level_from(nx: usize, ny: usize, fixed: &[f64]) -> Level {
    let mut l = Level::new(nx, ny);
    let h = l.h;
    for (c, (free, u)) in l.free.iter_mut().zip(l.u.iter_mut()).enumerate() {
        free.par_chunks_mut(h)
            .zip(u.par_chunks_mut(h))
            .enumerate()
            .with_min_len(rows_per_task(h))
            .for_each(|(j, (free, u))| {
                let (n, off) = row_cells(nx, j, c);
                for k in 0..n {
                    let v = fixed[j * nx + 2 * k + off];
                    free[k] = v.is_nan();
                    u[k] = if v.is_nan() { 0.0 } else { v as P };
                }
            });
    }
    l
}

/// The coarse version of a fixed-value grid: a coarse node is fixed when any fine node of its full-weighting
/// footprint is, at the mean of those fixed values (so thin constraint curves survive coarsening).
fn coarsen_fixed(nx: usize, ny: usize, fixed: &[f64], cnx: usize, cny: usize) -> Vec<f64> {
    (0..cnx * cny)
        .into_par_iter()
        .map(|k| {
            let (ci, cj) = ((k % cnx) as isize, (k / cnx) as isize);
            let (mut s, mut n) = (0.0, 0usize);
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (i, j) = (2 * ci + di, 2 * cj + dj);
                    if i < 0 || j < 0 || i >= nx as isize || j >= ny as isize {
                        continue;
                    }
                    let v = fixed[j as usize * nx + i as usize];
                    if !v.is_nan() {
                        s += v;
                        n += 1;
                    }
                }
            }
            if n > 0 {
                s / n as f64
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// Solves the Laplace equation on an `nx × ny` grid whose row-major `fixed` holds the fixed values (NaN on free
/// cells), until the largest `|mean of neighbours − value|` over free cells is at most `tolerance` or
/// `max_cycles` preconditioned conjugate-gradient steps have run.
pub(crate) fn solve(
    nx: usize,
    ny: usize,
    fixed: &[f64],
    tolerance: f64,
    max_cycles: usize,
) -> Solved {
    let mut levels = hierarchy(nx, ny, fixed);
    nested_iteration(&mut levels);
    // conjugate gradients on the error equation, preconditioned by one symmetric V-cycle: the V-cycle alone
    // slows down where coarse grids blur thin constraint curves, and the Krylov iteration takes those few modes
    let mut cg = Krylov::start(&levels[0], fixed);
    cg.run(&mut levels, tolerance, max_cycles);
    Solved {
        u: cg.row_major(),
        cycles: cg.cycles,
        residual: cg.res,
    }
}

/// The levels of the problem, finest first, each with the fixed values of its cells.
fn hierarchy(nx: usize, ny: usize, fixed: &[f64]) -> Vec<Level> {
    let dims = sizes(nx, ny);
    // the fixed values of every level, for the nested-iteration guess
    let mut coarse_fixed: Vec<Vec<f64>> = Vec::with_capacity(dims.len());
    for w in dims.windows(2) {
        let (a, b) = (w[0], w[1]);
        let prev = coarse_fixed.last().map_or(fixed, |v| v.as_slice());
        let next = coarsen_fixed(a.0, a.1, prev, b.0, b.1);
        coarse_fixed.push(next);
    }
    dims.iter()
        .zip(std::iter::once(fixed).chain(coarse_fixed.iter().map(|v| v.as_slice())))
        .map(|(&(x, y), f)| level_from(x, y, f))
        .collect()
}

/// Nested iteration: solves each level's own problem (one V-cycle below it), prolonged as the next level's
/// guess; the finest level's `u` ends up holding the guess.
fn nested_iteration(levels: &mut [Level]) {
    let last = levels.len() - 1;
    solve_coarsest(&mut levels[last]);
    for l in (0..last).rev() {
        let (fine, coarse) = levels.split_at_mut(l + 1);
        prolong_replace(&coarse[0], &mut fine[l]);
        if l > 0 {
            vcycle(&mut levels[l..]);
            // the coarse level's u now holds its solution; the levels below are scratch again
        }
    }
}

/// The state of the preconditioned conjugate gradients, in `f64` and colour-split like the levels.
struct Krylov {
    nx: usize,
    ny: usize,
    h: usize,
    /// The solution.
    x: [Vec<f64>; 2],
    /// The residual, kept up to date step by step.
    r: [Vec<f64>; 2],
    /// `−A p` of the current direction `p`.
    q: [Vec<f64>; 2],
    /// The preconditioned residual.
    z: [Vec<f64>; 2],
    /// The largest true residual, as last measured.
    res: f64,
    cycles: usize,
}

impl Krylov {
    /// The exact fixed values, the nested iteration's guess (`l0.u`) on the free cells, and its residual.
    fn start(l0: &Level, fixed: &[f64]) -> Krylov {
        let (nx, ny) = (l0.nx, l0.ny);
        let (h, n) = (l0.h, l0.h * l0.ny);
        let mut x = [vec![0.0; n], vec![0.0; n]];
        for (c, xc) in x.iter_mut().enumerate() {
            xc.par_chunks_mut(h).enumerate().for_each(|(j, row)| {
                let (cells, off) = row_cells(nx, j, c);
                for (k, v) in row[..cells].iter_mut().enumerate() {
                    let wanted = fixed[j * nx + 2 * k + off];
                    *v = if wanted.is_nan() {
                        l0.u[c][j * h + k] as f64
                    } else {
                        wanted
                    };
                }
            });
        }
        let mut r = [vec![0.0; n], vec![0.0; n]];
        let res = stencil(nx, ny, h, &l0.free, &x, None, &mut r).0;
        Krylov {
            nx,
            ny,
            h,
            x,
            r,
            q: [vec![0.0; n], vec![0.0; n]],
            z: [vec![0.0; n], vec![0.0; n]],
            res,
            cycles: 0,
        }
    }

    /// Iterates until the residual is at most `tolerance` or `max_cycles` steps have run: the recursively updated
    /// residual drifts from the true one by rounding, so when it reaches the tolerance the true residual is
    /// checked, and the iteration restarts from it if that is still above.
    fn run(&mut self, levels: &mut [Level], tolerance: f64, max_cycles: usize) {
        while self.res > tolerance && self.cycles < max_cycles {
            self.descend(levels, tolerance, max_cycles);
            let previous = self.res;
            self.res = stencil(
                self.nx,
                self.ny,
                self.h,
                &levels[0].free,
                &self.x,
                None,
                &mut self.r,
            )
            .0;
            if !(self.res < previous) {
                break; // no progress left at this precision
            }
        }
    }

    /// Conjugate-gradient steps from the current residual until the recursive residual is at most `tolerance`,
    /// the direction stops descending, or `max_cycles` steps have run in all.
    fn descend(&mut self, levels: &mut [Level], tolerance: f64, max_cycles: usize) {
        let (nx, ny, h) = (self.nx, self.ny, self.h);
        precondition(levels, &self.r, &mut self.z);
        let mut p = self.z.clone();
        let mut rz = dot(h, &self.r, &self.z);
        while self.cycles < max_cycles {
            // q = −A p, and p·A p with it
            let (_, p_q) = stencil(nx, ny, h, &levels[0].free, &p, None, &mut self.q);
            let pq = -p_q;
            if !(pq > 0.0) {
                break;
            }
            let alpha = rz / pq;
            let recursive = update_residual(nx, ny, h, alpha, &self.q, &mut self.r);
            self.cycles += 1;
            if recursive <= tolerance {
                axpy(alpha, &p, &mut self.x);
                break;
            }
            precondition(levels, &self.r, &mut self.z);
            let rz_next = dot(h, &self.r, &self.z);
            let beta = rz_next / rz;
            rz = rz_next;
            // x += alpha p with the old direction, then the new direction, in one pass
            for c in 0..2 {
                self.x[c]
                    .par_iter_mut()
                    .zip(p[c].par_iter_mut())
                    .zip(self.z[c].par_iter())
                    .with_min_len(TASK_CELLS)
                    .for_each(|((x, p), z)| {
                        *x += alpha * *p;
                        *p = z + beta * *p;
                    });
            }
        }
    }

    /// The solution, row-major.
    fn row_major(&self) -> Vec<f64> {
        let (nx, h) = (self.nx, self.h);
        let mut u = vec![0.0; nx * self.ny];
        u.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
            for (i, v) in row.iter_mut().enumerate() {
                *v = self.x[(i + j) & 1][j * h + i / 2];
            }
        });
        u
    }
}

/// One V-cycle on `A e = r` from `e = 0` (in single precision); the answer goes into `z`.
fn precondition(levels: &mut [Level], r: &[Vec<f64>; 2], z: &mut [Vec<f64>; 2]) {
    let l0 = &mut levels[0];
    for ((f, u), r) in l0.f.iter_mut().zip(l0.u.iter_mut()).zip(r) {
        f.par_iter_mut()
            .zip(r.par_iter())
            .with_min_len(TASK_CELLS)
            .for_each(|(f, r)| *f = *r as P);
        u.fill(0.0);
    }
    vcycle(levels);
    for (z, u) in z.iter_mut().zip(&levels[0].u) {
        z.par_iter_mut()
            .zip(u.par_iter())
            .with_min_len(TASK_CELLS)
            .for_each(|(z, u)| *z = *u as f64);
    }
}

/// Plain Jacobi iteration on the same equation (the baseline multigrid is measured against): every free cell
/// becomes the mean of its neighbours' previous values, until the largest change — which equals the residual
/// `|mean of neighbours − value|` — is at most `tolerance` or `max_iterations` have run. Starts from 0 on the free
/// cells.
pub(crate) fn jacobi(
    nx: usize,
    ny: usize,
    fixed: &[f64],
    tolerance: f64,
    max_iterations: usize,
) -> Solved {
    let free: Vec<bool> = fixed.iter().map(|v| v.is_nan()).collect();
    let mut u: Vec<f64> = fixed
        .iter()
        .map(|v| if v.is_nan() { 0.0 } else { *v })
        .collect();
    let mut next = u.clone();
    let mut iterations = 0;
    let mut res = f64::INFINITY;
    while iterations < max_iterations {
        let prev = u.as_slice();
        res = next
            .par_chunks_mut(nx)
            .zip(free.par_chunks(nx))
            .enumerate()
            .with_min_len(rows_per_task(nx))
            .map(|(j, (row, free))| {
                let mut worst = 0.0f64;
                for i in 0..nx {
                    if !free[i] {
                        continue;
                    }
                    let (mut s, mut d) = (0.0, 0.0);
                    if i > 0 {
                        s += prev[j * nx + i - 1];
                        d += 1.0;
                    }
                    if i + 1 < nx {
                        s += prev[j * nx + i + 1];
                        d += 1.0;
                    }
                    if j > 0 {
                        s += prev[(j - 1) * nx + i];
                        d += 1.0;
                    }
                    if j + 1 < ny {
                        s += prev[(j + 1) * nx + i];
                        d += 1.0;
                    }
                    let v = s / d;
                    worst = worst.max((v - prev[j * nx + i]).abs());
                    row[i] = v;
                }
                worst
            })
            .reduce(|| 0.0, f64::max);
        std::mem::swap(&mut u, &mut next);
        iterations += 1;
        if res <= tolerance {
            break;
        }
    }
    Solved {
        u,
        cycles: iterations,
        residual: res,
    }
}

#[cfg(test)]
mod tests;

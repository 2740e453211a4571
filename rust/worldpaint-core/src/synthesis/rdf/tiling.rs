//! The tiles of one sweep of the rdf-matching chain (see "Tiles and determinism" in the module documentation of
//! [`super::super`]): square tiles at a random offset in four 2 × 2 colour phases, or one tile over the region,
//! each with its members, its share of its phase's instances, its proposals and its seed.

use super::tile::Tile;
use super::RDF_SWEEPS;
use crate::geom::DVec2;
use crate::synthesis::mix_seed;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The tiling of one sweep: `nx × ny` tiles of `size` from `origin`, in 2 × 2 colour phases when `tiled`
/// (otherwise one tile over the region, in four phases of a quarter of its proposals when `quartered`).
pub(super) struct Tiling {
    tiled: bool,
    quartered: bool,
    origin: DVec2,
    size: DVec2,
    nx: usize,
    ny: usize,
}

impl Tiling {
    /// The tiling of a sweep: square tiles of `tile_size` at a random offset, or one tile over `bbox`.
    pub(super) fn draw(
        tiled: bool,
        quartered: bool,
        tile_size: f64,
        bbox: (DVec2, DVec2),
        rng: &mut ChaCha8Rng,
    ) -> Self {
        let (rlo, rhi) = bbox;
        let (origin, size, nx, ny) = if tiled {
            let off = DVec2::new(rng.random::<f64>(), rng.random::<f64>()) * tile_size;
            let origin = rlo - off;
            let nx = ((rhi.x - origin.x) / tile_size).floor() as usize + 1;
            let ny = ((rhi.y - origin.y) / tile_size).floor() as usize + 1;
            (origin, DVec2::splat(tile_size), nx, ny)
        } else {
            let ext = rhi - rlo;
            (rlo, ext * (1.0 + 1e-9) + DVec2::splat(1e-9), 1, 1)
        };
        Tiling {
            tiled,
            quartered,
            origin,
            size,
            nx,
            ny,
        }
    }

    pub(super) fn phases(&self) -> usize {
        if self.tiled || self.quartered {
            4
        } else {
            1
        }
    }

    fn tile_of(&self, p: DVec2) -> usize {
        let (origin, size, nx, ny) = (self.origin, self.size, self.nx, self.ny);
        let ix = (((p.x - origin.x) / size.x).floor().max(0.0) as usize).min(nx - 1);
        let iy = (((p.y - origin.y) / size.y).floor().max(0.0) as usize).min(ny - 1);
        iy * nx + ix
    }

    /// The sweep's tiles with their members among `own`, their colour phases, their shares of their phase's
    /// instances, proposals and seeds.
    pub(super) fn tiles(
        &self,
        own: &[DVec2],
        sweep_seed: u64,
        iterations_per_instance: f64,
    ) -> SweepTiles {
        let (nx, ny) = (self.nx, self.ny);
        let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); nx * ny];
        for (id, p) in own.iter().enumerate() {
            buckets[self.tile_of(*p)].push(id as u32);
        }
        let phase_of = |t: usize| {
            if self.tiled {
                ((t % nx) % 2) + 2 * ((t / nx) % 2)
            } else {
                0
            }
        };
        let mut phase_total = [0usize; 4];
        for (t, b) in buckets.iter().enumerate() {
            phase_total[phase_of(t)] += b.len();
        }
        let tiles = buckets
            .into_iter()
            .enumerate()
            .map(|(t, members)| {
                let phase = phase_of(t);
                let lo = self.origin + DVec2::new((t % nx) as f64, (t / nx) as f64) * self.size;
                let count = members.len();
                Tile {
                    lo,
                    hi: lo + self.size,
                    index: t,
                    phase,
                    share: count as f64 / phase_total[phase].max(1) as f64,
                    proposals: (count as f64 * iterations_per_instance / RDF_SWEEPS as f64).ceil()
                        as usize,
                    members,
                    seed: mix_seed(sweep_seed, (phase * nx * ny + t) as u64 + 1),
                }
            })
            .collect::<Vec<Tile>>();
        let (tiles, phase_total) = if self.quartered && !self.tiled {
            (quarters(tiles, sweep_seed), [phase_total[0]; 4])
        } else {
            (tiles, phase_total)
        };
        SweepTiles {
            tiles,
            nx,
            ny,
            phase_total,
        }
    }
}

/// The one tile over the region as four phases of a quarter of its proposals each (their own seeds), so that the
/// chain's stopping rule is read before each, as on tiles.
fn quarters(tiles: Vec<Tile>, sweep_seed: u64) -> Vec<Tile> {
    let Some(tile) = tiles.into_iter().next() else {
        return Vec::new();
    };
    (0..4)
        .map(|phase| Tile {
            phase,
            proposals: tile.proposals.div_ceil(4),
            members: tile.members.clone(),
            seed: mix_seed(sweep_seed, phase as u64 + 1),
            ..tile
        })
        .collect()
}

/// The tiles of one sweep, row-major, and the instances of each colour phase.
pub(super) struct SweepTiles {
    pub(super) tiles: Vec<Tile>,
    nx: usize,
    ny: usize,
    pub(super) phase_total: [usize; 4],
}

impl SweepTiles {
    /// The tiles next to tile `t` (its eight neighbours, fewer on the border).
    pub(super) fn neighbours(&self, t: usize) -> impl Iterator<Item = &Tile> + '_ {
        let (ix, iy) = ((t % self.nx) as isize, (t / self.nx) as isize);
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        (iy - 1..=iy + 1)
            .flat_map(move |y| (ix - 1..=ix + 1).map(move |x| (x, y)))
            .filter(move |&(x, y)| (x, y) != (ix, iy) && x >= 0 && y >= 0 && x < nx && y < ny)
            .map(move |(x, y)| &self.tiles[(y * nx + x) as usize])
    }
}

//! The engine's work budget, in one place. Synthesis, learning, terrains, regions, colors read from files and
//! village scenarios estimate the work an input asks for (instances, grid cells, histogram bins, region vertices,
//! nesting depth, buildings) from the input alone and refuse it with [`crate::Error::TooLarge`] before allocating
//! anything, so that a typo or a shared file with one bad number cannot exhaust memory or hang the host
//! application. (The village grid and the bucket indexes keep their own bounds, in the grid module.) The limits are far above real use: a 10 × 10 km world painted at
//! forest density is about 5M trees per call; a 4,096² terrain is 16.8M cells.

pub use crate::error::check::budget as check;

/// Instances one synthesis call may create (a paste, a brush dab, a fill).
pub const MAX_INSTANCES: u64 = 50_000_000;
/// Instances one world of tiles may hold: a thousand times the 10 × 10 km forest of the world benchmark.
pub const MAX_WORLD_INSTANCES: u64 = 10_000_000_000;
/// Chain proposals per instance one synthesis may be asked for: 250 times the default of 40.
pub const MAX_ITERATIONS_PER_INSTANCE: u64 = 10_000;
/// Buildings one village scenario may request (a town of ten thousand houses, ten times over).
pub(crate) const MAX_BUILDINGS: u64 = 100_000;
/// Cells of one grid (a terrain, a raster map, a conquest grid, a bucket index).
pub const MAX_GRID_CELLS: u64 = 64 * 1024 * 1024;
/// Bins of one histogram (an rdf, a map histogram): its extent over its bin width.
pub(crate) const MAX_HISTOGRAM_BINS: u64 = 4_096;
/// Largest bin value of a color's histogram: rdf values are ratios to a Poisson arrangement (a few hundred for
/// the most clustered content), map histograms and weights are masses (at most 1).
pub(crate) const MAX_HISTOGRAM_VALUE: f64 = 1e6;
/// Largest density of a category, per m² (one instance per cm²).
pub(crate) const MAX_DENSITY: f64 = 1e4;
/// Vertices of one region's polygons, all nested parts together.
pub(crate) const MAX_REGION_VERTICES: u64 = 1_000_000;
/// Bytes of one file of a real place (a map layer, an elevation model, a tree inventory): a GeoJSON layer is held
/// parsed in memory at several times its size.
pub const MAX_PLACE_FILE_BYTES: u64 = 512 * 1024 * 1024;
/// Slots of one triangle mesh binned for vertical look-ups (a triangle takes one in each cell its box meets): eight
/// per triangle of a 4,097² terrain mesh, 40 bytes each.
pub(crate) const MAX_BINNED_TRIANGLES: u64 = 1 << 28;
/// Nesting depth of a region (clipped inside clipped ...).
pub const MAX_REGION_DEPTH: u64 = 64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_past_the_limit_and_not_a_number() {
        assert!(check("grid", 100.0, 100, "cells").is_ok());
        let e = check("grid", 101.0, 100, "cells").unwrap_err();
        assert_eq!(
            e.to_string(),
            "too large: grid would need 101 cells, more than the limit of 100"
        );
        assert!(check("grid", f64::NAN, 100, "cells").is_err());
        assert!(check("grid", f64::INFINITY, 100, "cells").is_err());
    }
}

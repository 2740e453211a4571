//! Where the real data lives and how its lon/lat coordinates become metres, for the tests that measure against real
//! forests, terrains and villages. The data lies beside the project, in
//! `shared/data/real`, never in the repository: those tests are `#[ignore]`d with the reason, and `make test-rust`
//! runs them with `--ignored` where the folder is present.

use std::path::PathBuf;
use worldpaint_core::DVec2;

/// The real data folder (`shared/data/real` beside the project).
pub fn real_data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/real")
}

/// Panics with the reason when a real-data test is run without its data: it was asked for explicitly.
pub fn require(paths: &[PathBuf]) {
    if let Some(missing) = paths.iter().find(|p| !p.is_file()) {
        panic!(
            "{} not found: the real data lives beside the project, in shared/data/real (see its README)",
            missing.display()
        );
    }
}

/// Mean Earth radius (m).
const EARTH_RADIUS: f64 = 6_371_008.8;

/// Equirectangular projection about a centre (lon, lat in degrees) to metres east and north.
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    pub centre: [f64; 2],
    scale: DVec2,
}

impl Projection {
    pub fn new(centre: [f64; 2]) -> Projection {
        let metres_per_degree = EARTH_RADIUS.to_radians();
        Projection {
            centre,
            scale: DVec2::new(
                metres_per_degree * centre[1].to_radians().cos(),
                metres_per_degree,
            ),
        }
    }

    pub fn project(&self, lon_lat: [f64; 2]) -> DVec2 {
        DVec2::new(lon_lat[0] - self.centre[0], lon_lat[1] - self.centre[1]) * self.scale
    }

    pub fn unproject(&self, p: DVec2) -> [f64; 2] {
        let d = p / self.scale;
        [self.centre[0] + d.x, self.centre[1] + d.y]
    }

    /// Metres per degree east and north.
    pub fn scale(&self) -> DVec2 {
        self.scale
    }
}

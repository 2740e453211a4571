//! The SRTM tile (`.hgt`): 1201 × 1201 (3″) or 3601 × 3601 (1″) big-endian 16-bit heights, row 0 the northern edge,
//! samples on the grid lines (the first row on the tile's northern latitude, the last on its southern one); the
//! tile's south-west corner is in its name (`N49E011.hgt`: 49° N, 11° E). Void samples are -32768.

use super::{check_grid_size, ElevationModel, SRTM_VOID};
use crate::error::{Error, FileKind, Result};
use crate::place::read_file;
use std::path::Path;

/// The south-west corner (lon, lat in whole degrees) named by a tile's file name, e.g. `N49E011` or `s13w077`.
fn corner(name: &str) -> Option<[f64; 2]> {
    let b = name.as_bytes();
    if b.len() < 7 {
        return None;
    }
    let digits = |s: &[u8]| -> Option<f64> {
        s.iter()
            .all(u8::is_ascii_digit)
            .then(|| std::str::from_utf8(s).ok()?.parse::<f64>().ok())?
    };
    let lat = match b[0].to_ascii_uppercase() {
        b'N' => digits(&b[1..3])?,
        b'S' => -digits(&b[1..3])?,
        _ => return None,
    };
    let lon = match b[3].to_ascii_uppercase() {
        b'E' => digits(&b[4..7])?,
        b'W' => -digits(&b[4..7])?,
        _ => return None,
    };
    (lat.abs() < 90.0 && lon.abs() <= 180.0).then_some([lon, lat])
}

pub(super) fn read(path: &Path, source: &str) -> Result<ElevationModel> {
    let bad =
        |reason: String| Error::parse(FileKind::ElevationModel, format!("{source}: {reason}"));
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let [lon, lat] = corner(name).ok_or_else(|| {
        bad("an SRTM tile's name must begin with its south-west corner, like N49E011.hgt".into())
    })?;
    let bytes = read_file(path, FileKind::ElevationModel)?;
    let n = match bytes.len() {
        l if l == 1201 * 1201 * 2 => 1201,
        l if l == 3601 * 3601 * 2 => 3601,
        l => {
            return Err(bad(format!(
                "{l} bytes: an SRTM tile holds 1201 x 1201 or 3601 x 3601 samples of 2 bytes"
            )))
        }
    };
    check_grid_size(source, n, n)?;
    let heights: Vec<f64> = bytes
        .chunks_exact(2)
        .map(|b| {
            let v = i16::from_be_bytes([b[0], b[1]]) as f64;
            if v == SRTM_VOID {
                f64::NAN
            } else {
                v
            }
        })
        .collect();
    let step = 1.0 / (n - 1) as f64;
    Ok(ElevationModel::new(
        source,
        (n, n),
        [lon - 0.5 * step, lat - 0.5 * step],
        [step, step],
        heights,
    ))
}

#[cfg(test)]
mod tests {
    use super::corner;

    #[test]
    fn corners_from_names() {
        assert_eq!(corner("N49E011.hgt"), Some([11.0, 49.0]));
        assert_eq!(corner("s13w077.SRTMGL1.hgt"), Some([-77.0, -13.0]));
        assert_eq!(corner("tile.hgt"), None);
    }
}

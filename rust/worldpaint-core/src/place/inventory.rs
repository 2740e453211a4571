//! A tree inventory: a CSV file with a header, one tree a row. Columns are found by name (any case):
//!
//! | what | column names |
//! |---|---|
//! | position in lon/lat degrees | `lon` / `longitude` / `lng`, `lat` / `latitude` |
//! | position in local metres | `x` / `gx`, `y` / `gy` (ForestGEO plots write `gx, gy`) |
//! | species | `species` / `sp` |
//! | size | `size` / `dbh` / `height` (whatever unit the file uses; empty where unknown) |
//! | status | `status`: only the trees marked `A` or `alive` are kept (ForestGEO marks the dead `D`) |
//!
//! Lon/lat columns win over x, y when a file has both. A `.prj` beside the file may say which: WGS84 lon/lat (then x,
//! y are read as lon, lat) or a local frame (`LOCAL_CS`); any other CRS is refused. Local metres are taken as metres
//! east and north of the place's origin. A row without a readable position is counted as unreadable and left out; a
//! number that is infinite or not a number refuses the file.

use super::crs::{self, Crs};
use super::read_file;
use crate::error::{Error, FileKind, Result};
use std::path::Path;

/// How an inventory gives its positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InventoryCoordinates {
    /// Longitude and latitude in degrees (WGS84).
    LonLat,
    /// Metres east and north of the place's origin.
    LocalMetres,
}

/// One tree of an inventory as read.
#[derive(Clone, Debug, PartialEq)]
pub struct InventoryRow {
    /// Its position: (lon, lat) or (x, y), as the inventory's coordinates say.
    pub position: [f64; 2],
    /// Its species code or name (empty when the file has none).
    pub species: String,
    /// Its size (trunk diameter or height, the file's unit), when given.
    pub size: Option<f64>,
}

/// The living trees of an inventory file.
#[derive(Clone, Debug)]
pub struct TreeInventory {
    /// The file, as given.
    pub source: String,
    /// How its positions are given.
    pub coordinates: InventoryCoordinates,
    /// The kept trees, in file order.
    pub trees: Vec<InventoryRow>,
    /// Rows left out as not alive.
    pub not_alive: usize,
    /// Rows left out without a readable position.
    pub unreadable: usize,
}

fn column(header: &[String], names: &[&str]) -> Option<usize> {
    header.iter().position(|h| names.contains(&h.as_str()))
}

/// Reads a tree inventory (see the module doc).
pub fn read_tree_inventory(path: &Path) -> Result<TreeInventory> {
    let source = path.display().to_string();
    let bad = |reason: String| Error::parse(FileKind::TreeInventory, format!("{source}: {reason}"));
    let bytes = read_file(path, FileKind::TreeInventory)?;
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(bytes.as_slice());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| bad(format!("not a CSV file ({e})")))?
        .iter()
        .map(|h| h.trim_start_matches('\u{feff}').to_ascii_lowercase())
        .collect();
    let lon_lat = (
        column(&header, &["lon", "longitude", "lng"]),
        column(&header, &["lat", "latitude"]),
    );
    let x_y = (column(&header, &["x", "gx"]), column(&header, &["y", "gy"]));
    let prj = crs::of_prj_beside(path, FileKind::TreeInventory)?;
    let ((cx, cy), coordinates) = match (lon_lat, x_y, prj) {
        (_, _, Some(Crs::Other(name))) => return Err(crs::cannot_place(FileKind::TreeInventory, &source, &name)),
        ((Some(a), Some(b)), _, None | Some(Crs::LonLat)) => ((a, b), InventoryCoordinates::LonLat),
        (_, (Some(a), Some(b)), Some(Crs::LonLat)) => ((a, b), InventoryCoordinates::LonLat),
        (_, (Some(a), Some(b)), None | Some(Crs::LocalMetres)) => ((a, b), InventoryCoordinates::LocalMetres),
        _ => {
            return Err(bad(format!(
                "no position columns: a tree inventory needs 'x' and 'y' (metres) or 'lon' and 'lat', found {}",
                header.join(", ")
            )))
        }
    };
    let species = column(&header, &["species", "sp"]);
    let size = column(&header, &["size", "dbh", "height"]);
    let status = column(&header, &["status"]);
    let mut out = TreeInventory {
        source: source.clone(),
        coordinates,
        trees: Vec::new(),
        not_alive: 0,
        unreadable: 0,
    };
    for (k, record) in reader.records().enumerate() {
        let row = k + 2; // the header is line 1
        let record = record.map_err(|e| bad(format!("line {row}: {e}")))?;
        let field = |c: Option<usize>| c.and_then(|c| record.get(c)).unwrap_or("");
        if let Some(s) = status {
            let s = field(Some(s));
            if !(s.eq_ignore_ascii_case("a") || s.eq_ignore_ascii_case("alive")) {
                out.not_alive += 1;
                continue;
            }
        }
        let number = |c: Option<usize>, what: &str| -> Result<Option<f64>> {
            match field(c).parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Some(v)),
                Ok(v) => Err(bad(format!("line {row}: its {what} is not finite ({v})"))),
                Err(_) => Ok(None),
            }
        };
        let (Some(a), Some(b)) = (number(Some(cx), "position")?, number(Some(cy), "position")?)
        else {
            out.unreadable += 1;
            continue;
        };
        if coordinates == InventoryCoordinates::LonLat && !crs::is_lon_lat([a, b]) {
            return Err(crs::not_lon_lat(FileKind::TreeInventory, &source, [a, b]));
        }
        let size = number(size, "size")?;
        if let Some(s) = size.filter(|s| *s < 0.0) {
            return Err(bad(format!("line {row}: its size is negative ({s})")));
        }
        out.trees.push(InventoryRow {
            position: [a, b],
            species: field(species).to_string(),
            size,
        });
        crate::error::check::at_most_items(
            &format!("the trees of {source}"),
            out.trees.len(),
            crate::limits::MAX_INSTANCES as usize,
        )?;
    }
    if out.trees.is_empty() {
        return Err(bad(format!(
            "an empty inventory: no living tree with a readable position ({} rows not alive, {} unreadable)",
            out.not_alive, out.unreadable
        )));
    }
    Ok(out)
}

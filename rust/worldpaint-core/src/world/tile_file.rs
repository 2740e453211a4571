//! One tile of a tile set on disk: a compact little-endian binary file, the same bytes for the same tile.
//!
//! ```text
//! magic        8 bytes   "WPTILE01"
//! column, row  u32, u32
//! origin       f64, f64  the tile's min corner (world XY, m)
//! count        u32       instances
//! categories   u32       then per category: name length u16, name (UTF-8)
//! columns      count each, in this order: x, y (f32, relative to origin), z (f32, terrain height),
//!              rotation (f32, radians), scale (f32), tint (f32), category (u16), prototype (u16)
//! ```
//!
//! Positions relative to the tile's corner keep a tenth of a millimetre in f32 on tiles of kilometres; 28 bytes an
//! instance. Columns rather than records: a reader takes each as one array.

use super::{TileContent, TileId};
use crate::geom::DVec2;
use crate::scene::Instance;
use crate::{Error, FileKind, Result};

const MAGIC: &[u8; 8] = b"WPTILE01";

fn too_many(what: &str, n: usize) -> Error {
    Error::invalid(
        format!("tile {what}"),
        format!("{n} do not fit the tile file's 16-bit field"),
    )
}

/// The tile's bytes.
pub fn encode_tile(tile: &TileContent) -> Result<Vec<u8>> {
    let n = tile.instances.len();
    let count = u32::try_from(n).map_err(|_| too_many("instances", n))?;
    let mut out = Vec::with_capacity(64 + 28 * n);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&tile.tile.column.to_le_bytes());
    out.extend_from_slice(&tile.tile.row.to_le_bytes());
    out.extend_from_slice(&tile.origin.x.to_le_bytes());
    out.extend_from_slice(&tile.origin.y.to_le_bytes());
    out.extend_from_slice(&count.to_le_bytes());
    out.extend_from_slice(&(tile.categories.len() as u32).to_le_bytes());
    for name in &tile.categories {
        let len =
            u16::try_from(name.len()).map_err(|_| too_many("category name bytes", name.len()))?;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(name.as_bytes());
    }
    let f32s: [&dyn Fn(usize) -> f32; 6] = [
        &|k| (tile.instances[k].position.x - tile.origin.x) as f32,
        &|k| (tile.instances[k].position.y - tile.origin.y) as f32,
        &|k| tile.heights.get(k).copied().unwrap_or(0.0),
        &|k| tile.instances[k].rotation as f32,
        &|k| tile.instances[k].scale as f32,
        &|k| tile.instances[k].tint,
    ];
    for column in f32s {
        for k in 0..n {
            out.extend_from_slice(&column(k).to_le_bytes());
        }
    }
    for i in &tile.instances {
        let c = u16::try_from(i.category).map_err(|_| too_many("categories", i.category))?;
        out.extend_from_slice(&c.to_le_bytes());
    }
    for i in &tile.instances {
        let p =
            u16::try_from(i.prototype).map_err(|_| too_many("prototypes", i.prototype as usize))?;
        out.extend_from_slice(&p.to_le_bytes());
    }
    Ok(out)
}

/// Reads the file's fields in order, with a clear error where it ends early.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| Error::Parse {
            kind: FileKind::Tile,
            reason: format!("it ends at byte {} inside {what}", self.bytes.len()),
        })?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N, what)?);
        Ok(a)
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    fn f64(&mut self, what: &str) -> Result<f64> {
        Ok(f64::from_le_bytes(self.array(what)?))
    }

    fn column<const N: usize, T>(
        &mut self,
        n: usize,
        what: &str,
        from: fn([u8; N]) -> T,
    ) -> Result<Vec<T>> {
        let bytes = self.take(n * N, what)?;
        Ok(bytes
            .chunks_exact(N)
            .map(|c| {
                let mut a = [0u8; N];
                a.copy_from_slice(c);
                from(a)
            })
            .collect())
    }
}

/// The tile a file's bytes hold.
pub fn decode_tile(bytes: &[u8]) -> Result<TileContent> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(MAGIC.len(), "the header")? != MAGIC {
        return Err(Error::Parse {
            kind: FileKind::Tile,
            reason: "it does not start with the tile file's magic bytes".into(),
        });
    }
    let tile = TileId {
        column: r.u32("the column")?,
        row: r.u32("the row")?,
    };
    let origin = DVec2::new(r.f64("the origin")?, r.f64("the origin")?);
    let n = r.u32("the count")? as usize;
    let n_categories = r.u32("the category count")? as usize;
    // every category takes at least its two length bytes: a corrupt count cannot make this loop allocate much
    let mut categories = Vec::new();
    for _ in 0..n_categories {
        let len = u16::from_le_bytes(r.array("a category name")?) as usize;
        let name =
            std::str::from_utf8(r.take(len, "a category name")?).map_err(|_| Error::Parse {
                kind: FileKind::Tile,
                reason: "a category name is not UTF-8".into(),
            })?;
        categories.push(name.to_string());
    }
    let mut f32s = Vec::with_capacity(6);
    for what in ["x", "y", "z", "rotation", "scale", "tint"] {
        f32s.push(r.column(n, what, f32::from_le_bytes)?);
    }
    let category = r.column(n, "category", u16::from_le_bytes)?;
    let prototype = r.column(n, "prototype", u16::from_le_bytes)?;
    if r.at != bytes.len() {
        return Err(Error::Parse {
            kind: FileKind::Tile,
            reason: format!("{} bytes follow the last column", bytes.len() - r.at),
        });
    }
    if let Some(&c) = category.iter().find(|&&c| c as usize >= categories.len()) {
        return Err(Error::Parse {
            kind: FileKind::Tile,
            reason: format!(
                "category index {c} where the tile names {}",
                categories.len()
            ),
        });
    }
    let instances = (0..n)
        .map(|k| Instance {
            position: origin + DVec2::new(f32s[0][k] as f64, f32s[1][k] as f64),
            rotation: f32s[3][k] as f64,
            scale: f32s[4][k] as f64,
            tint: f32s[5][k],
            category: category[k] as usize,
            prototype: prototype[k] as u32,
            locked: false,
        })
        .collect();
    Ok(TileContent {
        tile,
        origin,
        categories,
        instances,
        heights: f32s.swap_remove(2),
    })
}

//! A world's tiles filled as a driver fills them: phase by phase, each tile given the border strips (as bytes,
//! decoded) of its earlier neighbours.

use std::collections::BTreeMap;
use worldpaint_core::{
    decode_tile, encode_tile, synthesize_tile, ColorMap, Obstacles, TileContent, TileId, WorldPlan,
};

/// Every tile's file bytes, the tiles of each phase taken in the order `order` gives them, keeping off the
/// `obstacles` (and seeing their roads).
pub fn fill_tiles(
    plan: &WorldPlan,
    map: &ColorMap,
    obstacles: &Obstacles,
    seed: u64,
    order: fn(&mut Vec<TileId>),
) -> BTreeMap<TileId, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut borders: BTreeMap<TileId, Vec<u8>> = BTreeMap::new();
    for phase in 0..4 {
        let mut tiles: Vec<TileId> = plan
            .tiles()
            .into_iter()
            .filter(|&t| plan.phase(t) == phase)
            .collect();
        order(&mut tiles);
        for t in tiles {
            let neighbours: Vec<TileContent> = plan
                .earlier_neighbours(t)
                .iter()
                .map(|n| match decode_tile(&borders[n]) {
                    Ok(b) => b,
                    Err(e) => panic!("border of {n:?}: {e}"),
                })
                .collect();
            let content =
                match synthesize_tile(plan, t, map, obstacles, None, &neighbours, seed, None) {
                    Ok(c) => c,
                    Err(e) => panic!("tile {t:?}: {e}"),
                };
            let encode = |c: &TileContent| match encode_tile(c) {
                Ok(b) => b,
                Err(e) => panic!("encoding {t:?}: {e}"),
            };
            borders.insert(t, encode(&content.border(plan)));
            files.insert(t, encode(&content));
        }
    }
    files
}

//! Texture variety (seed §5): painted details become texture components, packed into atlases without touching the
//! texture coordinates, and picked at random per variant with face locking.
//!
//! A texture component T_k = (P_k, M_k, C_k) (§5.1): P_k the pixel mask of the texels the edit changed, C_k the
//! cluster of faces whose texture coordinates cover any of them, M_k ⊇ P_k the texels those faces cover. The
//! component also keeps the painted colours of P_k's texels. Two components are non-conflicting, and may share an
//! atlas, when P_i ∩ M_j = ∅ and P_j ∩ M_i = ∅ (§5.2). The seed enumerates every packing and keeps the one with the
//! fewest atlases: that is a minimum colouring of the conflict graph, found here exactly by backtracking (up to
//! [`EXACT_STEPS`] steps) and otherwise by DSatur, a greedy colouring; [`Packing::exact`] says which. An atlas image is
//! the base texture with its components' texels painted in; a face showing a component is bound to that atlas, with
//! its own texture coordinates (§5.3).
//!
//! Readings chosen: images are RGBA, 8 bits a channel, rows from the bottom as Blender's `Image.pixels` (texel (x, y)
//! holds (u, v) = ((x + ½)/w, (y + ½)/h)); a face covers the texels whose centres its UV triangles hold, plus the
//! texels of its corners (so slivers are not lost); texture coordinates outside [0, 1]² wrap (tiling), so a face
//! that tiles covers every repetition — the seed instead subdivides such faces (Fig. 17), which would change the
//! texture coordinates, so here the component simply covers the whole face. A face whose UVs span more than 16
//! texture repetitions covers the whole image. Variety (§5.3): components are visited in a random order, each taken
//! with the given probability if none of its faces is locked yet; taking it locks its faces.

use super::model::Model;
use crate::error::{Error, Result};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Steps of the exact packing search before it falls back to DSatur.
pub(crate) const EXACT_STEPS: u64 = 2_000_000;

/// An RGBA image, 8 bits per channel, rows from the bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width × height × 4` bytes.
    pub rgba: Vec<u8>,
}

impl Image {
    /// An image of `rgba` bytes, checked against its size.
    pub fn new(width: u32, height: u32, rgba: Vec<u8>) -> Result<Image> {
        let image = Image {
            width,
            height,
            rgba,
        };
        image.check()?;
        Ok(image)
    }

    /// Checks the image's size and bytes (its fields are public, so one set by hand is checked before use).
    pub fn check(&self) -> Result<()> {
        let (width, height) = (self.width, self.height);
        if width == 0 || height == 0 {
            return Err(Error::invalid(
                "image",
                format!("{width}×{height} texels: both sides must be at least 1"),
            ));
        }
        let texels = width as u64 * height as u64;
        crate::limits::check(
            "image",
            texels as f64,
            crate::limits::MAX_GRID_CELLS,
            "texels",
        )?;
        crate::error::check::same_len("image bytes (RGBA)", self.rgba.len(), texels as usize * 4)
    }

    fn texels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The RGBA value of texel `i` (row-major from the bottom row), `None` past the image.
    pub fn texel(&self, i: usize) -> Option<[u8; 4]> {
        let s = self.rgba.get(i * 4..i * 4 + 4)?;
        Some([s[0], s[1], s[2], s[3]])
    }
}

/// One texture component T_k = (P_k, M_k, C_k) and its colours.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureComponent {
    /// P_k: the texels the edit changed (row-major indices, ascending).
    pub pixel_mask: Vec<u32>,
    /// The painted colour of each texel of P_k.
    pub colours: Vec<[u8; 4]>,
    /// C_k: the faces whose texture coordinates cover P_k (ascending).
    pub faces: Vec<u32>,
    /// M_k: every texel those faces cover, P_k included (ascending).
    pub face_mask: Vec<u32>,
}

/// Texels covered by face `f` of a model with texture coordinates `uvs` (ascending, unique), in an image of `w × h`.
fn face_texels(uvs: &[Vec<glam::DVec2>], f: usize, w: u32, h: u32) -> Vec<u32> {
    let (wf, hf) = (w as f64, h as f64);
    let corners: Vec<(f64, f64)> = uvs[f].iter().map(|uv| (uv.x * wf, uv.y * hf)).collect();
    let mut out = Vec::new();
    let wrap = |x: i64, y: i64| -> u32 {
        (y.rem_euclid(h as i64) * w as i64 + x.rem_euclid(w as i64)) as u32
    };
    let whole = || (0..w * h).collect::<Vec<u32>>();
    for k in 1..corners.len().saturating_sub(1) {
        let t = [corners[0], corners[k], corners[k + 1]];
        let (x0, x1) = (
            t.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
            t.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
        );
        let (y0, y1) = (
            t.iter().map(|p| p.1).fold(f64::INFINITY, f64::min),
            t.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
        );
        if (x1 - x0) * (y1 - y0) > 16.0 * wf * hf || x1 - x0 > 16.0 * wf || y1 - y0 > 16.0 * hf {
            return whole();
        }
        let area = (t[1].0 - t[0].0) * (t[2].1 - t[0].1) - (t[2].0 - t[0].0) * (t[1].1 - t[0].1);
        for p in t {
            out.push(wrap(p.0.floor() as i64, p.1.floor() as i64));
        }
        if area == 0.0 {
            continue;
        }
        for y in (y0.floor() as i64)..=(y1.ceil() as i64) {
            for x in (x0.floor() as i64)..=(x1.ceil() as i64) {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let inside = (0..3).all(|e| {
                    let (a, b) = (t[e], t[(e + 1) % 3]);
                    ((b.0 - a.0) * (py - a.1) - (b.1 - a.1) * (px - a.0)) * area.signum() >= 0.0
                });
                if inside {
                    out.push(wrap(x, y));
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Whether two ascending lists share an item.
fn overlap(a: &[u32], b: &[u32]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

impl TextureComponent {
    /// The component of one painting step: `painted` compared with `base` texel by texel, over `model`'s texture
    /// coordinates (which it only reads).
    pub fn from_edit(model: &Model, base: &Image, painted: &Image) -> Result<TextureComponent> {
        model.validate()?;
        base.check()?;
        painted.check()?;
        let uvs = model.uvs.as_ref().ok_or_else(|| {
            Error::invalid("model", "it has no texture coordinates to paint through")
        })?;
        if (base.width, base.height) != (painted.width, painted.height) {
            return Err(Error::invalid(
                "painted image",
                format!(
                    "it is {}×{} texels, the base texture {}×{}",
                    painted.width, painted.height, base.width, base.height
                ),
            ));
        }
        let mut pixel_mask = Vec::new();
        let mut colours = Vec::new();
        for i in 0..base.texels() {
            let (was, now) = (base.texel(i), painted.texel(i));
            if let (Some(was), Some(now)) = (was, now) {
                if was != now {
                    pixel_mask.push(i as u32);
                    colours.push(now);
                }
            }
        }
        if pixel_mask.is_empty() {
            return Err(Error::invalid(
                "painted image",
                "it does not differ from the base texture: nothing was painted",
            ));
        }
        let mut faces = Vec::new();
        let mut face_mask: Vec<u32> = pixel_mask.clone();
        for f in 0..model.faces.len() {
            let covered = face_texels(uvs, f, base.width, base.height);
            if overlap(&covered, &pixel_mask) {
                faces.push(f as u32);
                face_mask.extend(covered);
            }
        }
        face_mask.sort_unstable();
        face_mask.dedup();
        Ok(TextureComponent {
            pixel_mask,
            colours,
            faces,
            face_mask,
        })
    }

    /// Whether the two components conflict (§5.2): one's pixels fall in the other's face mask.
    pub fn conflicts(&self, other: &TextureComponent) -> bool {
        overlap(&self.pixel_mask, &other.face_mask) || overlap(&other.pixel_mask, &self.face_mask)
    }
}

/// Components packed into texture component atlases A_i.
#[derive(Clone, Debug, PartialEq)]
pub struct Packing {
    /// The atlas of each component.
    pub atlas_of: Vec<usize>,
    /// How many atlases.
    pub atlases: usize,
    /// Whether the count is proven the fewest (the exact search finished).
    pub exact: bool,
}

/// Packs components into the fewest atlases with no two conflicting components in one (§5.2).
pub fn pack_components(components: &[TextureComponent]) -> Packing {
    let n = components.len();
    let conflict: Vec<Vec<bool>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| i != j && components[i].conflicts(&components[j]))
                .collect()
        })
        .collect();
    let greedy = dsatur(&conflict);
    let greedy_count = greedy.iter().map(|&c| c + 1).max().unwrap_or(0);
    let mut best = (greedy_count, greedy);
    let mut colours = vec![usize::MAX; n];
    let mut steps = 0u64;
    // Order: most conflicts first.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| {
        (
            std::cmp::Reverse(conflict[i].iter().filter(|&&c| c).count()),
            i,
        )
    });
    let finished = search(&conflict, &order, 0, 0, &mut colours, &mut best, &mut steps);
    Packing {
        atlases: best.0,
        atlas_of: best.1,
        exact: finished,
    }
}

/// Backtracking colouring: returns false when it ran out of steps.
fn search(
    conflict: &[Vec<bool>],
    order: &[usize],
    at: usize,
    used: usize,
    colours: &mut [usize],
    best: &mut (usize, Vec<usize>),
    steps: &mut u64,
) -> bool {
    *steps += 1;
    if *steps > EXACT_STEPS {
        return false;
    }
    if used >= best.0 {
        return true;
    }
    let Some(&i) = order.get(at) else {
        *best = (used, colours.to_vec());
        return true;
    };
    for c in 0..(used + 1).min(best.0.saturating_sub(1)) {
        if (0..conflict.len()).any(|j| conflict[i][j] && colours[j] == c) {
            continue;
        }
        colours[i] = c;
        let ok = search(
            conflict,
            order,
            at + 1,
            used.max(c + 1),
            colours,
            best,
            steps,
        );
        colours[i] = usize::MAX;
        if !ok {
            return false;
        }
    }
    true
}

/// DSatur greedy colouring (ties to the lower index).
fn dsatur(conflict: &[Vec<bool>]) -> Vec<usize> {
    let n = conflict.len();
    let mut colours = vec![usize::MAX; n];
    for _ in 0..n {
        let mut pick = None;
        let mut key = (0usize, 0usize);
        for i in (0..n).filter(|&i| colours[i] == usize::MAX) {
            let mut seen: Vec<usize> = (0..n)
                .filter(|&j| conflict[i][j] && colours[j] != usize::MAX)
                .map(|j| colours[j])
                .collect();
            seen.sort_unstable();
            seen.dedup();
            let degree = conflict[i].iter().filter(|&&c| c).count();
            if pick.is_none() || (seen.len(), degree) > key {
                pick = Some(i);
                key = (seen.len(), degree);
            }
        }
        let Some(i) = pick else { break };
        let mut c = 0;
        while (0..n).any(|j| conflict[i][j] && colours[j] == c) {
            c += 1;
        }
        colours[i] = c;
    }
    colours
}

/// The atlas images: for each atlas, the base texture with its components' texels painted.
pub fn atlas_images(
    base: &Image,
    components: &[TextureComponent],
    packing: &Packing,
) -> Vec<Image> {
    let mut images = vec![base.clone(); packing.atlases];
    for (k, comp) in components.iter().enumerate() {
        let Some(image) = packing.atlas_of.get(k).and_then(|&a| images.get_mut(a)) else {
            continue;
        };
        for (&t, colour) in comp.pixel_mask.iter().zip(&comp.colours) {
            let at = t as usize * 4;
            if let Some(px) = image.rgba.get_mut(at..at + 4) {
                px.copy_from_slice(colour);
            }
        }
    }
    images
}

/// The texture components one variant shows, and the atlas each face binds.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureChoice {
    /// The chosen components (ascending).
    pub chosen: Vec<usize>,
    /// For each face, the atlas it binds (`None`: the base texture).
    pub face_atlas: Vec<Option<usize>>,
}

/// Picks texture components at random with face locking (§5.3): each component, in a random order, is taken with
/// `probability` unless one of its faces is already locked by a taken one.
pub fn pick_textures(
    components: &[TextureComponent],
    packing: &Packing,
    face_count: usize,
    probability: f64,
    seed: u64,
) -> Result<TextureChoice> {
    crate::error::check::within("texture component probability", probability, 0.0, 1.0)?;
    crate::error::check::same_len("packing", packing.atlas_of.len(), components.len())?;
    for (k, comp) in components.iter().enumerate() {
        if let Some(&f) = comp.faces.iter().find(|&&f| f as usize >= face_count) {
            return Err(Error::invalid(
                format!("texture component {k}"),
                format!("face {f} is not one of the model's {face_count}"),
            ));
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut order: Vec<usize> = (0..components.len()).collect();
    order.shuffle(&mut rng);
    let mut face_atlas = vec![None; face_count];
    let mut chosen = Vec::new();
    for k in order {
        let take = rng.random::<f64>() < probability;
        let comp = &components[k];
        if !take || comp.faces.iter().any(|&f| face_atlas[f as usize].is_some()) {
            continue;
        }
        for &f in &comp.faces {
            face_atlas[f as usize] = Some(packing.atlas_of[k]);
        }
        chosen.push(k);
    }
    chosen.sort_unstable();
    Ok(TextureChoice { chosen, face_atlas })
}

/// The texture choices of `count` variants: variant `i` picks with [`pick_textures`] under the `i`-th seed drawn from
/// one generator seeded with `seed`, so a variant's texture does not depend on how many variants are asked for.
pub fn pick_texture_variants(
    components: &[TextureComponent],
    packing: &Packing,
    face_count: usize,
    probability: f64,
    count: usize,
    seed: u64,
) -> Result<Vec<TextureChoice>> {
    crate::limits::check(
        &format!("the texture choices of {count} variants of {face_count} faces"),
        count as f64 * face_count as f64,
        crate::limits::MAX_GRID_CELLS,
        "faces",
    )?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..count)
        .map(|_| pick_textures(components, packing, face_count, probability, rng.random()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn component(faces: Vec<u32>, texel: u32) -> TextureComponent {
        TextureComponent {
            pixel_mask: vec![texel],
            colours: vec![[255, 0, 0, 255]],
            faces,
            face_mask: vec![texel],
        }
    }

    #[test]
    fn locked_components_are_taken_less_often_than_free_ones() {
        // components 0 and 1 share face 1 (face locking), component 2 is alone
        let comps = [
            component(vec![0, 1], 0),
            component(vec![1, 2], 1),
            component(vec![3], 2),
        ];
        let packing = pack_components(&comps);
        let picks = pick_texture_variants(&comps, &packing, 4, 0.5, 4000, 7).expect("picks");
        let taken =
            |k: usize| picks.iter().filter(|p| p.chosen.contains(&k)).count() as f64 / 4000.0;
        // a locked pair: taken first (½ · p) or second when the other was not taken (½ · p · (1 - p)) = 0.375
        assert!((taken(0) - 0.375).abs() < 0.03, "{}", taken(0));
        assert!((taken(1) - 0.375).abs() < 0.03, "{}", taken(1));
        assert!((taken(2) - 0.5).abs() < 0.03, "{}", taken(2));
        assert!(picks
            .iter()
            .all(|p| !(p.chosen.contains(&0) && p.chosen.contains(&1))));
        let again = pick_texture_variants(&comps, &packing, 4, 0.5, 10, 7).expect("picks");
        assert_eq!(
            again[..],
            picks[..10],
            "the first variants do not depend on the count"
        );
    }
}

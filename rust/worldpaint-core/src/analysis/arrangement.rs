//! Learning an arrangement color (Ijiri et al. 2008, §4): the elements of the scene's arrangement categories
//! inside the region become the reference, each keeping its symbol (its category), rotation, scale and prototype;
//! the categories get the same per-category statistics as any color's (count, density, prototypes), so the
//! palette shows and files them alike.

use glam::DVec2;

use super::{category_color, point_grid, Group};
use crate::arrangement::{ArrangementColor, ReferenceElement};
use crate::error::{Error, Result};
use crate::palette::{Color, ColorKind};
use crate::scene::{CategoryKind, Scene};

/// The rdf radius an arrangement color records, in the reference's mean edges: painting never reads it, but the
/// region of influence and the palette's figures need one.
const RADIUS_EDGES: f64 = 3.0;

/// Learns the arrangement of the elements of the scene's arrangement categories inside `region` as a color called
/// `name`: the reference's connectivity must build (at least one element with a complete ring).
pub fn learn_arrangement(scene: &Scene, region: &crate::geom::Region, name: &str) -> Result<Color> {
    region.validate()?;
    let region = &*region.with_bounded_detail();
    let mut order: Vec<usize> = (0..scene.categories.len())
        .filter(|&c| scene.categories[c].kind == CategoryKind::Arrangement)
        .collect();
    order.sort_by_key(|&c| (scene.categories[c].priority, c));
    let mut groups = Vec::new();
    for &c in &order {
        let own: Vec<_> = scene
            .instances
            .iter()
            .filter(|i| i.category == c && region.contains(i.position))
            .copied()
            .collect();
        if own.is_empty() {
            continue;
        }
        if let Some(i) = own
            .iter()
            .find(|i| !(i.position.is_finite() && i.scale.is_finite() && i.scale > 0.0))
        {
            return Err(Error::invalid(
                format!("category '{}'", scene.categories[c].name),
                format!(
                    "has an element at ({:.2}, {:.2}) of scale {}: positions must be finite, scales positive",
                    i.position.x, i.position.y, i.scale
                ),
            ));
        }
        groups.push(Group::new(&scene.categories[c], own));
    }
    if groups.is_empty() {
        return Err(Error::EmptyExemplar {
            reason: "no element of an arrangement category inside the region".into(),
        });
    }
    let elements: Vec<ReferenceElement> = groups
        .iter()
        .enumerate()
        .flat_map(|(symbol, g)| {
            g.instances.iter().map(move |i| ReferenceElement {
                position: i.position,
                symbol: symbol as u32,
                rotation: i.rotation,
                scale: i.scale,
                prototype: i.prototype,
            })
        })
        .collect();
    let pattern = ArrangementColor::new(elements);
    let reference = pattern.reference()?;
    let area = region.area();
    let max_radius = RADIUS_EDGES * reference.mean_edge();
    let categories = groups
        .iter()
        .map(|g| {
            let grid = point_grid(region, &g.positions, max_radius);
            category_color(g, area, &grid, max_radius)
        })
        .collect();
    let (lo, _) = region.bbox();
    let preview = pattern
        .elements
        .iter()
        .map(|e| {
            let p: DVec2 = e.position - lo;
            [p.x, p.y, e.symbol as f64]
        })
        .collect();
    let color = Color {
        name: name.to_string(),
        region: region.clone(),
        region_area: area,
        max_radius,
        bin_width: max_radius / 24.0,
        categories,
        pairs: Vec::new(),
        maps: Vec::new(),
        graphs: Vec::new(),
        polygons: Vec::new(),
        preview,
        kind: ColorKind::Arrangement(pattern),
    };
    color.validate()?;
    Ok(color)
}

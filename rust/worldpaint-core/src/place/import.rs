//! Importing a place: the files read, the frame chosen, every feature classified and projected, the terrain cropped
//! and resampled, in that order; nothing is returned unless everything could be read and placed.

use super::classify::{kind_of, FeatureKind};
use super::elevation::{read_elevation_model, ElevationModel, MAX_HOLE_SHARE};
use super::footprint::{area, centroid, min_area_rectangle, rings_of};
use super::frame::{LocalProjection, PlaceFrame, MAX_EXTENT_DEGREES};
use super::imported::{
    InventoryTree, MappedArea, MappedBuilding, MappedRoad, MappedWaterway, NamedPlace, Place,
    PlaceReport, PlaceSources, TerrainReport,
};
use super::inventory::{read_tree_inventory, InventoryCoordinates, TreeInventory};
use super::layer::{lon_lat_box, read_map_layer, LonLat, LonLatShape, MapFeature, MapLayer};
use super::terrain::{lon_lat_box_of, model_box, native_spacing, resample, LocalBox};
use crate::error::{check, Error, Result};
use glam::DVec2;
use std::path::{Path, PathBuf};

/// Margin (m) of terrain kept around the place's features by default.
pub const DEFAULT_MARGIN: f64 = 200.0;

/// How a place is imported.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaceOptions {
    /// The lon/lat (degrees) of the frame's origin; `None`: the centre of the map layers' box (else of the elevation
    /// model's, else of a lon/lat inventory's). Give a first import's origin to make a second one line up with it.
    pub origin: Option<[f64; 2]>,
    /// The terrain's cell (m); `None`: the elevation model's own spacing, the finer of east–west and north–south.
    pub cell: Option<f64>,
    /// Terrain kept around the features (m); the terrain is clipped to the elevation model.
    pub margin: f64,
}

impl Default for PlaceOptions {
    fn default() -> Self {
        PlaceOptions {
            origin: None,
            cell: None,
            margin: DEFAULT_MARGIN,
        }
    }
}

/// The stages of an import, as progress names them, with their share of the whole.
const READING_LAYERS: (&str, f64, f64) = ("reading map layers", 0.0, 0.5);
const READING_ELEVATION: (&str, f64, f64) = ("reading the elevation model", 0.5, 0.15);
const READING_INVENTORY: (&str, f64, f64) = ("reading the tree inventory", 0.65, 0.05);
const PROJECTING: (&str, f64, f64) = ("projecting", 0.7, 0.15);
const RESAMPLING: (&str, f64, f64) = ("resampling the terrain", 0.85, 0.15);

/// Imports a place from OpenStreetMap layers (GeoJSON), an elevation model and a tree inventory, any of which may be
/// missing (but not all). `progress(fraction, stage)` is called between steps; returning false cancels
/// ([`Error::Cancelled`]).
pub fn import_place(
    layers: &[PathBuf],
    elevation: Option<&Path>,
    inventory: Option<&Path>,
    options: &PlaceOptions,
    progress: &(dyn Fn(f64, &'static str) -> bool + Sync),
) -> Result<Place> {
    check::non_negative("margin", options.margin)?;
    if let Some(cell) = options.cell {
        check::positive("terrain cell", cell)?;
    }
    if let Some(origin) = options.origin {
        PlaceFrame::centred_on(origin)?;
    }
    if layers.is_empty() && elevation.is_none() && inventory.is_none() {
        return Err(Error::invalid(
            "a place",
            "needs a map layer, an elevation model or a tree inventory",
        ));
    }
    let report = |(name, start, span): (&'static str, f64, f64), f: f64| -> Result<()> {
        if progress(start + span * f, name) {
            Ok(())
        } else {
            Err(Error::Cancelled)
        }
    };

    let mut read_layers = Vec::with_capacity(layers.len());
    for (k, path) in layers.iter().enumerate() {
        report(READING_LAYERS, k as f64 / layers.len() as f64)?;
        read_layers.push(read_map_layer(path)?);
    }
    report(READING_ELEVATION, 0.0)?;
    let mut model = elevation.map(read_elevation_model).transpose()?;
    report(READING_INVENTORY, 0.0)?;
    let trees = inventory.map(read_tree_inventory).transpose()?;

    report(PROJECTING, 0.0)?;
    let frame = frame_of(options, &read_layers, model.as_ref(), trees.as_ref())?;
    if let Some(model) = &model {
        for layer in &read_layers {
            overlaps(&layer.source, layer.lon_lat_box(), model)?;
        }
        if let Some(t) = trees
            .as_ref()
            .filter(|t| t.coordinates == InventoryCoordinates::LonLat)
        {
            overlaps(
                &t.source,
                lon_lat_box(t.trees.iter().map(|r| &r.position)),
                model,
            )?;
        }
    }
    let projection = frame.projection()?;
    let mut place = Place {
        sources: PlaceSources {
            layers: read_layers.iter().map(|l| l.source.clone()).collect(),
            elevation: model.as_ref().map(|m| m.source.clone()),
            inventory: trees.as_ref().map(|t| t.source.clone()),
        },
        frame,
        terrain: None,
        buildings: Vec::new(),
        roads: Vec::new(),
        waterways: Vec::new(),
        areas: Vec::new(),
        places: Vec::new(),
        trees: Vec::new(),
        report: PlaceReport::default(),
    };
    if let Some(projection) = &projection {
        for (k, layer) in read_layers.iter().enumerate() {
            report(PROJECTING, k as f64 / read_layers.len() as f64)?;
            add_layer(&mut place, layer, projection)?;
        }
    }
    if let Some(t) = trees {
        place.trees = trees_of(&t, projection.as_ref())?;
        place.report.trees_not_alive = t.not_alive;
        place.report.trees_unreadable = t.unreadable;
    }

    if let (Some(model), Some(projection)) = (model.as_mut(), projection.as_ref()) {
        report(RESAMPLING, 0.0)?;
        let (terrain, terrain_report) = terrain_of(&place, model, projection, options)?;
        place.terrain = Some(terrain);
        place.report.terrain = Some(terrain_report);
    }
    report(RESAMPLING, 1.0)?;
    Ok(place)
}

/// The frame of the options' origin, else centred on the place's lon/lat data (see [`PlaceOptions::origin`]).
fn frame_of(
    options: &PlaceOptions,
    layers: &[MapLayer],
    model: Option<&ElevationModel>,
    trees: Option<&TreeInventory>,
) -> Result<PlaceFrame> {
    let tree_points = trees
        .filter(|t| t.coordinates == InventoryCoordinates::LonLat)
        .into_iter()
        .flat_map(|t| t.trees.iter().map(|r| &r.position));
    let data_box = lon_lat_box(
        layers
            .iter()
            .flat_map(|l| l.features.iter().flat_map(|f| f.shape.points()))
            .chain(tree_points),
    );
    if let Some((lo, hi)) = data_box {
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if span > MAX_EXTENT_DEGREES {
            return Err(Error::invalid(
                "the place",
                format!(
                    "spans {span:.1}° (lon {:.3}..{:.3}, lat {:.3}..{:.3}): more than the {MAX_EXTENT_DEGREES}° one \
                     local frame holds",
                    lo[0], hi[0], lo[1], hi[1]
                ),
            ));
        }
    }
    if let (Some(origin), Some((lo, hi))) = (options.origin, data_box) {
        let far = (lo[0] - origin[0])
            .abs()
            .max((hi[0] - origin[0]).abs())
            .max((lo[1] - origin[1]).abs())
            .max((hi[1] - origin[1]).abs());
        if !(far <= MAX_EXTENT_DEGREES) {
            return Err(Error::invalid(
                "the place's origin",
                format!(
                    "({}, {}) lies {far:.1}° from the farthest point of the place, more than the \
                     {MAX_EXTENT_DEGREES}° one local frame holds",
                    origin[0], origin[1]
                ),
            ));
        }
    }
    let centre = |(lo, hi): (LonLat, LonLat)| [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let origin = options
        .origin
        .or(data_box.map(centre))
        .or(model.map(|m| centre(m.lon_lat_box())));
    match origin {
        Some(origin) => PlaceFrame::centred_on(origin),
        None => Ok(PlaceFrame::local()),
    }
}

/// Refuses a layer whose box does not meet the model's.
fn overlaps(
    source: &str,
    layer_box: Option<(LonLat, LonLat)>,
    model: &ElevationModel,
) -> Result<()> {
    let Some((lo, hi)) = layer_box else {
        return Ok(());
    };
    let (mlo, mhi) = model.lon_lat_box();
    if lo[0] <= mhi[0] && hi[0] >= mlo[0] && lo[1] <= mhi[1] && hi[1] >= mlo[1] {
        return Ok(());
    }
    Err(Error::invalid(
        source.to_string(),
        format!(
            "does not overlap the elevation model {}: the layer spans lon {:.4}..{:.4}, lat {:.4}..{:.4}, the model \
             lon {:.4}..{:.4}, lat {:.4}..{:.4}",
            model.source, lo[0], hi[0], lo[1], hi[1], mlo[0], mhi[0], mlo[1], mhi[1]
        ),
    ))
}

fn name_of(feature: &MapFeature) -> Option<String> {
    feature.tag("name").map(str::to_string)
}

/// Classifies and projects the features of a layer into the place.
fn add_layer(place: &mut Place, layer: &MapLayer, projection: &LocalProjection) -> Result<()> {
    place.report.features += layer.features.len() + layer.unreadable;
    place.report.unreadable += layer.unreadable;
    let lines = |lines: &[Vec<LonLat>]| -> Result<Vec<Vec<DVec2>>> {
        lines.iter().map(|l| projection.to_local(l)).collect()
    };
    let polygons = |polygons: &[Vec<Vec<LonLat>>]| -> Result<Vec<Vec<DVec2>>> {
        let projected: Result<Vec<Vec<Vec<DVec2>>>> = polygons.iter().map(|p| lines(p)).collect();
        Ok(rings_of(projected?))
    };
    for feature in &layer.features {
        let Some(kind) = kind_of(feature) else {
            place.report.left_out += 1;
            continue;
        };
        match (kind, &feature.shape) {
            (FeatureKind::Building(kind), LonLatShape::Polygons(p)) => {
                let footprint = polygons(p)?;
                if footprint.is_empty() {
                    place.report.unreadable += 1;
                    continue;
                }
                let outer: Vec<DVec2> = footprint
                    .iter()
                    .filter(|r| crate::geom::polygon_signed_area(r) > 0.0)
                    .flatten()
                    .copied()
                    .collect();
                let (length, width, orientation) = min_area_rectangle(&outer);
                place.buildings.push(MappedBuilding {
                    kind,
                    name: name_of(feature),
                    tags: feature.tags.clone(),
                    centroid: centroid(&footprint),
                    area: area(&footprint),
                    size: [length, width],
                    orientation,
                    footprint,
                });
            }
            (FeatureKind::Road(class), LonLatShape::Lines(l)) => {
                let highway = feature.tag("highway").unwrap_or("").to_string();
                for points in lines(l)? {
                    place.roads.push(MappedRoad {
                        class,
                        highway: highway.clone(),
                        name: name_of(feature),
                        points,
                    });
                }
            }
            (FeatureKind::Waterway, LonLatShape::Lines(l)) => {
                let kind = feature.tag("waterway").unwrap_or("").to_string();
                for points in lines(l)? {
                    place.waterways.push(MappedWaterway {
                        kind: kind.clone(),
                        name: name_of(feature),
                        points,
                    });
                }
            }
            (FeatureKind::Area(class), LonLatShape::Polygons(p)) => {
                let rings = polygons(p)?;
                if rings.is_empty() {
                    place.report.unreadable += 1;
                    continue;
                }
                place.areas.push(MappedArea {
                    class,
                    tag: area_tag(feature),
                    name: name_of(feature),
                    rings,
                });
            }
            (FeatureKind::Place, LonLatShape::Point(p)) => place.places.push(NamedPlace {
                kind: feature.tag("place").unwrap_or("").to_string(),
                name: name_of(feature),
                position: projection.point_to_local(*p)?,
            }),
            _ => place.report.left_out += 1,
        }
    }
    Ok(())
}

/// The tag an area was classed by, as `key=value` (in the order of the classes' precedence).
fn area_tag(feature: &MapFeature) -> String {
    let tag = match (
        feature.tag("natural"),
        feature.tag("waterway"),
        feature.tag("water"),
        feature.tag("landuse"),
    ) {
        (Some("water"), _, _, _) => Some(("natural", "water")),
        (_, Some("riverbank"), _, _) => Some(("waterway", "riverbank")),
        (_, _, Some(w), _) => Some(("water", w)),
        (_, _, _, Some(l)) => Some(("landuse", l)),
        (Some(n), _, _, _) => Some(("natural", n)),
        _ => None,
    };
    tag.map_or_else(String::new, |(k, v)| format!("{k}={v}"))
}

/// The inventory's trees in the frame's metres (local metres are the frame's own).
fn trees_of(
    inventory: &TreeInventory,
    projection: Option<&LocalProjection>,
) -> Result<Vec<InventoryTree>> {
    let positions: Vec<DVec2> = match (inventory.coordinates, projection) {
        (InventoryCoordinates::LocalMetres, _) => inventory
            .trees
            .iter()
            .map(|t| DVec2::from_array(t.position))
            .collect(),
        (InventoryCoordinates::LonLat, Some(p)) => {
            let lon_lat: Vec<LonLat> = inventory.trees.iter().map(|t| t.position).collect();
            p.to_local(&lon_lat)?
        }
        (InventoryCoordinates::LonLat, None) => {
            return Err(Error::invalid(
                inventory.source.clone(),
                "gives lon/lat positions but the place has no lon/lat frame",
            ))
        }
    };
    Ok(inventory
        .trees
        .iter()
        .zip(positions)
        .map(|(t, position)| InventoryTree {
            position,
            species: t.species.clone(),
            size: t.size,
        })
        .collect())
}

/// The local box of everything the place holds, `None` when it holds nothing.
fn features_box(place: &Place) -> Option<LocalBox> {
    let points = place
        .buildings
        .iter()
        .flat_map(|b| b.footprint.iter().flatten())
        .chain(place.roads.iter().flat_map(|r| &r.points))
        .chain(place.waterways.iter().flat_map(|w| &w.points))
        .chain(place.areas.iter().flat_map(|a| a.rings.iter().flatten()))
        .chain(place.places.iter().map(|p| &p.position))
        .chain(place.trees.iter().map(|t| &t.position));
    let mut out: Option<LocalBox> = None;
    for p in points {
        let b = out.get_or_insert((*p, *p));
        b.0 = b.0.min(*p);
        b.1 = b.1.max(*p);
    }
    out
}

/// The terrain under the place: the features' box and the margin, within the model; holes filled when few.
fn terrain_of(
    place: &Place,
    model: &mut ElevationModel,
    projection: &LocalProjection,
    options: &PlaceOptions,
) -> Result<(crate::terrain::Heightfield, TerrainReport)> {
    let within = model_box(model, projection)?;
    let bounds = match features_box(place) {
        Some((lo, hi)) => (
            (lo - options.margin).max(within.0),
            (hi + options.margin).min(within.1),
        ),
        None => within,
    };
    let spacing = native_spacing(model, projection)?;
    let cell = options.cell.unwrap_or(spacing.x.min(spacing.y));
    let (holes, samples) = if bounds.0.x < bounds.1.x && bounds.0.y < bounds.1.y {
        let (lo, hi) = lon_lat_box_of(bounds, projection)?;
        model.holes_in(lo, hi)
    } else {
        (0, 1)
    };
    let hole_share = holes as f64 / samples.max(1) as f64;
    if hole_share > MAX_HOLE_SHARE {
        return Err(Error::invalid(
            format!("the elevation model {}", model.source),
            format!(
                "has no data in {:.1} % of its samples under the place ({holes} of {samples}); holes are filled only \
                 up to {:.0} %",
                100.0 * hole_share,
                100.0 * MAX_HOLE_SHARE
            ),
        ));
    }
    let holes_filled = model.fill_holes()?;
    let terrain = resample(model, projection, bounds, cell)?;
    Ok((
        terrain,
        TerrainReport {
            source_size: [model.ncols, model.nrows],
            source_spacing: spacing.to_array(),
            holes_filled,
            hole_share,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_tags() {
        let f = |tags: &[(&str, &str)]| MapFeature {
            tags: tags
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            shape: LonLatShape::Point([0.0, 0.0]),
        };
        assert_eq!(area_tag(&f(&[("landuse", "forest")])), "landuse=forest");
        assert_eq!(
            area_tag(&f(&[("natural", "water"), ("landuse", "x")])),
            "natural=water"
        );
        assert_eq!(area_tag(&f(&[("natural", "wood")])), "natural=wood");
        assert_eq!(
            area_tag(&f(&[("waterway", "riverbank")])),
            "waterway=riverbank"
        );
    }
}

//! What a map feature is, from its OpenStreetMap tags: a building of a type, a road of a class, a waterway, an area
//! of a class or a named place. Every tag value outside the lists below falls to `Other`, so nothing mapped is lost
//! and the Blender side may leave out what it does not draw.

use super::layer::MapFeature;
use serde::{Deserialize, Serialize};

/// The type of a building, from `building=*`, else from what the building holds (`amenity`, `shop`, `tourism`).
///
/// | type | `building=` | or, on `building=yes` |
/// |---|---|---|
/// | house | house, detached, semidetached_house, terrace, residential, bungalow, cabin, static_caravan | |
/// | farm | farm (a farmhouse) | |
/// | church | church, chapel, cathedral, religious, shrine, temple, mosque, synagogue | `amenity=place_of_worship` |
/// | barn | barn, farm_auxiliary, stable, cowshed, sty, greenhouse, silo | |
/// | shed | shed, hut, roof, allotment_house | |
/// | apartments | apartments, dormitory | |
/// | industrial | industrial, warehouse, factory, manufacture, hangar, storage_tank, service, transformer_tower | |
/// | commercial | commercial, retail, office, supermarket, kiosk, hotel | `shop=*`, `tourism=hotel`, an `amenity` of trade (restaurant, pub, cafe, fuel, bank...) |
/// | garage | garage, garages, carport | |
/// | other | yes and anything else (public, school, hospital, ...) | |
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BuildingType {
    /// A dwelling for one household.
    House,
    /// A farmhouse.
    Farm,
    /// A place of worship.
    Church,
    /// A farm building for animals, crops or machines.
    Barn,
    /// A small outbuilding.
    Shed,
    /// A dwelling for several households.
    Apartments,
    /// Industry and storage.
    Industrial,
    /// Shops, offices, inns.
    Commercial,
    /// Cars.
    Garage,
    /// Any other or unknown use (most of OpenStreetMap's buildings are `building=yes`).
    Other,
}

/// The class of a road or path, from `highway=*`.
///
/// | class | `highway=` |
/// |---|---|
/// | major | motorway, trunk, primary, secondary and their links |
/// | minor | tertiary, unclassified, road and their links |
/// | residential | residential, living_street, service |
/// | track | track |
/// | path | path, footway, cycleway, bridleway, steps, pedestrian, via_ferrata |
/// | other | anything else (construction, proposed, platform, raceway, ...) |
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RoadClass {
    /// Roads between towns.
    Major,
    /// Roads between villages.
    Minor,
    /// Streets and service ways a house is served by.
    Residential,
    /// Farm and forest tracks.
    Track,
    /// Ways for people on foot, on bicycles, on horses.
    Path,
    /// Ways of no class above.
    Other,
}

/// The class of an area, from `landuse=*`, the water tags or natural land cover.
///
/// | class | tags |
/// |---|---|
/// | water | `natural=water`, `waterway=riverbank`, `landuse=reservoir` or `basin`, `water=*` |
/// | residential | `landuse=residential` |
/// | commercial | `landuse=commercial`, `retail` |
/// | industrial | `landuse=industrial`, `quarry`, `landfill`, `railway`, `construction`, `brownfield` |
/// | farmland | `landuse=farmland`, `greenhouse_horticulture` |
/// | meadow | `landuse=meadow`, `grass`, `village_green`, `greenfield`, `recreation_ground`; `natural=grassland`, `heath` |
/// | orchard | `landuse=orchard`, `vineyard`, `allotments`, `plant_nursery` |
/// | forest | `landuse=forest`; `natural=wood`, `scrub` |
/// | farmyard | `landuse=farmyard`, `farm` |
/// | cemetery | `landuse=cemetery`, `religious` |
/// | wetland | `natural=wetland` |
/// | other | any other `landuse` |
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AreaClass {
    /// Lakes, ponds, reservoirs, river areas.
    Water,
    /// Where people live.
    Residential,
    /// Shops and offices.
    Commercial,
    /// Industry, quarries, railways.
    Industrial,
    /// Fields.
    Farmland,
    /// Meadows and grass.
    Meadow,
    /// Orchards, vineyards, allotments.
    Orchard,
    /// Woods.
    Forest,
    /// Farm yards.
    Farmyard,
    /// Cemeteries.
    Cemetery,
    /// Marshes and bogs.
    Wetland,
    /// Any other land use.
    Other,
}

macro_rules! names {
    ($t:ty { $($v:ident => $s:literal),* $(,)? }) => {
        impl $t {
            /// Every value, in order.
            pub const ALL: &'static [$t] = &[$(<$t>::$v),*];

            /// The name as files and the bindings write it.
            pub fn name(self) -> &'static str {
                match self {
                    $(<$t>::$v => $s),*
                }
            }
        }
    };
}

names!(BuildingType { House => "house", Farm => "farm", Church => "church", Barn => "barn", Shed => "shed",
    Apartments => "apartments", Industrial => "industrial", Commercial => "commercial", Garage => "garage",
    Other => "other" });
names!(RoadClass { Major => "major", Minor => "minor", Residential => "residential", Track => "track",
    Path => "path", Other => "other" });
names!(AreaClass { Water => "water", Residential => "residential", Commercial => "commercial",
    Industrial => "industrial", Farmland => "farmland", Meadow => "meadow", Orchard => "orchard",
    Forest => "forest", Farmyard => "farmyard", Cemetery => "cemetery", Wetland => "wetland", Other => "other" });

/// What a feature is, in this order of precedence: a building (`building=*` other than `no`, on a polygon), a road
/// (`highway=*` on a line), a waterway (a flowing `waterway=*` on a line), an area (water, land use or land cover, on
/// a polygon), a place (`place=*` on a point); else nothing the import keeps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum FeatureKind {
    Building(BuildingType),
    Road(RoadClass),
    Waterway,
    Area(AreaClass),
    Place,
}

/// `waterway` values of flowing water drawn as lines (dams, weirs and lock gates are not).
const FLOWING: [&str; 10] = [
    "river",
    "stream",
    "canal",
    "drain",
    "ditch",
    "brook",
    "tidal_channel",
    "rapids",
    "fish_pass",
    "canoe_pass",
];

pub(crate) fn kind_of(feature: &MapFeature) -> Option<FeatureKind> {
    use super::layer::LonLatShape as S;
    let tag = |k: &str| feature.tag(k);
    match &feature.shape {
        S::Polygons(_) => {
            if let Some(b) = tag("building").filter(|b| *b != "no") {
                return Some(FeatureKind::Building(building_type(b, feature)));
            }
            area_class(feature).map(FeatureKind::Area)
        }
        S::Lines(_) => {
            if let Some(h) = tag("highway") {
                return Some(FeatureKind::Road(road_class(h)));
            }
            tag("waterway")
                .filter(|w| FLOWING.contains(w))
                .map(|_| FeatureKind::Waterway)
        }
        S::Point(_) => tag("place").map(|_| FeatureKind::Place),
    }
}

fn building_type(building: &str, feature: &MapFeature) -> BuildingType {
    use BuildingType as B;
    match building {
        "house" | "detached" | "semidetached_house" | "terrace" | "residential" | "bungalow"
        | "cabin" | "static_caravan" => B::House,
        "farm" => B::Farm,
        "church" | "chapel" | "cathedral" | "religious" | "shrine" | "temple" | "mosque"
        | "synagogue" => B::Church,
        "barn" | "farm_auxiliary" | "stable" | "cowshed" | "sty" | "greenhouse" | "silo" => B::Barn,
        "shed" | "hut" | "roof" | "allotment_house" => B::Shed,
        "apartments" | "dormitory" => B::Apartments,
        "industrial" | "warehouse" | "factory" | "manufacture" | "hangar" | "storage_tank"
        | "service" | "transformer_tower" => B::Industrial,
        "commercial" | "retail" | "office" | "supermarket" | "kiosk" | "hotel" => B::Commercial,
        "garage" | "garages" | "carport" => B::Garage,
        _ => {
            let amenity = feature.tag("amenity").unwrap_or("");
            if amenity == "place_of_worship" {
                B::Church
            } else if feature.tag("shop").is_some()
                || feature.tag("tourism") == Some("hotel")
                || matches!(
                    amenity,
                    "restaurant"
                        | "pub"
                        | "cafe"
                        | "bar"
                        | "fast_food"
                        | "fuel"
                        | "bank"
                        | "pharmacy"
                        | "marketplace"
                )
            {
                B::Commercial
            } else {
                B::Other
            }
        }
    }
}

fn road_class(highway: &str) -> RoadClass {
    use RoadClass as R;
    match highway {
        "motorway" | "motorway_link" | "trunk" | "trunk_link" | "primary" | "primary_link"
        | "secondary" | "secondary_link" => R::Major,
        "tertiary" | "tertiary_link" | "unclassified" | "road" => R::Minor,
        "residential" | "living_street" | "service" => R::Residential,
        "track" => R::Track,
        "path" | "footway" | "cycleway" | "bridleway" | "steps" | "pedestrian" | "via_ferrata" => {
            R::Path
        }
        _ => R::Other,
    }
}

fn area_class(feature: &MapFeature) -> Option<AreaClass> {
    use AreaClass as A;
    let landuse = feature.tag("landuse");
    let natural = feature.tag("natural");
    if natural == Some("water")
        || feature.tag("waterway") == Some("riverbank")
        || matches!(landuse, Some("reservoir" | "basin"))
        || feature.tag("water").is_some()
    {
        return Some(A::Water);
    }
    if let Some(landuse) = landuse {
        return Some(match landuse {
            "residential" => A::Residential,
            "commercial" | "retail" => A::Commercial,
            "industrial" | "quarry" | "landfill" | "railway" | "construction" | "brownfield" => {
                A::Industrial
            }
            "farmland" | "greenhouse_horticulture" => A::Farmland,
            "meadow" | "grass" | "village_green" | "greenfield" | "recreation_ground" => A::Meadow,
            "orchard" | "vineyard" | "allotments" | "plant_nursery" => A::Orchard,
            "forest" => A::Forest,
            "farmyard" | "farm" => A::Farmyard,
            "cemetery" | "religious" => A::Cemetery,
            _ => A::Other,
        });
    }
    match natural {
        Some("wood" | "scrub") => Some(A::Forest),
        Some("grassland" | "heath") => Some(A::Meadow),
        Some("wetland") => Some(A::Wetland),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::place::layer::LonLatShape;

    fn feature(shape: LonLatShape, tags: &[(&str, &str)]) -> MapFeature {
        MapFeature {
            tags: tags
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            shape,
        }
    }

    #[test]
    fn tags_make_kinds() {
        let square = LonLatShape::Polygons(vec![vec![vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 0.0],
        ]]]);
        let line = LonLatShape::Lines(vec![vec![[0.0, 0.0], [1.0, 0.0]]]);
        let kind =
            |shape: &LonLatShape, tags: &[(&str, &str)]| kind_of(&feature(shape.clone(), tags));
        use FeatureKind as K;
        assert_eq!(
            kind(&square, &[("building", "yes")]),
            Some(K::Building(BuildingType::Other))
        );
        assert_eq!(
            kind(
                &square,
                &[("building", "yes"), ("amenity", "place_of_worship")]
            ),
            Some(K::Building(BuildingType::Church))
        );
        assert_eq!(
            kind(&square, &[("building", "cowshed")]),
            Some(K::Building(BuildingType::Barn))
        );
        assert_eq!(
            kind(&line, &[("highway", "secondary_link")]),
            Some(K::Road(RoadClass::Major))
        );
        assert_eq!(
            kind(&line, &[("highway", "construction")]),
            Some(K::Road(RoadClass::Other))
        );
        assert_eq!(kind(&line, &[("waterway", "stream")]), Some(K::Waterway));
        assert_eq!(kind(&line, &[("waterway", "dam")]), None);
        assert_eq!(
            kind(&square, &[("landuse", "reservoir")]),
            Some(K::Area(AreaClass::Water))
        );
        assert_eq!(
            kind(&square, &[("natural", "wood")]),
            Some(K::Area(AreaClass::Forest))
        );
        assert_eq!(kind(&square, &[("amenity", "parking")]), None);
        assert_eq!(
            kind(&LonLatShape::Point([0.0, 0.0]), &[("place", "hamlet")]),
            Some(K::Place)
        );
    }
}

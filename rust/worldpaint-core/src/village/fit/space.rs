//! The parameters a village type is learned over, and their coordinates for the optimizer.
//!
//! Each parameter is a [`Dimension`]: a bounded range, read on a log scale where the parameter is a scale or a
//! cost (distances, ratios, road cost weights), linearly where it is a weight or a share. The optimizer moves in
//! unbounded coordinates; each is folded back into `[0, 1]` by reflection at the bounds (a triangle wave), then
//! mapped onto the range: every point the optimizer asks about is a valid village type, and no penalty is needed.
//!
//! Per building type learned (the types of the base village type that the scenario builds many of: houses and farms),
//! the interest weights of sociability, accessibility, slope and domination (the criteria a real village's layout tells
//! about), the sociability and accessibility shapes (`λ_min`, and `λ_0`, `λ_max` as ratios of the one before, so that
//! `λ_min ≤ λ_0 ≤ λ_max` always holds), the parcel's road reach, the footprint's aspect (width along the road over
//! depth) and scale and the share of footprints turned; for all of them, the share of footprints skewed from their road
//! (starting from the real village's share of buildings neither along nor across their road) and the share of buildings
//! seeded beside a standing one (starting from the real village's close pairs, see [`Starts`]); for the village type's
//! roads, the slope, curvature and re-use weights, the grade limit, the move mask's radius, the longest cycle road and
//! the street length laid past a new building; for the scenario, the buildings asked for per real building (the
//! generator loses some in narrow parcels) and the share of farms.

use super::objective::Figure;
use crate::village::encyclopedia::{Encyclopedia, FootprintSize, RoadParams, Shape, VillageType};
use crate::village::figures::{VillageFigures, ORIENTATION_BINS};
use crate::{Error, Result};
use std::collections::BTreeMap;

/// What one coordinate sets.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Knob {
    /// An interest weight of a building type: 0 sociability, 2 accessibility, 3 slope, 6 domination (the
    /// order of `InterestWeights::as_array`).
    Weight(String, usize),
    /// `λ_min` of the sociability shape (m).
    SociabilityMin(String),
    /// `λ_0 / λ_min` of the sociability shape.
    SociabilityZero(String),
    /// `λ_max / λ_0` of the sociability shape.
    SociabilityMax(String),
    /// `λ_min` of the accessibility shape (m).
    AccessibilityMin(String),
    /// `λ_0 / λ_min` of the accessibility shape.
    AccessibilityZero(String),
    /// `λ_max / λ_0` of the accessibility shape.
    AccessibilityMax(String),
    /// The parcel conquest's road reach (m).
    RoadReach(String),
    /// The footprint's width along the road over its depth (both sizes, smallest and largest, keep their area).
    FootprintAspect(String),
    /// The footprint's sides over the base's.
    FootprintScale(String),
    /// The share of footprints turned (width and depth swapped).
    TurnedShare(String),
    /// The share of footprints skewed from their road, one for every learned building type.
    SkewShare,
    /// The share of buildings seeded beside a standing one, one for every learned building type.
    ClusterShare,
    RoadSlopeWeight,
    RoadCurvatureWeight,
    RoadReuseWeight,
    RoadMaxGrade,
    RoadMaskRadius,
    RoadCycleMaxLength,
    RoadStreetLength,
    /// Buildings asked of the generator per building of the real village.
    CountFactor,
    /// Share of the buildings asked for that are farms.
    FarmShare,
}

/// A bounded parameter.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Dimension {
    pub(crate) knob: Knob,
    pub(crate) low: f64,
    pub(crate) high: f64,
    /// Read on a log scale (both bounds above 0).
    pub(crate) log: bool,
}

impl Dimension {
    fn new(knob: Knob, low: f64, high: f64, log: bool) -> Dimension {
        Dimension {
            knob,
            low,
            high,
            log,
        }
    }

    /// The value at unit coordinate `u` in `[0, 1]`.
    pub(crate) fn value(&self, u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        if self.log {
            (self.low.ln() + u * (self.high.ln() - self.low.ln())).exp()
        } else {
            self.low + u * (self.high - self.low)
        }
    }

    /// The unit coordinate of `v`, clamped into the range.
    pub(crate) fn unit(&self, v: f64) -> f64 {
        let v = v.clamp(self.low, self.high);
        let u = if self.log {
            (v.ln() - self.low.ln()) / (self.high.ln() - self.low.ln())
        } else {
            (v - self.low) / (self.high - self.low)
        };
        if u.is_finite() {
            u
        } else {
            0.5
        }
    }
}

/// An unbounded coordinate folded into `[0, 1]` by reflection at 0 and 1.
pub(crate) fn fold(x: f64) -> f64 {
    if !x.is_finite() {
        return 0.5;
    }
    let t = x.rem_euclid(2.0);
    if t > 1.0 {
        2.0 - t
    } else {
        t
    }
}

/// The learned village type and scenario counts a point of the space stands for.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Candidate {
    pub(crate) village_type: VillageType,
    pub(crate) count_factor: f64,
    pub(crate) farm_share: f64,
}

/// The parameter space around a base village type.
#[derive(Clone, Debug)]
pub(crate) struct ParameterSpace {
    pub(crate) dimensions: Vec<Dimension>,
    base: VillageType,
    roads: RoadParams,
    /// The base's footprint sizes of the building types learned.
    footprints: BTreeMap<String, FootprintSize>,
    /// The shares the search starts from (its count factor is 1: the real village's count).
    starts: Starts,
}

/// The shares the search starts from, not the base type's: the scenario's farms, and the skewed footprints and
/// clustered buildings read from the real village (the shipped types have none of either).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Starts {
    pub(crate) farm_share: f64,
    pub(crate) skew_share: f64,
    pub(crate) cluster_share: f64,
}

impl Starts {
    /// The starts for a real village of `figures` with `farm_share` of farms.
    pub(crate) fn of(figures: &VillageFigures, farm_share: f64) -> Starts {
        Starts {
            farm_share,
            skew_share: skew_share_of(&figures.orientation_to_road),
            cluster_share: cluster_share_of(
                figures.layout.share_within_20m,
                figures.buildings_per_hectare,
            ),
        }
    }
}

/// The share of buildings seeded beside another, read from the share `within_20m` of buildings with another
/// within 20 m at `per_hectare` buildings: the excess over buildings scattered at random at that density
/// (`1 - exp(-λπ 20²)`), as though each building seeded beside another made a pair of them.
pub(crate) fn cluster_share_of(within_20m: f64, per_hectare: f64) -> f64 {
    let scattered = 1.0 - (-per_hectare / 1e4 * std::f64::consts::PI * 400.0).exp();
    (0.5 * (within_20m - scattered)).clamp(0.0, 1.0)
}

/// The share of buildings standing at any angle to their road, read from the histogram of `orientation` to the
/// road: those of the bins neither along nor across the road, as though spread evenly over every bin.
pub(crate) fn skew_share_of(orientation: &[f64; ORIENTATION_BINS]) -> f64 {
    let between: f64 = orientation[1..ORIENTATION_BINS - 1].iter().sum();
    (between * ORIENTATION_BINS as f64 / (ORIENTATION_BINS - 2) as f64).clamp(0.0, 1.0)
}

/// Building types learned when the base village type has them.
pub(crate) const LEARNED_BUILDINGS: [&str; 2] = ["house", "farm"];

/// The grade limit's step at the end of a fit, a share of its value (see [`ParameterSpace::grade_steps`]).
const GRADE_STEP: f64 = 0.2;

impl ParameterSpace {
    /// The space around `base_type` of `enc`, starting from its values and from `starts`.
    pub(crate) fn new(
        enc: &Encyclopedia,
        base_type: &str,
        starts: Starts,
    ) -> Result<ParameterSpace> {
        let base = enc.village_types.get(base_type).ok_or_else(|| {
            Error::invalid(
                "base village type",
                format!("'{base_type}' is not in the encyclopedia"),
            )
        })?;
        let learned: Vec<String> = LEARNED_BUILDINGS
            .iter()
            .filter(|b| base.buildings.contains_key(**b))
            .map(|b| b.to_string())
            .collect();
        if !learned.iter().any(|b| b == "house") {
            return Err(Error::invalid(
                "base village type",
                format!("'{base_type}' builds no houses"),
            ));
        }
        let mut dimensions = Vec::new();
        let mut footprints = BTreeMap::new();
        for b in &learned {
            let kind = enc.buildings.get(b).ok_or_else(|| {
                Error::invalid("base village type", format!("'{b}' is not a building type"))
            })?;
            footprints.insert(b.clone(), base.buildings[b].footprint_sizes(kind));
            for criterion in [0, 2, 3, 6] {
                dimensions.push(Dimension::new(
                    Knob::Weight(b.clone(), criterion),
                    0.0,
                    1.0,
                    false,
                ));
            }
            dimensions.extend([
                Dimension::new(Knob::SociabilityMin(b.clone()), 3.0, 60.0, true),
                Dimension::new(Knob::SociabilityZero(b.clone()), 1.05, 4.0, true),
                Dimension::new(Knob::SociabilityMax(b.clone()), 1.2, 8.0, true),
                Dimension::new(Knob::AccessibilityMin(b.clone()), 2.0, 40.0, true),
                Dimension::new(Knob::AccessibilityZero(b.clone()), 1.05, 4.0, true),
                Dimension::new(Knob::AccessibilityMax(b.clone()), 1.2, 8.0, true),
                Dimension::new(Knob::RoadReach(b.clone()), 4.0, 30.0, true),
                Dimension::new(Knob::FootprintAspect(b.clone()), 0.4, 3.0, true),
                Dimension::new(Knob::FootprintScale(b.clone()), 0.7, 1.6, true),
                Dimension::new(Knob::TurnedShare(b.clone()), 0.0, 1.0, false),
            ]);
        }
        dimensions.extend([
            Dimension::new(Knob::SkewShare, 0.0, 1.0, false),
            Dimension::new(Knob::ClusterShare, 0.0, 1.0, false),
            Dimension::new(Knob::RoadSlopeWeight, 0.2, 20.0, true),
            Dimension::new(Knob::RoadCurvatureWeight, 0.2, 20.0, true),
            Dimension::new(Knob::RoadReuseWeight, 0.02, 0.6, true),
            Dimension::new(Knob::RoadMaxGrade, 0.08, 0.35, false),
            Dimension::new(Knob::RoadMaskRadius, 1.0, 4.0, false),
            Dimension::new(Knob::RoadCycleMaxLength, 0.0, 500.0, false),
            Dimension::new(Knob::RoadStreetLength, 0.0, 120.0, false),
            Dimension::new(Knob::CountFactor, 0.8, 2.0, true),
            Dimension::new(Knob::FarmShare, 0.0, 0.6, false),
        ]);
        Ok(ParameterSpace {
            dimensions,
            base: base.clone(),
            roads: enc.road_params(base_type),
            footprints,
            starts,
        })
    }

    /// The unit coordinates of the base village type (the search's start).
    pub(crate) fn start(&self) -> Vec<f64> {
        self.dimensions
            .iter()
            .map(|d| d.unit(self.read(&d.knob)))
            .collect()
    }

    /// The base's value of a knob.
    fn read(&self, knob: &Knob) -> f64 {
        let p = |b: &String| &self.base.buildings[b];
        let ratio = |a: f64, b: f64| if a > 0.0 { b / a } else { f64::INFINITY };
        let r = &self.roads;
        match knob {
            Knob::Weight(b, c) => p(b).weights.as_array()[*c],
            Knob::SociabilityMin(b) => p(b).sociability.min,
            Knob::SociabilityZero(b) => ratio(p(b).sociability.min, p(b).sociability.zero),
            Knob::SociabilityMax(b) => ratio(p(b).sociability.zero, p(b).sociability.max),
            Knob::AccessibilityMin(b) => p(b).accessibility.min,
            Knob::AccessibilityZero(b) => ratio(p(b).accessibility.min, p(b).accessibility.zero),
            Knob::AccessibilityMax(b) => ratio(p(b).accessibility.zero, p(b).accessibility.max),
            Knob::RoadReach(b) => p(b).parcel.road_reach,
            Knob::FootprintAspect(b) => {
                let max = self.footprints[b].max;
                max[0] / max[1]
            }
            Knob::FootprintScale(_) => 1.0,
            Knob::TurnedShare(b) => p(b).turned_share,
            Knob::SkewShare => self.starts.skew_share,
            Knob::ClusterShare => self.starts.cluster_share,
            Knob::RoadSlopeWeight => r.slope_weight,
            Knob::RoadCurvatureWeight => r.curvature_weight,
            Knob::RoadReuseWeight => r.reuse_weight,
            Knob::RoadMaxGrade => r.max_grade,
            Knob::RoadMaskRadius => r.mask_radius as f64,
            Knob::RoadCycleMaxLength => r.cycle_max_length,
            Knob::RoadStreetLength => r.street_length,
            Knob::CountFactor => 1.0,
            Knob::FarmShare => self.starts.farm_share,
        }
    }

    /// The value of `knob` at optimizer coordinates `x` (the base's where the space has no coordinate for it).
    fn value_at(&self, x: &[f64], knob: &Knob) -> f64 {
        self.dimensions
            .iter()
            .zip(x)
            .find(|(d, _)| d.knob == *knob)
            .map_or_else(|| self.read(knob), |(d, xi)| d.value(fold(*xi)))
    }

    /// The point `x` with its orientation knobs moved by one step towards `real`'s histogram of the orientation
    /// to the road from the histogram `grown` its villages stood at: the skewed share by the share between along
    /// and across that is missing (a skewed footprint stands in every bin alike, so in those between by four in
    /// six), and each learned type's turned share by the share of the aligned buildings that stand across their
    /// road (turning a footprint wider along its road than deep stands it across; one deeper than wide, along).
    /// The search leaves these knobs where the other figures' noise drowns them; their effect on the histogram
    /// is direct.
    pub(crate) fn orientation_step(
        &self,
        x: &[f64],
        grown: &[f64; ORIENTATION_BINS],
        real: &[f64; ORIENTATION_BINS],
    ) -> Vec<f64> {
        let value = |knob: &Knob| self.value_at(x, knob);
        let between = |h: &[f64; ORIENTATION_BINS]| h[1..ORIENTATION_BINS - 1].iter().sum::<f64>();
        let across = |h: &[f64; ORIENTATION_BINS]| {
            let aligned = h[0] + h[ORIENTATION_BINS - 1];
            (aligned > 0.0).then(|| h[ORIENTATION_BINS - 1] / aligned)
        };
        let skew = (between(real) - between(grown)) * ORIENTATION_BINS as f64
            / (ORIENTATION_BINS - 2) as f64;
        // of the aligned, the skewed share stands one in six along and across alike: turning moves the others
        let s = value(&Knob::SkewShare);
        let unskewed = ((1.0 - s) / (1.0 - s * 2.0 / 3.0)).max(0.1);
        let turn = across(real)
            .zip(across(grown))
            .map(|(r, g)| (r - g) / unskewed);
        self.dimensions
            .iter()
            .zip(x)
            .map(|(d, xi)| {
                let v = d.value(fold(*xi));
                match &d.knob {
                    Knob::SkewShare => d.unit(v + skew),
                    Knob::TurnedShare(b) => match turn {
                        Some(t) if value(&Knob::FootprintAspect(b.clone())) >= 1.0 => d.unit(v + t),
                        Some(t) => d.unit(v - t),
                        None => *xi,
                    },
                    _ => *xi,
                }
            })
            .collect()
    }

    /// The point `x` with its roads' grade limit moved towards `real` hairpins per km from the `grown` ones its
    /// villages made (pooled over seeds), by one and by two steps of [`GRADE_STEP`]: lower where they made too few,
    /// higher where too many; none within a quarter of the figure's band, and none past the range's end. Hairpins
    /// are where a road too steep to climb straight turns back on itself, so the limit moves them most, within a
    /// narrow range (on the hamlet's terrain near les Bons every shipped type made about the real rate at 0.15, four
    /// times it at 0.12 and none from 0.20 on): a range the search, moving it with every other coordinate, steps
    /// over easily, and a fit that made none gives no slope to aim by.
    pub(crate) fn grade_steps(&self, x: &[f64], grown: f64, real: f64) -> Vec<Vec<f64>> {
        let band = Figure::HairpinsPerKm.tolerance();
        if !(grown.is_finite() && real.is_finite()) || (grown - real).abs() <= 0.25 * band {
            return Vec::new();
        }
        let ratio = if grown < real {
            1.0 - GRADE_STEP
        } else {
            1.0 / (1.0 - GRADE_STEP)
        };
        let grade = |x: &[f64]| self.value_at(x, &Knob::RoadMaxGrade);
        let mut steps: Vec<Vec<f64>> = Vec::new();
        for factor in [ratio, ratio * ratio] {
            let stepped: Vec<f64> = self
                .dimensions
                .iter()
                .zip(x)
                .map(|(d, xi)| match d.knob {
                    Knob::RoadMaxGrade => d.unit(d.value(fold(*xi)) * factor),
                    _ => *xi,
                })
                .collect();
            let last = steps.last().map_or(x, |s| s.as_slice());
            if grade(&stepped) != grade(last) {
                steps.push(stepped);
            }
        }
        steps
    }

    /// The candidate at optimizer coordinates `x` (one per dimension, unbounded: folded into `[0, 1]`).
    pub(crate) fn candidate(&self, x: &[f64]) -> Candidate {
        let mut t = self.base.clone();
        let (mut count_factor, mut farm_share) = (1.0, self.starts.farm_share);
        // shapes are set from their three coordinates together, after the loop
        let mut shapes: Vec<(String, bool, [f64; 3])> = Vec::new();
        let mut shape = |b: &String, accessibility: bool, k: usize, v: f64| match shapes
            .iter_mut()
            .find(|s| s.0 == *b && s.1 == accessibility)
        {
            Some(s) => s.2[k] = v,
            None => {
                let placement = &self.base.buildings[b];
                let s = if accessibility {
                    placement.accessibility
                } else {
                    placement.sociability
                };
                let mut values = [s.min, s.zero / s.min.max(1e-9), s.max / s.zero.max(1e-9)];
                values[k] = v;
                shapes.push((b.clone(), accessibility, values));
            }
        };
        // footprints are set from their aspect and scale together, after the loop
        let mut sizes: BTreeMap<String, (Option<f64>, f64)> = BTreeMap::new();
        let roads = &mut t.roads;
        for (d, xi) in self.dimensions.iter().zip(x) {
            let v = d.value(fold(*xi));
            match &d.knob {
                Knob::Weight(b, c) => {
                    // the knobs name only building types the base has (`ParameterSpace::new`)
                    if let Some(p) = t.buildings.get_mut(b) {
                        let w = &mut p.weights;
                        match c {
                            0 => w.sociability = v,
                            2 => w.accessibility = v,
                            3 => w.slope = v,
                            _ => w.domination = v,
                        }
                    }
                }
                Knob::SociabilityMin(b) => shape(b, false, 0, v),
                Knob::SociabilityZero(b) => shape(b, false, 1, v),
                Knob::SociabilityMax(b) => shape(b, false, 2, v),
                Knob::AccessibilityMin(b) => shape(b, true, 0, v),
                Knob::AccessibilityZero(b) => shape(b, true, 1, v),
                Knob::AccessibilityMax(b) => shape(b, true, 2, v),
                Knob::RoadReach(b) => {
                    if let Some(p) = t.buildings.get_mut(b) {
                        p.parcel.road_reach = v;
                    }
                }
                Knob::FootprintAspect(b) => {
                    sizes.entry(b.clone()).or_insert((None, 1.0)).0 = Some(v)
                }
                Knob::FootprintScale(b) => sizes.entry(b.clone()).or_insert((None, 1.0)).1 = v,
                Knob::TurnedShare(b) => {
                    if let Some(p) = t.buildings.get_mut(b) {
                        p.turned_share = v;
                    }
                }
                Knob::SkewShare | Knob::ClusterShare => {
                    for b in self.footprints.keys() {
                        if let Some(p) = t.buildings.get_mut(b) {
                            if d.knob == Knob::SkewShare {
                                p.skew_share = v;
                            } else {
                                p.cluster_share = v;
                            }
                        }
                    }
                }
                Knob::RoadSlopeWeight => roads.slope_weight = Some(v),
                Knob::RoadCurvatureWeight => roads.curvature_weight = Some(v),
                Knob::RoadReuseWeight => roads.reuse_weight = Some(v),
                Knob::RoadMaxGrade => roads.max_grade = Some(v),
                Knob::RoadMaskRadius => roads.mask_radius = Some(v.round() as u32),
                Knob::RoadCycleMaxLength => roads.cycle_max_length = Some(v),
                Knob::RoadStreetLength => roads.street_length = Some(v),
                Knob::CountFactor => count_factor = v,
                Knob::FarmShare => farm_share = v,
            }
        }
        for (b, accessibility, [min, zero, max]) in shapes {
            let s = Shape {
                min,
                zero: min * zero,
                max: min * zero * max,
            };
            if let Some(p) = t.buildings.get_mut(&b) {
                if accessibility {
                    p.accessibility = s;
                } else {
                    p.sociability = s;
                }
            }
        }
        for (b, (aspect, scale)) in sizes {
            let base = self.footprints[&b];
            let turn = |side: [f64; 2]| {
                let area = side[0] * side[1] * scale * scale;
                let a = aspect.unwrap_or(side[0] / side[1]);
                [(area * a).sqrt(), (area / a).sqrt()]
            };
            let (min, max) = (turn(base.min), turn(base.max));
            // the smallest never above the largest, side by side
            let min = [min[0].min(max[0]), min[1].min(max[1])];
            if let Some(p) = t.buildings.get_mut(&b) {
                p.footprint = Some(FootprintSize { min, max });
            }
        }
        Candidate {
            village_type: t,
            count_factor,
            farm_share,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ENCYCLOPEDIA: &str = include_str!("../../../../../assets/villages/encyclopedia.json");

    fn enc() -> Encyclopedia {
        Encyclopedia::from_json(ENCYCLOPEDIA).expect("the shipped encyclopedia")
    }

    /// The space around the shipped highland type, from 20 % farms, 30 % skewed and 10 % clustered.
    fn highland() -> ParameterSpace {
        let starts = Starts {
            farm_share: 0.2,
            skew_share: 0.3,
            cluster_share: 0.1,
        };
        ParameterSpace::new(&enc(), "highland", starts).expect("highland")
    }

    #[test]
    fn the_start_is_the_base_type_and_every_point_is_a_valid_type() {
        let enc = enc();
        let space = highland();
        assert_eq!(
            space.footprints.keys().collect::<Vec<_>>(),
            ["farm", "house"]
        );
        assert_eq!(space.dimensions.len(), 2 * 14 + 11);
        let start = space.candidate(&space.start());
        let base = &enc.village_types["highland"];
        // the base's values inside the bounds come back (up to rounding through logarithms)
        let (h, b) = (
            &start.village_type.buildings["house"],
            &base.buildings["house"],
        );
        assert!((h.sociability.min - b.sociability.min).abs() < 1e-9);
        assert!((h.sociability.max - b.sociability.max).abs() < 1e-9);
        assert!((h.accessibility.zero - b.accessibility.zero).abs() < 1e-9);
        assert!((h.weights.domination - b.weights.domination).abs() < 1e-12);
        assert_eq!(start.village_type.roads.mask_radius, Some(2));
        assert!((start.farm_share - 0.2).abs() < 1e-12);
        assert!((h.skew_share - 0.3).abs() < 1e-12);
        assert!((start.village_type.buildings["farm"].cluster_share - 0.1).abs() < 1e-12);
        // far-off coordinates fold into the bounds and give a type the encyclopedia accepts
        for k in 0..20 {
            let x: Vec<f64> = (0..space.dimensions.len())
                .map(|i| ((i * 7 + k * 13) % 17) as f64 * 1.9 - 15.0)
                .collect();
            let c = space.candidate(&x);
            let mut e = enc.clone();
            e.village_types
                .insert("learned".into(), c.village_type.clone());
            e.validate()
                .expect("a folded point is a valid village type");
            let h = &c.village_type.buildings["house"];
            assert!(
                h.sociability.min <= h.sociability.zero && h.sociability.zero <= h.sociability.max
            );
            assert!((0.8..=2.0).contains(&c.count_factor) && (0.0..=0.6).contains(&c.farm_share));
            let radius = c.village_type.roads.mask_radius.unwrap_or(0);
            assert!((1..=4).contains(&radius));
        }
    }

    #[test]
    fn log_dimensions_are_even_in_ratio_and_folding_reflects() {
        let d = Dimension::new(Knob::CountFactor, 1.0, 100.0, true);
        assert!((d.value(0.5) - 10.0).abs() < 1e-9);
        assert!((d.unit(10.0) - 0.5).abs() < 1e-12);
        assert_eq!(d.unit(1e6), 1.0);
        assert!((fold(1.25) - 0.75).abs() < 1e-12);
        assert!((fold(-0.25) - 0.25).abs() < 1e-12);
        assert!((fold(2.25) - 0.25).abs() < 1e-12);
        assert_eq!(fold(f64::NAN), 0.5);
    }

    #[test]
    fn the_skew_share_spreads_the_buildings_between_along_and_across_over_every_bin() {
        // near les Bons: 67 % along the road, 8 % across, 26 % between
        let s = skew_share_of(&[0.67, 0.08, 0.04, 0.04, 0.10, 0.07]);
        assert!((s - 0.39).abs() < 1e-9, "{s}");
        assert_eq!(skew_share_of(&[0.5, 0.0, 0.0, 0.0, 0.0, 0.5]), 0.0);
        assert_eq!(skew_share_of(&[0.0, 0.4, 0.3, 0.3, 0.0, 0.0]), 1.0);
    }

    #[test]
    fn the_orientation_step_turns_and_skews_towards_the_real_histogram() {
        let space = highland();
        let x = space.start();
        // near les Bons (67 % along, 8 % across, 26 % between) against a type grown 21 % across
        let real = [0.67, 0.08, 0.04, 0.04, 0.10, 0.07];
        let grown = [0.53, 0.08, 0.04, 0.04, 0.10, 0.21];
        assert_eq!(space.orientation_step(&x, &real, &real), x);
        let (before, after) = (
            space.candidate(&x),
            space.candidate(&space.orientation_step(&x, &grown, &real)),
        );
        for b in ["house", "farm"] {
            let (p, q) = (
                &before.village_type.buildings[b],
                &after.village_type.buildings[b],
            );
            // the same between along and across: the skewed share stays
            assert!((q.skew_share - p.skew_share).abs() < 1e-12);
            // 7 / 74 of the aligned across, not 21 / 74: turned less where wider than deep, more where deeper
            let size = q.footprint.expect("learned footprint").max;
            let turned = q.turned_share - p.turned_share;
            // 30 % skewed: of the aligned, 0.7 of 0.8 stand as turned
            let step = 14.0 / 74.0 / (0.7 / 0.8f64);
            let expected = if size[0] >= size[1] {
                (-step).max(-p.turned_share)
            } else {
                step.min(1.0 - p.turned_share)
            };
            assert!(
                (turned - expected).abs() < 1e-9,
                "{b}: {turned} against {expected}"
            );
        }
        // too few between: more skewed, by the missing share over four bins of six
        let along = [0.85, 0.02, 0.02, 0.02, 0.02, 0.07];
        let skewed = space.candidate(&space.orientation_step(&x, &along, &real));
        let h = &skewed.village_type.buildings["house"];
        assert!(
            (h.skew_share - (0.3 + (0.26 - 0.08) * 1.5)).abs() < 1e-9,
            "{}",
            h.skew_share
        );
    }

    #[test]
    fn the_grade_steps_lower_the_limit_for_too_few_hairpins_and_raise_it_for_too_many() {
        let space = highland();
        let x = space.start();
        let grade = |x: &[f64]| {
            let roads = space.candidate(x).village_type.roads;
            roads.max_grade.expect("a learned grade limit")
        };
        let base = grade(&x);
        let near = |steps: &[Vec<f64>], want: &[f64]| {
            steps.len() == want.len()
                && steps
                    .iter()
                    .zip(want)
                    .all(|(s, w)| (grade(s) - w).abs() < 1e-9)
        };
        // the hamlet near les Bons: none grown against 0.57 per km
        let lower = space.grade_steps(&x, 0.0, 0.57);
        assert!(near(&lower, &[0.8 * base, 0.64 * base]), "{base}");
        let higher = space.grade_steps(&x, 2.0, 0.57);
        assert!(near(&higher, &[base / 0.8, base / 0.64]), "{base}");
        // every other coordinate stays
        for s in lower.iter().chain(&higher) {
            let others = x
                .iter()
                .zip(s)
                .zip(&space.dimensions)
                .all(|((p, q), d)| d.knob == Knob::RoadMaxGrade || p == q);
            assert!(others);
        }
        // near enough or unknown: no step
        assert!(space.grade_steps(&x, 0.5, 0.57).is_empty());
        assert!(space.grade_steps(&x, f64::NAN, 0.57).is_empty());
        // at the range's end: none past it, and one step where the second would only reach it again
        let at = |g: f64| -> Vec<f64> {
            let mut y = x.clone();
            for (d, yi) in space.dimensions.iter().zip(&mut y) {
                if d.knob == Knob::RoadMaxGrade {
                    *yi = d.unit(g);
                }
            }
            y
        };
        assert!(space.grade_steps(&at(0.08), 0.0, 0.57).is_empty());
        assert!(near(&space.grade_steps(&at(0.09), 0.0, 0.57), &[0.08]));
        assert_eq!(space.grade_steps(&at(0.08), 2.0, 0.57).len(), 2);
    }

    #[test]
    fn the_cluster_share_is_half_the_close_pairs_beyond_a_random_scatter() {
        // the hamlet near les Bons: 68 % within 20 m at 0.22 buildings per hectare (2.7 % at random)
        let s = cluster_share_of(0.682, 0.22);
        assert!((s - 0.5 * (0.682 - 0.0273)).abs() < 1e-3, "{s}");
        // Encamp's 26 % at 0.96 per hectare: 11 % at random
        assert!((cluster_share_of(0.26, 0.96) - 0.075).abs() < 0.005);
        // a village more scattered than random starts from none
        assert_eq!(cluster_share_of(0.01, 2.0), 0.0);
    }

    #[test]
    fn an_unknown_or_houseless_base_is_refused() {
        let enc = enc();
        let starts = Starts {
            farm_share: 0.2,
            skew_share: 0.0,
            cluster_share: 0.0,
        };
        assert!(ParameterSpace::new(&enc, "no such type", starts).is_err());
    }
}

//! A color read from a file may be anything: what synthesis relies on is checked here, each error naming the
//! color and the field's path.

use super::{
    Color, Histogram, Interaction, MapSource, RoadFacing, MAX_FACING_BANDS, MAX_LOG_SCALE,
};
use crate::error::{check, Error, Result};
use crate::limits;

impl Color {
    /// Checks what synthesis relies on (as read from a file it may be anything): the engine's limits on histogram
    /// bins, densities and regions (`limits`), positive finite radii, finite bounded histogram values,
    /// unique and known category names. Errors name the field's path in the color.
    pub fn validate(&self) -> Result<()> {
        self.validate_scales()?;
        self.validate_categories()?;
        self.validate_pairs()?;
        self.validate_maps()?;
        self.validate_graphs()?;
        self.validate_polygons()?;
        if let Some(pattern) = self.arrangement() {
            pattern.validate(self.categories.len(), &|path| self.at(path))?;
        }
        check::at_most_items(
            "preview",
            self.preview.len(),
            limits::MAX_INSTANCES as usize,
        )?;
        if self.preview.iter().flatten().any(|v| !v.is_finite()) {
            return self.invalid("preview", "has non-finite values".into());
        }
        Ok(())
    }

    /// The path of a field of this color in error messages.
    fn at(&self, path: &str) -> String {
        format!("color '{}' {path}", self.name)
    }

    /// A validation error naming the color and the field.
    fn invalid<T>(&self, path: &str, reason: String) -> Result<T> {
        Err(Error::invalid(self.at(path), reason))
    }

    /// A histogram has at most [`limits::MAX_HISTOGRAM_BINS`] valid bins (or no values) and finite values from 0
    /// to [`limits::MAX_HISTOGRAM_VALUE`].
    fn check_hist(&self, h: &Histogram, path: &str) -> Result<()> {
        check::at_most_items(
            &self.at(path),
            h.values.len(),
            limits::MAX_HISTOGRAM_BINS as usize,
        )?;
        if !h.values.is_empty() {
            check::positive(&self.at(&format!("{path}.bin_width")), h.bin_width)?;
            check::finite(&self.at(&format!("{path}.start")), h.start)?;
        }
        self.check_values(&h.values, path)
    }

    /// Histogram values are finite, from 0 to [`limits::MAX_HISTOGRAM_VALUE`].
    fn check_values(&self, values: &[f64], path: &str) -> Result<()> {
        match values
            .iter()
            .position(|v| !(*v >= 0.0 && *v <= limits::MAX_HISTOGRAM_VALUE))
        {
            Some(k) => check::within(
                &self.at(&format!("{path}.values[{k}]")),
                values[k],
                0.0,
                limits::MAX_HISTOGRAM_VALUE,
            )
            .map(drop),
            None => Ok(()),
        }
    }

    /// The rdf's radius and bin width (at most [`limits::MAX_HISTOGRAM_BINS`] bins), the region and its area.
    fn validate_scales(&self) -> Result<()> {
        check::positive(&self.at("max_radius"), self.max_radius)?;
        check::positive(&self.at("bin_width"), self.bin_width)?;
        limits::check(
            &self.at("max_radius / bin_width"),
            self.max_radius / self.bin_width,
            limits::MAX_HISTOGRAM_BINS,
            "histogram bins",
        )?;
        check::non_negative(&self.at("region_area"), self.region_area)?;
        self.region
            .validate()
            .map_err(|e| Error::invalid(self.at("region"), e.reason()))
    }

    fn validate_categories(&self) -> Result<()> {
        for (k, c) in self.categories.iter().enumerate() {
            let at = |field: &str| format!("categories[{k}].{field}");
            let name = &c.category.name;
            if self.categories[..k]
                .iter()
                .any(|o| &o.category.name == name)
            {
                return self.invalid(&at("category.name"), format!("'{name}' is named twice"));
            }
            check::within(
                &self.at(&at("density")),
                c.density,
                0.0,
                limits::MAX_DENSITY,
            )?;
            if !(c.min_distance >= 0.0) {
                return self.invalid(
                    &at("min_distance"),
                    format!("must be zero or more, got {}", c.min_distance),
                );
            }
            self.check_hist(&c.scale, &at("scale"))?;
            self.check_hist(&c.rotation, &at("rotation"))?;
            self.check_hist(&c.size, &at("size"))?;
            // a scale is the exponential of a size: a finite one
            if !c.size.values.is_empty()
                && !(c.size.start >= -MAX_LOG_SCALE && c.size.end() <= MAX_LOG_SCALE)
            {
                return self.invalid(
                    &at("size"),
                    format!(
                        "spans the log scales [{}, {}], beyond ±{MAX_LOG_SCALE}",
                        c.size.start,
                        c.size.end()
                    ),
                );
            }
            if let Some(f) = &c.facing {
                self.validate_facing(f, &at("facing"))?;
            }
            check::at_most_items(
                &self.at(&at("prototype_weights")),
                c.prototype_weights.len(),
                limits::MAX_HISTOGRAM_BINS as usize,
            )?;
            self.check_values(&c.prototype_weights, &at("prototype_weights"))?;
        }
        Ok(())
    }

    /// The roads are known categories, the bands ascend from 0 with one angle histogram each, the angles lie in
    /// [0, 2π].
    fn validate_facing(&self, f: &RoadFacing, path: &str) -> Result<()> {
        let at = |field: &str| format!("{path}.{field}");
        for road in &f.roads {
            self.check_known(&at("roads"), road)?;
        }
        check::at_most_items(&self.at(&at("bands")), f.bands.len(), MAX_FACING_BANDS)?;
        if f.bands.is_empty() || f.angles.len() != f.bands.len() {
            return self.invalid(
                &at("angles"),
                format!(
                    "are {} histograms for {} distance bands (at least one)",
                    f.angles.len(),
                    f.bands.len()
                ),
            );
        }
        let mut below = 0.0;
        for (k, edge) in f.bands.iter().enumerate() {
            check::positive(&self.at(&at(&format!("bands[{k}]"))), *edge)?;
            if !(*edge > below) {
                return self.invalid(&at("bands"), "must ascend".into());
            }
            below = *edge;
        }
        check::within(&self.at(&at("near_share")), f.near_share, 0.0, 1.0)?;
        for (k, h) in f.angles.iter().enumerate() {
            let path = at(&format!("angles[{k}]"));
            self.check_hist(h, &path)?;
            if !h.values.is_empty() && !(h.start >= 0.0 && h.end() <= std::f64::consts::TAU + 1e-9)
            {
                return self.invalid(
                    &path,
                    format!("spans [{}, {}], not within [0, 2π]", h.start, h.end()),
                );
            }
        }
        Ok(())
    }

    /// A category name used by a field: known to the color.
    fn check_known(&self, path: &str, name: &str) -> Result<()> {
        match self.category(name) {
            Some(_) => Ok(()),
            None => self.invalid(path, format!("names unknown category '{name}'")),
        }
    }

    fn validate_pairs(&self) -> Result<()> {
        for (k, p) in self.pairs.iter().enumerate() {
            let at = |field: &str| format!("pairs[{k}].{field}");
            self.check_known(&at("category"), &p.category)?;
            self.check_known(&at("other"), &p.other)?;
            match &p.interaction {
                Interaction::Rdf { hist } => self.check_hist(hist, &at("hist"))?,
                Interaction::OrientedRdf {
                    distance_bin,
                    angle_bins,
                    values,
                } => {
                    check::positive(&self.at(&at("distance_bin")), *distance_bin)?;
                    limits::check(
                        &self.at(&at("distance_bin")),
                        self.max_radius / distance_bin,
                        limits::MAX_HISTOGRAM_BINS,
                        "histogram bins",
                    )?;
                    check::within(&self.at(&at("angle_bins")), *angle_bins as f64, 1.0, 360.0)?;
                    check::at_most_items(
                        &self.at(&at("values")),
                        values.len(),
                        limits::MAX_HISTOGRAM_BINS as usize * angle_bins,
                    )?;
                    if values.len() % angle_bins != 0 {
                        return self.invalid(
                            &at("values"),
                            format!("are not a multiple of {angle_bins} angle bins"),
                        );
                    }
                    self.check_values(values, &at("values"))?;
                }
            }
        }
        Ok(())
    }

    fn validate_maps(&self) -> Result<()> {
        for (k, m) in self.maps.iter().enumerate() {
            let at = |field: &str| format!("maps[{k}].{field}");
            self.check_known(&at("category"), &m.category)?;
            self.check_hist(&m.hist, &at("hist"))?;
            self.check_hist(&m.region_hist, &at("region_hist"))?;
            if m.source != MapSource::Terrain {
                self.check_known(&at("map"), &m.map)?;
            }
        }
        Ok(())
    }

    fn validate_graphs(&self) -> Result<()> {
        for (k, g) in self.graphs.iter().enumerate() {
            let at = |field: &str| format!("graphs[{k}].{field}");
            self.check_known(&at("category"), &g.category)?;
            self.check_hist(&g.edge_length, &at("edge_length"))?;
            self.check_hist(&g.angle, &at("angle"))?;
            self.check_hist(&g.turn, &at("turn"))?;
            check::within(
                &self.at(&at("min_angle")),
                g.min_angle,
                0.0,
                std::f64::consts::PI,
            )?;
            check::within(&self.at(&at("edges_per_node")), g.edges_per_node, 0.0, 64.0)?;
            check::within(
                &self.at(&at("components_per_area")),
                g.components_per_area,
                0.0,
                limits::MAX_DENSITY,
            )?;
            check::at_most_items(&self.at(&at("degree")), g.degree.len(), 64)?;
            self.check_values(&g.degree, &at("degree"))?;
            for (other, d) in &g.clearance {
                self.check_known(&at("clearance"), other)?;
                check::non_negative(&self.at(&at(&format!("clearance['{other}']"))), *d)?;
            }
            for other in &g.avoids {
                self.check_known(&at("avoids"), other)?;
            }
        }
        Ok(())
    }

    fn validate_polygons(&self) -> Result<()> {
        for (k, p) in self.polygons.iter().enumerate() {
            let at = |field: &str| format!("polygons[{k}].{field}");
            self.check_known(&at("category"), &p.category)?;
            check::positive(&self.at(&at("spacing")), p.spacing)?;
            check::within(
                &self.at(&at("islands_per_area")),
                p.islands_per_area,
                0.0,
                limits::MAX_DENSITY,
            )?;
            check::at_most_items(
                &self.at(&at("island_areas")),
                p.island_areas.len(),
                limits::MAX_HISTOGRAM_BINS as usize,
            )?;
            for (i, a) in p.island_areas.iter().enumerate() {
                check::within(&self.at(&at(&format!("island_areas[{i}]"))), *a, 0.0, 1e12)?;
            }
            if let Some(lakes) = p.lakes_per_area {
                check::within(
                    &self.at(&at("lakes_per_area")),
                    lakes,
                    0.0,
                    limits::MAX_DENSITY,
                )?;
            }
            limits::check(
                &self.at(&at("spacing")),
                self.max_radius / p.spacing,
                limits::MAX_HISTOGRAM_BINS,
                "histogram bins",
            )?;
        }
        Ok(())
    }
}

//! Typed errors of the engine. Every failure says what was wrong; nothing in the core panics on user
//! or file data, so the bindings can turn each variant into a Python exception with this message.
//!
//! Each variant carries the name of the input it is about (`what`: a parameter, a file field's path, an object), and
//! where there is one, the bad value and the rule or limit it breaks. The checks that make them are in [`check`].

use std::fmt;

/// The kind of file a reader was given; its errors name it, since a user imports all of them through the same dialogs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A palette: several colors.
    Palette,
    /// A single color.
    Color,
    /// A village building encyclopedia.
    Encyclopedia,
    /// A village growth scenario.
    Scenario,
    /// A set of named growth scenarios.
    ScenarioPresets,
    /// One tile of a world's tile set.
    Tile,
    /// A map layer of a real place (GeoJSON).
    MapLayer,
    /// An elevation model of a real place (ESRI ASCII grid, SRTM `.hgt`, GeoTIFF).
    ElevationModel,
    /// A tree inventory of a real place (CSV).
    TreeInventory,
    /// A real place as imported and saved.
    Place,
}

impl fmt::Display for FileKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileKind::Palette => "palette",
            FileKind::Color => "color",
            FileKind::Encyclopedia => "encyclopedia",
            FileKind::Scenario => "scenario",
            FileKind::ScenarioPresets => "scenario presets",
            FileKind::Tile => "world tile",
            FileKind::MapLayer => "map layer (GeoJSON)",
            FileKind::ElevationModel => "elevation model",
            FileKind::TreeInventory => "tree inventory",
            FileKind::Place => "place",
        })
    }
}

/// What went wrong in an engine call.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A number outside the range its input allows.
    #[error("invalid input: {what} must be {rule}, got {value}")]
    OutOfRange {
        /// The input.
        what: String,
        /// The range it must lie in, in words ("positive", "zero or more", "at most 1").
        rule: String,
        /// The value given.
        value: f64,
    },
    /// Inputs whose sizes must agree and do not.
    #[error("invalid input: {what} has {found} items where {expected} are needed")]
    SizeMismatch {
        /// The input whose size is wrong.
        what: String,
        /// Its size.
        found: usize,
        /// The size it must have.
        expected: usize,
    },
    /// A name that is not defined where it is used.
    #[error("invalid input: unknown {kind} '{name}'")]
    Unknown {
        /// What kind of thing the name should name ("category", "building type").
        kind: String,
        /// The name given.
        name: String,
    },
    /// Work past the engine's limits (its work budget): refused before anything is allocated.
    #[error("too large: {what} would need {needed:.0} {unit}, more than the limit of {limit}")]
    TooLarge {
        /// The input that asks for the work.
        what: String,
        /// How much it would take.
        needed: f64,
        /// The limit.
        limit: u64,
        /// What is counted ("instances", "grid cells", "histogram bins").
        unit: &'static str,
    },
    /// Any other invalid input.
    #[error("invalid input: {what}: {reason}")]
    Invalid {
        /// The input.
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A region with no area, or one that cannot be used as given.
    #[error("region is empty or degenerate: {reason}")]
    BadRegion {
        /// What is wrong with it.
        reason: String,
    },
    /// A region that does not lie on the terrain where it must.
    #[error("region lies outside the terrain: {reason}")]
    RegionOffTerrain {
        /// Where it lies and where the terrain is.
        reason: String,
    },
    /// A file of a format version this build does not read.
    #[error("unsupported {kind} format version {found} (this build reads {supported})")]
    UnsupportedVersion {
        /// The kind of file.
        kind: FileKind,
        /// Its version.
        found: u32,
        /// The version this build reads.
        supported: u32,
    },
    /// A file that cannot be read as its kind: not JSON, a missing or mistyped field, or a value that makes no sense.
    #[error("not a valid {kind} file: {reason}")]
    Parse {
        /// The kind of file.
        kind: FileKind,
        /// What is wrong, with the path of the field where there is one.
        reason: String,
    },
    /// A region to learn from that holds no example content.
    #[error("nothing to learn: {reason}")]
    EmptyExemplar {
        /// What is missing.
        reason: String,
    },
    /// The progress callback asked to stop.
    #[error("cancelled")]
    Cancelled,
}

impl Error {
    /// An [`Error::Invalid`] about `what`.
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Error {
        Error::Invalid {
            what: what.into(),
            reason: reason.into(),
        }
    }

    /// An [`Error::Unknown`] name of a `kind` of thing.
    pub fn unknown(kind: impl Into<String>, name: impl Into<String>) -> Error {
        Error::Unknown {
            kind: kind.into(),
            name: name.into(),
        }
    }

    /// An [`Error::BadRegion`].
    pub fn bad_region(reason: impl Into<String>) -> Error {
        Error::BadRegion {
            reason: reason.into(),
        }
    }

    /// Whether the error is about an input the caller gave (a value, a size, a name, the work it asks for), as
    /// opposed to a region, a file, an empty example or a cancel.
    pub fn is_invalid_input(&self) -> bool {
        matches!(
            self,
            Error::OutOfRange { .. }
                | Error::SizeMismatch { .. }
                | Error::Unknown { .. }
                | Error::TooLarge { .. }
                | Error::Invalid { .. }
        )
    }

    /// The message without the prefix that says which variant it is ("invalid input: "), for a caller that puts it
    /// in its own context.
    pub fn reason(&self) -> String {
        let message = self.to_string();
        match message.strip_prefix("invalid input: ") {
            Some(rest) => rest.to_string(),
            None => message,
        }
    }

    /// The error as one of a file of `kind`: a value that breaks a rule, read from a file, makes the file invalid.
    pub fn in_file(self, kind: FileKind) -> Error {
        if self.is_invalid_input() {
            Error::parse(kind, self.reason())
        } else {
            self
        }
    }

    /// An [`Error::Parse`] of a `kind` of file.
    pub fn parse(kind: FileKind, reason: impl Into<String>) -> Error {
        Error::Parse {
            kind,
            reason: reason.into(),
        }
    }
}

/// Result of an engine call.
pub type Result<T> = std::result::Result<T, Error>;

/// The checks of numbers given to the engine. Each returns the value when it passes, so a check reads as the value.
pub(crate) mod check {
    use super::{Error, Result};

    fn out_of_range(what: &str, rule: impl Into<String>, value: f64) -> Error {
        Error::OutOfRange {
            what: what.to_string(),
            rule: rule.into(),
            value,
        }
    }

    /// `value` is finite and above zero.
    pub(crate) fn positive(what: &str, value: f64) -> Result<f64> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(out_of_range(what, "positive", value))
        }
    }

    /// `value` is finite and zero or more.
    pub(crate) fn non_negative(what: &str, value: f64) -> Result<f64> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(out_of_range(what, "zero or more", value))
        }
    }

    /// `value` is a finite number.
    pub(crate) fn finite(what: &str, value: f64) -> Result<f64> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(out_of_range(what, "finite", value))
        }
    }

    /// `value` lies in `[lo, hi]`.
    pub(crate) fn within(what: &str, value: f64, lo: f64, hi: f64) -> Result<f64> {
        if value >= lo && value <= hi {
            Ok(value)
        } else {
            Err(out_of_range(what, format!("between {lo} and {hi}"), value))
        }
    }

    /// At most `limit` items (a list read from a file, whose length is work the engine would do).
    pub(crate) fn at_most_items(what: &str, found: usize, limit: usize) -> Result<()> {
        budget(what, found as f64, limit as u64, "items")
    }

    /// Refuses `needed` units of work past `limit` (the engine's work budget, `limits`). `needed` is a float so
    /// that an estimate from absurd inputs (1e300, or not a number) is refused instead of overflowing an integer.
    pub fn budget(what: &str, needed: f64, limit: u64, unit: &'static str) -> Result<()> {
        if needed <= limit as f64 {
            Ok(())
        } else {
            Err(Error::TooLarge {
                what: what.to_string(),
                needed,
                limit,
                unit,
            })
        }
    }

    /// A grid of `found` (nx, ny) nodes laid on a terrain of `terrain` nodes: they must be the same.
    pub(crate) fn fits_terrain(
        what: &str,
        found: (usize, usize),
        terrain: (usize, usize),
    ) -> Result<()> {
        if found == terrain {
            Ok(())
        } else {
            Err(Error::invalid(
                what,
                format!(
                    "{}x{} nodes do not fit a {}x{} terrain",
                    found.0, found.1, terrain.0, terrain.1
                ),
            ))
        }
    }

    /// `found` items where `expected` are needed.
    pub(crate) fn same_len(what: &str, found: usize, expected: usize) -> Result<()> {
        if found == expected {
            Ok(())
        } else {
            Err(Error::SizeMismatch {
                what: what.to_string(),
                found,
                expected,
            })
        }
    }
}

//! Typed errors of the engine. Every failure says what was wrong; nothing in the core panics on user
//! or file data, so the bindings can turn each variant into a Python exception with this message.

/// What went wrong in an engine call.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// An argument or a value read from data is out of range, not finite, or inconsistent with the others.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A region has no area, non-finite coordinates or too few points (see [`crate::Region::validate`]).
    #[error("region is empty or degenerate: {0}")]
    BadRegion(String),
    /// The region does not overlap the terrain the operation reads (its maps, its heights).
    #[error("region lies outside the terrain: {0}")]
    RegionOffTerrain(String),
    /// A palette or encyclopedia file was written in a format version this build does not read.
    #[error("unsupported palette format version {found} (this build reads {supported})")]
    UnsupportedVersion {
        /// The version the file declares.
        found: u32,
        /// The version this build reads.
        supported: u32,
    },
    /// A file (palette, color, encyclopedia, scenario) is not valid JSON or does not have the expected fields.
    #[error("not a valid file: {0}")]
    Json(String),
    /// The region a color is learned from holds nothing to learn (no instances, paths or contours).
    #[error("nothing to learn: {0}")]
    EmptyExemplar(String),
    /// The progress callback asked to stop.
    #[error("cancelled")]
    Cancelled,
}

/// Result of an engine call.
pub type Result<T> = std::result::Result<T, Error>;

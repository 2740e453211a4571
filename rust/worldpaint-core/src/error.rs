//! Typed errors of the engine. Every failure says what was wrong; nothing in the core panics on user
//! or file data, so the bindings can turn each variant into a Python exception with this message.

/// What went wrong in an engine call.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("invalid input: {0}")]
    InvalidInput(String),
    #[error("region is empty or degenerate: {0}")]
    BadRegion(String),
    #[error("region lies outside the terrain: {0}")]
    RegionOffTerrain(String),
    #[error("unsupported palette format version {found} (this build reads {supported})")]
    UnsupportedVersion { found: u32, supported: u32 },
    #[error("not a valid file: {0}")]
    Json(String),
    #[error("nothing to learn: {0}")]
    EmptyExemplar(String),
    #[error("cancelled")]
    Cancelled,
}

/// Result of an engine call.
pub type Result<T> = std::result::Result<T, Error>;

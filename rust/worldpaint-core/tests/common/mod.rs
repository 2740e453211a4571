//! What the integration tests share, one concern per module; each test binary declares `mod common;` and uses the
//! parts it needs. The synthesis and variety benchmarks include it too (`benches/synthesis.rs`, `benches/variety.rs`).

// Every test binary compiles the whole module and uses a part of it.
#![allow(dead_code)]

pub mod arrangement;
pub mod birch;
pub mod checks;
pub mod forest_report;
pub mod geojson;
pub mod pcf;
pub mod real_data;
pub mod real_places;
pub mod rings;
pub mod squares;
pub mod variety_models;
pub mod village_painting_report;
pub mod world_driver;

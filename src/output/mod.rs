//! What a run writes: CSV rows as they are made ([`csv_sink`]), PNG plots of output
//! columns ([`plot`], feature `plot`), and animated glTF files ([`animation`], feature
//! `animation`).

#[cfg(feature = "animation")]
pub mod animation;
pub mod csv_sink;
pub mod npz;
pub mod paths;
#[cfg(feature = "plot")]
pub mod plot;
pub mod units;
#[cfg(feature = "animation")]
pub mod viewer;
pub use csv_sink::CsvSink;

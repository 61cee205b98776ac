//! What a run writes: CSV rows as they are made ([`csv_sink`]), its hinge events ([`events`]) and read back with every
//! body's pose ([`table`]), PNG plots of output columns ([`plot`], feature `plot`) and of a
//! fit's data against its run ([`fit_plot`]), and animated glTF files ([`animation`], feature
//! `animation`).

#[cfg(feature = "animation")]
pub mod animation;
pub mod csv_sink;
pub mod events;
#[cfg(feature = "plot")]
pub mod fit_plot;
pub mod npz;
pub mod paths;
#[cfg(feature = "plot")]
pub mod plot;
pub mod table;
pub mod units;
#[cfg(feature = "animation")]
pub mod viewer;
pub use csv_sink::CsvSink;

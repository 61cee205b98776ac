//! What a run writes: CSV rows as they are made ([`csv_sink`]), and PNG plots of output
//! columns ([`plot`], feature `plot`).

pub mod csv_sink;
#[cfg(feature = "plot")]
pub mod plot;

pub use csv_sink::CsvSink;

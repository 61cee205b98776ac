//! The summary table written as CSV, one row per run as the runs finish (docs/sweep.md).

use super::run::SweepRow;
use std::io::Write;

/// Writes the summary table's rows as CSV: the header first, then one row per call, flushed,
/// so a long sweep's table can be read while it runs.
pub struct CsvTable<W: Write> {
    out: csv::Writer<W>,
    width: usize,
}

impl<W: Write> CsvTable<W> {
    /// Starts a table with `header` ([`super::Sweep::header`]).
    pub fn new(out: W, header: &[String]) -> Result<Self, String> {
        let mut out = csv::Writer::from_writer(out);
        out.write_record(header).map_err(|e| e.to_string())?;
        Ok(Self { out, width: header.len() })
    }

    /// Writes one run's row: `run`, `status` (`ok` or `failed`), the values, the metrics
    /// (shortest round-trip decimals; empty where there is none), `error`.
    pub fn write(&mut self, row: &SweepRow) -> Result<(), String> {
        let mut fields: Vec<String> = Vec::with_capacity(self.width);
        fields.push(row.run.to_string());
        fields.push(if row.error.is_some() { "failed" } else { "ok" }.into());
        let mut number = ryu::Buffer::new();
        fields.extend(row.values.iter().map(|x| number.format(*x).to_string()));
        fields.extend(row.metrics.iter().map(|m| m.map_or(String::new(), |x| number.format(x).to_string())));
        fields.push(row.error.clone().unwrap_or_default());
        debug_assert_eq!(fields.len(), self.width);
        self.out.write_record(&fields).map_err(|e| e.to_string())?;
        self.out.flush().map_err(|e| e.to_string())
    }

    /// Flushes and returns the writer.
    pub fn finish(self) -> Result<W, String> {
        self.out.into_inner().map_err(|e| e.to_string())
    }
}

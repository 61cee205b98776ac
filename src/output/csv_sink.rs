//! CSV output written atomically: rows stream to `<path>.partial`, which is renamed to
//! `<path>` only when the run has finished, so an interrupted or failed run never leaves a
//! file that looks complete. A path that is not a regular file (`/dev/null`, `/dev/stdout`,
//! a named pipe) is written to directly: renaming over it would replace the device or pipe
//! with a file.

use crate::observe::{Observation, Selection, row};
use crate::simulate::Sink;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How often rows are flushed to the file at the latest, so that a long or stuck run's
/// partial file shows its rows so far.
pub const FLUSH_EVERY: Duration = Duration::from_secs(2);

/// Streams observations as CSV rows (the columns of a [`Selection`]) to a partial file, or
/// straight to a target that is not a regular file.
pub struct CsvSink {
    writer: csv::Writer<BufWriter<File>>,
    /// The file written: `<target>.partial`, or the target itself when it is a device or a
    /// pipe.
    partial: PathBuf,
    target: PathBuf,
    columns: Selection,
    flushed: Instant,
}

impl CsvSink {
    /// Creates `<target>.partial` (or opens `target` itself if it exists and is not a
    /// regular file) and writes the header of `columns`.
    pub fn create(target: &Path, columns: &Selection) -> Result<Self, String> {
        let partial = match std::fs::metadata(target) {
            Ok(m) if m.is_dir() => return Err(format!("{} is a directory: name a CSV file", target.display())),
            Ok(m) if !m.is_file() => target.to_path_buf(),
            _ => super::paths::partial_path(target),
        };
        let file = File::create(&partial).map_err(|e| format!("cannot create {}: {e}", partial.display()))?;
        let mut writer = csv::Writer::from_writer(BufWriter::new(file));
        let error = |e: &dyn std::fmt::Display| format!("{}: {e}", partial.display());
        writer.write_record(&columns.names).map_err(|e| error(&e))?;
        writer.flush().map_err(|e| error(&e))?;
        Ok(Self {
            writer,
            partial: partial.clone(),
            target: target.to_path_buf(),
            columns: columns.clone(),
            flushed: Instant::now(),
        })
    }

    /// Flushes and renames the partial file to its final name.
    pub fn finish(mut self) -> Result<PathBuf, String> {
        self.writer.flush().map_err(|e| format!("{}: {e}", self.partial.display()))?;
        drop(self.writer);
        if self.partial != self.target {
            std::fs::rename(&self.partial, &self.target)
                .map_err(|e| format!("cannot rename {} to {}: {e}", self.partial.display(), self.target.display()))?;
        }
        Ok(self.target)
    }

    /// The path the rows go to until [`Self::finish`] (a partial file, left in place when a
    /// run fails; or the target itself when it is a device or a pipe).
    pub fn partial_path(&self) -> &Path {
        &self.partial
    }
}

impl Sink for CsvSink {
    fn record(&mut self, o: &Observation) -> Result<(), String> {
        // Field by field from one formatting buffer (shortest round-trip digits, as before,
        // with an exponent for very large or small values), then the record's end.
        let partial = &self.partial;
        let error = |e: csv::Error| format!("{}: {e}", partial.display());
        let mut buffer = ryu::Buffer::new();
        let values = row(o);
        for x in self.columns.pick(&values) {
            self.writer.write_field(buffer.format(x)).map_err(error)?;
        }
        self.writer.write_record(None::<&[u8]>).map_err(error)?;
        if self.flushed.elapsed() >= FLUSH_EVERY {
            self.writer.flush().map_err(|e| format!("{}: {e}", partial.display()))?;
            self.flushed = Instant::now();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every number in the CSV reads back to exactly the value observed (shortest round-trip
    /// formatting loses nothing), on the 1-DOF example's first seconds: signed zeros, values
    /// of order 1 and momenta at round-off (1e-14 and below, printed with an exponent). A
    /// formatting with fixed digits would lose the small ones.
    #[test]
    fn csv_reads_back_exactly() {
        let s = crate::scenario::example_with("hinged-panels-1dof.toml", &["duration"], "2.0");
        let path = std::env::temp_dir().join(format!("foldsim-output-{}.csv", std::process::id()));
        let mut csv = CsvSink::create(&path, &Selection::matching(&s.model, &["*".into()]).unwrap()).expect("created");
        let mut observed: Vec<Vec<f64>> = Vec::new();
        let mut sink = |o: &Observation| -> Result<(), String> {
            observed.push(row(o));
            csv.record(o)
        };
        crate::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect("runs");
        let path = csv.finish().expect("finished");
        let text = std::fs::read_to_string(&path).expect("written");
        std::fs::remove_file(&path).ok();
        let rows: Vec<&str> = text.lines().skip(1).collect();
        assert_eq!(rows.len(), observed.len());
        let mut tiny = 0;
        for (line, values) in rows.iter().zip(&observed) {
            let read: Vec<f64> = line.split(',').map(|f| f.parse().expect("a number")).collect();
            assert_eq!(read.len(), values.len());
            for (r, v) in read.iter().zip(values) {
                assert_eq!(r.to_bits(), v.to_bits(), "{v:e} read back as {r:e}");
                tiny += usize::from(*v != 0.0 && v.abs() < 1e-12);
            }
        }
        assert!(tiny > 0, "the run should have values at round-off level");
    }
}

//! CSV output written atomically: rows stream to `<path>.partial`, which is renamed to
//! `<path>` only when the run has finished, so an interrupted or failed run never leaves a
//! file that looks complete.

use crate::model::Model;
use crate::observe::{Observation, columns, row};
use crate::simulate::Sink;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Streams observations as CSV rows (columns of [`columns`]) to a partial file.
pub struct CsvSink {
    writer: csv::Writer<BufWriter<File>>,
    partial: PathBuf,
    target: PathBuf,
}

impl CsvSink {
    /// Creates `<target>.partial` and writes the header.
    pub fn create(target: &Path, model: &Model) -> Result<Self, String> {
        let mut partial = target.as_os_str().to_owned();
        partial.push(".partial");
        let partial = PathBuf::from(partial);
        let file = File::create(&partial).map_err(|e| format!("cannot create {}: {e}", partial.display()))?;
        let mut writer = csv::Writer::from_writer(BufWriter::new(file));
        writer.write_record(columns(model)).map_err(|e| format!("{}: {e}", partial.display()))?;
        Ok(Self { writer, partial, target: target.to_path_buf() })
    }

    /// Flushes and renames the partial file to its final name.
    pub fn finish(mut self) -> Result<PathBuf, String> {
        self.writer.flush().map_err(|e| format!("{}: {e}", self.partial.display()))?;
        drop(self.writer);
        std::fs::rename(&self.partial, &self.target)
            .map_err(|e| format!("cannot rename {} to {}: {e}", self.partial.display(), self.target.display()))?;
        Ok(self.target)
    }

    /// The partial file's path (left in place when a run fails).
    pub fn partial_path(&self) -> &Path {
        &self.partial
    }
}

impl Sink for CsvSink {
    fn record(&mut self, o: &Observation) -> Result<(), String> {
        let values = row(o);
        self.writer
            .write_record(values.iter().map(|x| x.to_string()))
            .map_err(|e| format!("{}: {e}", self.partial.display()))
    }
}

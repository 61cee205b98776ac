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
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, sync_channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How often rows are flushed to the file at the latest, so that a long or stuck run's
/// partial file shows its rows so far.
pub const FLUSH_EVERY: Duration = Duration::from_secs(2);

/// Rows a run may be ahead of the writer before it waits for it (a bound on the memory held).
const ROWS_IN_FLIGHT: usize = 4096;

/// Streams observations as CSV rows (the columns of a [`Selection`]) to a partial file, or
/// straight to a target that is not a regular file.
///
/// The rows are formatted and written on a thread of their own: shortest round-trip
/// formatting of every number is 14–16 % of a large run's time on one core (the 228- and
/// 996-panel starshades under `auto`), which the second core takes off the run. The run
/// hands each row over as numbers; the writer formats, writes and flushes at least every
/// [`FLUSH_EVERY`].
pub struct CsvSink {
    /// Rows to the writer; `None` once finished.
    rows: Option<SyncSender<Vec<f64>>>,
    /// The writer: its result when the rows end.
    writer: Option<JoinHandle<Result<(), String>>>,
    /// The file written: `<target>.partial`, or the target itself when it is a device or a
    /// pipe.
    partial: PathBuf,
    target: PathBuf,
    columns: Selection,
}

/// The writer thread: rows from `rows` to `writer` until the run drops its end.
fn write_rows(
    mut writer: csv::Writer<BufWriter<File>>,
    rows: Receiver<Vec<f64>>,
    partial: PathBuf,
) -> Result<(), String> {
    let error = |e: &dyn std::fmt::Display| format!("{}: {e}", partial.display());
    // Field by field from one formatting buffer (shortest round-trip digits, with an
    // exponent for very large or small values), then the record's end.
    let mut buffer = ryu::Buffer::new();
    let mut flushed = Instant::now();
    loop {
        let wait = FLUSH_EVERY.saturating_sub(flushed.elapsed());
        match rows.recv_timeout(wait) {
            Ok(values) => {
                for x in values {
                    writer.write_field(buffer.format(x)).map_err(|e| error(&e))?;
                }
                writer.write_record(None::<&[u8]>).map_err(|e| error(&e))?;
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if flushed.elapsed() >= FLUSH_EVERY {
            writer.flush().map_err(|e| error(&e))?;
            flushed = Instant::now();
        }
    }
    writer.flush().map_err(|e| error(&e))
}

impl CsvSink {
    /// Creates `<target>.partial` (or opens `target` itself if it exists and is not a
    /// regular file), writes the header of `columns` and starts the writer.
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
        let (send, receive) = sync_channel(ROWS_IN_FLIGHT);
        let path = partial.clone();
        let thread = std::thread::Builder::new()
            .name("csv writer".into())
            .spawn(move || write_rows(writer, receive, path))
            .map_err(|e| format!("cannot start the writer of {}: {e}", partial.display()))?;
        Ok(Self {
            rows: Some(send),
            writer: Some(thread),
            partial,
            target: target.to_path_buf(),
            columns: columns.clone(),
        })
    }

    /// Waits for the writer to write every row handed over and flush; its error if it failed.
    fn close(&mut self) -> Result<(), String> {
        self.rows = None;
        match self.writer.take() {
            Some(thread) => {
                thread.join().map_err(|_| format!("{}: the writer stopped unexpectedly", self.partial.display()))?
            }
            None => Ok(()),
        }
    }

    /// Writes every row, flushes and renames the partial file to its final name.
    pub fn finish(mut self) -> Result<PathBuf, String> {
        self.close()?;
        if self.partial != self.target {
            std::fs::rename(&self.partial, &self.target)
                .map_err(|e| format!("cannot rename {} to {}: {e}", self.partial.display(), self.target.display()))?;
        }
        Ok(self.target.clone())
    }

    /// The path the rows go to until [`Self::finish`] (a partial file, left in place when a
    /// run fails; or the target itself when it is a device or a pipe).
    pub fn partial_path(&self) -> &Path {
        &self.partial
    }
}

impl Drop for CsvSink {
    /// A sink dropped without [`CsvSink::finish`] (a run that failed) still writes the rows
    /// it was given to its partial file before the caller reports it.
    fn drop(&mut self) {
        let _ = self.close();
    }
}

impl Sink for CsvSink {
    fn record(&mut self, o: &Observation) -> Result<(), String> {
        let values = row(o);
        let picked: Vec<f64> = self.columns.pick(&values).collect();
        let sent = self.rows.as_ref().is_some_and(|rows| rows.send(picked).is_ok());
        if sent {
            return Ok(());
        }
        // The writer has stopped: its error.
        self.close()?;
        Err(format!("{}: the writer stopped", self.partial.display()))
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

    /// A sink dropped without `finish` (a run that failed part-way) leaves every row it was
    /// given in its partial file, written by the time the drop returns, and no target.
    #[test]
    fn a_dropped_sink_leaves_its_rows_in_the_partial_file_only() {
        let s = crate::scenario::example_with("hinged-panels-1dof.toml", &["duration"], "0.5");
        let path = std::env::temp_dir().join(format!("foldsim-dropped-{}.csv", std::process::id()));
        let mut csv = CsvSink::create(&path, &Selection::matching(&s.model, &["*".into()]).unwrap()).expect("created");
        let partial = csv.partial_path().to_path_buf();
        let mut rows = 0;
        let mut sink = |o: &Observation| -> Result<(), String> {
            rows += 1;
            csv.record(o)
        };
        crate::simulate::simulate(&s.model, &s.initial, &s.settings, &mut sink, None).expect("runs");
        drop(csv);
        let text = std::fs::read_to_string(&partial).expect("the partial file");
        std::fs::remove_file(&partial).ok();
        assert!(rows > 10);
        assert_eq!(text.lines().count(), rows + 1, "header and every row");
        assert!(!path.exists(), "no file that looks complete");
    }
}

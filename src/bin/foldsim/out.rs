//! Standard output without panics: `print!` and `println!` panic when the reader has gone
//! (`foldsim generate ... | head -1`) or the device is full (`> /dev/full`). Here a closed
//! pipe ends the program quietly with success, as Unix filters do, and any other write error
//! is an error naming standard output.

use std::io::Write;

/// Writes `text` to standard output and flushes it. A closed pipe exits the process quietly
/// (status 0); another error is returned in words.
pub(crate) fn print(text: &str) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(format!("cannot write to standard output: {e}")),
    }
}

/// `println!` through [`print`]: a closed pipe exits quietly, another error (a full disk) is
/// reported and exits with failure, since a report line cannot be returned from where it is
/// printed.
macro_rules! outln {
    ($($arg:tt)*) => {
        if let Err(e) = $crate::out::print(&format!("{}\n", format_args!($($arg)*))) {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    };
}

/// Whether an error message comes from writing to a reader that has gone (EPIPE): such a run
/// ends quietly, as Unix filters do.
pub(crate) fn is_broken_pipe(message: &str) -> bool {
    message.contains(&std::io::Error::from(std::io::ErrorKind::BrokenPipe).to_string())
        || message.contains("os error 32")
}

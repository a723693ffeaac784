//! Results on standard output. `println!` panics when the reader has gone (`mcrender diff A B
//! | head -1` closes the pipe after one line); these writes return the error instead, as a
//! [`ReaderGone`], which `main` turns into a quiet exit with status 141, the one a shell
//! reports for a process stopped by SIGPIPE.

use std::io::Write;

/// Standard output was closed by its reader.
#[derive(Debug, thiserror::Error)]
#[error("standard output was closed by its reader")]
pub struct ReaderGone;

/// The exit status for [`ReaderGone`] (128 + SIGPIPE, as a shell reports a process it stopped).
pub const READER_GONE_STATUS: u8 = 141;

/// Write `text` to standard output and flush it.
pub fn write(text: &str) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Err(ReaderGone.into()),
        Err(e) => Err(anyhow::Error::new(e).context("cannot write to standard output")),
    }
}

/// `println!` that returns from the enclosing function (which returns an `anyhow::Result`)
/// with the error when standard output cannot be written.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::stdout::write(&format!("{}\n", format_args!($($arg)*)))?
    };
}
pub(crate) use say;

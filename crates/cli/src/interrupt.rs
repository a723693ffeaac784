//! SIGINT and SIGTERM (with `signal-hook`): the first one sets a flag the render session
//! checks between work units, so the render stops, writes the image so far and a
//! checkpoint, and exits 130 (SIGINT) or 143 (SIGTERM). A second one of the same kind ends
//! the process at once, like kill -9 (the last checkpoint is then the one to resume).

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{Context, Result};
use signal_hook::consts::{SIGINT, SIGTERM};

/// The flags the signal handlers set.
pub struct Interrupt {
    /// Set by either signal: the render's cancel flag.
    pub cancel: Arc<AtomicBool>,
    sigint: Arc<AtomicBool>,
    sigterm: Arc<AtomicBool>,
}

/// Install the handlers (for the rest of the process).
pub fn install() -> Result<Interrupt> {
    let cancel = Arc::new(AtomicBool::new(false));
    let (sigint, sigterm) = (Arc::new(AtomicBool::new(false)), Arc::new(AtomicBool::new(false)));
    for (signal, which, code) in [(SIGINT, &sigint, 130), (SIGTERM, &sigterm, 143)] {
        // Registered first, so it sees the flag as the previous signal left it.
        signal_hook::flag::register_conditional_shutdown(signal, code, Arc::clone(which))
            .and_then(|_| signal_hook::flag::register(signal, Arc::clone(which)))
            .and_then(|_| signal_hook::flag::register(signal, Arc::clone(&cancel)))
            .context("cannot install the signal handlers")?;
    }
    Ok(Interrupt {
        cancel,
        sigint,
        sigterm,
    })
}

impl Interrupt {
    /// The signal received, if any (SIGTERM wins when both came).
    pub fn received(&self) -> Option<Interrupted> {
        if self.sigterm.load(Ordering::SeqCst) {
            Some(Interrupted {
                signal: "SIGTERM",
                code: 143,
            })
        } else if self.sigint.load(Ordering::SeqCst) || self.cancel.load(Ordering::SeqCst) {
            Some(Interrupted {
                signal: "SIGINT",
                code: 130,
            })
        } else {
            None
        }
    }
}

/// The error a render interrupted by a signal ends with; `main` exits with its code.
#[derive(Debug, Clone, Copy)]
pub struct Interrupted {
    /// The signal's name.
    pub signal: &'static str,
    /// The exit code: 128 + the signal number.
    pub code: u8,
}

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "interrupted by {}", self.signal)
    }
}

impl std::error::Error for Interrupted {}

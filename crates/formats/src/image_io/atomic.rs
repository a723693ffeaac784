//! Atomic file writes: [`stage`] writes `.name.tmp-<pid>-<n>` beside the target, flushed
//! and synced; [`Staged::commit`] renames it over the target. On any error, or when a
//! staged file is dropped uncommitted, the temporary file is removed.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::ImageError;

/// Distinguishes temporary files of concurrent writes in one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A complete file written beside its target under a temporary name, not yet in place:
/// [`Staged::commit`] renames it over the target; dropping it uncommitted removes it.
#[derive(Debug)]
#[must_use = "a staged file is removed unless committed"]
pub struct Staged {
    tmp: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl Staged {
    /// Move the file into place.
    ///
    /// # Errors
    /// When the rename fails (the temporary file is then removed).
    pub fn commit(mut self) -> Result<(), ImageError> {
        fs::rename(&self.tmp, &self.target).map_err(|source| ImageError::Io {
            path: self.target.clone(),
            source,
        })?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// Write the temporary file of `path` completely (flushed and synced) without putting it in
/// place.
///
/// # Errors
/// Whatever `write` returns, or the I/O error of creating or syncing; nothing is left
/// behind then.
pub fn stage(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), ImageError>,
) -> Result<Staged, ImageError> {
    let tmp = temp_path(path);
    let io_err = |source| ImageError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = File::options()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(io_err)?;
    // From here on the temporary file is removed on any error, by the guard's drop.
    let staged = Staged {
        tmp,
        target: path.to_path_buf(),
        committed: false,
    };
    let mut out = BufWriter::new(file);
    write(&mut out)?;
    out.flush().map_err(io_err)?;
    let file = out.into_inner().map_err(|e| io_err(e.into_error()))?;
    file.sync_all().map_err(io_err)?;
    Ok(staged)
}

fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "image".into(), |n| n.to_string_lossy().into_owned());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
}

//! Where the loader's files come from: [`DiskFiles`] (the file system) or [`MemoryFiles`]
//! (a set of named byte buffers, for tests, fuzzing and front ends that hold scenes in
//! memory). Every file the pbrt loader reads (the scene, `Include`s, PLY meshes, images)
//! goes through a [`FileSource`].

use std::collections::HashMap;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// A read-only set of files.
pub trait FileSource: fmt::Debug + Send + Sync {
    /// The whole contents of `path`.
    ///
    /// # Errors
    /// When the file does not exist or cannot be read.
    fn read(&self, path: &Path) -> io::Result<Vec<u8>>;

    /// Whether `path` names a file that [`Self::read`] could open.
    fn exists(&self, path: &Path) -> bool;

    /// The size of `path` in bytes, when known without reading it.
    fn len(&self, path: &Path) -> Option<u64>;
}

/// The file system.
#[derive(Clone, Copy, Debug, Default)]
pub struct DiskFiles;

impl FileSource for DiskFiles {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        std::fs::read(path)
    }

    fn exists(&self, path: &Path) -> bool {
        path.exists()
    }

    fn len(&self, path: &Path) -> Option<u64> {
        std::fs::metadata(path).ok().map(|m| m.len())
    }
}

/// Files held in memory, by path. Paths are compared as given after removing `.`
/// components, so `dir/./a.ply` and `dir/a.ply` are the same file.
#[derive(Clone, Default)]
pub struct MemoryFiles {
    files: HashMap<PathBuf, Vec<u8>>,
}

impl fmt::Debug for MemoryFiles {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The names and sizes only: the contents may be megabytes.
        let mut names: Vec<_> = self
            .files
            .iter()
            .map(|(p, b)| (p.display().to_string(), b.len()))
            .collect();
        names.sort();
        f.debug_struct("MemoryFiles").field("files", &names).finish()
    }
}

impl MemoryFiles {
    /// An empty set.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Add (or replace) the file `path`.
    pub fn insert(&mut self, path: impl AsRef<Path>, bytes: impl Into<Vec<u8>>) {
        self.files.insert(normalize(path.as_ref()), bytes.into());
    }

    fn get(&self, path: &Path) -> Option<&Vec<u8>> {
        self.files.get(&normalize(path))
    }
}

impl FileSource for MemoryFiles {
    fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.get(path)
            .cloned()
            .ok_or_else(|| io::Error::from(io::ErrorKind::NotFound))
    }

    fn exists(&self, path: &Path) -> bool {
        self.get(path).is_some()
    }

    fn len(&self, path: &Path) -> Option<u64> {
        self.get(path).map(|b| b.len() as u64)
    }
}

/// `path` without `.` components (and without a leading `./`).
fn normalize(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, std::path::Component::CurDir))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_files_are_found_with_or_without_dot_components() {
        let mut files = MemoryFiles::new();
        files.insert("scene/./mesh.ply", b"ply".to_vec());
        assert_eq!(files.read(Path::new("scene/mesh.ply")).unwrap(), b"ply");
        assert!(files.exists(Path::new("./scene/mesh.ply")));
        assert_eq!(files.len(Path::new("scene/mesh.ply")), Some(3));
        let err = files.read(Path::new("scene/other.ply")).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::NotFound);
        assert!(!format!("{files:?}").contains("112")); // no byte dump
    }
}

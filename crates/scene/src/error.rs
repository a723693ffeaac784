//! Errors of the scene loaders: a [`Location`] in a scene file and the [`SceneError`] that
//! points at it, so every message reads like `scene.pbrt:12:5: expected a number, found "abc"`.

use std::fmt;
use std::sync::Arc;

/// A position in a scene file: file name as given by the caller (or resolved from an
/// `Include`), 1-based line and 1-based column (counted in characters).
///
/// A location with line 0 names a whole file (e.g. when it cannot be opened).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Location {
    /// File name as shown in messages.
    pub file: Arc<str>,
    /// 1-based line; 0 when the location is the whole file.
    pub line: u32,
    /// 1-based column.
    pub column: u32,
}

impl Location {
    /// A location at `line`:`column` of `file`.
    #[must_use]
    pub fn new(file: Arc<str>, line: u32, column: u32) -> Self {
        Self { file, line, column }
    }

    /// A location naming a whole file.
    #[must_use]
    pub fn file_only(file: Arc<str>) -> Self {
        Self {
            file,
            line: 0,
            column: 0,
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}", self.file)
        } else {
            write!(f, "{}:{}:{}", self.file, self.line, self.column)
        }
    }
}

/// What kind of problem a [`SceneError`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneErrorKind {
    /// The text is not well-formed: bad token, wrong parameter type or arity, unbalanced
    /// blocks, unknown directive.
    Syntax,
    /// Well-formed, but a value is out of range or inconsistent (negative radius, absurd
    /// resolution, index out of bounds, undefined named material, ...).
    Invalid,
    /// A valid pbrt-v4 feature that mcrender does not render yet.
    Unsupported,
    /// A file (scene, include or mesh) could not be opened or read.
    Io,
}

/// An error while loading a scene, with the place in the scene file that caused it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{location}: {message}")]
pub struct SceneError {
    /// What kind of problem this is.
    pub kind: SceneErrorKind,
    /// Where in which file.
    pub location: Location,
    /// Human-readable description, without the location.
    pub message: String,
}

impl SceneError {
    /// An error of `kind` at `location`.
    #[must_use]
    pub fn new(kind: SceneErrorKind, location: Location, message: impl Into<String>) -> Self {
        Self {
            kind,
            location,
            message: message.into(),
        }
    }

    /// A [`SceneErrorKind::Syntax`] error.
    #[must_use]
    pub fn syntax(location: &Location, message: impl Into<String>) -> Self {
        Self::new(SceneErrorKind::Syntax, location.clone(), message)
    }

    /// A [`SceneErrorKind::Invalid`] error.
    #[must_use]
    pub fn invalid(location: &Location, message: impl Into<String>) -> Self {
        Self::new(SceneErrorKind::Invalid, location.clone(), message)
    }

    /// A [`SceneErrorKind::Unsupported`] error.
    #[must_use]
    pub fn unsupported(location: &Location, message: impl Into<String>) -> Self {
        Self::new(SceneErrorKind::Unsupported, location.clone(), message)
    }

    /// A [`SceneErrorKind::Io`] error.
    #[must_use]
    pub fn io(location: &Location, message: impl Into<String>) -> Self {
        Self::new(SceneErrorKind::Io, location.clone(), message)
    }
}

/// The text of an I/O error without Rust's ` (os error N)` suffix, so messages read like
/// `No such file or directory`.
#[must_use]
pub fn io_error_text(err: &std::io::Error) -> String {
    let text = err.to_string();
    match text.rfind(" (os error ") {
        Some(i) if text.ends_with(')') => text[..i].to_string(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_has_file_line_column() {
        let e = SceneError::syntax(
            &Location::new("scene.pbrt".into(), 12, 5),
            "expected a number, found \"abc\"",
        );
        assert_eq!(e.to_string(), "scene.pbrt:12:5: expected a number, found \"abc\"");
        let e = SceneError::io(&Location::file_only("a.pbrt".into()), "cannot open scene file: gone");
        assert_eq!(e.to_string(), "a.pbrt: cannot open scene file: gone");
    }

    #[test]
    fn io_text_drops_os_error_code() {
        let err = std::fs::File::open("/definitely/not/here").unwrap_err();
        assert_eq!(io_error_text(&err), "No such file or directory");
    }
}

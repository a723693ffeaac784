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
            message: tidy_message(&message.into()),
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

/// At most this many characters of user input are shown in a message.
pub const QUOTE_MAX_CHARS: usize = 80;

/// `text` in double quotes for an error message: control characters, quotes and
/// backslashes escaped (`\n`, `\0`, `\u{1b}`, ...), and cut after [`QUOTE_MAX_CHARS`]
/// characters with the full length noted, so a 10 MB token or a NUL byte never reaches the
/// terminal as is.
#[must_use]
pub fn quoted(text: &str) -> String {
    let mut out = String::with_capacity(text.len().min(4 * QUOTE_MAX_CHARS) + 2);
    out.push('"');
    for (shown, c) in text.chars().enumerate() {
        if shown == QUOTE_MAX_CHARS {
            out.push_str(&format!("...\" ({} characters)", text.chars().count()));
            return out;
        }
        push_escaped(&mut out, c);
    }
    out.push('"');
    out
}

/// `text` with control characters escaped as in [`quoted`], without quotes or shortening
/// (for whole messages that may embed input).
#[must_use]
pub fn escape_control(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_string();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            push_escaped(&mut out, c);
        } else {
            out.push(c);
        }
    }
    out
}

/// Longest message a [`SceneError`] keeps (characters); beyond it the text is cut.
const MESSAGE_MAX_CHARS: usize = 1000;

/// A message made safe to print on one line: every double-quoted part longer than
/// [`QUOTE_MAX_CHARS`] is cut as [`quoted`] cuts it, control characters are escaped, and
/// the whole is at most [`MESSAGE_MAX_CHARS`] characters.
#[must_use]
pub fn tidy_message(message: &str) -> String {
    let chars: Vec<char> = message.chars().collect();
    let mut out = String::with_capacity(message.len().min(4 * MESSAGE_MAX_CHARS));
    let mut i = 0;
    while i < chars.len() {
        if chars[i] != '"' {
            push_escaped_control(&mut out, chars[i]);
            i += 1;
            continue;
        }
        // A quoted part: up to the next quote that is not escaped.
        let mut j = i + 1;
        while j < chars.len() && chars[j] != '"' {
            j += if chars[j] == '\\' { 2 } else { 1 };
        }
        let inner = &chars[i + 1..j.min(chars.len())];
        out.push('"');
        // A part that `quoted` already shortened (ending in "...", at most four characters
        // per character shown once escaped) stays as it is.
        let shortened = inner.ends_with(&['.', '.', '.']) && inner.len() <= 4 * QUOTE_MAX_CHARS + 3;
        let keep = if shortened { inner.len() } else { QUOTE_MAX_CHARS };
        for &c in inner.iter().take(keep) {
            push_escaped_control(&mut out, c);
        }
        if inner.len() > keep {
            out.push_str(&format!("...\" ({} characters)", inner.len()));
        } else if j < chars.len() {
            out.push('"');
        }
        i = j + 1;
    }
    if out.chars().count() > MESSAGE_MAX_CHARS {
        let cut: String = out.chars().take(MESSAGE_MAX_CHARS).collect();
        return format!("{cut}... (message cut)");
    }
    out
}

fn push_escaped_control(out: &mut String, c: char) {
    if c.is_control() {
        push_escaped(out, c);
    } else {
        out.push(c);
    }
}

fn push_escaped(out: &mut String, c: char) {
    match c {
        '"' => out.push_str("\\\""),
        '\\' => out.push_str("\\\\"),
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        '\0' => out.push_str("\\0"),
        c if c.is_control() => out.push_str(&format!("\\u{{{:x}}}", u32::from(c))),
        c => out.push(c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_escapes_control_characters_and_cuts_long_input() {
        assert_eq!(quoted("abc"), "\"abc\"");
        assert_eq!(quoted("a\0b\n\u{1b}[31m\"q\"\\"), r#""a\0b\n\u{1b}[31m\"q\"\\""#);
        let long = "x".repeat(10_000_000);
        let q = quoted(&long);
        assert!(q.len() < 120, "{}", q.len());
        assert!(q.ends_with("...\" (10000000 characters)"), "{q}");
        assert_eq!(escape_control("a\0b"), "a\\0b");
        assert_eq!(escape_control("plain"), "plain");
    }

    #[test]
    fn ten_megabyte_token_is_not_echoed_in_full() {
        let long = "y".repeat(10_000_000);
        let e = SceneError::syntax(
            &Location::new("s.pbrt".into(), 1, 1),
            format!("unknown directive \"{long}\""),
        );
        let text = e.to_string();
        assert!(text.len() < 200, "{}", text.len());
        assert!(text.contains("(10000000 characters)"), "{text}");
        // Short quoted parts and the text around them are kept as they are.
        let e = SceneError::syntax(&Location::new("s.pbrt".into(), 1, 1), "expected \"[\", found \"x\"");
        assert_eq!(e.message, "expected \"[\", found \"x\"");
    }

    #[test]
    fn raw_nul_bytes_are_not_printed() {
        let e = SceneError::syntax(&Location::new("s.pbrt".into(), 1, 1), "unknown directive \"a\0b\u{7}\"");
        assert!(!e.to_string().chars().any(char::is_control), "{e}");
        assert!(e.to_string().contains("a\\0b\\u{7}"), "{e}");
    }

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

//! The pbrt-v4 tokenizer: splits one scene file into bare words (directives, `true`,
//! `false`), numbers, quoted strings, `[` and `]`, skipping whitespace and `#` comments.
//!
//! As in pbrt-v4, a bare word runs until whitespace, a quote or a bracket; a quoted string
//! may not span lines and knows the escapes `\b \f \n \r \t \\ \' \"`. Every token carries
//! its [`Location`] (file, 1-based line and column).

use std::fmt;
use std::sync::Arc;

use crate::error::{quoted, Location, SceneError};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A bare word that is not a finite number: a directive name, `true`, `false`, or junk.
    Word(String),
    /// A bare word that parses as a finite number; `text` is its spelling in the file.
    Number {
        /// The value.
        value: f64,
        /// The text as written (used to check integers and for messages).
        text: String,
    },
    /// A quoted string, escapes resolved, quotes removed.
    Str(String),
    /// `[`
    OpenBracket,
    /// `]`
    CloseBracket,
}

/// A token and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// What it is.
    pub kind: TokenKind,
    /// Where it starts.
    pub loc: Location,
}

impl fmt::Display for TokenKind {
    /// How a token is named in "expected X, found Y" messages.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Word(w) => write!(f, "{}", quoted(w)),
            Self::Number { text, .. } => write!(f, "{}", quoted(text)),
            Self::Str(s) => write!(f, "string {}", quoted(s)),
            Self::OpenBracket => write!(f, "\"[\""),
            Self::CloseBracket => write!(f, "\"]\""),
        }
    }
}

/// Tokenizer over the text of one file.
#[derive(Debug)]
pub struct Tokenizer {
    file: Arc<str>,
    src: String,
    /// Byte offset of the next character.
    pos: usize,
    line: u32,
    column: u32,
}

impl Tokenizer {
    /// A tokenizer over `source`, reporting locations in `file`.
    #[must_use]
    pub fn new(source: &str, file: Arc<str>) -> Self {
        // A leading UTF-8 byte order mark is not part of the scene.
        let source = source.strip_prefix('\u{feff}').unwrap_or(source);
        Self {
            file,
            src: source.to_string(),
            pos: 0,
            line: 1,
            column: 1,
        }
    }

    /// Location of the next character (the end of the file once everything is read).
    #[must_use]
    pub fn location(&self) -> Location {
        Location::new(self.file.clone(), self.line, self.column)
    }

    fn peek_char(&self) -> Option<char> {
        self.src.get(self.pos..)?.chars().next()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek_char()?;
        self.pos += c.len_utf8();
        if c == '\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
        Some(c)
    }

    /// The next token, `Ok(None)` at the end of the file.
    ///
    /// # Errors
    /// An unterminated string, or an unknown escape in a string.
    pub fn next_token(&mut self) -> Result<Option<Token>, SceneError> {
        loop {
            let loc = self.location();
            let Some(c) = self.bump() else {
                return Ok(None);
            };
            match c {
                ' ' | '\t' | '\r' | '\n' => {}
                '#' => {
                    while let Some(c) = self.peek_char() {
                        if c == '\n' || c == '\r' {
                            break;
                        }
                        self.bump();
                    }
                }
                '[' => {
                    return Ok(Some(Token {
                        kind: TokenKind::OpenBracket,
                        loc,
                    }))
                }
                ']' => {
                    return Ok(Some(Token {
                        kind: TokenKind::CloseBracket,
                        loc,
                    }))
                }
                '"' => return self.string(loc).map(Some),
                _ => return Ok(Some(self.word(c, loc))),
            }
        }
    }

    fn string(&mut self, loc: Location) -> Result<Token, SceneError> {
        let mut s = String::new();
        loop {
            let esc_loc = self.location();
            match self.bump() {
                None | Some('\n') => return Err(SceneError::syntax(&loc, "unterminated string")),
                Some('"') => {
                    return Ok(Token {
                        kind: TokenKind::Str(s),
                        loc,
                    })
                }
                Some('\\') => {
                    let decoded = match self.bump() {
                        None | Some('\n') => return Err(SceneError::syntax(&loc, "unterminated string")),
                        Some('b') => '\u{8}',
                        Some('f') => '\u{c}',
                        Some('n') => '\n',
                        Some('r') => '\r',
                        Some('t') => '\t',
                        Some(c @ ('\\' | '\'' | '"')) => c,
                        Some(other) => {
                            return Err(SceneError::syntax(
                                &esc_loc,
                                format!("unknown escape \"\\{other}\" in string"),
                            ))
                        }
                    };
                    s.push(decoded);
                }
                Some(c) => s.push(c),
            }
        }
    }

    fn word(&mut self, first: char, loc: Location) -> Token {
        let mut text = String::from(first);
        while let Some(c) = self.peek_char() {
            if matches!(c, ' ' | '\t' | '\r' | '\n' | '"' | '[' | ']') {
                break;
            }
            text.push(c);
            self.bump();
        }
        let kind = match parse_number(&text) {
            Some(value) if value.is_finite() => TokenKind::Number { value, text },
            _ => TokenKind::Word(text),
        };
        Token { kind, loc }
    }
}

/// Parse a bare word as a number the way pbrt writes them (`1`, `-2.5`, `.5`, `1e-3`).
/// Words that Rust would read as numbers but pbrt would not (`inf`, `nan`) are not numbers.
#[must_use]
pub fn parse_number(text: &str) -> Option<f64> {
    let first = text.chars().next()?;
    if !(first.is_ascii_digit() || matches!(first, '-' | '+' | '.')) {
        return None;
    }
    let rest = text.trim_start_matches(['-', '+']);
    if !rest.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
        return None;
    }
    text.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(src: &str) -> Vec<(TokenKind, u32, u32)> {
        let mut t = Tokenizer::new(src, "t.pbrt".into());
        let mut out = Vec::new();
        while let Some(tok) = t.next_token().unwrap() {
            out.push((tok.kind, tok.loc.line, tok.loc.column));
        }
        out
    }

    fn word(s: &str) -> TokenKind {
        TokenKind::Word(s.into())
    }

    fn num(v: f64, s: &str) -> TokenKind {
        TokenKind::Number {
            value: v,
            text: s.into(),
        }
    }

    #[test]
    fn splits_words_numbers_strings_brackets_with_locations() {
        let toks = tokens("Shape \"sphere\"\n  \"float radius\" [ 2.5 ] # comment\n\tTranslate -1 .5 1e2");
        assert_eq!(
            toks,
            vec![
                (word("Shape"), 1, 1),
                (TokenKind::Str("sphere".into()), 1, 7),
                (TokenKind::Str("float radius".into()), 2, 3),
                (TokenKind::OpenBracket, 2, 18),
                (num(2.5, "2.5"), 2, 20),
                (TokenKind::CloseBracket, 2, 24),
                (word("Translate"), 3, 2),
                (num(-1.0, "-1"), 3, 12),
                (num(0.5, ".5"), 3, 15),
                (num(100.0, "1e2"), 3, 18),
            ]
        );
    }

    #[test]
    fn brackets_and_quotes_end_words() {
        let toks = tokens("[1 2]\"a\"b");
        assert_eq!(
            toks.into_iter().map(|t| t.0).collect::<Vec<_>>(),
            vec![
                TokenKind::OpenBracket,
                num(1.0, "1"),
                num(2.0, "2"),
                TokenKind::CloseBracket,
                TokenKind::Str("a".into()),
                word("b"),
            ]
        );
    }

    #[test]
    fn escapes_are_decoded() {
        let toks = tokens(r#""a\"b\\c\n\t""#);
        assert_eq!(toks[0].0, TokenKind::Str("a\"b\\c\n\t".into()));
    }

    #[test]
    fn non_finite_and_junk_are_words() {
        let toks = tokens("1e999 nan inf -inf 1.2.3 abc");
        for (kind, _, _) in &toks {
            assert!(matches!(kind, TokenKind::Word(_)), "{kind:?}");
        }
    }

    #[test]
    fn unterminated_string_reports_its_start() {
        let mut t = Tokenizer::new("Shape \"sphere\n\"", "s.pbrt".into());
        t.next_token().unwrap();
        assert_eq!(
            t.next_token().unwrap_err().to_string(),
            "s.pbrt:1:7: unterminated string"
        );
        let mut t = Tokenizer::new("  \"abc", "s.pbrt".into());
        assert_eq!(
            t.next_token().unwrap_err().to_string(),
            "s.pbrt:1:3: unterminated string"
        );
    }

    #[test]
    fn unknown_escape_is_an_error() {
        let mut t = Tokenizer::new("\"a\\qb\"", "s.pbrt".into());
        assert_eq!(
            t.next_token().unwrap_err().to_string(),
            "s.pbrt:1:3: unknown escape \"\\q\" in string"
        );
    }

    #[test]
    fn comment_at_end_of_file() {
        assert_eq!(tokens("# only a comment"), vec![]);
        assert_eq!(tokens("A # c\r\nB"), vec![(word("A"), 1, 1), (word("B"), 2, 1)]);
    }
}

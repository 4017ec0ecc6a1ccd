//! Errors of the scene reader. Every one names the file, the line and column, and the key, so a
//! typo can be found without miette; as a [`miette::Diagnostic`] it also points at the text.

use std::ops::Range;
use std::sync::Arc;

use miette::{Diagnostic, NamedSource, SourceSpan};

/// An unreadable or invalid scene file.
///
/// Displays as `scene.toml:12:1: body[2].radius: radius must be positive (got -1)`:
/// file, 1-based line and column, key path (array indices 0-based), message.
#[derive(Debug, Clone, thiserror::Error, Diagnostic)]
#[error("{}", self.headline())]
#[diagnostic(code(pbdda::scene))]
pub struct SceneError {
    /// The file name as given to [`crate::scene::load`] or [`crate::scene::parse`].
    pub file: String,
    /// 1-based line of the offending key or value; 0 when the file could not be read.
    pub line: usize,
    /// 1-based column, counted in characters; 0 when the file could not be read.
    pub column: usize,
    /// Key path such as `body[2].radius` or `time.step`; empty when no key applies
    /// (a TOML syntax error between keys, an unreadable file).
    pub key: String,
    /// What is wrong, e.g. `radius must be positive (got -1)`.
    pub message: String,
    #[source_code]
    source_code: Arc<NamedSource<String>>,
    #[label("here")]
    span: Option<SourceSpan>,
}

impl SceneError {
    /// An error at the byte range `span` of `source`.
    pub(crate) fn at(file: &str, source: &str, span: Range<usize>, key: String, message: String) -> Self {
        let start = span.start.min(source.len());
        let end = span.end.clamp(start, source.len());
        let (line, column) = line_column(source, start);
        Self {
            file: file.to_owned(),
            line,
            column,
            key,
            message,
            source_code: Arc::new(NamedSource::new(file, source.to_owned())),
            span: Some(SourceSpan::from(start..end)),
        }
    }

    /// The file could not be read at all.
    pub(crate) fn unreadable(file: &str, error: &std::io::Error) -> Self {
        Self {
            file: file.to_owned(),
            line: 0,
            column: 0,
            key: String::new(),
            message: format!("cannot read the scene file: {error}"),
            source_code: Arc::new(NamedSource::new(file, String::new())),
            span: None,
        }
    }

    fn headline(&self) -> String {
        let Self { file, line, column, key, message, .. } = self;
        match (*line, key.is_empty()) {
            (0, _) => format!("{file}: {message}"),
            (_, true) => format!("{file}:{line}:{column}: {message}"),
            (_, false) => format!("{file}:{line}:{column}: {key}: {message}"),
        }
    }
}

/// 1-based line and column (in characters) of the byte `offset` of `source`.
fn line_column(source: &str, offset: usize) -> (usize, usize) {
    let before = &source.as_bytes()[..offset.min(source.len())];
    let line_start = before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    // count UTF-8 lead bytes only, so a multi-byte character is one column
    let column = before[line_start..].iter().filter(|&&b| b & 0xC0 != 0x80).count() + 1;
    (line, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based_and_count_characters() {
        let s = "a = 1\nbé = 2\n";
        assert_eq!(line_column(s, 0), (1, 1));
        assert_eq!(line_column(s, 4), (1, 5));
        assert_eq!(line_column(s, 6), (2, 1));
        // 'é' is two bytes: "bé " is 4 bytes but 3 characters, so '=' (byte 10) is column 4
        assert_eq!(line_column(s, 10), (2, 4));
        assert_eq!(line_column(s, 999), (3, 1));
    }

    #[test]
    fn display_names_file_line_key() {
        let e = SceneError::at(
            "scene.toml",
            "x\nradius = -1\n",
            2..13,
            "body[2].radius".into(),
            "radius must be positive (got -1)".into(),
        );
        assert_eq!(e.to_string(), "scene.toml:2:1: body[2].radius: radius must be positive (got -1)");
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "not found");
        assert_eq!(
            SceneError::unreadable("a.toml", &io).to_string(),
            "a.toml: cannot read the scene file: not found"
        );
    }
}

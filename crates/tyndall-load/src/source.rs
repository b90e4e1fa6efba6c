//! Scene source text and errors that point into it.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use tyndall::description::{DescError, Origin};

/// An error in a scene file: where it is and what was expected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    pub path: PathBuf,
    /// 1-based line and column (in characters); 0 when the error concerns
    /// the whole file.
    pub line: usize,
    pub column: usize,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.as_os_str().is_empty() {
            write!(f, "{}", self.message)
        } else if self.line == 0 {
            write!(f, "{}: {}", self.path.display(), self.message)
        } else {
            write!(
                f,
                "{}:{}:{}: {}",
                self.path.display(),
                self.line,
                self.column,
                self.message
            )
        }
    }
}

impl std::error::Error for SceneError {}

/// `errors` as one: the first, with each further one appended to its
/// message on a line of its own (`None` if there are none).
pub(crate) fn located_together(errors: impl IntoIterator<Item = SceneError>) -> Option<SceneError> {
    let mut errors = errors.into_iter();
    let mut first = errors.next()?;
    for e in errors {
        first.message.push('\n');
        first.message.push_str(&e.to_string());
    }
    Some(first)
}

/// A description error outside any text this crate holds: at its origin's
/// line and column where it has them, else naming the file and element.
impl From<DescError> for SceneError {
    fn from(e: DescError) -> Self {
        match e.origin {
            Origin::Location { file, line, column } => SceneError {
                path: file.to_path_buf(),
                line,
                column,
                message: e.message,
            },
            Origin::Span { file, .. } => SceneError {
                path: file.to_path_buf(),
                line: 0,
                column: 0,
                message: format!("`{}`: {}", e.field, e.message),
            },
            Origin::Element { file, path } => SceneError {
                path: file.to_path_buf(),
                line: 0,
                column: 0,
                message: format!("{path}: {}", e.message),
            },
            Origin::Code => SceneError {
                path: PathBuf::new(),
                line: 0,
                column: 0,
                message: e.message,
            },
        }
    }
}

/// A scene file's text with its path, to turn byte offsets into
/// line:column positions.
pub struct SourceText {
    pub path: PathBuf,
    pub text: String,
}

impl SourceText {
    pub fn new(path: impl Into<PathBuf>, text: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            text: text.into(),
        }
    }

    /// Reads a file; the error names the file.
    /// Files longer than [`crate::files::MAX_SCENE_FILE_BYTES`] are
    /// refused before they are read whole.
    pub fn read(path: &Path) -> Result<Self, SceneError> {
        let error = |message: String| SceneError {
            path: path.to_owned(),
            line: 0,
            column: 0,
            message,
        };
        let bytes = crate::files::read_capped(path, crate::files::MAX_SCENE_FILE_BYTES)
            .map_err(|e| error(format!("cannot read the file: {e}")))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let offset = e.utf8_error().valid_up_to();
            error(format!(
                "cannot read the file: it is not UTF-8 text (byte {offset})"
            ))
        })?;
        Ok(Self::new(path, text))
    }

    /// 1-based (line, column) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        (line, column)
    }

    /// An error at a byte offset.
    pub fn error_at(&self, offset: usize, message: impl Into<String>) -> SceneError {
        let (line, column) = self.line_col(offset);
        SceneError {
            path: self.path.clone(),
            line,
            column,
            message: message.into(),
        }
    }

    /// An error at the key `key` in the table whose header starts the byte
    /// range `table` (a table's span covers its header), or at the header
    /// if the key is not written there.
    pub fn error_at_key(
        &self,
        table: Range<usize>,
        key: &str,
        message: impl Into<String>,
    ) -> SceneError {
        let body = self.table_body(table.start);
        let offset =
            find_key(&self.text[body.clone()], key).map_or(table.start, |i| body.start + i);
        self.error_at(offset, message)
    }

    /// The byte range from `start` to the next table header (a line that
    /// starts with `[`) or the end of the text.
    pub fn table_body(&self, start: usize) -> Range<usize> {
        let start = start.min(self.text.len());
        let after_header = self.text[start..]
            .find('\n')
            .map_or(self.text.len(), |i| start + i + 1);
        let end = self.text[after_header..]
            .match_indices('\n')
            .map(|(i, _)| after_header + i + 1)
            .find(|&line| self.text[line..].starts_with('['))
            .unwrap_or(self.text.len());
        after_header..end
    }

    /// A description error placed in this text: at the key it names in
    /// the table of a [`Origin::Span`] of this file, or where its origin
    /// says otherwise.
    pub fn locate(&self, e: &DescError) -> SceneError {
        match &e.origin {
            Origin::Span { file, span } if **file == *self.path => {
                self.error_at_key(span.clone(), e.field, e.message.clone())
            }
            _ => SceneError::from(e.clone()),
        }
    }

    /// Every error of a description as one error: the first placed by
    /// [`SourceText::locate`], each further one on a line of its own
    /// after its message, placed the same way.
    pub fn locate_all(&self, errors: &[DescError]) -> Option<SceneError> {
        located_together(errors.iter().map(|e| self.locate(e)))
    }

    /// An error about the whole file.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError {
            path: self.path.clone(),
            line: 0,
            column: 0,
            message: message.into(),
        }
    }
}

/// Byte offset of `key` written as a TOML key (at a line start or after
/// `{`/`,`, followed by `=`) within `text`.
pub(crate) fn find_key(text: &str, key: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(i) = text[from..].find(key) {
        let at = from + i;
        let before = text[..at].trim_end_matches([' ', '\t']);
        let after = text[at + key.len()..].trim_start_matches([' ', '\t']);
        let starts_key = before.is_empty() || before.ends_with(['\n', '{', ',']);
        if starts_key && after.starts_with('=') {
            return Some(at);
        }
        from = at + key.len();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column() {
        let s = SourceText::new("a.toml", "ab\ncdé\nf");
        assert_eq!(s.line_col(0), (1, 1));
        assert_eq!(s.line_col(3), (2, 1));
        assert_eq!(s.line_col(7), (2, 4));
        assert_eq!(s.line_col(8), (3, 1));
    }

    #[test]
    fn finds_keys_not_substrings() {
        let s = SourceText::new("a.toml", "[x]\nmy_cutoff = 1\ncutoff = 2\n");
        let e = s.error_at_key(0..s.text.len(), "cutoff", "bad");
        assert_eq!((e.line, e.column), (3, 1));
    }
}

//! Errors of the field loaders: every one names the file, line and column and
//! says what was expected.

use std::fmt;

/// A place in a text file; line and column count from 1. Line 0 means the
/// file as a whole (an I/O error, or a problem of no single line).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Location {
    /// The file as the user named it.
    pub file: String,
    /// 1-based line, or 0 for the whole file.
    pub line: usize,
    /// 1-based column (in characters), or 0 for the whole line.
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (self.line, self.column) {
            (0, _) => write!(f, "{}", self.file),
            (l, 0) => write!(f, "{}:{l}", self.file),
            (l, c) => write!(f, "{}:{l}:{c}", self.file),
        }
    }
}

/// A file could not be read as a field.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct FieldError {
    /// Where.
    pub location: Location,
    /// What was expected and what was found, in one sentence.
    pub message: String,
}

impl FieldError {
    /// An error at a line and column of `file`.
    pub fn at(file: &str, line: usize, column: usize, message: impl Into<String>) -> Self {
        FieldError {
            location: Location {
                file: file.to_string(),
                line,
                column,
            },
            message: message.into(),
        }
    }

    /// An error about `file` as a whole.
    pub fn whole(file: &str, message: impl Into<String>) -> Self {
        FieldError::at(file, 0, 0, message)
    }

    /// An I/O error on `file`.
    pub fn io(file: &str, e: &std::io::Error) -> Self {
        FieldError::whole(file, format!("cannot access file: {e}"))
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

impl std::error::Error for FieldError {}

/// Splits text into lines the way every loader counts them: 1-based numbers,
/// LF or CRLF endings, the `\r` removed.
pub(crate) fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
}

/// Whitespace-separated tokens of a line with their 1-based character
/// columns.
pub(crate) fn tokens(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    let mut col = 0;
    let mut start_col = 0;
    for (i, c) in line.char_indices() {
        col += 1;
        if c.is_whitespace() {
            if let Some(s) = start.take() {
                out.push((start_col, &line[s..i]));
            }
        } else if start.is_none() {
            start = Some(i);
            start_col = col;
        }
    }
    if let Some(s) = start {
        out.push((start_col, &line[s..]));
    }
    out
}

/// Parses a coordinate token (an `i16`) or says what was expected.
pub(crate) fn coordinate(
    file: &str,
    line: usize,
    (col, tok): (usize, &str),
    what: &str,
) -> Result<i16, FieldError> {
    tok.parse::<i16>().map_err(|_| {
        FieldError::at(
            file,
            line,
            col,
            format!("expected {what} as an integer in -32768..=32767, found '{tok}'"),
        )
    })
}

/// Where each node and start of a file was written, so that a validation
/// problem found after parsing can point at its line.
#[derive(Default)]
pub(crate) struct SourceMap {
    pub nodes: std::collections::HashMap<core_algo::geometry::Pos, (usize, usize)>,
    pub starts: Vec<(usize, usize)>,
}

impl SourceMap {
    /// The first problem of `err`, located at the line of the node or start
    /// it is about.
    pub fn locate(&self, file: &str, err: &super::ValidationError) -> FieldError {
        let (line, column) = err
            .problems
            .first()
            .and_then(|p| match p.start_index() {
                Some(i) => self.starts.get(i).copied(),
                None => p.pos().and_then(|pos| self.nodes.get(&pos).copied()),
            })
            .unwrap_or((0, 0));
        FieldError::at(file, line, column, err.to_string())
    }
}

//! The crate's errors. A value out of range is a `ConfigError`, naming the parameter (and the
//! line, when the value came from a file); a file that cannot be what it claims (a weights file, a
//! memory file, a YAML arena, an event log) is a `FileError`, naming the kind of file and what in
//! it is wrong. `Error` is either, for what can fail both ways (a run needs valid settings and a
//! readable model; a memory file must be sound and fit the run).

use std::fmt;

/// A configuration error: names the field, and the line for values read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigError {
    /// 1-based line in the source file, when the value came from a file.
    pub line: Option<usize>,
    /// The parameter or field, e.g. `items[2].sizes[0].x` or `seed`.
    pub field: String,
    /// What is wrong, with the allowed range.
    pub message: String,
}

impl ConfigError {
    /// An error about `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        ConfigError { line: None, field: field.into(), message: message.into() }
    }
    /// An error about `field` at 1-based `line` of a file.
    pub fn at(line: usize, field: impl Into<String>, message: impl Into<String>) -> Self {
        ConfigError { line: Some(line), field: field.into(), message: message.into() }
    }
}

/// "line 3: field: message", or "field: message".
fn show(f: &mut fmt::Formatter<'_>, line: Option<usize>, field: &str, message: &str) -> fmt::Result {
    match line {
        Some(line) => write!(f, "line {line}: {field}: {message}"),
        None => write!(f, "{field}: {message}"),
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        show(f, self.line, &self.field, &self.message)
    }
}

impl std::error::Error for ConfigError {}

/// A file refused: corrupt, truncated, of another kind or version, or not fitting the run.
#[derive(Clone, Debug, PartialEq)]
pub struct FileError {
    /// What the file is: `weights`, `memory`, `arena` (YAML) or `events`.
    pub file: &'static str,
    /// 1-based line, for text files.
    pub line: Option<usize>,
    /// What in it is wrong: a field (`arenas.0.t`, `n`), or the kind of file when it is the whole.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl FileError {
    /// The whole file is wrong.
    pub fn new(file: &'static str, message: impl Into<String>) -> Self {
        FileError { file, line: None, field: file.to_string(), message: message.into() }
    }

    /// One field of the file is wrong (or does not fit the run).
    pub fn field(file: &'static str, field: impl Into<String>, message: impl Into<String>) -> Self {
        FileError { file, line: None, field: field.into(), message: message.into() }
    }

    /// A value of the file out of range, as the value's own check reported it.
    pub fn value(file: &'static str, e: ConfigError) -> Self {
        FileError { file, line: e.line, field: e.field, message: e.message }
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        show(f, self.line, &self.field, &self.message)
    }
}

impl std::error::Error for FileError {}

/// A configuration or a file error.
#[derive(Clone, Debug, PartialEq)]
pub enum Error {
    /// A value out of range.
    Config(ConfigError),
    /// A file refused.
    File(FileError),
}

impl Error {
    /// The parameter or field named.
    pub fn field(&self) -> &str {
        match self {
            Error::Config(e) => &e.field,
            Error::File(e) => &e.field,
        }
    }
}

impl From<ConfigError> for Error {
    fn from(e: ConfigError) -> Self {
        Error::Config(e)
    }
}

impl From<FileError> for Error {
    fn from(e: FileError) -> Self {
        Error::File(e)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Config(e) => e.fmt(f),
            Error::File(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for Error {}

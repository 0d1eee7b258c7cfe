//! Errors of the files that shapes name (meshes, terrain grids): each names the file
//! and, where the format has lines, the line.

/// A problem with the content of a shape file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FormatError {
    /// At a line of a text format (1-based).
    #[error("line {line}: {problem}")]
    AtLine { line: usize, problem: String },
    /// Of the file as a whole (a count, a missing header, a non-finite value).
    #[error("{0}")]
    Whole(String),
}

impl FormatError {
    /// The problem `problem` at the 0-based line index `index`.
    pub fn at(index: usize, problem: impl Into<String>) -> Self {
        FormatError::AtLine {
            line: index + 1,
            problem: problem.into(),
        }
    }
}

/// An error reading a shape file.
#[derive(Debug, thiserror::Error)]
pub enum ShapeFileError {
    #[error("cannot read {file}: {source}")]
    Read {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: unknown mesh format `.{ext}`; use .obj or .stl")]
    UnknownFormat { file: String, ext: String },
    #[error("{file}: {error}")]
    Format { file: String, error: FormatError },
}

//! Scene errors: every one names the file, the key path and, when known, the line.

use std::fmt;

/// An error in a scene file or in a `--set` override.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// File the scene came from (or `<string>`).
    pub file: String,
    /// Dotted key path, e.g. `materials[0].friction_angle`.
    pub path: String,
    /// 1-based line in the file, when it could be located.
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(l) => write!(f, "{}:{}: ", self.file, l)?,
            None => write!(f, "{}: ", self.file)?,
        }
        if self.path.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "`{}`: {}", self.path, self.message)
        }
    }
}

impl std::error::Error for SceneError {}

//! Scene errors: every one names the file, the key path and, when known, the line.

/// An error in a scene file or in a `--set` override.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", self.located())]
pub struct SceneError {
    /// File the scene came from (or `<string>`).
    pub file: String,
    /// Dotted key path, e.g. `materials[0].friction_angle`.
    pub path: String,
    /// 1-based line in the file, when it could be located.
    pub line: Option<usize>,
    pub message: String,
}

impl SceneError {
    /// `file:line: `key`: message`, leaving out what is not known.
    fn located(&self) -> String {
        let at = match self.line {
            Some(l) => format!("{}:{}: ", self.file, l),
            None => format!("{}: ", self.file),
        };
        if self.path.is_empty() {
            format!("{at}{}", self.message)
        } else {
            format!("{at}`{}`: {}", self.path, self.message)
        }
    }
}

/// An error at a scene key, found before it is located in the file's text
/// ([`at`](super::at) locates it into a [`SceneError`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{path}`: {message}")]
pub struct KeyError {
    /// Dotted key path, e.g. `regions[0].shape`.
    pub path: String,
    pub message: String,
}

impl KeyError {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        KeyError {
            path: path.into(),
            message: message.into(),
        }
    }
}

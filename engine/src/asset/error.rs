use std::fmt;

/// A load failure: which file, and what is wrong with it. Never a panic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AssetError {
    /// The file (or asset name) being loaded.
    pub file: String,
    /// A one-line description of the problem.
    pub problem: String,
}

impl AssetError {
    pub fn new(file: impl Into<String>, problem: impl Into<String>) -> Self {
        Self {
            file: file.into(),
            problem: problem.into(),
        }
    }
}

impl fmt::Display for AssetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.problem)
    }
}

impl std::error::Error for AssetError {}

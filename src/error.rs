//! Library errors: bad input (naming file, field and reason) versus planning failures.
//!
//! A solver that stops early is *not* an error: it returns a result whose status says so.

use std::path::PathBuf;

/// Everything that can go wrong in pushpack.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input (instance, plan or scenario file) is invalid.
    #[error("{file}: field `{field}`: {reason}")]
    Input {
        /// The file the value came from (or `<memory>`).
        file: String,
        /// Dotted path of the offending field, e.g. `objects[2].size[1]`.
        field: String,
        /// Why the value is rejected.
        reason: String,
    },
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The path involved.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The instance is valid, but no plan satisfying every constraint exists within the search.
    #[error("no feasible plan: {reason}")]
    Infeasible {
        /// What made it infeasible.
        reason: String,
    },
}

impl Error {
    /// Shorthand for an [`Error::Input`].
    pub fn input(file: impl Into<String>, field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Input {
            file: file.into(),
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// True when the error is caused by bad input (the CLI exits with code 2).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Input { .. } | Error::Io { .. })
    }
}

/// Result alias used across the crate.
pub type Result<T> = std::result::Result<T, Error>;

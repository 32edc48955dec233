//! Errors of the file readers and writers.

use std::path::PathBuf;

use asperity_core::CoreError;

/// A failure to read or write a file, always naming the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoError {
    /// The operating system refused (missing file, permissions, disk full…).
    #[error("{}: {source}", path.display())]
    Os {
        /// The file.
        path: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The file's contents do not follow its format.
    #[error("{}: not a valid {format} file: {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// Format name.
        format: &'static str,
        /// What is wrong, with line or byte position where known.
        message: String,
    },
    /// The file parsed but describes invalid geometry (bad index, NaN…).
    #[error("{}: {source}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The geometry error.
        #[source]
        source: CoreError,
    },
    /// The extension names no format asperity knows.
    #[error("{}: unknown file type {ext:?} (run `asperity formats` for the list)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// Its extension.
        ext: String,
    },
    /// The format cannot hold this kind of data (e.g. a height field as STL).
    #[error("{}: {format} files cannot hold {kind}", path.display())]
    WrongKind {
        /// The file.
        path: PathBuf,
        /// Format name.
        format: &'static str,
        /// What was asked for ("a height field", …).
        kind: &'static str,
    },
    /// An output is a file the command read (by its name, a symlink or a
    /// hard link): writing it would replace the input.
    #[error(
        "{}: is the input {} (the same file): write the output elsewhere",
        path.display(),
        input.display()
    )]
    OutputIsInput {
        /// The output asked for.
        path: PathBuf,
        /// The input it is.
        input: PathBuf,
    },
    /// The channel asked for is not in the file (its channels are named).
    #[error("{}: {message}", path.display())]
    NoChannel {
        /// The file.
        path: PathBuf,
        /// What was asked and what the file has.
        message: String,
    },
    /// A valid file holding something asperity cannot represent yet
    /// (compression, a series of surfaces, a channel layout).
    #[error("{}: {format} file that asperity cannot read yet: {message}", path.display())]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// Format name.
        format: &'static str,
        /// What it holds.
        message: String,
    },
}

impl IoError {
    /// An OS error on `path`.
    pub fn os(path: &std::path::Path, source: std::io::Error) -> Self {
        IoError::Os {
            path: path.to_path_buf(),
            source,
        }
    }

    /// Invalid geometry read from or about to be written to `path`.
    pub fn invalid(path: &std::path::Path, source: CoreError) -> Self {
        IoError::Invalid {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// An error inside one format's code, before the path is known.
#[derive(Debug)]
pub(crate) enum FormatError {
    Io(std::io::Error),
    Malformed(String),
    Unsupported(String),
    Invalid(CoreError),
    NoChannel(String),
}

impl From<std::io::Error> for FormatError {
    fn from(e: std::io::Error) -> Self {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            FormatError::Malformed("file ends early (truncated)".into())
        } else {
            FormatError::Io(e)
        }
    }
}

impl From<CoreError> for FormatError {
    fn from(e: CoreError) -> Self {
        FormatError::Invalid(e)
    }
}

impl FormatError {
    pub(crate) fn at(self, path: &std::path::Path, format: &'static str) -> IoError {
        let path = path.to_path_buf();
        match self {
            FormatError::Io(source) => IoError::Os { path, source },
            FormatError::Malformed(message) => IoError::Malformed {
                path,
                format,
                message,
            },
            FormatError::Unsupported(message) => IoError::Unsupported {
                path,
                format,
                message,
            },
            FormatError::Invalid(source) => IoError::Invalid { path, source },
            FormatError::NoChannel(message) => IoError::NoChannel { path, message },
        }
    }
}

/// Shorthand for a malformed-file error.
pub(crate) fn malformed<T>(msg: impl Into<String>) -> Result<T, FormatError> {
    Err(FormatError::Malformed(msg.into()))
}

/// Shorthand for a valid file asperity cannot represent yet.
pub(crate) fn unsupported<T>(msg: impl Into<String>) -> Result<T, FormatError> {
    Err(FormatError::Unsupported(msg.into()))
}

pub(crate) type FResult<T> = Result<T, FormatError>;

/// The message of a refused read, for the readers' tests (`{e:?}` names the
/// cause); panics if the read was accepted.
#[cfg(test)]
pub(crate) fn refused<T>(r: FResult<T>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => format!("{e:?}"),
    }
}

//! The formats asperity reads and writes: what each holds, its extensions,
//! and how a file's format is told (by extension, else by its first bytes).

use std::path::Path;

use crate::{FORMATS, Format, IoError};

/// What a format can do with one kind of data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Access {
    /// Not supported.
    None,
    /// Read only.
    Read,
    /// Write only.
    Write,
    /// Read and write.
    ReadWrite,
}

impl Access {
    /// Can this be read?
    pub fn can_read(self) -> bool {
        matches!(self, Access::Read | Access::ReadWrite)
    }
    /// Can this be written?
    pub fn can_write(self) -> bool {
        matches!(self, Access::Write | Access::ReadWrite)
    }
}

/// A row of the format table (`asperity formats`).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct FormatInfo {
    /// The format.
    pub format: Format,
    /// Human name.
    pub name: &'static str,
    /// File extensions, lower case, without dots.
    pub extensions: &'static [&'static str],
    /// Triangle meshes.
    pub mesh: Access,
    /// Point sets.
    pub points: Access,
    /// Height fields.
    pub height: Access,
    /// What to know (precision, conventions).
    pub notes: &'static str,
}

mod registration;
pub(crate) mod registry;

pub(crate) use registration::{Claim, Codec, Magic, Registration};
pub(crate) use registry::registry;

/// `path`'s extension, lower case ("" when it has none).
fn lower_extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// The first 64 KiB of a text file (enough for a header and data lines).
fn text_head(path: &Path) -> Vec<u8> {
    let mut head = Vec::new();
    let _ = std::fs::File::open(path)
        .and_then(|f| std::io::Read::read_to_end(&mut std::io::Read::take(f, 1 << 16), &mut head));
    head
}

impl Format {
    /// The format of the file at `path`: by its extension, or, where the
    /// extension names none (instruments' own or none at all), by the magic
    /// its content starts with (SDF, Digital Surf, npy, PNG, EXR, GSF, .gwy,
    /// PLY, TrueMap, BCR, MetroPro, Alicona, WSxM, the instruments' formats
    /// with a magic, and OLE compound files as Mountains documents).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`] when neither tells (or the file cannot be
    /// opened to look).
    pub fn of_file(path: &Path) -> Result<Format, IoError> {
        let ext = lower_extension(path);
        let mut text = None;
        let claimed = Format::ALL.iter().copied().find(|f| {
            f.registration().claim.is_some_and(|claim| {
                claim.extensions.contains(&ext.as_str())
                    && (claim.test)(text.get_or_insert_with(|| text_head(path)))
            })
        });
        if let Some(format) = claimed {
            return Ok(format);
        }
        Format::from_path(path).or_else(|e| {
            // A file that cannot be opened keeps the message about its name.
            let mut head = [0u8; 64];
            let n = std::fs::File::open(path)
                .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
                .unwrap_or(0);
            Format::from_content(&head[..n]).ok_or(e)
        })
    }

    /// The format whose magic `bytes` start with, if one does (the first
    /// in the registry's order).
    pub fn from_content(bytes: &[u8]) -> Option<Format> {
        Format::ALL
            .iter()
            .copied()
            .find(|f| f.registration().magic.matches(bytes))
    }

    /// The format named by `path`'s extension (case-insensitive).
    ///
    /// # Errors
    /// [`IoError::UnknownFormat`].
    pub fn from_path(path: &Path) -> Result<Format, IoError> {
        let ext = lower_extension(path);
        FORMATS
            .iter()
            .find(|f| f.extensions.contains(&ext.as_str()))
            .map(|f| f.format)
            .ok_or_else(|| IoError::UnknownFormat {
                path: path.to_path_buf(),
                ext,
            })
    }

    /// Whether files of this format can hold several channels (`--channel`
    /// picks one; other formats accept only channel 0).
    pub fn has_channels(self) -> bool {
        self.registration()
            .codec
            .is_some_and(|c| c.channels.is_some())
    }

    /// Whether a file of this format is told by its content where its
    /// extension names none ([`Format::from_content`]).
    pub fn has_magic(self) -> bool {
        !matches!(self.registration().magic, Magic::None)
    }

    /// This format's row of [`FORMATS`].
    pub fn info(self) -> &'static FormatInfo {
        // The registry lists the rows in the variants' order.
        &FORMATS[self as usize]
    }
}

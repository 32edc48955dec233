//! What one format registers: its row of the format table, how its files are
//! told by their content, and how a file of it is decoded. Each format's
//! module holds its registration (`FORMAT`, or one per format where a module
//! reads several); [`super::registry`] lists them, one line each.

use asperity_core::HeightField;

use super::{Access, Format, FormatInfo};
use crate::channel::{Channel, ChannelInfo};
use crate::error::FResult;
use crate::{Metadata, Surface};

/// Reads the height field of the channel chosen (None: the default one).
pub(crate) type Height = fn(&[u8], Option<&Channel>) -> FResult<HeightField>;
/// Lists a file's channels.
pub(crate) type Channels = fn(&[u8]) -> FResult<Vec<ChannelInfo>>;
/// Reads the instrument's metadata.
pub(crate) type Meta = fn(&[u8]) -> FResult<Metadata>;
/// The bytes a file declares it decodes to (before decoding anything).
pub(crate) type Declared = fn(&[u8]) -> FResult<u128>;
/// Reads a file whose content decides what it holds.
pub(crate) type Read = fn(&[u8]) -> FResult<Surface>;

/// How a file whose extension names no format is told as this one by its
/// first 64 bytes.
#[derive(Clone, Copy)]
pub(crate) enum Magic {
    /// Not by content.
    None,
    /// It starts with one of these.
    Starts(&'static [&'static [u8]]),
    /// This test holds of its first bytes.
    Test(fn(&[u8]) -> bool),
}

impl Magic {
    /// Whether `head` (a file's first bytes) is told as this format.
    pub(crate) fn matches(self, head: &[u8]) -> bool {
        match self {
            Magic::None => false,
            Magic::Starts(magics) => magics.iter().any(|m| head.starts_with(m)),
            Magic::Test(test) => test(head),
        }
    }
}

/// A format that shares an extension with another and claims the files of
/// that extension whose content passes its test (a Dektak export among CSV
/// grids, plain-text heights among `.txt` points).
#[derive(Clone, Copy)]
pub(crate) struct Claim {
    /// The extensions it claims files of.
    pub(crate) extensions: &'static [&'static str],
    /// The test, on the file's first 64 KiB.
    pub(crate) test: fn(&[u8]) -> bool,
}

/// How a file that holds a height field is decoded: its reader (of a chosen
/// channel where it has several), its channels, the instrument's metadata,
/// and what its header declares it decodes to.
#[derive(Clone, Copy)]
pub(crate) struct Codec {
    pub(crate) height: Height,
    /// Set for the formats whose files hold several channels.
    pub(crate) channels: Option<Channels>,
    pub(crate) metadata: Option<Meta>,
    /// Set for the compressed containers whose memory estimate is what
    /// they declare rather than a multiple of the file's size.
    pub(crate) declared: Option<Declared>,
}

impl Codec {
    /// A height reader that ignores the channel (the format has one).
    pub(crate) const fn new(height: Height) -> Self {
        Self {
            height,
            channels: None,
            metadata: None,
            declared: None,
        }
    }
    pub(crate) const fn channels(mut self, c: Channels) -> Self {
        self.channels = Some(c);
        self
    }
    pub(crate) const fn metadata(mut self, m: Meta) -> Self {
        self.metadata = Some(m);
        self
    }
    pub(crate) const fn declared(mut self, d: Declared) -> Self {
        self.declared = Some(d);
        self
    }
}

/// One format, as its module registers it.
#[derive(Clone, Copy)]
pub(crate) struct Registration {
    /// Human name.
    pub(crate) name: &'static str,
    /// File extensions, lower case, without dots.
    pub(crate) extensions: &'static [&'static str],
    pub(crate) mesh: Access,
    pub(crate) points: Access,
    pub(crate) height: Access,
    /// What to know (precision, conventions).
    pub(crate) notes: &'static str,
    pub(crate) magic: Magic,
    pub(crate) claim: Option<Claim>,
    /// Set for the formats whose files hold meshes or points, or whose
    /// content decides what they hold (a PLY without faces is a point set);
    /// the others are read as height fields by their codec.
    pub(crate) read: Option<Read>,
    /// Set for every format that reads height fields.
    pub(crate) codec: Option<Codec>,
    /// Set for the compressed point formats: what a file declares it
    /// decodes to (the height formats declare theirs in their codec).
    pub(crate) declared: Option<Declared>,
}

impl Registration {
    /// Nothing read, written or told: the base a registration fills in.
    pub(crate) const NONE: Registration = Registration {
        name: "",
        extensions: &[],
        mesh: Access::None,
        points: Access::None,
        height: Access::None,
        notes: "",
        magic: Magic::None,
        claim: None,
        read: None,
        codec: None,
        declared: None,
    };

    /// What a file of this format declares it decodes to, where it says.
    pub(crate) fn declared_size(&self) -> Option<Declared> {
        self.codec.and_then(|c| c.declared).or(self.declared)
    }

    /// The row of the format table.
    pub(crate) const fn info(&self, format: Format) -> FormatInfo {
        FormatInfo {
            format,
            name: self.name,
            extensions: self.extensions,
            mesh: self.mesh,
            points: self.points,
            height: self.height,
            notes: self.notes,
        }
    }
}

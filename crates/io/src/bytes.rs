//! Bounded reading of binary files, shared by the readers: numbers at fixed
//! offsets ([`Fields`], for headers laid out by offset) and in sequence
//! ([`Cursor`], for tagged or variable-length structures), little- or
//! big-endian. A read past the end is a [`FormatError::Malformed`] that says
//! where the file ends, never a panic or an out-of-bounds slice. (Gwyddion's
//! readers share `get.h`, SurfaceTopography's a `binary` helper, for the same
//! reason: each reader had its own copy of this.)
//!
//! Written here rather than taken from a crate (`byteorder`, `scroll`): the
//! readers need their own error type and message, offsets that saturate, and
//! both a positional and a sequential view of one slice; the whole is a few
//! lines over `from_le_bytes` / `from_be_bytes`.

use crate::error::{FResult, FormatError};

/// The byte order of a file's numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Endian {
    Little,
    Big,
}

/// The error of a read of `n` bytes at `at` from a file of `len` bytes.
fn past_end(at: usize, n: usize, len: usize) -> FormatError {
    FormatError::Malformed(format!(
        "the file ends at byte {len}, before byte {} (truncated?)",
        at.saturating_add(n)
    ))
}

/// Defines the typed getters of [`Fields`] (at an offset) and [`Cursor`]
/// (at its position, which they advance).
macro_rules! numbers {
    ($($name:ident: $ty:ty),* $(,)?) => {
        impl Fields<'_> {
            $(
                #[doc = concat!("The `", stringify!($ty), "` at byte `at`.")]
                #[allow(dead_code)]
                pub(crate) fn $name(&self, at: usize) -> FResult<$ty> {
                    let b = self.array(at)?;
                    Ok(match self.endian {
                        Endian::Little => <$ty>::from_le_bytes(b),
                        Endian::Big => <$ty>::from_be_bytes(b),
                    })
                }
            )*
        }

        impl Cursor<'_> {
            $(
                #[doc = concat!("The next `", stringify!($ty), "`.")]
                #[allow(dead_code)]
                pub(crate) fn $name(&mut self) -> FResult<$ty> {
                    let v = self.fields.$name(self.at)?;
                    self.at += std::mem::size_of::<$ty>();
                    Ok(v)
                }
            )*
        }
    };
}

numbers! {
    u8: u8, i8: i8, u16: u16, i16: i16, u32: u32, i32: i32, u64: u64, i64: i64,
    f32: f32, f64: f64,
}

/// A file's bytes read at fixed offsets.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fields<'a> {
    bytes: &'a [u8],
    endian: Endian,
}

impl<'a> Fields<'a> {
    /// Little-endian numbers.
    pub(crate) const fn le(bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            endian: Endian::Little,
        }
    }

    /// Big-endian numbers.
    pub(crate) const fn be(bytes: &'a [u8]) -> Self {
        Self {
            bytes,
            endian: Endian::Big,
        }
    }

    /// The bytes it reads.
    pub(crate) const fn all(&self) -> &'a [u8] {
        self.bytes
    }

    /// The `n` bytes at `at`.
    pub(crate) fn bytes(&self, at: usize, n: usize) -> FResult<&'a [u8]> {
        at.checked_add(n)
            .and_then(|end| self.bytes.get(at..end))
            .ok_or_else(|| past_end(at, n, self.bytes.len()))
    }

    /// The `N` bytes at `at`, as an array.
    pub(crate) fn array<const N: usize>(&self, at: usize) -> FResult<[u8; N]> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.bytes(at, N)?);
        Ok(out)
    }

    /// The `f32` at `at`, widened.
    pub(crate) fn f32_wide(&self, at: usize) -> FResult<f64> {
        self.f32(at).map(f64::from)
    }

    /// A cursor over these bytes, at `at`.
    pub(crate) const fn cursor(self, at: usize) -> Cursor<'a> {
        Cursor { fields: self, at }
    }
}

/// A file's bytes read in sequence.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cursor<'a> {
    fields: Fields<'a>,
    at: usize,
}

impl<'a> Cursor<'a> {
    /// Little-endian numbers, from the first byte.
    pub(crate) const fn le(bytes: &'a [u8]) -> Self {
        Fields::le(bytes).cursor(0)
    }

    /// Big-endian numbers, from the first byte.
    #[allow(dead_code)]
    pub(crate) const fn be(bytes: &'a [u8]) -> Self {
        Fields::be(bytes).cursor(0)
    }

    /// Where the next read starts.
    pub(crate) const fn at(&self) -> usize {
        self.at
    }

    /// The bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.fields.bytes.len().saturating_sub(self.at)
    }

    /// Whether every byte has been read.
    pub(crate) fn is_done(&self) -> bool {
        self.remaining() == 0
    }

    /// Moves to byte `at` (a read there fails if it is past the end).
    pub(crate) fn seek(&mut self, at: usize) {
        self.at = at;
    }

    /// A cursor at this one's position over the bytes before `end` (a
    /// block's end), which must be in the file and not before the position.
    pub(crate) fn up_to(&self, end: usize) -> FResult<Cursor<'a>> {
        if end < self.at {
            return Err(past_end(self.at, 0, end));
        }
        let bytes = self.fields.bytes(0, end)?;
        Ok(Fields {
            bytes,
            ..self.fields
        }
        .cursor(self.at))
    }

    /// The next `n` bytes.
    pub(crate) fn take(&mut self, n: usize) -> FResult<&'a [u8]> {
        let b = self.fields.bytes(self.at, n)?;
        self.at += n;
        Ok(b)
    }

    /// Skips `n` bytes (which must be there).
    pub(crate) fn skip(&mut self, n: usize) -> FResult<()> {
        self.take(n).map(|_| ())
    }

    /// The next bytes up to a NUL (which is skipped).
    pub(crate) fn c_string(&mut self) -> FResult<&'a [u8]> {
        let rest = &self.fields.bytes[self.at.min(self.fields.bytes.len())..];
        let n = rest.iter().position(|&b| b == 0).ok_or_else(|| {
            FormatError::Malformed(format!(
                "a string at byte {} has no terminating NUL (truncated?)",
                self.at
            ))
        })?;
        self.at += n + 1;
        Ok(&rest[..n])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_either_order_at_offsets_and_in_sequence() {
        let b = [0x01, 0x02, 0x03, 0x04, 0x00, 0x00, 0x80, 0x3f];
        let le = Fields::le(&b);
        assert_eq!(le.u16(0).unwrap(), 0x0201);
        assert_eq!(le.u32(0).unwrap(), 0x0403_0201);
        assert_eq!(le.f32(4).unwrap(), 1.0);
        assert_eq!(Fields::be(&b).u16(0).unwrap(), 0x0102);
        assert_eq!(Fields::be(&b).i32(0).unwrap(), 0x0102_0304);
        let mut c = Cursor::le(&b);
        assert_eq!(c.u8().unwrap(), 1);
        assert_eq!(c.u8().unwrap(), 2);
        assert_eq!(c.u16().unwrap(), 0x0403);
        assert_eq!(c.f32().unwrap(), 1.0);
        assert_eq!((c.at(), c.remaining()), (8, 0));
    }

    #[test]
    fn a_read_past_the_end_is_an_error_saying_where_the_file_ends() {
        let b = [0u8; 6];
        let f = Fields::le(&b);
        let FormatError::Malformed(e) = f.u32(4).unwrap_err() else {
            panic!("not a Malformed error")
        };
        assert_eq!(e, "the file ends at byte 6, before byte 8 (truncated?)");
        assert!(f.u64(usize::MAX - 2).is_err());
        assert!(f.bytes(usize::MAX, 2).is_err());
        let mut c = Cursor::le(&b);
        c.skip(5).unwrap();
        assert!(c.u16().is_err());
        assert_eq!(c.at(), 5, "a failed read does not move the cursor");
        assert!(Cursor::le(b"abc").c_string().is_err());
        let mut c = Cursor::le(b"ab\0cd\0");
        assert_eq!(c.c_string().unwrap(), b"ab");
        assert_eq!(c.c_string().unwrap(), b"cd");
        assert!(c.c_string().is_err());
    }
}

//! TIFF directories walked by hand, for the instruments that keep their
//! data and metadata in TIFF pages (Olympus LEXT). Only what those readers
//! need: every page's entries, ASCII and UNDEFINED values, sub-directories
//! (the EXIF directory) and one uncompressed single-sample raster a page.
//! The `tiff` crate decodes images but does not expose private tags or
//! sub-directories, hence this. Classic TIFF only (BigTIFF is refused);
//! every offset is bounds-checked, and a loop of pages ends the walk.

use std::collections::HashSet;

use crate::error::{FResult, FormatError, malformed, unsupported};

/// One directory entry: tag, type and the value's bytes.
pub(crate) struct Entry<'a> {
    pub tag: u16,
    pub kind: u16,
    pub value: &'a [u8],
}

/// A TIFF file's byte order and bytes.
#[derive(Clone, Copy)]
pub(crate) struct Tiff<'a> {
    pub bytes: &'a [u8],
    little: bool,
}

const MAX_PAGES: usize = 4096;

fn type_size(kind: u16) -> Option<usize> {
    match kind {
        1 | 2 | 6 | 7 => Some(1),
        3 | 8 => Some(2),
        4 | 9 | 11 | 13 => Some(4),
        5 | 10 | 12 => Some(8),
        _ => None,
    }
}

impl<'a> Tiff<'a> {
    /// The file, if it is a classic TIFF.
    pub(crate) fn new(bytes: &'a [u8]) -> FResult<Tiff<'a>> {
        let little = match bytes.get(..4) {
            Some(b"II*\0") => true,
            Some(b"MM\0*") => false,
            Some(b"II+\0" | b"MM\0+") => return unsupported("a BigTIFF file"),
            _ => return malformed("not a TIFF file"),
        };
        Ok(Tiff { bytes, little })
    }

    fn get(&self, o: usize, n: usize) -> FResult<&'a [u8]> {
        self.bytes.get(o..o.saturating_add(n)).ok_or_else(|| {
            FormatError::Malformed(format!(
                "a TIFF offset {o} runs past the file's end (truncated?)"
            ))
        })
    }

    pub(crate) fn u16(&self, b: &[u8]) -> u16 {
        let a = [b[0], b[1]];
        if self.little {
            u16::from_le_bytes(a)
        } else {
            u16::from_be_bytes(a)
        }
    }

    pub(crate) fn u32(&self, b: &[u8]) -> u32 {
        let a = [b[0], b[1], b[2], b[3]];
        if self.little {
            u32::from_le_bytes(a)
        } else {
            u32::from_be_bytes(a)
        }
    }

    /// The entries of the directory at `at`, and the next directory's offset.
    pub(crate) fn directory(&self, at: usize) -> FResult<(Vec<Entry<'a>>, usize)> {
        let n = usize::from(self.u16(self.get(at, 2)?));
        let mut out = Vec::with_capacity(n.min(1024));
        for k in 0..n {
            let e = self.get(at + 2 + 12 * k, 12)?;
            let (tag, kind, count) = (self.u16(e), self.u16(&e[2..]), self.u32(&e[4..]));
            let Some(size) = type_size(kind) else {
                continue; // an unknown type: skipped, as TIFF readers do
            };
            let len = size.checked_mul(count as usize).ok_or_else(|| {
                FormatError::Malformed(format!("tag {tag}: {count} values overflow"))
            })?;
            let value = if len <= 4 {
                &e[8..8 + len]
            } else {
                self.get(self.u32(&e[8..]) as usize, len)?
            };
            out.push(Entry { tag, kind, value });
        }
        let next = self.u32(self.get(at + 2 + 12 * n, 4)?) as usize;
        Ok((out, next))
    }

    /// Every page's entries, in order.
    pub(crate) fn pages(&self) -> FResult<Vec<Vec<Entry<'a>>>> {
        let mut at = self.u32(self.get(4, 4)?) as usize;
        let mut seen = HashSet::new();
        let mut out = Vec::new();
        while at != 0 && seen.insert(at) && out.len() < MAX_PAGES {
            let (entries, next) = self.directory(at)?;
            out.push(entries);
            at = next;
        }
        Ok(out)
    }

    /// The first number of an integer entry.
    pub(crate) fn number(&self, e: &Entry<'_>) -> Option<u32> {
        match (e.kind, e.value.len()) {
            (3, 2..) => Some(u32::from(self.u16(e.value))),
            (4, 4..) => Some(self.u32(e.value)),
            _ => None,
        }
    }

    /// The first number of an integer or floating-point entry, as f64.
    pub(crate) fn real(&self, e: &Entry<'_>) -> Option<f64> {
        match (e.kind, e.value.len()) {
            (12, 8..) => {
                let mut a: [u8; 8] = e.value[..8].try_into().expect("8 bytes");
                if !self.little {
                    a.reverse();
                }
                Some(f64::from_le_bytes(a))
            }
            (11, 4..) => Some(f64::from(f32::from_bits(self.u32(e.value)))),
            _ => self.number(e).map(f64::from),
        }
    }
}

/// The text of an ASCII or UNDEFINED entry (Latin-1, up to its first NUL).
pub(crate) fn text(e: &Entry<'_>) -> String {
    e.value
        .iter()
        .take_while(|&&b| b != 0)
        .map(|&b| char::from(b))
        .collect()
}

/// The entry with `tag`, if the page has one.
pub(crate) fn find<'e, 'a>(page: &'e [Entry<'a>], tag: u16) -> Option<&'e Entry<'a>> {
    page.iter().find(|e| e.tag == tag)
}

/// A page's raster: width, height and the samples as f64, row by row.
/// Uncompressed, one sample a point, 8/16/32-bit integers or 32/64-bit
/// floats in strips.
pub(crate) fn raster(tiff: &Tiff<'_>, page: &[Entry<'_>]) -> FResult<(usize, usize, Vec<f64>)> {
    let num = |tag: u16, default: Option<u32>| -> FResult<u32> {
        find(page, tag)
            .and_then(|e| tiff.number(e))
            .or(default)
            .ok_or_else(|| FormatError::Malformed(format!("a page has no tag {tag}")))
    };
    let (w, h) = (num(256, None)? as usize, num(257, None)? as usize);
    let bits = num(258, Some(1))?;
    let format = num(339, Some(1))?;
    if num(259, Some(1))? != 1 {
        return unsupported("a compressed raster (only uncompressed rasters are read)");
    }
    if num(277, Some(1))? != 1 {
        return unsupported("a raster of several samples a point");
    }
    let size = match (format, bits) {
        (1 | 2, 8 | 16 | 32) | (3, 32) => bits as usize / 8,
        (3, 64) => 8,
        _ => return unsupported(format!("samples of {bits} bits in sample format {format}")),
    };
    let offsets =
        find(page, 273).ok_or_else(|| FormatError::Malformed("no strip offsets".into()))?;
    let counts =
        find(page, 279).ok_or_else(|| FormatError::Malformed("no strip byte counts".into()))?;
    let n = w
        .checked_mul(h)
        .filter(|&n| n > 0)
        .ok_or_else(|| FormatError::Malformed(format!("a raster of {w} × {h} points")))?;
    // An uncompressed raster is no larger than the file that holds it (a
    // strip list naming the same bytes over and over is refused).
    let need = n
        .checked_mul(size)
        .filter(|&need| need <= tiff.bytes.len())
        .ok_or_else(|| {
            FormatError::Malformed(format!(
                "a raster of {w} × {h} points is larger than the file"
            ))
        })?;
    let values = |e: &Entry<'_>| -> Vec<usize> {
        let step = if e.kind == 3 { 2 } else { 4 };
        e.value
            .chunks_exact(step)
            .map(|c| {
                if step == 2 {
                    usize::from(tiff.u16(c))
                } else {
                    tiff.u32(c) as usize
                }
            })
            .collect()
    };
    let mut data = Vec::with_capacity(need.min(tiff.bytes.len()));
    for (o, c) in values(offsets).into_iter().zip(values(counts)) {
        data.extend_from_slice(tiff.get(o, c)?);
        if data.len() >= need {
            break;
        }
    }
    if data.len() < need {
        return malformed(format!(
            "{w} × {h} samples need {need} bytes, the strips hold {}",
            data.len()
        ));
    }
    let sample = |c: &[u8]| -> f64 {
        let mut a = [0u8; 8];
        a[..c.len()].copy_from_slice(c);
        if !tiff.little {
            a[..c.len()].reverse();
        }
        let u = u64::from_le_bytes(a);
        match (format, c.len()) {
            (1, _) => u as f64,
            (2, 1) => f64::from(u as u8 as i8),
            (2, 2) => f64::from(u as u16 as i16),
            (2, _) => f64::from(u as u32 as i32),
            (3, 4) => f64::from(f32::from_bits(u as u32)),
            _ => f64::from_bits(u),
        }
    };
    Ok((w, h, data[..need].chunks_exact(size).map(sample).collect()))
}

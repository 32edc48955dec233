//! Zip members read with a bound, shared by the readers of zipped formats
//! (NumPy `.npz`, Sensofar `.plux`, Keyence VK6/VK7, SIOS NMM, packed Olympus
//! `.poir`, Mahr `.qep`), as Gwyddion's readers share `gwyzip.h`. A member is
//! inflated to at most the size its entry declares — the size the memory
//! estimate (a row's `declared` in `codecs.rs`) counted before anything was read —
//! and to at most the reader's own limit, so a lying entry cannot grow past
//! either.

use std::io::{Cursor, Read};

use crate::error::{FResult, FormatError};

/// A zip archive over a file's bytes.
pub(crate) type Archive<'a> = zip::ZipArchive<Cursor<&'a [u8]>>;

/// The archive in `bytes`; what the zip crate could not read is told through
/// the reader's `bad`.
pub(crate) fn open(bytes: &[u8], bad: impl Fn(String) -> FormatError) -> FResult<Archive<'_>> {
    zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| bad(e.to_string()))
}

/// Twice the inflated members of a zip-based format (each member inflated,
/// then parsed or converted): the memory estimate of npz, PLUX, QEP, NMM,
/// Mitutoyo workbooks and packed OIR.
pub(crate) fn declared_twice(bytes: &[u8]) -> FResult<u128> {
    declared_bytes(bytes).map(|n| n.saturating_mul(2))
}

/// The bytes the archive's members declare once inflated (from its central
/// directory, before anything is inflated): what the memory estimate counts.
pub(crate) fn declared_bytes(bytes: &[u8]) -> FResult<u128> {
    let bad = |e: String| FormatError::Malformed(format!("not a readable zip archive: {e}"));
    let mut zip = open(bytes, bad)?;
    let mut total = 0u128;
    for k in 0..zip.len() {
        let size = zip.by_index_raw(k).map_err(|e| bad(e.to_string()))?.size();
        total = total.saturating_add(u128::from(size));
    }
    Ok(total)
}

/// `file`'s bytes, at most `declared` and `limit` of them.
fn inflate(file: impl Read, declared: u64, limit: u64) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    file.take(declared.min(limit)).read_to_end(&mut out)?;
    Ok(out)
}

/// Member `name`'s bytes (at most `limit`); None where the archive has no such
/// member. A read error is "member NAME: cause", through `bad`.
pub(crate) fn by_name(
    zip: &mut Archive<'_>,
    name: &str,
    limit: u64,
    bad: impl Fn(String) -> FormatError,
) -> FResult<Option<Vec<u8>>> {
    let Ok(file) = zip.by_name(name) else {
        return Ok(None);
    };
    let declared = file.size();
    inflate(file, declared, limit)
        .map(Some)
        .map_err(|e| bad(format!("member {name:?}: {e}")))
}

/// Member `name`'s bytes (at most `limit`); a missing member is "the archive
/// has no member NAME".
pub(crate) fn required(
    zip: &mut Archive<'_>,
    name: &str,
    limit: u64,
    bad: impl Fn(String) -> FormatError,
) -> FResult<Vec<u8>> {
    by_name(zip, name, limit, bad)?
        .ok_or_else(|| FormatError::Malformed(format!("the archive has no member {name:?}")))
}

/// Member `k`'s name and bytes (at most their declared size).
pub(crate) fn by_index(
    zip: &mut Archive<'_>,
    k: usize,
    bad: impl Fn(String) -> FormatError,
) -> FResult<(String, Vec<u8>)> {
    let file = zip.by_index(k).map_err(|e| bad(e.to_string()))?;
    let name = file.name().map_err(|e| bad(e.to_string()))?.into_owned();
    let declared = file.size();
    let bytes =
        inflate(file, declared, u64::MAX).map_err(|e| bad(format!("member {name:?}: {e}")))?;
    Ok((name, bytes))
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn archive(members: &[(&str, &[u8])]) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        for (name, bytes) in members {
            zip.start_file(*name, zip::write::SimpleFileOptions::default())
                .unwrap();
            zip.write_all(bytes).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    fn bad(e: String) -> FormatError {
        FormatError::Malformed(format!("not a test archive: {e}"))
    }

    #[test]
    fn members_by_name_and_index_within_their_limits() {
        let bytes = archive(&[("a.txt", b"hello"), ("b.bin", &[7; 100])]);
        let mut zip = open(&bytes, bad).unwrap();
        assert_eq!(required(&mut zip, "a.txt", 64, bad).unwrap(), b"hello");
        assert_eq!(required(&mut zip, "b.bin", 10, bad).unwrap(), [7; 10]);
        assert_eq!(by_name(&mut zip, "c", 64, bad).unwrap(), None);
        match required(&mut zip, "c", 64, bad) {
            Err(FormatError::Malformed(m)) => assert_eq!(m, "the archive has no member \"c\""),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            by_index(&mut zip, 1, bad).unwrap(),
            ("b.bin".into(), vec![7; 100])
        );
        assert!(
            matches!(open(b"not a zip", bad), Err(FormatError::Malformed(m)) if m.starts_with("not a test archive: "))
        );
    }
}

//! The parameters a file was made with (issue #36): every format with a place
//! for metadata records the job's `params` (the resolved values, the seed and
//! the schema version, as the JSON report's `params`), so a file alone says
//! how to make it again (`asperity … --params FILE`).
//!
//! | Format | Where |
//! | --- | --- |
//! | PLY | a header line `comment asperity-params {…}` |
//! | OBJ | a line `# asperity-params {…}` |
//! | glTF (`.glb`) | `asset.extras.asperity_params` (a JSON object) |
//! | PNG | a `tEXt` chunk `asperity:params` |
//! | OpenEXR | the standard `comments` attribute |
//! | GSF | a header field `AsperityParams = {…}` (Gwyddion lists it as metadata) |
//! | `.gwy` | `/0/meta`'s string `asperity params` (Gwyddion's metadata browser) |
//! | x3p | `Record2/Comment` |
//! | CSV | a comment line `# asperity params: {…}` |
//!
//! `.npy`, STL and XYZ have no such place (numpy refuses unknown header keys;
//! STL's 80-byte header is too small); their JSON report holds the parameters.
//!
//! The text is one line of compact JSON with every non-ASCII character
//! escaped (`\uXXXX`), so it fits PNG's Latin-1 `tEXt`, EXR's text attributes
//! and one header line anywhere; keys are sorted, so a value written from the
//! CLI and from Python gives the same bytes.

use std::path::Path;

use serde_json::Value;

use crate::error::{FResult, FormatError};
use crate::{Format, IoError, exr_io, glb, gsf, gwy, png_io, sdf, x3p};

/// The PLY comment's and the OBJ comment's keyword.
pub(crate) const KEYWORD: &str = "asperity-params";
/// The CSV comment's prefix.
pub(crate) const CSV_PREFIX: &str = "# asperity params: ";

/// How much of a PLY, OBJ, CSV, GSF or PNG file is read for its record (the
/// headers the writers put it in are a few kilobytes).
const HEAD_BYTES: u64 = 1 << 20;

/// `params` as one line of compact, ASCII-only JSON (keys sorted).
pub fn params_text(params: &Value) -> String {
    let text = serde_json::to_string(params).unwrap_or_default();
    let mut ascii = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_ascii() {
            ascii.push(c);
        } else {
            // JSON's \u escape, a surrogate pair beyond the BMP; non-ASCII
            // characters only occur inside strings, where the escape is valid.
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                ascii += &format!("\\u{u:04x}");
            }
        }
    }
    ascii
}

/// Parses a recorded parameter text (a JSON object).
fn parse(text: &str) -> FResult<Value> {
    match serde_json::from_str::<Value>(text.trim()) {
        Ok(v @ Value::Object(_)) => Ok(v),
        Ok(_) => Err(FormatError::Malformed(
            "the recorded parameters are not a JSON object".into(),
        )),
        Err(e) => Err(FormatError::Malformed(format!(
            "the recorded parameters are not JSON: {e}"
        ))),
    }
}

/// The parameters recorded in `path` (see the module docs), or `None` when
/// the file records none or its format has no place for them.
///
/// # Errors
/// [`IoError`] when the file cannot be read or is not of its format, or its
/// record is not a JSON object.
pub fn read_params(path: &Path) -> Result<Option<Value>, IoError> {
    let f = Format::of_file(path)?;
    let os = |e| IoError::os(path, e);
    // Text headers come first: a huge mesh need not be read for them.
    let bytes = if matches!(
        f,
        Format::Ply | Format::Obj | Format::Csv | Format::Gsf | Format::Png
    ) {
        let mut head = Vec::new();
        std::io::Read::read_to_end(
            &mut std::io::Read::take(std::fs::File::open(path).map_err(os)?, HEAD_BYTES),
            &mut head,
        )
        .map_err(os)?;
        head
    } else {
        std::fs::read(path).map_err(os)?
    };
    params_from_bytes(&bytes, f).map_err(|e| e.at(path, f.info().name))
}

/// [`read_params`] on bytes of format `f`.
///
/// # Errors
/// As [`read_params`].
pub(crate) fn params_from_bytes(bytes: &[u8], f: Format) -> FResult<Option<Value>> {
    let text = match f {
        Format::Ply => header_line(ply_header(bytes), &format!("comment {KEYWORD} ")),
        Format::Obj => header_line(
            std::str::from_utf8(bytes).unwrap_or_default(),
            &format!("# {KEYWORD} "),
        ),
        Format::Csv => header_line(std::str::from_utf8(bytes).unwrap_or_default(), CSV_PREFIX),
        Format::Gsf => gsf::header_field(bytes, gsf::PARAMS_FIELD)?,
        Format::Png => png_io::text_chunk(bytes, png_io::PARAMS_KEY)?,
        Format::Exr => exr_io::comments(bytes)?,
        Format::Gwy => gwy::meta_string(bytes, gwy::PARAMS_KEY)?,
        Format::X3p => x3p::comment(bytes)?,
        Format::Sdf => sdf::params(bytes),
        Format::Glb => return glb::params(bytes),
        // Formats without a place for the parameters, and the instrument
        // formats (read-only, made by no recipe).
        _ => None,
    };
    text.map(|t| parse(&t)).transpose()
}

/// A PLY file's header (up to `end_header`) as text.
fn ply_header(bytes: &[u8]) -> &str {
    let end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .unwrap_or(bytes.len().min(1 << 20));
    std::str::from_utf8(&bytes[..end]).unwrap_or_default()
}

/// The rest of the first line of `text` that starts with `prefix`.
fn header_line(text: &str, prefix: &str) -> Option<String> {
    text.lines()
        .find_map(|l| l.trim_end_matches('\r').strip_prefix(prefix))
        .map(str::to_owned)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn text_is_one_ascii_line_that_parses_back_to_the_same_value() {
        let v = json!({"job": "fbm", "title": "µm — 表面 🙂", "rms": 1e-5, "size": [64, 32]});
        let t = params_text(&v);
        assert!(t.is_ascii() && !t.contains('\n'), "{t}");
        assert!(t.contains("\\u00b5") && t.contains("\\ud83d\\ude42"), "{t}");
        assert_eq!(parse(&t).unwrap(), v);
    }

    #[test]
    fn keys_are_sorted_so_equal_values_give_equal_text() {
        let a: Value = serde_json::from_str(r#"{"b": 1, "a": 2.50}"#).unwrap();
        let b: Value = serde_json::from_str(r#"{"a": 2.5, "b": 1}"#).unwrap();
        assert_eq!(params_text(&a), params_text(&b));
        assert_eq!(params_text(&a), r#"{"a":2.5,"b":1}"#);
    }

    #[test]
    fn a_record_that_is_not_an_object_is_refused() {
        assert!(parse("[1, 2]").is_err());
        assert!(parse("{oops").is_err());
    }
}

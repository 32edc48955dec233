//! A text header's `key = value` pairs, read with getters whose errors name
//! the key and the value it has: shared by the readers whose headers are such
//! pairs (Alicona `.al3d` tags, BCR-STM, WSxM, ISO 25178-71 SDF), as
//! Gwyddion's readers share `gwy_text_header_parse` and its typed lookups.

use std::collections::HashMap;

use crate::error::{FResult, FormatError};

/// The pairs of one header, and how a missing key is told.
pub(crate) struct HeaderKeys<'a> {
    keys: &'a HashMap<String, String>,
    missing: fn(&str) -> String,
}

impl<'a> HeaderKeys<'a> {
    /// A header's keys: a missing one is "the header has no KEY".
    pub(crate) fn new(keys: &'a HashMap<String, String>) -> Self {
        Self {
            keys,
            missing: |k| format!("the header has no {k}"),
        }
    }

    /// A file's tags (Alicona): a missing one is "the file has no KEY tag".
    pub(crate) fn tags(keys: &'a HashMap<String, String>) -> Self {
        Self {
            keys,
            missing: |k| format!("the file has no {k} tag"),
        }
    }

    /// The value of `k`, if the header has it.
    pub(crate) fn get(&self, k: &str) -> Option<&'a str> {
        self.keys.get(k).map(String::as_str)
    }

    /// The value of `k`; a missing key is an error.
    pub(crate) fn text(&self, k: &str) -> FResult<&'a str> {
        self.get(k)
            .ok_or_else(|| FormatError::Malformed((self.missing)(k)))
    }

    /// `k` as a count of at least one.
    pub(crate) fn count(&self, k: &str) -> FResult<usize> {
        let v = self.text(k)?;
        v.parse()
            .ok()
            .filter(|&n: &usize| n > 0)
            .ok_or_else(|| FormatError::Malformed(format!("{k} = {v:?} is not a positive count")))
    }

    /// `k` as a whole number (zero included).
    pub(crate) fn whole(&self, k: &str) -> FResult<usize> {
        let v = self.text(k)?;
        v.parse()
            .map_err(|_| FormatError::Malformed(format!("{k} = {v:?} is not a whole number")))
    }

    /// `k` as a number.
    pub(crate) fn real(&self, k: &str) -> FResult<f64> {
        let v = self.text(k)?;
        v.parse()
            .map_err(|_| FormatError::Malformed(format!("{k} = {v:?} is not a number")))
    }

    /// `k` as a number, `default` where the header does not have it.
    pub(crate) fn real_or(&self, k: &str, default: f64) -> FResult<f64> {
        match self.get(k) {
            None => Ok(default),
            Some(_) => self.real(k),
        }
    }

    /// `k` as a byte-sized number, 0 where the header does not have it.
    pub(crate) fn small_or_zero(&self, k: &str) -> FResult<u8> {
        match self.get(k) {
            None => Ok(0),
            Some(v) => v
                .parse()
                .map_err(|_| FormatError::Malformed(format!("{k} = {v:?} is not a small number"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_getter_names_the_key_and_the_value() {
        let map: HashMap<String, String> = [("n", "0"), ("x", "1.5"), ("w", "7"), ("s", "300")]
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v.to_owned()))
            .collect();
        let (h, t) = (HeaderKeys::new(&map), HeaderKeys::tags(&map));
        let msg = |r: FResult<f64>| match r {
            Err(FormatError::Malformed(m)) => m,
            other => panic!("{other:?}"),
        };
        assert!(msg(h.real("y")).contains("the header has no y"));
        assert!(msg(t.real("y")).contains("the file has no y tag"));
        assert_eq!(h.real("x").unwrap(), 1.5);
        assert_eq!(h.real_or("y", 2.0).unwrap(), 2.0);
        assert!(msg(h.count("n").map(|n| n as f64)).contains("n = \"0\" is not a positive count"));
        assert_eq!(h.whole("n").unwrap(), 0);
        assert_eq!(h.count("w").unwrap(), 7);
        assert!(msg(h.whole("x").map(|n| n as f64)).contains("x = \"1.5\" is not a whole number"));
        assert_eq!(h.small_or_zero("y").unwrap(), 0);
        assert!(
            msg(h.small_or_zero("s").map(f64::from)).contains("s = \"300\" is not a small number")
        );
    }
}

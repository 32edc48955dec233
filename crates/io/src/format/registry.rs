//! The registry's macro: from one line per format (in `lib.rs`) it declares
//! the format's module, the variant of [`Format`], the variant's
//! registration and [`FORMATS`]. A line `Vk => vk,` declares `mod vk` and
//! registers `vk::FORMAT`; a module that reads several formats is declared
//! in `lib.rs` and its lines name each registration (`Hfm => xz::HFM,`). The
//! variant's name, lower-cased, is the format's key (its JSON name, the name
//! of its reader in the fuzz binary and of its seeds' folder).

use super::Format;

/// Declares every format: see the module's doc.
macro_rules! registry {
    ($($(#[$doc:meta])* $variant:ident => $module:ident $(:: $registration:ident)?,)*) => {
        $($crate::format::registry::declare_module!($module $(:: $registration)?);)*

        /// The file formats asperity knows.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
        #[serde(rename_all = "lowercase")]
        pub enum Format {
            $($(#[$doc])* $variant,)*
        }

        impl Format {
            /// Every format, in the order `asperity formats` lists them.
            pub const ALL: &[Format] = &[$(Format::$variant,)*];

            /// The format's registration.
            pub(crate) const fn registration(self) -> &'static $crate::format::Registration {
                match self {
                    $(Format::$variant => &$crate::format::registry::registration!($module $(:: $registration)?),)*
                }
            }

            /// The variant's name (the key, before lower-casing).
            pub(crate) const fn variant_name(self) -> &'static str {
                match self {
                    $(Format::$variant => stringify!($variant),)*
                }
            }
        }

        /// Every format, in the order `asperity formats` lists them.
        pub const FORMATS: &[$crate::FormatInfo] = &[$(
            $crate::format::registry::registration!($module $(:: $registration)?).info(Format::$variant),
        )*];
    };
}

/// `mod vk;` for a line that registers a module's one format.
macro_rules! declare_module {
    ($module:ident) => {
        pub mod $module;
    };
    ($module:ident :: $registration:ident) => {};
}

/// The registration a line names: `vk::FORMAT`, or the one it spells out.
macro_rules! registration {
    ($module:ident) => {
        $module::FORMAT
    };
    ($module:ident :: $registration:ident) => {
        $module::$registration
    };
}

pub(crate) use {declare_module, registration, registry};

impl Format {
    /// The format's key: its name in JSON (`"metropro"`), the name of its
    /// reader in the fuzz binary and of its seeds' folder (`fuzz/seeds/`).
    pub fn key(self) -> String {
        self.variant_name().to_ascii_lowercase()
    }

    /// The format whose key is `key` (case-insensitive).
    pub fn from_key(key: &str) -> Option<Format> {
        Format::ALL
            .iter()
            .copied()
            .find(|f| f.variant_name().eq_ignore_ascii_case(key))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FORMATS;

    #[test]
    fn the_rows_follow_the_variants_and_the_keys_are_their_json_names() {
        assert_eq!(FORMATS.len(), Format::ALL.len());
        for (k, (&format, row)) in Format::ALL.iter().zip(FORMATS).enumerate() {
            assert_eq!(row.format, format);
            assert_eq!(format as usize, k);
            assert_eq!(format.info().name, row.name);
            let json = serde_json::to_value(format).unwrap();
            assert_eq!(json, serde_json::Value::String(format.key()));
            assert_eq!(Format::from_key(&format.key()), Some(format));
            assert_eq!(Format::from_key(&format.key().to_uppercase()), Some(format));
        }
        assert_eq!(Format::from_key("nonesuch"), None);
    }

    /// A format reads height fields exactly when it registers a codec, and a
    /// codec's channel list comes with a reader of a chosen channel.
    #[test]
    fn every_height_reader_registers_its_codec() {
        for &format in Format::ALL {
            let r = format.registration();
            assert_eq!(r.codec.is_some(), r.height.can_read(), "{}", r.name);
            assert_eq!(
                format.has_channels(),
                r.codec.is_some_and(|c| c.channels.is_some())
            );
        }
    }

    /// Names, extensions and notes filled in; an extension listed twice only
    /// where the later format claims the file by its content (CSV grids and
    /// Dektak exports).
    #[test]
    fn every_registration_is_filled_in_and_its_extensions_are_told_apart() {
        let mut seen: Vec<(&str, Format)> = Vec::new();
        for &format in Format::ALL {
            let r = format.registration();
            assert!(!r.name.is_empty() && !r.notes.is_empty(), "{format:?}");
            assert!(!r.extensions.is_empty(), "{format:?}");
            for &ext in r.extensions {
                assert_eq!(ext, ext.to_ascii_lowercase(), "{format:?}");
                if let Some(&(_, first)) = seen.iter().find(|(e, _)| *e == ext) {
                    let claims = r.claim.is_some_and(|c| c.extensions.contains(&ext));
                    assert!(
                        claims,
                        "{format:?} lists .{ext} of {first:?} without a claim"
                    );
                }
                seen.push((ext, format));
            }
        }
    }
}

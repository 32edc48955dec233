#![no_main]
//! The plain-text heights reader: matrices, Gwyddion exports, profiles (`asperity_io::decode`), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Asc, data);
});

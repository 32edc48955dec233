#![no_main]
//! The Olympus `.lext` reader (`asperity_io::decode`; TIFF pages, EXIF
//! directory), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Lext, data);
});

#![no_main]
//! The exr reader (`asperity_io::decode`), as every command reads a .exr file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Exr, data);
});

#![no_main]
//! The xyz reader (`asperity_io::decode`), as every command reads a .xyz file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Xyz, data);
});

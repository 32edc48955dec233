#![no_main]
//! The ply reader (`asperity_io::decode`), as every command reads a .ply file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Ply, data);
    read_poly_as(asperity_io::Format::Ply, data);
});

#![no_main]
//! The stl reader (`asperity_io::decode`), as every command reads a .stl file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Stl, data);
    read_poly_as(asperity_io::Format::Stl, data);
});

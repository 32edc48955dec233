#![no_main]
//! The obj reader (`asperity_io::decode`), as every command reads a .obj file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Obj, data);
    read_poly_as(asperity_io::Format::Obj, data);
});

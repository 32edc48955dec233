#![no_main]
//! The x3p reader (`asperity_io::decode`), as every command reads a .x3p file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::X3p, data);
});

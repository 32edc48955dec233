#![no_main]
//! The gwy reader (`asperity_io::decode`), as every command reads a .gwy file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Gwy, data);
});

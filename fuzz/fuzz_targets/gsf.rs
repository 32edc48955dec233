#![no_main]
//! The gsf reader (`asperity_io::decode`), as every command reads a .gsf file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Gsf, data);
});

#![no_main]
//! The png reader (`asperity_io::decode`), as every command reads a .png file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Png, data);
});

#![no_main]
//! The Keyence `.zon` reader (`asperity_io::decode`; plain and Zstandard
//! members), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Zon, data);
});

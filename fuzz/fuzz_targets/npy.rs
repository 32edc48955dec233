#![no_main]
//! The npy reader (`asperity_io::decode`), as every command reads a .npy file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Npy, data);
});

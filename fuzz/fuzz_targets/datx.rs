#![no_main]
//! The Zygo `.datx` reader (`asperity_io::decode`), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Datx, data);
});

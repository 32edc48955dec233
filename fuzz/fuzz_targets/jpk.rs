#![no_main]
//! The JPK image scan `.jpk` reader (`asperity_io::decode`; TIFF pages and
//! private tags), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Jpk, data);
});

#![no_main]
//! The titled CSV line-scan reader (`asperity_io::decode`; UTF-8 and UTF-16),
//! as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::CsvLineScan, data);
});

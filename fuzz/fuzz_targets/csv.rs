#![no_main]
//! The csv reader (`asperity_io::decode`), as every command reads a .csv file.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Csv, data);
});

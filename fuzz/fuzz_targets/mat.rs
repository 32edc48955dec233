#![no_main]
//! The MATLAB `.mat` reader (`asperity_io::decode`; version 5, plain and
//! compressed, and 7.3 through HDF5), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Mat, data);
});

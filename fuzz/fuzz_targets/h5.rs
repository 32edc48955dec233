#![no_main]
//! The HDF5 reader (hdf5-reader crate) (`asperity_io::decode`), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::H5, data);
});

#![no_main]
//! `x,y` lists: curves to drape (`facet --polyline`) and points to interpolate.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = asperity_io::decode_xy(std::path::Path::new("fuzzed"), data);
});

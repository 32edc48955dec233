#![no_main]
//! Subdivision detail files (`--apply-details`, JSON).

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = asperity_subdiv::detail_file::DetailFile::from_json(text);
});

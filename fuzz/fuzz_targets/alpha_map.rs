#![no_main]
//! Blend alpha maps (one value per base vertex, text).

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = asperity_subdiv::blend::parse_alpha_map(text);
});

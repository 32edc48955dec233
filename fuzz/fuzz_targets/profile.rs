#![no_main]
//! Revolution profiles (`--base revolution:PROFILE`, `r z` rows).

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(profile) = asperity_subdiv::base::parse_profile(text) {
        let _ = asperity_subdiv::base::revolution(&profile, 16);
    }
});

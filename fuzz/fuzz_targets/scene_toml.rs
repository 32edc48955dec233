#![no_main]
//! Subdivision scene files (TOML), parsed at the start, the middle and the end
//! of an animation, as `asperity subdiv SCENE --frames N` does.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    for t in [0.0, 0.5, 1.0] {
        let _ = asperity_subdiv::scene::parse(text, t);
    }
});

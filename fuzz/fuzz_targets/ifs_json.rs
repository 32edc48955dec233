#![no_main]
//! Projected-IFS model files (JSON): parsed, validated (operators, spectra,
//! contractivity, adjacency), then a shallow attractor drawn, as `asperity ifs
//! surface --ifs FILE` does.

use asperity_ifs::model::{Model, ModelFile};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(file) = ModelFile::from_json(text) else { return };
    let Ok(model) = file.build() else { return };
    let budget = asperity_core::MemoryBudget::new(64 << 20);
    match model {
        Model::Curve(c) => {
            let _ = c.attractor(4);
        }
        Model::Surface(s) => {
            let _ = s.attractor_mesh(3, &budget);
        }
    }
});

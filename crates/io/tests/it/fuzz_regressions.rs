//! Every input the fuzzers (`fuzz/`) found to crash a reader, read again the
//! way the fuzz target reads it: each must now be answered with a value or an
//! error naming the input, never a panic. The inputs live in
//! `tests/fuzz_regressions/TARGET/`, named after what they broke.

use std::path::Path;

use asperity_core::MemoryBudget;
use asperity_io::{Format, decode, decode_poly_mesh};

#[test]
fn every_crash_the_fuzzers_found_is_a_clean_answer_now() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let budget = MemoryBudget::new(256 << 20);
    let mut seen = 0;
    for dir in std::fs::read_dir(&root).unwrap() {
        let dir = dir.unwrap().path();
        let target = dir.file_name().unwrap().to_string_lossy().into_owned();
        let format = Format::from_path(Path::new(&format!("x.{target}"))).unwrap();
        for file in std::fs::read_dir(&dir).unwrap() {
            let file = file.unwrap().path();
            let bytes = std::fs::read(&file).unwrap();
            let label = Path::new("fuzzed");
            if let Err(e) = decode(label, format, &bytes, &budget) {
                assert!(
                    e.to_string().starts_with("fuzzed"),
                    "{}: {e}",
                    file.display()
                );
            }
            if matches!(format, Format::Ply | Format::Obj | Format::Stl) {
                let _ = decode_poly_mesh(label, format, &bytes, &budget);
            }
            seen += 1;
        }
    }
    assert!(
        seen >= 1,
        "no regression input found under {}",
        root.display()
    );
}

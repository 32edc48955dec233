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

/// The fuzz binary's table of readers (`fuzz/fuzz_targets/readers.rs`, outside
/// this workspace): sorted by name (it is binary-searched), one seed folder per
/// name and no other, and every format asperity reads among its rows.
#[test]
fn the_fuzz_binary_reaches_every_reader_from_its_seeds() {
    let fuzz = asperity_fixtures::workspace().join("fuzz");
    let source = std::fs::read_to_string(fuzz.join("fuzz_targets/readers.rs")).unwrap();
    let table = &source[source.find("const READERS").unwrap()..];
    let table = &table[..table.find("\n];").unwrap()];
    let names: Vec<&str> = table
        .lines()
        .filter_map(|l| l.trim().strip_prefix("(\""))
        .map(|l| &l[..l.find('"').unwrap()])
        .collect();
    assert!(names.is_sorted(), "the table is not sorted: {names:?}");
    let mut seeds: Vec<String> = std::fs::read_dir(fuzz.join("seeds"))
        .unwrap()
        .map(|d| d.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    seeds.sort();
    assert_eq!(names, seeds, "readers against seed folders");
    for name in &names {
        let n = std::fs::read_dir(fuzz.join("seeds").join(name))
            .unwrap()
            .count();
        assert!(n >= 1, "no seed for {name}");
    }
    for info in asperity_io::FORMATS {
        if info.mesh.can_read() || info.points.can_read() || info.height.can_read() {
            let row = format!("Format::{:?}", info.format);
            assert!(
                table.contains(&format!("{row})")) || table.contains(&format!("{row},")),
                "{} is read but not fuzzed",
                info.name
            );
        }
    }
}

/// Detection agrees with where each seed is filed: every file format seed in
/// `fuzz/seeds/NAME/` is told by `Format::of_file` (extension, then content,
/// as every command tells a file) as a format that the fuzz binary's row
/// `NAME` reads.
#[test]
fn every_seed_is_detected_as_the_format_its_reader_reads() {
    let fuzz = asperity_fixtures::workspace().join("fuzz");
    let source = std::fs::read_to_string(fuzz.join("fuzz_targets/readers.rs")).unwrap();
    let table = &source[source.find("const READERS").unwrap()..];
    let table = &table[..table.find("\n];").unwrap()];
    let mut checked = 0;
    for row in table.split("\n    (\"").skip(1) {
        let name = &row[..row.find('"').unwrap()];
        let formats: Vec<&str> = row
            .split("Format::")
            .skip(1)
            .map(|t| &t[..t.find(|c: char| !c.is_alphanumeric()).unwrap()])
            .collect();
        if formats.is_empty() {
            continue; // a parameter text, not a file format
        }
        for file in std::fs::read_dir(fuzz.join("seeds").join(name)).unwrap() {
            let file = file.unwrap().path();
            let told = asperity_io::Format::of_file(&file)
                .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            let told = format!("{told:?}");
            assert!(
                formats.contains(&told.as_str()),
                "{} is told as {told}, but the reader {name} reads {formats:?}",
                file.display()
            );
            checked += 1;
        }
    }
    assert!(checked >= 60, "{checked} seeds checked");
}

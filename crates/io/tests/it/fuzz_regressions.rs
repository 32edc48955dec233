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

/// The fuzz binary (`fuzz/fuzz_targets/readers.rs`, outside this workspace)
/// reads a format by its key and the parameter texts by its table (sorted:
/// it is binary-searched); the seed folders are exactly the readable
/// formats' keys and the table's names, each with a seed.
#[test]
fn the_fuzz_binary_reaches_every_reader_from_its_seeds() {
    let fuzz = asperity_fixtures::workspace().join("fuzz");
    let source = std::fs::read_to_string(fuzz.join("fuzz_targets/readers.rs")).unwrap();
    let table = &source[source.find("const READERS").unwrap()..];
    let table = &table[..table.find("\n];").unwrap()];
    let texts: Vec<String> = table
        .lines()
        .filter_map(|l| l.trim().strip_prefix("(\""))
        .map(|l| l[..l.find('"').unwrap()].to_string())
        .collect();
    assert!(texts.is_sorted(), "the table is not sorted: {texts:?}");
    let mut names: Vec<String> = Format::ALL
        .iter()
        .filter(|f| readable(**f))
        .map(|f| f.key())
        .chain(texts.iter().cloned())
        .collect();
    names.sort();
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
    for text in &texts {
        assert!(
            Format::from_key(text).is_none(),
            "{text} is also a format's key"
        );
    }
}

fn readable(f: Format) -> bool {
    let info = f.info();
    info.mesh.can_read() || info.points.can_read() || info.height.can_read()
}

/// Detection agrees with the registry: every seed in `fuzz/seeds/KEY/` is
/// told by `Format::of_file` (extension, then content, as every command tells
/// a file) as the format whose key it is filed under, and a format told by
/// its content (a magic) is told so from some seed's bytes alone.
#[test]
fn every_seed_is_detected_as_the_format_it_is_filed_under() {
    let seeds = asperity_fixtures::workspace().join("fuzz/seeds");
    let mut checked = 0;
    for &format in Format::ALL.iter().filter(|f| readable(**f)) {
        let mut by_content = false;
        for file in std::fs::read_dir(seeds.join(format.key())).unwrap() {
            let file = file.unwrap().path();
            let told = Format::of_file(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
            assert_eq!(told, format, "{}", file.display());
            let head: Vec<u8> = std::fs::read(&file).unwrap().into_iter().take(64).collect();
            by_content |= Format::from_content(&head) == Some(format);
            checked += 1;
        }
        assert_eq!(
            by_content,
            format.has_magic(),
            "{format:?}: told by content from its seeds"
        );
    }
    assert!(checked >= 60, "{checked} seeds checked");
}

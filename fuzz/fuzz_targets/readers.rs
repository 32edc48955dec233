#![no_main]
//! Every reader of a file a user can hand to asperity, in one fuzz binary.
//!
//! An input is `NAME\0BYTES`: `NAME` picks the reader (a format's key, or one
//! row of [`READERS`]; the folder of its seeds in `fuzz/seeds/` and of its
//! corpus in `fuzz/corpus/`), `BYTES` is the file. One binary instead of one per reader:
//! CI links one AddressSanitizer build (~80 MB) instead of 57 (~5 GB), and a
//! failing input names its reader in its first bytes, so it reproduces alone.
//! `fuzz/run.sh` runs each reader from its own seeds and corpus; an input whose
//! name libFuzzer mutated into no reader's is skipped.

use asperity_io::Format;

/// A reader of one of the parameter texts.
type Reader = fn(&[u8]);

/// The readers of the parameter texts by name, sorted (the fuzz README's
/// table lists what each covers). Every other name is a format's key
/// (`Format::key`, the registry in `crates/io/src/lib.rs`): the file goes
/// through `asperity_io::decode` as every command reads a file, then through
/// the checks `info` makes; a mesh format's also as a polygon mesh
/// (subdivision bases).
const READERS: &[(&str, Reader)] = &[
    ("alpha_map", alpha_map),
    ("detail_json", detail_json),
    ("ifs_json", ifs_json),
    ("profile", profile),
    ("scene_toml", scene_toml),
    ("xy", |d| {
        let _ = asperity_io::decode_xy(std::path::Path::new("fuzzed"), d);
    }),
];

libfuzzer_sys::fuzz_target!(|input: &[u8]| {
    let Some(end) = input.iter().position(|&b| b == 0) else { return };
    let (name, data) = (&input[..end], &input[end + 1..]);
    if let Ok(k) = READERS.binary_search_by(|(reader, _)| reader.as_bytes().cmp(name)) {
        (READERS[k].1)(data);
    } else if let Some(format) = std::str::from_utf8(name).ok().and_then(Format::from_key) {
        if format.info().mesh.can_read() {
            read_mesh_as(format, data);
        } else {
            read_as(format, data);
        }
    }
});

/// The budget a fuzzed read runs under: 256 MiB. libFuzzer's `-malloc_limit_mb`
/// (set by `fuzz/run.sh`) fails the run on any larger single allocation, so an
/// input that makes a reader allocate past its own estimate is a crash.
fn budget() -> asperity_core::MemoryBudget {
    asperity_core::MemoryBudget::new(256 << 20)
}

/// Reads `data` as `format` the way every command does; an error is fine, a
/// panic, an abort, a hang or an allocation over the limit is not.
fn read_as(format: Format, data: &[u8]) {
    let label = std::path::Path::new("fuzzed");
    if let Ok(s) = asperity_io::decode(label, format, data, &budget()) {
        // What a command does next with it: the same checks as `info`.
        match s {
            asperity_io::Surface::Mesh(m) => {
                let _ = m.is_watertight();
                let _ = asperity_core::mesh_check::check_triangles(&m, Default::default());
            }
            asperity_io::Surface::Points(p) => {
                let _ = p.validate();
            }
            asperity_io::Surface::Height(h) => {
                let _ = h.validate();
            }
        }
    }
}

/// A mesh format, also read as a polygon mesh (subdivision bases).
fn read_mesh_as(format: Format, data: &[u8]) {
    read_as(format, data);
    let label = std::path::Path::new("fuzzed");
    if let Ok(m) = asperity_io::decode_poly_mesh(label, format, data, &budget()) {
        let _ = asperity_core::mesh_check::check_polygons(&m, Default::default());
    }
}

/// Blend alpha maps (one value per base vertex, text).
fn alpha_map(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = asperity_subdiv::blend::parse_alpha_map(text);
}

/// Subdivision detail files (`--apply-details`, JSON).
fn detail_json(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = asperity_subdiv::detail_file::DetailFile::from_json(text);
}

/// Projected-IFS model files (JSON): parsed, validated (operators, spectra,
/// contractivity, adjacency), then a shallow attractor drawn, as `asperity ifs
/// surface --ifs FILE` does.
fn ifs_json(data: &[u8]) {
    use asperity_ifs::model::{Model, ModelFile};
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(file) = ModelFile::from_json(text) else { return };
    let Ok(model) = file.build() else { return };
    match model {
        Model::Curve(c) => {
            let _ = c.attractor(4);
        }
        Model::Surface(s) => {
            let _ = s.attractor_mesh(3, &asperity_core::MemoryBudget::new(64 << 20));
        }
    }
}

/// Revolution profiles (`--base revolution:PROFILE`, `r z` rows), then the
/// base mesh.
fn profile(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(profile) = asperity_subdiv::base::parse_profile(text) {
        let _ = asperity_subdiv::base::revolution(&profile, 16);
    }
}

/// Subdivision scene files (TOML), parsed at the start, the middle and the end
/// of an animation, as `asperity subdiv SCENE --frames N` does.
fn scene_toml(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    for t in [0.0, 0.5, 1.0] {
        let _ = asperity_subdiv::scene::parse(text, t);
    }
}

#![no_main]
//! Every reader of a file a user can hand to asperity, in one fuzz binary.
//!
//! An input is `NAME\0BYTES`: `NAME` picks the reader (one row of [`READERS`],
//! the folder of its seeds in `fuzz/seeds/` and of its corpus in
//! `fuzz/corpus/`), `BYTES` is the file. One binary instead of one per reader:
//! CI links one AddressSanitizer build (~80 MB) instead of 57 (~5 GB), and a
//! failing input names its reader in its first bytes, so it reproduces alone.
//! `fuzz/run.sh` runs each reader from its own seeds and corpus; an input whose
//! name libFuzzer mutated into no reader's is skipped.

use asperity_io::Format;

/// What is read: a file of a format, or one of the parameter texts.
type Reader = fn(&[u8]);

/// The readers by name, sorted (the fuzz README's table lists what each
/// covers). The file formats go through `asperity_io::decode` as every command
/// reads a file, then through the checks `info` makes; the mesh formats also
/// as polygon meshes (subdivision bases).
const READERS: &[(&str, Reader)] = &[
    ("al3d", |d| read_as(Format::Al3d, d)),
    ("alpha_map", alpha_map),
    ("asc", |d| read_as(Format::Asc, d)),
    ("bcr", |d| read_as(Format::Bcr, d)),
    ("csv", |d| read_as(Format::Csv, d)),
    ("csv_line_scan", |d| read_as(Format::CsvLineScan, d)),
    ("datx", |d| read_as(Format::Datx, d)),
    ("dektak", |d| read_as(Format::Dektak, d)),
    ("detail_json", detail_json),
    ("di", |d| read_as(Format::Di, d)),
    ("exr", |d| read_as(Format::Exr, d)),
    ("frt", |d| read_as(Format::Frt, d)),
    ("gsf", |d| read_as(Format::Gsf, d)),
    ("gwy", |d| read_as(Format::Gwy, d)),
    ("h5", |d| read_as(Format::H5, d)),
    ("hfm", |d| read_as(Format::Hfm, d)),
    ("hgt", |d| read_as(Format::Hgt, d)),
    ("ibw", |d| read_as(Format::Ibw, d)),
    ("ifs_json", ifs_json),
    ("jpk", |d| read_as(Format::Jpk, d)),
    ("lext", |d| read_as(Format::Lext, d)),
    ("mat", |d| read_as(Format::Mat, d)),
    ("mdt", |d| read_as(Format::Mdt, d)),
    ("metropro", |d| read_as(Format::MetroPro, d)),
    ("mi", |d| read_as(Format::Mi, d)),
    ("mnt", |d| read_as(Format::Mnt, d)),
    ("nc", |d| read_as(Format::Nc, d)),
    ("nid", |d| read_as(Format::Nid, d)),
    ("nmm", |d| read_as(Format::Nmm, d)),
    ("nms", |d| read_as(Format::Nms, d)),
    ("npy", |d| read_as(Format::Npy, d)),
    ("npz", |d| read_as(Format::Npz, d)),
    ("obj", |d| read_mesh_as(Format::Obj, d)),
    // The packed `.poir` is a zip of `.oir`: every input is read as both.
    ("oir", |d| {
        read_as(Format::Oir, d);
        read_as(Format::Poir, d);
    }),
    ("opd", |d| read_as(Format::Opd, d)),
    ("opdx", |d| read_as(Format::Opdx, d)),
    ("os3d", |d| read_as(Format::Os3d, d)),
    ("park", |d| read_as(Format::Park, d)),
    ("plu", |d| read_as(Format::Plu, d)),
    ("plux", |d| read_as(Format::Plux, d)),
    ("ply", |d| read_mesh_as(Format::Ply, d)),
    ("png", |d| read_as(Format::Png, d)),
    ("profile", profile),
    ("qep", |d| read_as(Format::Qep, d)),
    ("scene_toml", scene_toml),
    ("sdf", |d| read_as(Format::Sdf, d)),
    ("stl", |d| read_mesh_as(Format::Stl, d)),
    ("sur", |d| read_as(Format::Sur, d)),
    ("tmd", |d| read_as(Format::Tmd, d)),
    ("vk", |d| read_as(Format::Vk, d)),
    ("wsxm", |d| read_as(Format::Wsxm, d)),
    ("x3p", |d| read_as(Format::X3p, d)),
    ("xlsx", |d| read_as(Format::Mitutoyo, d)),
    ("xy", |d| {
        let _ = asperity_io::decode_xy(std::path::Path::new("fuzzed"), d);
    }),
    ("xyz", |d| read_as(Format::Xyz, d)),
    ("zmg", |d| read_as(Format::Zmg, d)),
    ("zon", |d| read_as(Format::Zon, d)),
];

libfuzzer_sys::fuzz_target!(|input: &[u8]| {
    let Some(end) = input.iter().position(|&b| b == 0) else { return };
    let Ok(k) = READERS.binary_search_by(|(name, _)| name.as_bytes().cmp(&input[..end])) else {
        return;
    };
    (READERS[k].1)(&input[end + 1..]);
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

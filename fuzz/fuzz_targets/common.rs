// Shared by every file-format target (included with `include!`, since fuzz
// targets are separate binaries).

/// The budget a fuzzed read runs under: 256 MiB. libFuzzer's `-malloc_limit_mb`
/// (set by `fuzz/run.sh`) fails the run on any larger single allocation, so an
/// input that makes a reader allocate past its own estimate is a crash.
fn budget() -> asperity_core::MemoryBudget {
    asperity_core::MemoryBudget::new(256 << 20)
}

/// Reads `data` as `format` the way every command does; an error is fine, a
/// panic, an abort, a hang or an allocation over the limit is not.
fn read_as(format: asperity_io::Format, data: &[u8]) {
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

/// Also as a polygon mesh (subdivision bases).
#[allow(dead_code)] // not every target reads polygons
fn read_poly_as(format: asperity_io::Format, data: &[u8]) {
    let label = std::path::Path::new("fuzzed");
    if let Ok(m) = asperity_io::decode_poly_mesh(label, format, data, &budget()) {
        let _ = asperity_core::mesh_check::check_polygons(&m, Default::default());
    }
}

//! Reading the files a job takes: refusals by kind, so every front end can
//! map them (a missing file is the system's, an oversized one the budget's,
//! an unknown built-in the caller's).

use asperity_engine::ErrorKind;
use asperity_engine::core::MemoryBudget;
use asperity_engine::files::{load, load_mesh};

/// Files are refused by kind: a missing file is the system's, an oversized
/// one the budget's, an unknown built-in the caller's.
#[test]
fn files_are_refused_with_the_right_kind() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.ply");
    let e = load(&missing, &MemoryBudget::unlimited()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Os);
    assert!(e.to_string().contains("missing.ply"), "{e}");

    let npy = dir.path().join("h.npy");
    let h = asperity_core::HeightField::filled([64, 64], 0.0);
    asperity_io::write(
        &npy,
        &asperity_io::Surface::Height(h),
        &asperity_io::WriteOptions::default(),
    )
    .unwrap();
    let e = load(&npy, &MemoryBudget::new(1024)).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Memory);
    assert!(load(&npy, &MemoryBudget::unlimited()).is_ok());

    let e = load_mesh("builtin:teapot", &MemoryBudget::unlimited()).unwrap_err();
    assert_eq!(e.kind(), ErrorKind::Invalid);
    assert!(
        e.to_string().contains("sphere"),
        "names the known ones: {e}"
    );
}

//! Atomic file writes: temp file in the target's directory, then rename.
//!
//! A crash, a full disk or an error in the middle of a write leaves the target
//! untouched: either the old file (if any) or the complete new one. The file
//! being written is anonymous where the system allows, else a temporary
//! `.NAME.XXXXXX.tmp` beside the target, removed on failure and by the drop
//! guard of `tempfile` if the process unwinds ([`crate::staging`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::IoError;

/// Writes `path` by calling `fill` on a buffered temp file, then renaming it over
/// `path`. Nothing is left at `path` unless `fill` and the flush succeed.
///
/// # Errors
/// [`IoError::Os`] from the OS; errors returned by `fill` are passed through.
pub fn write_atomic<E>(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), E>
where
    E: From<IoError>,
{
    let os = |source: std::io::Error| IoError::Os {
        path: path.to_path_buf(),
        source,
    };
    // A symlink's target is written, not the link.
    let resolved;
    let path = if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        resolved = link_target(path).map_err(os)?;
        resolved.as_path()
    } else {
        path
    };
    crate::staging::refuse_input(path)?;
    // A FIFO, a device or a socket is written in place, never replaced by a
    // regular file (there is nothing to keep atomic about a stream).
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(os)?;
        let mut w = BufWriter::new(file);
        fill(&mut w)?;
        w.flush().map_err(os)?;
        return Ok(());
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    crate::staging::remove_leftovers(dir);
    let (file, blank) = crate::staging::create(path).map_err(|e| IoError::Os {
        path: dir.to_path_buf(),
        source: folder_error(dir, &e),
    })?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    fill(&mut w)?;
    w.flush().map_err(os)?;
    let file = w.into_inner().map_err(|e| os(e.into_error()))?;
    file.sync_all().map_err(os)?;
    crate::staging::persist_or_stage(file, blank, path)?;
    Ok(())
}

/// Where the symlink `path` finally points (its target need not exist yet).
fn link_target(path: &Path) -> std::io::Result<std::path::PathBuf> {
    if let Ok(p) = std::fs::canonicalize(path) {
        return Ok(p);
    }
    let target = std::fs::read_link(path)?;
    Ok(match path.parent() {
        Some(dir) if target.is_relative() => dir.join(target),
        _ => target,
    })
}

/// Why no file can be made in `dir`, naming the folder rather than the
/// temporary file's random name, and what to do.
fn folder_error(dir: &Path, e: &std::io::Error) -> std::io::Error {
    use std::io::{Error, ErrorKind};
    match std::fs::metadata(dir) {
        Err(_) => Error::new(
            ErrorKind::NotFound,
            "the folder does not exist (create it first, or write elsewhere)",
        ),
        Ok(m) if !m.is_dir() => Error::new(ErrorKind::NotADirectory, "this is not a folder"),
        Ok(_) if e.kind() == ErrorKind::PermissionDenied => Error::new(
            ErrorKind::PermissionDenied,
            "no permission to create files in this folder",
        ),
        Ok(_) => Error::new(
            e.kind(),
            format!("cannot create a file in this folder ({})", e.kind()),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect()
    }

    #[test]
    fn failed_write_leaves_nothing_and_keeps_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.ply");
        let r: Result<(), IoError> = write_atomic(&target, |w| {
            w.write_all(b"half a file").unwrap();
            Err(IoError::Malformed {
                path: target.clone(),
                format: "test",
                message: "boom".into(),
            })
        });
        assert!(r.is_err());
        assert!(!target.exists());
        assert!(
            leftovers(dir.path()).is_empty(),
            "{:?}",
            leftovers(dir.path())
        );

        std::fs::write(&target, b"old").unwrap();
        let _ = write_atomic::<IoError>(&target, |w| {
            w.write_all(&[0u8; 3 << 20]).unwrap(); // more than the buffer: really hits the temp file
            Err(IoError::Malformed {
                path: target.clone(),
                format: "test",
                message: "boom".into(),
            })
        });
        assert_eq!(std::fs::read(&target).unwrap(), b"old");
        assert_eq!(leftovers(dir.path()), vec!["out.ply".to_string()]);
    }

    #[test]
    fn panic_mid_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.npy");
        let result = std::panic::catch_unwind(|| {
            let _ = write_atomic::<IoError>(&target, |w| {
                w.write_all(&[1u8; 2 << 20]).unwrap();
                panic!("simulated crash");
            });
        });
        assert!(result.is_err());
        assert!(!target.exists());
        assert!(leftovers(dir.path()).is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn outputs_are_not_private() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("p.txt");
        write_atomic::<IoError>(&target, |_| Ok(())).unwrap();
        let mode = std::fs::metadata(&target).unwrap().permissions().mode();
        assert_eq!(
            mode & 0o044,
            0o044 & !umask_guess(),
            "group/other read unless the umask forbids: {mode:o}"
        );
    }

    #[cfg(unix)]
    fn umask_guess() -> u32 {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("probe");
        std::fs::write(&p, b"").unwrap();
        0o666 & !std::fs::metadata(&p).unwrap().permissions().mode()
    }

    #[test]
    fn success_replaces_target() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("a.txt");
        std::fs::write(&target, b"old").unwrap();
        write_atomic::<IoError>(&target, |w| {
            w.write_all(b"new").map_err(|e| IoError::Os {
                path: target.clone(),
                source: e,
            })
        })
        .unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert_eq!(leftovers(dir.path()).len(), 1);
    }

    #[test]
    fn a_missing_folder_is_named_not_the_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("nosuch").join("out.npy");
        let e = write_atomic::<IoError>(&target, |_| Ok(())).unwrap_err();
        let text = e.to_string();
        assert!(
            text.starts_with(&format!("{}:", dir.path().join("nosuch").display())),
            "{text}"
        );
        assert!(
            text.contains("does not exist") && !text.contains(".out.npy"),
            "{text}"
        );
    }
}

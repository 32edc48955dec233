//! All-or-nothing outputs and clean interruption.
//!
//! While a [`Transaction`] is open, every write of this crate ([`crate::atomic`])
//! leaves its complete temporary file (`.NAME.XXXXXX.tmp` beside the target) in
//! place instead of renaming it; [`Transaction::commit`] renames them all, and
//! dropping the transaction uncommitted deletes them. A command that fails half
//! way therefore leaves every existing file as it was, whichever output failed.
//!
//! Every temporary file alive in the process is registered, so a signal handler
//! can delete them with [`exit_removing_temporaries`] (a
//! SIGKILL cannot be caught: its leftovers keep the `.tmp` name, are never
//! reused, since each temporary name is random, and are reported by
//! [`stale_temporaries`] when a later run writes the same output).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use tempfile::TempPath;

use crate::IoError;

/// A temporary file waiting for its rename, and the registration that lets a
/// signal handler find it.
type Staged = (TempPath, PathBuf, Live);

static STAGED: Mutex<Option<Vec<Staged>>> = Mutex::new(None);
/// Folders made for outputs while a transaction is open, deepest first: an
/// uncommitted transaction removes the ones it left empty.
static MADE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Names that look like our temporaries, per folder, as found at the first
/// write into it (before this process made any there).
static FOLDERS: Mutex<Vec<(PathBuf, Vec<String>)>> = Mutex::new(Vec::new());
/// Leftover temporaries found beside this process's outputs.
static STALE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Whether `name` has the shape of a temporary file of ours: `.NAME.XXXXXX.tmp`.
fn is_temporary_name(name: &str) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
        return false;
    };
    inner.rsplit_once('.').is_some_and(|(target, rand)| {
        !target.is_empty() && rand.len() == 6 && rand.bytes().all(|b| b.is_ascii_alphanumeric())
    })
}

/// Notes the temporaries a killed run (SIGKILL, a power cut) left for the
/// target `name` in `dir`. They are never reused or overwritten — every
/// temporary gets a fresh random name — but they are found and reported by
/// [`stale_temporaries`], so a front end can say where they are.
pub(crate) fn note_leftovers(dir: &Path, name: &str) {
    let mut folders = lock(&FOLDERS);
    let listed = match folders.iter().position(|(d, _)| d == dir) {
        Some(i) => &folders[i].1,
        None => {
            let names = std::fs::read_dir(dir)
                .map(|rd| {
                    rd.filter_map(|e| e.ok())
                        .map(|e| e.file_name().to_string_lossy().into_owned())
                        .filter(|n| is_temporary_name(n))
                        .collect()
                })
                .unwrap_or_default();
            folders.push((dir.to_path_buf(), names));
            &folders.last().expect("just pushed").1
        }
    };
    let prefix = format!(".{name}.");
    let mut stale = lock(&STALE);
    for n in listed
        .iter()
        .filter(|n| n.starts_with(&prefix) && n.len() == prefix.len() + 10)
    {
        let p = if dir == Path::new(".") {
            PathBuf::from(n)
        } else {
            dir.join(n)
        };
        if !stale.contains(&p) {
            stale.push(p);
        }
    }
}

/// Temporary files left beside this process's outputs by an earlier run that
/// was killed before it could clean up (they are not this process's own).
pub fn stale_temporaries() -> Vec<PathBuf> {
    lock(&STALE).clone()
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic while holding the lock leaves plain data behind; keep using it.
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A registered temporary file: known to [`exit_removing_temporaries`] until dropped.
pub(crate) struct Live(PathBuf);

impl Live {
    /// Creates a temporary file with `builder` in `dir` and registers it, both
    /// under the registry's lock, so [`exit_removing_temporaries`] never misses a
    /// file created while it runs.
    pub(crate) fn create(
        builder: &tempfile::Builder<'_, '_>,
        dir: &Path,
    ) -> std::io::Result<(std::fs::File, TempPath, Self)> {
        let mut live = lock(&LIVE);
        let (file, path) = builder.tempfile_in(dir)?.into_parts();
        live.push(path.to_path_buf());
        let registration = Self(path.to_path_buf());
        Ok((file, path, registration))
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        let mut live = lock(&LIVE);
        if let Some(i) = live.iter().rposition(|p| *p == self.0) {
            live.swap_remove(i);
        }
    }
}

/// Renames `tmp` over `path` now, or stages it when a transaction is open.
pub(crate) fn persist_or_stage(tmp: TempPath, path: &Path, live: Live) -> Result<(), IoError> {
    if let Some(staged) = lock(&STAGED).as_mut() {
        staged.push((tmp, path.to_path_buf(), live));
        return Ok(());
    }
    tmp.persist(path).map_err(|e| IoError::os(path, e.error))?;
    drop(live);
    Ok(())
}

/// The size of what was last written to `path`: its staged temporary file while
/// a transaction is open, else the file on disk.
pub fn written_len(path: &Path) -> Option<u64> {
    let staged = lock(&STAGED).as_ref().and_then(|s| {
        s.iter()
            .rev()
            .find(|(_, p, _)| p == path)
            .map(|(t, _, _)| t.to_path_buf())
    });
    std::fs::metadata(staged.as_deref().unwrap_or(path))
        .ok()
        .map(|m| m.len())
}

/// Deletes every temporary file this process has open or staged, then exits
/// with `code`; for signal handlers. It holds the registry's lock until the
/// process is gone, so no temporary file can be created behind it. A lock the
/// interrupted program holds is waited for briefly (it is only held while a
/// file is created or a list updated), then the exit goes ahead regardless.
pub fn exit_removing_temporaries(code: i32) -> ! {
    for _ in 0..500 {
        if let Ok(live) = LIVE.try_lock() {
            for p in live.iter() {
                let _ = std::fs::remove_file(p);
            }
            std::process::exit(code);
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    std::process::exit(code);
}

/// Makes the folder `dir` and any missing parents for outputs. While a
/// [`Transaction`] is open the folders made are recorded, and dropping the
/// transaction uncommitted removes those it leaves empty, so a failed command
/// leaves no empty output folder behind.
///
/// # Errors
/// [`IoError::Os`] when a folder cannot be made.
pub fn create_output_dir(dir: &Path) -> Result<(), IoError> {
    let mut missing = Vec::new();
    let mut d = Some(dir);
    while let Some(p) = d {
        if p.as_os_str().is_empty() || p.exists() {
            break;
        }
        missing.push(p.to_path_buf());
        d = p.parent();
    }
    std::fs::create_dir_all(dir).map_err(|e| IoError::os(dir, e))?;
    if lock(&STAGED).is_some() {
        // `missing` runs from `dir` up: deepest first, the order to remove them.
        lock(&MADE).extend(missing);
    }
    Ok(())
}

/// The outputs of one command, committed together (see the module docs). Only
/// one is open at a time in a process: it is meant for a command-line run.
#[must_use = "outputs are only renamed into place by commit()"]
pub struct Transaction(());

impl Transaction {
    /// Starts staging every write.
    pub fn begin() -> Self {
        *lock(&STAGED) = Some(Vec::new());
        lock(&MADE).clear();
        Self(())
    }

    /// Renames every staged file into place, in the order they were written.
    ///
    /// # Errors
    /// [`IoError::Os`] when a rename fails; the files not yet renamed are
    /// deleted.
    pub fn commit(self) -> Result<(), IoError> {
        lock(&MADE).clear();
        let staged = lock(&STAGED).take().unwrap_or_default();
        for (tmp, path, live) in staged {
            tmp.persist(&path)
                .map_err(|e| IoError::os(&path, e.error))?;
            drop(live);
        }
        Ok(())
    }
}

impl Drop for Transaction {
    fn drop(&mut self) {
        // Uncommitted: deleting the temporaries (TempPath's drop) leaves every
        // target as it was.
        let staged = lock(&STAGED).take();
        drop(staged);
        // Then the folders made for them, where now empty (remove_dir refuses
        // a folder with anything in it).
        for dir in std::mem::take(&mut *lock(&MADE)) {
            let _ = std::fs::remove_dir(&dir);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_recognised() {
        assert!(is_temporary_name(".h.npy.Ab12Cd.tmp"));
        assert!(is_temporary_name(".a.b.c.ply.zzzzzz.tmp"));
        for other in [
            ".h.npy.tmp",
            "h.npy.Ab12Cd.tmp",
            ".h.npy.Ab12C.tmp",
            "..Ab12Cd.tmp",
            ".h.npy.Ab-2Cd.tmp",
        ] {
            assert!(!is_temporary_name(other), "{other}");
        }
    }

    #[test]
    fn a_killed_run_s_leftover_is_reported_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let leftover = dir.path().join(".out.npy.Xy12Zw.tmp");
        std::fs::write(&leftover, b"half").unwrap();
        std::fs::write(dir.path().join(".other.npy.Xy12Zw.tmp"), b"x").unwrap();
        crate::write_atomic::<IoError>(&dir.path().join("out.npy"), |_| Ok(())).unwrap();
        let stale = stale_temporaries();
        assert!(stale.contains(&leftover), "{stale:?}");
        assert!(!stale.iter().any(|p| p.ends_with(".other.npy.Xy12Zw.tmp")));
        assert_eq!(std::fs::read(&leftover).unwrap(), b"half");
    }
}

//! All-or-nothing outputs and clean interruption.
//!
//! While a [`Transaction`] is open, every write of this crate ([`crate::atomic`])
//! leaves its complete temporary file (`.NAME.XXXXXX.tmp` beside the target) in
//! place instead of renaming it; [`Transaction::commit`] renames them all, and
//! dropping the transaction uncommitted deletes them. A command that fails half
//! way therefore leaves every existing file as it was, whichever output failed.
//!
//! Every temporary file alive in the process is registered, so a signal handler
//! can delete them with [`exit_removing_temporaries`]. A SIGKILL (or a power
//! cut) cannot be caught: its temporaries stay. Each temporary is held under
//! an exclusive advisory lock (`flock`) by the process writing it, until it is
//! renamed or deleted; the operating system drops the lock when the process
//! dies. The first write of a later run into a folder removes the
//! temporaries of ours there whose lock it can take — those of dead runs —
//! and leaves those of live ones (another asperity writing there now); it
//! lists what it removed in [`stale_temporaries`]. On a filesystem without
//! advisory locks every lock succeeds: a leftover there is removed as stale,
//! and so would be a live run's, so do not run two commands into one such
//! folder at once.

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
/// The folders this process has written into (their leftovers removed at
/// the first write).
static FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Leftover temporaries of dead runs removed beside this process's outputs.
static STALE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// The files read while a transaction is open, by device and inode: an
/// output that is one of them (by its name, a symlink or a hard link) is
/// refused rather than renamed over the input.
static INPUTS: Mutex<Vec<(PathBuf, FileId)>> = Mutex::new(Vec::new());

/// A file's identity: device and inode (Unix); elsewhere its canonical path.
#[cfg(unix)]
type FileId = (u64, u64);
#[cfg(not(unix))]
type FileId = PathBuf;

#[cfg(unix)]
fn file_id(path: &Path) -> Option<FileId> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn file_id(path: &Path) -> Option<FileId> {
    std::fs::canonicalize(path).ok()
}

/// Notes that the command read `path` (every reader of this crate does; a
/// front end reading a file itself calls this too), so that an output over
/// it is refused. Outside a transaction (a library call, Python) nothing is
/// noted.
pub fn note_input(path: &Path) {
    if lock(&STAGED).is_none() {
        return;
    }
    if let Some(id) = file_id(path) {
        lock(&INPUTS).push((path.to_path_buf(), id));
    }
}

/// Refuses to write `path` when it is a file the command read (every writer
/// checks; a front end may ask first, before it warns about the output).
///
/// # Errors
/// [`IoError::OutputIsInput`] naming both.
pub fn refuse_input(path: &Path) -> Result<(), IoError> {
    let Some(id) = file_id(path) else {
        return Ok(());
    };
    match lock(&INPUTS).iter().find(|(_, i)| *i == id) {
        Some((input, _)) => Err(IoError::OutputIsInput {
            path: path.to_path_buf(),
            input: input.clone(),
        }),
        None => Ok(()),
    }
}

/// Whether `name` has the shape of a temporary file of ours: `.NAME.XXXXXX.tmp`.
fn is_temporary_name(name: &str) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
        return false;
    };
    inner.rsplit_once('.').is_some_and(|(target, rand)| {
        !target.is_empty() && rand.len() == 6 && rand.bytes().all(|b| b.is_ascii_alphanumeric())
    })
}

/// Removes, at this process's first write into `dir`, the temporaries of
/// ours there that no live process holds (see the module docs).
pub(crate) fn remove_leftovers(dir: &Path) {
    let mut folders = lock(&FOLDERS);
    if folders.iter().any(|d| d == dir) {
        return;
    }
    folders.push(dir.to_path_buf());
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut stale = lock(&STALE);
    for entry in entries.filter_map(Result::ok) {
        let name = entry.file_name().to_string_lossy().into_owned();
        if !is_temporary_name(&name) {
            continue;
        }
        let path = if dir == Path::new(".") {
            PathBuf::from(&name)
        } else {
            dir.join(&name)
        };
        // A live writer holds its lock: taking it means the writer is gone.
        let dead = std::fs::File::open(&path).is_ok_and(|f| f.try_lock().is_ok());
        if dead && std::fs::remove_file(&path).is_ok() && !stale.contains(&path) {
            stale.push(path);
        }
    }
}

/// Temporary files left beside this process's outputs by earlier runs that
/// were killed before they could clean up, which this process removed.
pub fn stale_temporaries() -> Vec<PathBuf> {
    lock(&STALE).clone()
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    // A panic while holding the lock leaves plain data behind; keep using it.
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A registered temporary file: known to [`exit_removing_temporaries`] until
/// dropped, and locked (through its own handle) so that no later run takes it
/// for a dead one's.
pub(crate) struct Live {
    path: PathBuf,
    /// The handle that holds the lock (none where the filesystem has no locks).
    _held: Option<std::fs::File>,
}

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
        // The lock belongs to the open file, which this handle keeps open
        // after the writer's own handle is closed. A filesystem without
        // locks writes unlocked.
        let held = file.try_clone().ok().filter(|h| h.try_lock().is_ok());
        let registration = Self {
            path: path.to_path_buf(),
            _held: held,
        };
        Ok((file, path, registration))
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        let mut live = lock(&LIVE);
        if let Some(i) = live.iter().rposition(|p| *p == self.path) {
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
        lock(&INPUTS).clear();
        Self(())
    }

    /// Renames every staged file into place, in the order they were written.
    ///
    /// # Errors
    /// [`IoError::Os`] when a rename fails; the files not yet renamed are
    /// deleted.
    pub fn commit(self) -> Result<(), IoError> {
        lock(&MADE).clear();
        lock(&INPUTS).clear();
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
        lock(&INPUTS).clear();
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
    fn a_dead_run_s_leftovers_are_removed_and_a_live_one_s_kept() {
        let dir = tempfile::tempdir().unwrap();
        let leftover = dir.path().join(".out.npy.Xy12Zw.tmp");
        std::fs::write(&leftover, b"half").unwrap();
        let other = dir.path().join(".other.npy.Ab34Cd.tmp");
        std::fs::write(&other, b"x").unwrap();
        // A live writer's temporary: locked through an open handle.
        let live = dir.path().join(".live.npy.Ef56Gh.tmp");
        std::fs::write(&live, b"being written").unwrap();
        let holder = std::fs::File::open(&live).unwrap();
        holder.lock().unwrap();
        let not_ours = dir.path().join(".keep.tmp");
        std::fs::write(&not_ours, b"someone else's").unwrap();
        crate::write_atomic::<IoError>(&dir.path().join("out.npy"), |_| Ok(())).unwrap();
        let stale = stale_temporaries();
        for gone in [&leftover, &other] {
            assert!(!gone.exists(), "{} left", gone.display());
            assert!(stale.contains(gone), "{stale:?}");
        }
        assert_eq!(std::fs::read(&live).unwrap(), b"being written");
        assert!(!stale.contains(&live));
        assert_eq!(std::fs::read(&not_ours).unwrap(), b"someone else's");
        drop(holder);
    }
}

//! All-or-nothing outputs and clean interruption.
//!
//! While a [`Transaction`] is open, every write of this crate ([`crate::atomic`])
//! keeps its complete staged file instead of renaming it into place;
//! [`Transaction::commit`] renames them all, and dropping the transaction
//! uncommitted deletes them. A command that fails half way therefore leaves
//! every existing file as it was, whichever output failed.
//!
//! **Where a write is staged.** On Linux a write goes to an *anonymous* file
//! in the target's folder (`O_TMPFILE`): it has no name until it is complete
//! and committed, when it is linked in (`linkat` through `/proc/self/fd`) —
//! straight to the target's name when that is new, else to a temporary name
//! that is at once renamed over the target. A process killed in any other
//! moment, even by SIGKILL or a power cut, leaves nothing behind: the kernel
//! frees an unlinked file with its last handle. Only the two system calls
//! between the link and the rename of a *replaced* output leave a named
//! temporary if the process dies between them. A transaction holds at most
//! [`ANONYMOUS_STAGED`] anonymous files open; later outputs of the same
//! command (frames of a long turntable) are given temporary names at once.
//!
//! Elsewhere — another system, a filesystem without `O_TMPFILE` (it is tried
//! and the write falls back), or `ASPERITY_STAGING=named` in the environment
//! (how the tests exercise this path) — a write goes to a named temporary,
//! `.NAME.XXXXXX.tmp` beside the target.
//!
//! Every named temporary alive in the process is registered, so a signal
//! handler can delete them with [`exit_removing_temporaries`]. A SIGKILL
//! cannot be caught: its named temporaries stay. Each is held under an
//! exclusive advisory lock (`flock`) by the process writing it, until it is
//! renamed or deleted; the operating system drops the lock when the process
//! dies. The first write of a later run into a folder removes the
//! temporaries of ours there whose lock it can take — those of dead runs —
//! and leaves those of live ones (another asperity writing there now); it
//! lists what it removed in [`stale_temporaries`]. On a filesystem without
//! advisory locks every lock succeeds: a leftover there is removed as stale,
//! and so would be a live run's, so do not run two commands into one such
//! folder at once.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use tempfile::TempPath;

use crate::IoError;

/// A complete output waiting for its commit, and its target.
type Staged = (Pending, PathBuf);

/// The most anonymous files one transaction keeps open (each is an open
/// file handle; the usual limit is 1024 a process).
pub const ANONYMOUS_STAGED: usize = 256;

/// Where a finished output waits for its rename.
pub(crate) enum Pending {
    /// A named temporary beside the target, locked and registered.
    Named(TempPath, Live),
    /// An anonymous file in the target's folder (Linux `O_TMPFILE`), locked.
    #[cfg(target_os = "linux")]
    Anonymous(std::fs::File),
}

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
    _held: Option<File>,
}

/// The builder of our temporary names, `.NAME.XXXXXX.tmp`, for `prefix`
/// `.NAME.`.
fn builder(prefix: &str) -> tempfile::Builder<'_, 'static> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix).suffix(".tmp");
    // tempfile creates 0600 files; outputs should get the usual 0666 & !umask.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder
}

/// The folder of `path` (`.` for a bare name) and the prefix of its
/// temporaries.
fn folder_and_prefix(path: &Path) -> (&Path, String) {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    (dir, format!(".{name}."))
}

impl Live {
    /// Creates a named temporary file for `path` in its folder and registers
    /// it, both under the registry's lock, so [`exit_removing_temporaries`]
    /// never misses a file created while it runs.
    fn create(path: &Path) -> std::io::Result<(File, TempPath, Self)> {
        let (dir, prefix) = folder_and_prefix(path);
        let mut live = lock(&LIVE);
        let (file, path) = builder(&prefix).tempfile_in(dir)?.into_parts();
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

/// A blank file an output is written into, and how it will be named.
pub(crate) enum Blank {
    Named(TempPath, Live),
    #[cfg(target_os = "linux")]
    Anonymous,
}

/// Creates the file the output `path` is written into: anonymous where the
/// system allows, else a named temporary beside it (see the module docs).
pub(crate) fn create(path: &Path) -> std::io::Result<(File, Blank)> {
    #[cfg(target_os = "linux")]
    if let Some(file) = anonymous::create(folder_and_prefix(path).0) {
        return Ok((file, Blank::Anonymous));
    }
    let (file, tmp, live) = Live::create(path)?;
    Ok((file, Blank::Named(tmp, live)))
}

/// Puts the complete, synced `file` (made by [`create`]) at `path` now, or
/// stages it when a transaction is open.
pub(crate) fn persist_or_stage(file: File, blank: Blank, path: &Path) -> Result<(), IoError> {
    let pending = match blank {
        Blank::Named(tmp, live) => {
            drop(file);
            Pending::Named(tmp, live)
        }
        #[cfg(target_os = "linux")]
        Blank::Anonymous => Pending::Anonymous(file),
    };
    let mut staged = lock(&STAGED);
    let Some(staged) = staged.as_mut() else {
        drop(staged);
        return pending.commit(path);
    };
    #[cfg(target_os = "linux")]
    let pending = match pending {
        Pending::Anonymous(file) if anonymous::count(staged) >= ANONYMOUS_STAGED => {
            let (tmp, live) = anonymous::name(file, path).map_err(|e| IoError::os(path, e))?;
            Pending::Named(tmp, live)
        }
        other => other,
    };
    staged.push((pending, path.to_path_buf()));
    Ok(())
}

impl Pending {
    /// Gives the staged file the name `path`, replacing what was there.
    fn commit(self, path: &Path) -> Result<(), IoError> {
        match self {
            Self::Named(tmp, live) => {
                tmp.persist(path).map_err(|e| IoError::os(path, e.error))?;
                drop(live);
                Ok(())
            }
            #[cfg(target_os = "linux")]
            Self::Anonymous(file) => anonymous::link(file, path).map_err(|e| IoError::os(path, e)),
        }
    }

    fn len(&self) -> Option<u64> {
        match self {
            Self::Named(tmp, _) => std::fs::metadata(tmp).ok().map(|m| m.len()),
            #[cfg(target_os = "linux")]
            Self::Anonymous(file) => file.metadata().ok().map(|m| m.len()),
        }
    }
}

/// Anonymous staging: `O_TMPFILE` files named by `linkat` once complete.
/// Written here because no crate offers it with a fallback (`tempfile`
/// always names its files); `rustix` makes the system calls.
#[cfg(target_os = "linux")]
mod anonymous {
    use std::fs::File;
    use std::io::{Seek, Write};
    use std::os::fd::AsRawFd;
    use std::path::Path;

    use rustix::fs::{AtFlags, CWD, Mode, OFlags};
    use tempfile::TempPath;

    use super::{LIVE, Live, Pending, Staged, builder, folder_and_prefix, lock};

    /// Whether writes may be anonymous: not when `ASPERITY_STAGING=named`.
    fn allowed() -> bool {
        static ALLOWED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
        *ALLOWED.get_or_init(|| std::env::var_os("ASPERITY_STAGING").is_none_or(|v| v != "named"))
    }

    /// An anonymous file in `dir`, locked; none where the filesystem (or the
    /// kernel, before 3.11) has no `O_TMPFILE`.
    pub(super) fn create(dir: &Path) -> Option<File> {
        if !allowed() {
            return None;
        }
        let flags = OFlags::TMPFILE | OFlags::RDWR | OFlags::CLOEXEC;
        let fd = rustix::fs::openat(CWD, dir, flags, Mode::from_raw_mode(0o666)).ok()?;
        let file = File::from(fd);
        // Locked so that, once linked under a temporary name, no other run
        // takes it for a dead one's; a filesystem without locks goes unlocked.
        let _ = file.try_lock();
        Some(file)
    }

    pub(super) fn count(staged: &[Staged]) -> usize {
        staged
            .iter()
            .filter(|(p, _)| matches!(p, Pending::Anonymous(_)))
            .count()
    }

    /// Links `file` at `to` (which must not exist).
    fn link_at(file: &File, to: &Path) -> std::io::Result<()> {
        let open = format!("/proc/self/fd/{}", file.as_raw_fd());
        rustix::fs::linkat(CWD, open.as_str(), CWD, to, AtFlags::SYMLINK_FOLLOW)
            .map_err(std::io::Error::from)
    }

    /// Names `file` `path`: linked there when `path` is new, else linked under
    /// a temporary name and renamed over it.
    pub(super) fn link(file: File, path: &Path) -> std::io::Result<()> {
        match link_at(&file, path) {
            Ok(()) => return Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            // No /proc: `name` copies.
            Err(_) => {}
        }
        let (tmp, live) = name(file, path)?;
        tmp.persist(path).map_err(|e| e.error)?;
        drop(live);
        Ok(())
    }

    /// Gives `file` a registered temporary name beside `path`; the file
    /// keeps its lock. Where it cannot be linked (no `/proc`), its bytes are
    /// copied into a named temporary.
    pub(super) fn name(mut file: File, path: &Path) -> std::io::Result<(TempPath, Live)> {
        let (dir, prefix) = folder_and_prefix(path);
        let linked = {
            let mut live = lock(&LIVE);
            let linked = builder(&prefix).make_in(dir, |to| link_at(&file, to));
            if let Ok(named) = &linked {
                live.push(named.path().to_path_buf());
            }
            linked
        };
        if let Ok(named) = linked {
            let tmp = named.into_temp_path();
            let registration = Live {
                path: tmp.to_path_buf(),
                _held: Some(file),
            };
            return Ok((tmp, registration));
        }
        let (mut copy, tmp, live) = Live::create(path)?;
        file.rewind()?;
        std::io::copy(&mut file, &mut copy)?;
        copy.flush()?;
        copy.sync_all()?;
        Ok((tmp, live))
    }
}

/// Whether a write into the folder `dir` is staged anonymously (Linux
/// `O_TMPFILE` on a filesystem that has it, and `ASPERITY_STAGING` not
/// `named`): then a killed run leaves nothing there (see the module docs).
pub fn stages_anonymously(dir: &Path) -> bool {
    #[cfg(target_os = "linux")]
    return anonymous::create(dir).is_some();
    #[cfg(not(target_os = "linux"))]
    return false;
}

/// The size of what was last written to `path`: its staged file while
/// a transaction is open, else the file on disk.
pub fn written_len(path: &Path) -> Option<u64> {
    if let Some(staged) = lock(&STAGED).as_ref()
        && let Some((pending, _)) = staged.iter().rev().find(|(_, p)| p == path)
    {
        return pending.len();
    }
    std::fs::metadata(path).ok().map(|m| m.len())
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
        for (pending, path) in staged {
            pending.commit(&path)?;
        }
        Ok(())
    }
}

impl Drop for Transaction {
    fn drop(&mut self) {
        // Uncommitted: deleting the temporaries (TempPath's drop) and closing
        // the anonymous files leaves every target as it was.
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

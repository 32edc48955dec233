//! The memory a process may really use: physical RAM, its memory cgroup's
//! limit less what the cgroup already uses, and its resource limits less its
//! current size — read from `/proc` and `/sys/fs/cgroup` (Linux; elsewhere
//! half of RAM, or 8 GiB where even that cannot be read).
//!
//! A budget of half the machine's RAM is wrong in a container, a Slurm job or
//! a Dask worker, where the cgroup's `memory.max` (v2) or
//! `memory.limit_in_bytes` (v1) kills the process long before RAM runs out,
//! and under `ulimit -v`, where an allocation fails and Rust aborts. Reading
//! the limits lets [`crate::MemoryBudget::check`] refuse such jobs with the
//! estimate instead. Every level of the cgroup's path counts (a parent's limit
//! binds its children); where the process's own cgroup directory is not
//! visible (a cgroup namespace), the mount's root is read instead.
//!
//! The files are read through [`SystemMemory`], whose root can be a folder of
//! fake files, so each rule is tested without a cgroup to run in.

use std::path::{Path, PathBuf};

use crate::MemoryBudget;
use crate::memory::{FALLBACK_RAM, LimitSource};

impl MemoryBudget {
    /// The least of half of physical RAM and the headroom under this
    /// process's memory cgroup and resource limits, read now
    /// ([`SystemMemory::budget`]).
    pub fn from_system() -> Self {
        SystemMemory::real().budget()
    }
}

impl Default for MemoryBudget {
    /// [`MemoryBudget::from_system`].
    fn default() -> Self {
        Self::from_system()
    }
}

/// The files memory limits are read from, under a root (`/` for the real
/// system, a folder of fake files in tests).
#[derive(Clone, Debug)]
pub struct SystemMemory {
    root: PathBuf,
}

/// cgroup v1 writes "no limit" as a huge number (2⁶³ rounded to pages).
const V1_UNLIMITED: u64 = 1 << 62;

impl SystemMemory {
    /// The running system's files.
    pub fn real() -> Self {
        Self::at("/")
    }

    /// The files under `root` (e.g. `root/proc/self/cgroup`).
    pub fn at(root: impl Into<PathBuf>) -> Self {
        Self { root: root.into() }
    }

    fn read(&self, path: impl AsRef<Path>) -> Option<String> {
        let rel = path.as_ref().strip_prefix("/").unwrap_or(path.as_ref());
        std::fs::read_to_string(self.root.join(rel)).ok()
    }

    fn number(&self, path: impl AsRef<Path>) -> Option<u64> {
        self.read(path)?.trim().parse().ok()
    }

    /// Total physical memory in bytes (`/proc/meminfo`).
    pub fn physical_ram(&self) -> Option<u64> {
        kib_field(&self.read("/proc/meminfo")?, "MemTotal:")
    }

    /// The least headroom (limit − usage) over the levels of this process's
    /// memory cgroup, v2 (`memory.max`, `memory.high`) or v1
    /// (`memory.limit_in_bytes`); `None` where no level has a limit.
    pub fn cgroup_headroom(&self) -> Option<u64> {
        let table = self.read("/proc/self/cgroup")?;
        let mut least: Option<u64> = None;
        for line in table.lines() {
            let mut fields = line.splitn(3, ':');
            let (Some(_), Some(controllers), Some(path)) =
                (fields.next(), fields.next(), fields.next())
            else {
                continue;
            };
            let found = if controllers.is_empty() {
                self.levels("/sys/fs/cgroup", path, |dir| self.v2_headroom(dir))
            } else if controllers.split(',').any(|c| c == "memory") {
                self.levels("/sys/fs/cgroup/memory", path, |dir| self.v1_headroom(dir))
            } else {
                None
            };
            if let Some(h) = found {
                least = Some(least.map_or(h, |l| l.min(h)));
            }
        }
        least
    }

    /// The least `headroom` over the cgroup directory of `path` under `mount`
    /// and its parents; the mount's root alone when `path`'s directory is not
    /// there (a cgroup namespace shows its own root).
    fn levels(
        &self,
        mount: &str,
        path: &str,
        headroom: impl Fn(&Path) -> Option<u64>,
    ) -> Option<u64> {
        let mount = Path::new(mount);
        let rel = path.trim_start_matches('/');
        let own = mount.join(rel);
        let visible = self
            .root
            .join(own.strip_prefix("/").unwrap_or(&own))
            .is_dir();
        let mut dirs = vec![mount.to_path_buf()];
        if visible && !rel.is_empty() {
            let mut dir = mount.to_path_buf();
            for part in rel.split('/').filter(|p| !p.is_empty()) {
                dir = dir.join(part);
                dirs.push(dir.clone());
            }
        }
        dirs.iter().filter_map(|d| headroom(d)).min()
    }

    fn v2_headroom(&self, dir: &Path) -> Option<u64> {
        let limit = ["memory.max", "memory.high"]
            .iter()
            .filter_map(|f| self.number(dir.join(f)))
            .min()?;
        let used = self.number(dir.join("memory.current")).unwrap_or(0);
        Some(limit.saturating_sub(used))
    }

    fn v1_headroom(&self, dir: &Path) -> Option<u64> {
        let limit = self
            .number(dir.join("memory.limit_in_bytes"))
            .filter(|&l| l < V1_UNLIMITED)?;
        let used = self.number(dir.join("memory.usage_in_bytes")).unwrap_or(0);
        Some(limit.saturating_sub(used))
    }

    /// The headroom under the soft address-space limit (less `VmSize`) and
    /// under the soft data-size limit (less `VmData`), where set.
    pub fn rlimit_headroom(&self) -> [(LimitSource, Option<u64>); 2] {
        let limits = self.read("/proc/self/limits").unwrap_or_default();
        let status = self.read("/proc/self/status").unwrap_or_default();
        let soft = |name: &str| {
            let line = limits.lines().find(|l| l.starts_with(name))?;
            line[name.len()..]
                .split_whitespace()
                .next()?
                .parse::<u64>()
                .ok()
        };
        let headroom = |limit: &str, used: &str| {
            let l = soft(limit)?;
            Some(l.saturating_sub(kib_field(&status, used).unwrap_or(0)))
        };
        [
            (
                LimitSource::AddressSpace,
                headroom("Max address space", "VmSize:"),
            ),
            (LimitSource::DataSize, headroom("Max data size", "VmData:")),
        ]
    }

    /// The least of half of RAM (8 GiB assumed unreadable), the cgroup's
    /// headroom and the resource limits' headroom, with its source.
    pub fn budget(&self) -> MemoryBudget {
        let ram = self.physical_ram().unwrap_or(FALLBACK_RAM);
        let mut best = (ram / 2, LimitSource::HalfOfRam);
        let cgroup = (LimitSource::Cgroup, self.cgroup_headroom());
        for (source, headroom) in std::iter::once(cgroup).chain(self.rlimit_headroom()) {
            if let Some(h) = headroom
                && h < best.0
            {
                best = (h, source);
            }
        }
        MemoryBudget::with_source(best.0, best.1)
    }
}

/// A `Name:   123 kB` field of `/proc/meminfo` or `/proc/self/status`, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GIB: u64 = 1 << 30;

    /// A fake system: `files` are (path, text) under a temporary root.
    fn system(files: &[(&str, String)]) -> (tempfile::TempDir, SystemMemory) {
        let dir = tempfile::tempdir().unwrap();
        let mut all = vec![(
            "proc/meminfo",
            format!("MemTotal: {} kB\n", 64 * GIB / 1024),
        )];
        all.extend(files.iter().map(|(p, t)| (*p, t.clone())));
        for (path, text) in all {
            let p = dir.path().join(path);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, text).unwrap();
        }
        let s = SystemMemory::at(dir.path());
        (dir, s)
    }

    #[test]
    fn without_limits_the_budget_is_half_of_ram() {
        let (_d, s) = system(&[]);
        let b = s.budget();
        assert_eq!((b.limit(), b.source()), (32 * GIB, LimitSource::HalfOfRam));
    }

    /// cgroup v2: the least of memory.max and memory.high over the levels,
    /// less the level's use; "max" is no limit.
    #[test]
    fn a_v2_cgroup_limit_binds_at_any_level() {
        let (_d, s) = system(&[
            ("proc/self/cgroup", "0::/slurm/job42\n".into()),
            ("sys/fs/cgroup/slurm/memory.max", format!("{}\n", 6 * GIB)),
            ("sys/fs/cgroup/slurm/memory.current", format!("{}\n", GIB)),
            ("sys/fs/cgroup/slurm/job42/memory.max", "max\n".into()),
            (
                "sys/fs/cgroup/slurm/job42/memory.high",
                format!("{}\n", 8 * GIB),
            ),
            (
                "sys/fs/cgroup/slurm/job42/memory.current",
                format!("{}\n", GIB / 2),
            ),
        ]);
        let b = s.budget();
        assert_eq!((b.limit(), b.source()), (5 * GIB, LimitSource::Cgroup));
    }

    /// cgroup v1: memory.limit_in_bytes less memory.usage_in_bytes; the huge
    /// "unlimited" value is no limit; a namespaced cgroup (own directory not
    /// visible) is read at the mount's root.
    #[test]
    fn a_v1_cgroup_limit_and_its_unlimited_value() {
        let (_d, s) = system(&[
            (
                "proc/self/cgroup",
                "4:memory:/docker/abc\n1:cpu:/docker/abc\n".into(),
            ),
            (
                "sys/fs/cgroup/memory/memory.limit_in_bytes",
                format!("{}\n", 4 * GIB),
            ),
            (
                "sys/fs/cgroup/memory/memory.usage_in_bytes",
                format!("{}\n", GIB),
            ),
        ]);
        assert_eq!(s.cgroup_headroom(), Some(3 * GIB));
        let (_d, s) = system(&[
            ("proc/self/cgroup", "4:cpuacct,memory:/x\n".into()),
            (
                "sys/fs/cgroup/memory/x/memory.limit_in_bytes",
                "9223372036854771712\n".into(),
            ),
            (
                "sys/fs/cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712\n".into(),
            ),
        ]);
        assert_eq!(s.cgroup_headroom(), None);
        assert_eq!(s.budget().source(), LimitSource::HalfOfRam);
    }

    /// ulimit -v 8 GiB with 200 MiB mapped leaves 8 GiB − 200 MiB; a data
    /// limit binds when it is the smaller.
    #[test]
    fn resource_limits_less_the_process_size() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max data size             unlimited            unlimited            bytes\n\
                      Max address space         8589934592           unlimited            bytes\n";
        let status = "Name:\tasperity\nVmSize:\t  204800 kB\nVmData:\t  102400 kB\n";
        let (_d, s) = system(&[
            ("proc/self/limits", limits.into()),
            ("proc/self/status", status.into()),
        ]);
        let b = s.budget();
        assert_eq!(
            (b.limit(), b.source()),
            (8 * GIB - 200 * (1 << 20), LimitSource::AddressSpace)
        );
        let limits = limits.replace(
            "Max data size             unlimited",
            "Max data size             1073741824",
        );
        let (_d, s) = system(&[
            ("proc/self/limits", limits),
            ("proc/self/status", status.into()),
        ]);
        let b = s.budget();
        assert_eq!(
            (b.limit(), b.source()),
            (GIB - 100 * (1 << 20), LimitSource::DataSize)
        );
        let e = b.check(2 * GIB, "a grid").unwrap_err().to_string();
        assert!(e.contains("ulimit -d"), "{e}");
    }

    /// On this machine: a budget no larger than half of RAM, from a source
    /// the rules above can give.
    #[test]
    fn the_real_system_gives_a_budget() {
        let b = SystemMemory::real().budget();
        if let Some(ram) = SystemMemory::real().physical_ram() {
            assert!(b.limit() <= ram / 2);
        }
        assert_ne!(b.source(), LimitSource::Given);
    }
}

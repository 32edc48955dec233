//! Memory budgets: estimate before allocating, refuse with the estimate.
//!
//! Every algorithm that allocates a grid or buffer whose size the user controls
//! calls [`MemoryBudget::check`] with its estimate first. The CLI's
//! `--max-memory` (Python's `max_memory=`) sets the limit; the default,
//! [`MemoryBudget::from_system`], is the least of half of physical RAM and the
//! headroom the process really has — under its memory cgroup (a container, a
//! Slurm job, a Dask worker) and under its address-space and data-size limits
//! (`ulimit -v`, `ulimit -d`) — so a job too big for them is refused with its
//! estimate instead of being killed (see [`crate::system_memory`]).

use crate::CoreError;

/// Where a memory budget's limit came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitSource {
    /// Given by the user (`--max-memory`, `max_memory=`).
    Given,
    /// No limit (tests, trusted callers).
    Unlimited,
    /// Half of physical RAM.
    HalfOfRam,
    /// The memory cgroup's limit less its current use.
    Cgroup,
    /// The address-space limit (`RLIMIT_AS`, `ulimit -v`) less the process's size.
    AddressSpace,
    /// The data-segment limit (`RLIMIT_DATA`, `ulimit -d`) less the process's data.
    DataSize,
}

impl LimitSource {
    /// How a message names it.
    pub const fn describe(self) -> &'static str {
        match self {
            LimitSource::Given => "as given",
            LimitSource::Unlimited => "no limit",
            LimitSource::HalfOfRam => "half of the RAM",
            LimitSource::Cgroup => "this process's memory cgroup limit, less what the cgroup uses",
            LimitSource::AddressSpace => {
                "the address-space limit of ulimit -v, less what the process maps"
            }
            LimitSource::DataSize => "the data-size limit of ulimit -d, less the process's data",
        }
    }

    /// A short name for reports (`cgroup`, `rlimit_as`, …).
    pub const fn name(self) -> &'static str {
        match self {
            LimitSource::Given => "given",
            LimitSource::Unlimited => "unlimited",
            LimitSource::HalfOfRam => "half_of_ram",
            LimitSource::Cgroup => "cgroup",
            LimitSource::AddressSpace => "rlimit_as",
            LimitSource::DataSize => "rlimit_data",
        }
    }
}

/// An upper bound on the bytes one operation may allocate, and where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    limit: u64,
    source: LimitSource,
}

/// Physical RAM assumed when `/proc/meminfo` cannot be read (8 GiB).
pub(crate) const FALLBACK_RAM: u64 = 8 << 30;

impl MemoryBudget {
    /// A budget of `limit` bytes, as given by the user.
    pub const fn new(limit: u64) -> Self {
        Self {
            limit,
            source: LimitSource::Given,
        }
    }

    /// A budget of `limit` bytes set by `source`.
    pub const fn with_source(limit: u64, source: LimitSource) -> Self {
        Self { limit, source }
    }

    /// No limit at all (tests, trusted callers).
    pub const fn unlimited() -> Self {
        Self {
            limit: u64::MAX,
            source: LimitSource::Unlimited,
        }
    }

    /// Half of physical RAM (read from `/proc/meminfo`; 8 GiB assumed if unreadable).
    pub fn half_of_ram() -> Self {
        Self::with_source(
            physical_ram().unwrap_or(FALLBACK_RAM) / 2,
            LimitSource::HalfOfRam,
        )
    }

    /// The limit in bytes.
    pub const fn limit(&self) -> u64 {
        self.limit
    }

    /// Where the limit came from.
    pub const fn source(&self) -> LimitSource {
        self.source
    }

    /// `Ok` if `bytes` fit in the budget, else [`CoreError::MemoryLimit`] naming `what`.
    ///
    /// # Errors
    /// [`CoreError::MemoryLimit`] with the estimate and the limit.
    pub fn check(&self, bytes: u64, what: impl Into<String>) -> crate::Result<()> {
        if bytes > self.limit {
            return Err(CoreError::MemoryLimit {
                what: what.into(),
                needed: bytes,
                limit: self.limit,
                from: self.source.describe(),
            });
        }
        Ok(())
    }

    /// Checks `count` elements of `elem_bytes` each, guarding the multiplication.
    ///
    /// # Errors
    /// [`CoreError::MemoryLimit`] when the product overflows or exceeds the budget.
    pub fn check_elements(&self, count: u128, elem_bytes: u64, what: &str) -> crate::Result<()> {
        let bytes = count.saturating_mul(elem_bytes as u128);
        let bytes = u64::try_from(bytes).unwrap_or(u64::MAX);
        self.check(bytes, what)
    }
}

/// Total physical memory in bytes, from `/proc/meminfo` (Linux only).
pub fn physical_ram() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Parses sizes such as `512M`, `4G`, `1.5GiB`, `2048` (bytes). Units are binary.
///
/// # Errors
/// [`CoreError::InvalidParameter`] for anything else.
pub fn parse_size(text: &str) -> crate::Result<u64> {
    let bad = || CoreError::InvalidParameter {
        name: "memory size",
        reason: format!("{text:?} is not a size like 512M, 4G or 1.5GiB"),
    };
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.parse().map_err(|_| bad())?;
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" | "kib" => 1 << 10,
        "m" | "mb" | "mib" => 1 << 20,
        "g" | "gb" | "gib" => 1 << 30,
        "t" | "tb" | "tib" => 1 << 40,
        _ => return Err(bad()),
    };
    let bytes = value * scale as f64;
    if !bytes.is_finite() || bytes < 1.0 || bytes > u64::MAX as f64 {
        return Err(bad());
    }
    Ok(bytes as u64)
}

/// Human-readable binary size, e.g. `1.50 GiB`.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut v = bytes as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{bytes} B")
    } else {
        format!("{v:.2} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_sizes() {
        assert_eq!(parse_size("2048").unwrap(), 2048);
        assert_eq!(parse_size("512M").unwrap(), 512 << 20);
        assert_eq!(parse_size("4g").unwrap(), 4 << 30);
        assert_eq!(parse_size("1.5GiB").unwrap(), 3 << 29);
        for bad in ["", "G", "-1G", "12X", "0", "1.2.3M"] {
            assert!(parse_size(bad).is_err(), "{bad:?} should be rejected");
        }
    }

    #[test]
    fn refuses_with_estimate() {
        let b = MemoryBudget::new(1 << 20);
        assert!(b.check(1 << 20, "x").is_ok());
        let err = b.check_elements(1 << 20, 8, "a 3-D grid").unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("8.00 MiB") && msg.contains("1.00 MiB"),
            "{msg}"
        );
        assert!(b.check_elements(u128::MAX, 8, "huge").is_err());
    }

    #[test]
    fn ram_is_read_on_linux() {
        if cfg!(target_os = "linux") {
            let ram = physical_ram().expect("/proc/meminfo");
            assert!(ram > 64 << 20);
            assert_eq!(MemoryBudget::half_of_ram().limit(), ram / 2);
        }
    }

    #[test]
    fn formats_bytes() {
        assert_eq!(format_bytes(10), "10 B");
        assert_eq!(format_bytes(3 << 29), "1.50 GiB");
    }
}

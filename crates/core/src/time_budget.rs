//! Time budgets: estimate a run's duration before starting, refuse what would
//! take longer than the limit.
//!
//! A typo in a step count (`--steps 1000000000`, `--runs 1e9`) can mean a run of
//! years that otherwise just sits there. Each long job describes its work as a
//! [`Work`] — a count of units (cell updates, depositions, node updates) and the
//! rate at which one thread of a fast machine does them — and checks it with
//! [`TimeBudget::check`] before any work. The rate is deliberately optimistic
//! (several times what the benchmarks in `BENCHMARKS.md` measure), so the
//! estimate is a lower bound: a run is refused only when even a fast machine
//! could not finish it within the limit. The CLI's `--max-time` sets the limit;
//! the default is one day.

use std::time::Duration;

use crate::CoreError;

/// Default limit: one day.
pub const DEFAULT_LIMIT: Duration = Duration::from_secs(24 * 3600);

/// An upper bound on how long one operation may be expected to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeBudget {
    limit_s: f64,
    threads: usize,
}

/// The work of one run, in units a rate is known for.
#[derive(Clone, Debug, PartialEq)]
pub struct Work {
    /// What runs, e.g. "the CA evolution".
    pub what: String,
    /// How many units it takes.
    pub units: f64,
    /// The unit's name, plural: "cell updates".
    pub unit: &'static str,
    /// Units per second one thread of a fast machine manages (optimistic).
    pub per_thread_per_s: f64,
    /// Whether the work spreads over threads (false for a sequential loop).
    pub parallel: bool,
}

impl Work {
    /// `units` of `unit` at `per_thread_per_s`, spread over the threads.
    pub fn new(
        what: impl Into<String>,
        units: f64,
        unit: &'static str,
        per_thread_per_s: f64,
    ) -> Self {
        Self {
            what: what.into(),
            units,
            unit,
            per_thread_per_s,
            parallel: true,
        }
    }

    /// The same work done by one thread only.
    pub fn sequential(mut self) -> Self {
        self.parallel = false;
        self
    }

    /// Seconds this takes at least on `threads` threads.
    pub fn seconds(&self, threads: usize) -> f64 {
        let lanes = if self.parallel { threads.max(1) } else { 1 };
        self.units / (self.per_thread_per_s * lanes as f64)
    }
}

impl TimeBudget {
    /// A limit of `limit` for work spread over `threads` threads.
    pub fn new(limit: Duration, threads: usize) -> Self {
        Self {
            limit_s: limit.as_secs_f64(),
            threads: threads.max(1),
        }
    }

    /// No limit (tests, trusted callers, interactive front ends that can cancel).
    pub const fn unlimited() -> Self {
        Self {
            limit_s: f64::INFINITY,
            threads: 1,
        }
    }

    /// The limit in seconds (infinite when unlimited).
    pub fn limit_s(&self) -> f64 {
        self.limit_s
    }

    /// `Ok` when `work` may finish within the limit.
    ///
    /// # Errors
    /// [`CoreError::TimeLimit`] with the estimate, the rate and the limit.
    pub fn check(&self, work: &Work) -> crate::Result<()> {
        let seconds = work.seconds(self.threads);
        // NaN work (never expected) is refused rather than waved through.
        if seconds.is_nan() || seconds > self.limit_s {
            let lanes = if work.parallel { self.threads } else { 1 };
            return Err(CoreError::TimeLimit {
                what: work.what.clone(),
                detail: format!(
                    "{:.3e} {} at ≤ {:.1e} per second on {lanes} thread{}",
                    work.units,
                    work.unit,
                    work.per_thread_per_s * lanes as f64,
                    if lanes == 1 { "" } else { "s" }
                ),
                seconds,
                limit_s: self.limit_s,
            });
        }
        Ok(())
    }
}

impl Default for TimeBudget {
    fn default() -> Self {
        Self::new(DEFAULT_LIMIT, 1)
    }
}

/// Parses durations such as `90s`, `30m`, `2h`, `1.5d`, `1w`, a bare number of
/// seconds, or `none` / `unlimited` (no limit, returned as `None`).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for anything else.
pub fn parse_duration(text: &str) -> crate::Result<Option<Duration>> {
    let bad = || CoreError::InvalidParameter {
        name: "duration",
        reason: format!("{text:?} is not a duration like 90s, 30m, 2h, 1d or none"),
    };
    let t = text.trim().to_ascii_lowercase();
    if matches!(t.as_str(), "none" | "unlimited" | "inf") {
        return Ok(None);
    }
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.parse().map_err(|_| bad())?;
    let scale = match unit.trim() {
        "" | "s" | "sec" => 1.0,
        "m" | "min" => 60.0,
        "h" => 3600.0,
        "d" => 86400.0,
        "w" => 7.0 * 86400.0,
        _ => return Err(bad()),
    };
    let s = value * scale;
    if !s.is_finite() || s <= 0.0 || s > 1e15 {
        return Err(bad());
    }
    Ok(Some(Duration::from_secs_f64(s)))
}

/// A duration for people: `45 s`, `12 min`, `3.4 h`, `2.1 days`, `3.4 years`.
pub fn format_seconds(s: f64) -> String {
    const YEAR: f64 = 365.25 * 86400.0;
    if !s.is_finite() {
        "forever".into()
    } else if s < 100.0 {
        format!("{s:.0} s")
    } else if s < 6000.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 2.0 * 86400.0 {
        format!("{:.1} h", s / 3600.0)
    } else if s < YEAR {
        format!("{:.1} days", s / 86400.0)
    } else if s < 1e4 * YEAR {
        format!("{:.1} years", s / YEAR)
    } else {
        format!("{:.1e} years", s / YEAR)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_parse_and_print() {
        assert_eq!(
            parse_duration("90s").unwrap(),
            Some(Duration::from_secs(90))
        );
        assert_eq!(
            parse_duration("2h").unwrap(),
            Some(Duration::from_secs(7200))
        );
        assert_eq!(
            parse_duration("1.5d").unwrap(),
            Some(Duration::from_secs(129_600))
        );
        assert_eq!(parse_duration("none").unwrap(), None);
        for bad in ["", "-1h", "0", "1y", "nan", "1e400"] {
            assert!(parse_duration(bad).is_err(), "{bad}");
        }
        assert_eq!(format_seconds(42.0), "42 s");
        assert_eq!(format_seconds(3.0 * 3600.0), "3.0 h");
        assert_eq!(format_seconds(2.0 * 365.25 * 86400.0), "2.0 years");
    }

    #[test]
    fn a_run_of_years_is_refused_with_its_estimate() {
        let b = TimeBudget::new(DEFAULT_LIMIT, 2);
        // 2⁶⁴ steps on 10⁵ cells at 10⁹ per thread and second: ~29 000 years.
        let w = Work::new("the corrosion", 1.8447e19 * 1e5, "cell updates", 1e9);
        let e = b.check(&w).unwrap_err().to_string();
        assert!(
            e.contains("the corrosion") && e.contains("years") && e.contains("⟨max_time⟩"),
            "{e}"
        );
        assert!(
            b.check(&Work::new("a second", 2e9, "cell updates", 1e9))
                .is_ok()
        );
        // Sequential work does not get the second thread.
        let seq = Work::new("seq", 1.5 * 86400.0 * 1e9, "steps", 1e9).sequential();
        assert!(b.check(&seq).is_err());
        assert!(TimeBudget::unlimited().check(&w).is_ok());
    }
}

//! Run-time estimates of the long jobs, checked against a [`TimeBudget`] before
//! any work (see [`asperity_core::time_budget`]).
//!
//! Each rate below is what one thread of a fast machine does, set several times
//! above the figures measured on the project's 2-core machine (`BENCHMARKS.md`),
//! so an estimate is a lower bound: only runs that no machine could finish
//! within the limit are refused. The progress bars show the measured ETA while
//! a run goes on.

use asperity_core::{TimeBudget, Work};

use crate::error::{Result, ensure};

/// CA cell updates per thread and second (bit-sliced evolution; measured
/// ~15 G per core with AVX-512, ~3 G per core with accumulation).
pub const CA_CELL_UPDATES_PER_S: f64 = 5e10;
/// A CA step costs at least as much as this many cells: about 1 µs of per-step
/// overhead (measured 2.6 µs a step on a 64² grid).
pub const CA_MIN_CELLS_PER_STEP: f64 = 65_536.0;
/// Depositions per thread and second (RD measured at 240 M per core).
pub const DEPOSITIONS_PER_S: f64 = 1e9;
/// DLA particles per second, one thread (measured 54–97 k/s).
pub const DLA_PARTICLES_PER_S: f64 = 1e6;
/// Surface-CA cell updates per thread and second (Voronoi measured at 127 M).
pub const SURFCA_CELL_UPDATES_PER_S: f64 = 1e9;
/// Level-set node updates per thread and second, counted over the whole grid
/// (the flow touches only the narrow band, so this is far above measured).
pub const LEVELSET_NODE_UPDATES_PER_S: f64 = 2e10;
/// Output quads of subdivision per thread and second (measured 5 M).
pub const SUBDIV_QUADS_PER_S: f64 = 1e8;
/// Rendered pixels per thread and second (measured ~10 M with shadows).
pub const RENDER_PIXELS_PER_S: f64 = 1e9;

/// The most numbered files (frames, saved steps) one command writes.
pub const MAX_NUMBERED_FILES: u64 = 100_000;

/// Refuses a command that would write more than [`MAX_NUMBERED_FILES`] files.
///
/// # Errors
/// [`crate::EngineError::Invalid`] naming the count and the option.
pub fn check_file_count(files: u64, option: &str) -> Result<()> {
    ensure(files <= MAX_NUMBERED_FILES, || {
        format!(
            "{option} would write {files} files (at most {MAX_NUMBERED_FILES}); write fewer frames"
        )
    })
}

/// A CA run: `steps` steps of `cells` cells.
pub fn ca(cells: f64, steps: f64) -> Work {
    Work::new(
        "the CA evolution",
        steps * cells.max(CA_MIN_CELLS_PER_STEP),
        "cell updates",
        CA_CELL_UPDATES_PER_S,
    )
}

/// `depositions` particle depositions of RD, RDSR or BD.
pub fn deposition(depositions: f64) -> Work {
    Work::new(
        "the deposition",
        depositions,
        "depositions",
        DEPOSITIONS_PER_S,
    )
}

/// A DLA cluster of `particles` (sequential).
pub fn dla(particles: f64) -> Work {
    Work::new(
        "the DLA growth",
        particles,
        "particles",
        DLA_PARTICLES_PER_S,
    )
    .sequential()
}

/// A surface CA of `steps` steps on `cells` cells.
pub fn surface_ca(cells: f64, steps: f64) -> Work {
    Work::new(
        "the surface CA",
        cells * steps,
        "cell updates",
        SURFCA_CELL_UPDATES_PER_S,
    )
}

/// A level-set flow of `iterations` on a grid of `nodes`.
pub fn level_set(nodes: f64, iterations: f64) -> Work {
    Work::new(
        "the level-set flow",
        nodes * iterations,
        "node updates",
        LEVELSET_NODE_UPDATES_PER_S,
    )
}

/// `frames` subdivisions of `quads` output quads each.
pub fn subdiv_frames(quads: f64, frames: f64) -> Work {
    Work::new(
        "the animation",
        quads * frames,
        "output quads",
        SUBDIV_QUADS_PER_S,
    )
}

/// `frames` pictures of `pixels` each.
pub fn render_frames(pixels: f64, frames: f64) -> Work {
    Work::new(
        "the turntable",
        pixels * frames,
        "pixels",
        RENDER_PIXELS_PER_S,
    )
}

/// Checks `work` against `time`.
///
/// # Errors
/// [`asperity_core::CoreError::TimeLimit`] with the estimate.
pub fn check(time: &TimeBudget, work: &Work) -> Result<()> {
    Ok(time.check(work)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_s_typos_are_refused_and_ordinary_runs_pass() {
        let day = TimeBudget::new(asperity_core::time_budget::DEFAULT_LIMIT, 2);
        // 2⁶⁴ corrosion steps on 91 680 cells.
        assert!(check(&day, &surface_ca(91_680.0, 1.8e19)).is_err());
        // 10⁹ runs of 100 layers on 256².
        assert!(check(&day, &deposition(1e9 * 100.0 * 65536.0)).is_err());
        // 10¹⁰ flow iterations on 128³ (the CLI caps iterations at 10⁶ anyway).
        assert!(check(&day, &level_set(2.1e6, 1e10)).is_err());
        // The README's commands.
        assert!(check(&day, &ca(8192.0 * 8192.0, 256.0)).is_ok());
        assert!(check(&day, &surface_ca(220_000.0, 950.0)).is_ok());
        assert!(check(&day, &dla(1e7)).is_ok());
        assert!(check_file_count(500, "⟨frames⟩").is_ok());
        assert!(check_file_count(1 << 40, "⟨frames⟩").is_err());
    }
}

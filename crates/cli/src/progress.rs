//! Progress behind `asperity_engine::core::Progress`: indicatif bars on a
//! terminal, or plain lines for logs (`--progress lines`).

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use asperity_engine::core::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// `--progress`: how long work shows that it is moving.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ProgressMode {
    /// A bar on a terminal, after a second of work (unless --quiet or --json); nothing otherwise.
    #[default]
    Auto,
    /// A plain line on stderr when each stage starts, at every tenth of it and when it ends:
    /// for logs of batch jobs (printed even with --quiet or --json).
    Lines,
    /// Nothing.
    None,
}

/// A bar on stderr, drawn only when stderr is a terminal and not `--quiet`
/// (it appears after one second, so quick work shows nothing), or lines.
pub struct Bar {
    bar: Mutex<Option<ProgressBar>>,
    visible: bool,
    /// `--progress lines`: the stage being run, when one is.
    lines: Option<Mutex<Option<Stage>>>,
}

/// A stage reported by lines: its name, length, position, the tenth last
/// printed and when it started.
struct Stage {
    message: String,
    total: u64,
    done: u64,
    tenth: u64,
    started: Instant,
}

impl Bar {
    /// Progress as `mode` asks; `hushed` is `--quiet` or `--json`.
    pub fn new(mode: ProgressMode, hushed: bool) -> Self {
        Self {
            bar: Mutex::new(None),
            visible: mode == ProgressMode::Auto && !hushed && std::io::stderr().is_terminal(),
            lines: (mode == ProgressMode::Lines).then(|| Mutex::new(None)),
        }
    }

    /// Ends the stage reported by lines, if any.
    fn end_stage(lines: &mut Option<Stage>) {
        if let Some(s) = lines.take() {
            let secs = s.started.elapsed().as_secs_f64();
            eprintln!(
                "progress: {}: done ({}/{}, {secs:.1} s)",
                s.message, s.done, s.total
            );
        }
    }
}

impl Progress for Bar {
    fn start(&self, total: u64, message: &str) {
        if let Some(lines) = &self.lines {
            let mut lines = lines.lock().expect("progress lock");
            Self::end_stage(&mut lines);
            eprintln!("progress: {message}: started ({total} steps)");
            *lines = Some(Stage {
                message: message.to_owned(),
                total,
                done: 0,
                tenth: 0,
                started: Instant::now(),
            });
            return;
        }
        let target = if self.visible {
            ProgressDrawTarget::stderr_with_hz(10)
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(total), target);
        bar.set_style(
            ProgressStyle::with_template(
                "{msg:24} [{bar:30}] {pos}/{len} {elapsed_precise} eta {eta}",
            )
            .expect("static template")
            .progress_chars("=> "),
        );
        bar.set_message(message.to_owned());
        // Draw only once the work has taken a second.
        if self.visible {
            bar.set_draw_target(ProgressDrawTarget::hidden());
            let b = bar.clone();
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_secs(1));
                if !b.is_finished() {
                    b.set_draw_target(ProgressDrawTarget::stderr_with_hz(10));
                }
            });
        }
        if let Some(old) = self.bar.lock().expect("progress lock").replace(bar) {
            old.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(lines) = &self.lines {
            if let Some(s) = lines.lock().expect("progress lock").as_mut() {
                s.done = s.done.saturating_add(n);
                let tenth = (s.done.min(s.total) as u128 * 10 / s.total.max(1) as u128) as u64;
                if tenth > s.tenth && tenth < 10 {
                    s.tenth = tenth;
                    eprintln!(
                        "progress: {}: {} % ({}/{})",
                        s.message,
                        tenth * 10,
                        s.done,
                        s.total
                    );
                }
            }
            return;
        }
        if let Some(b) = self.bar.lock().expect("progress lock").as_ref() {
            b.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(lines) = &self.lines {
            Self::end_stage(&mut lines.lock().expect("progress lock"));
            return;
        }
        if let Some(b) = self.bar.lock().expect("progress lock").take() {
            b.finish_and_clear();
        }
    }
}

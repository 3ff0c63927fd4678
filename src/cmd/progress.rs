//! Progress of a long command: an indicatif bar on a terminal, otherwise a line on stderr at
//! most every few seconds (logs, CI), so no command runs for minutes without a sign of life.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// Seconds between plain-text lines.
const EVERY: Duration = Duration::from_secs(5);

pub struct Progress {
    label: String,
    bar: Option<indicatif::ProgressBar>,
    total: u64,
    done: u64,
    start: Instant,
    last: Instant,
}

impl Progress {
    /// `total` steps of `label` (the command's name, printed before each line).
    pub fn new(label: &str, total: u64) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(total);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} {msg:32} [{bar:40}] {pos}/{len} {elapsed_precise} (eta {eta})",
            ) {
                bar.set_style(style);
            }
            bar.set_prefix(label.to_string());
            bar.enable_steady_tick(Duration::from_millis(250));
            bar
        });
        let now = Instant::now();
        Self {
            label: label.to_string(),
            bar,
            total,
            done: 0,
            start: now,
            last: now,
        }
    }

    /// One step done, `msg` saying what.
    pub fn step(&mut self, msg: &str) {
        self.set(self.done + 1, self.total, msg);
    }

    /// `done` of `total` steps (either may change as the work discovers itself).
    pub fn set(&mut self, done: u64, total: u64, msg: &str) {
        (self.done, self.total) = (done, total);
        if let Some(bar) = &self.bar {
            bar.set_length(total);
            bar.set_position(done);
            bar.set_message(msg.to_string());
        } else if self.last.elapsed() >= EVERY {
            self.last = Instant::now();
            eprintln!(
                "{}: {done}/{total} {msg} ({:.0} s)",
                self.label,
                self.start.elapsed().as_secs_f64()
            );
        }
    }

    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

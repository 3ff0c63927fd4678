//! Progress of a long command: an indicatif bar on a terminal (its elapsed time ticks even
//! while one long step runs), otherwise a line on stderr every few seconds (logs, CI) from a
//! ticker thread, so no command runs for minutes without a sign of life, even inside a single
//! step that reports nothing (a table bake, a GPU device and its pipelines).

use std::io::IsTerminal;
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Seconds between plain-text lines.
const EVERY: Duration = Duration::from_secs(5);

/// What the plain-text ticker prints: steps done, of total, and what is under way.
#[derive(Default)]
struct State {
    done: u64,
    total: u64,
    msg: String,
}

/// The plain-text ticker: a thread that prints the state every [`EVERY`] until stopped.
struct Ticker {
    stop: Sender<()>,
    thread: Option<JoinHandle<()>>,
}

pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    state: Arc<Mutex<State>>,
    ticker: Option<Ticker>,
}

impl Progress {
    /// `total` steps of `label` (the command's name, printed before each line).
    pub fn new(label: &str, total: u64) -> Self {
        let state = Arc::new(Mutex::new(State {
            total,
            ..State::default()
        }));
        if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::new(total);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} {msg:32} [{bar:40}] {pos}/{len} {elapsed_precise} (eta {eta})",
            ) {
                bar.set_style(style);
            }
            bar.set_prefix(label.to_string());
            bar.enable_steady_tick(Duration::from_millis(250));
            return Self {
                bar: Some(bar),
                state,
                ticker: None,
            };
        }
        let ticker = Ticker::start(label.to_string(), state.clone());
        Self {
            bar: None,
            state,
            ticker: Some(ticker),
        }
    }

    /// The next step has started: `msg` says what (shown until the next call).
    pub fn begin(&mut self, msg: &str) {
        let (done, total) = self.counts();
        self.set(done, total, msg);
    }

    /// One step done, `msg` saying what.
    pub fn step(&mut self, msg: &str) {
        let (done, total) = self.counts();
        self.set(done + 1, total, msg);
    }

    /// `done` of `total` steps (either may change as the work discovers itself).
    pub fn set(&mut self, done: u64, total: u64, msg: &str) {
        if let Some(bar) = &self.bar {
            bar.set_length(total);
            bar.set_position(done);
            bar.set_message(msg.to_string());
        }
        if let Ok(mut s) = self.state.lock() {
            s.done = done;
            s.total = total;
            if s.msg != msg {
                s.msg = msg.to_string();
            }
        }
    }

    /// Runs `f`, which prints, with the bar hidden so its lines and the bar do not mix.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        match &self.bar {
            Some(bar) => bar.suspend(f),
            None => f(),
        }
    }

    fn counts(&self) -> (u64, u64) {
        self.state.lock().map_or((0, 0), |s| (s.done, s.total))
    }

    pub fn finish(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        self.ticker = None;
    }
}

impl Ticker {
    fn start(label: String, state: Arc<Mutex<State>>) -> Self {
        let (stop, stopped) = mpsc::channel::<()>();
        let start = Instant::now();
        let thread = std::thread::Builder::new()
            .name("progress".into())
            .spawn(move || {
                // Ends when told to or when the sender is dropped.
                while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(EVERY) {
                    if let Ok(s) = state.lock() {
                        eprintln!(
                            "{label}: {}/{} {} ({:.0} s)",
                            s.done,
                            s.total,
                            s.msg,
                            start.elapsed().as_secs_f64()
                        );
                    }
                }
            })
            .ok();
        Self { stop, thread }
    }
}

impl Drop for Ticker {
    fn drop(&mut self) {
        let _ = self.stop.send(());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

//! The soak's writer thread (off the render thread): appends final frames to `frames.jsonl`,
//! samples the process's memory when a second's record arrives, and rewrites the running
//! `soak.json` every few seconds. Without a directory it only samples memory.

use super::{report, write_atomic, FrameRec, SecondRec};
use dermis_engine::heap::{page_bytes, MemorySample};
use serde_json::Value;
use std::fs::File;
use std::io::Write;
use std::path::PathBuf;
use std::sync::mpsc;
use std::thread::JoinHandle;

enum Msg {
    Frames(Vec<FrameRec>),
    Second(SecondRec),
}

/// The writer thread's handle.
pub struct Writer {
    tx: mpsc::Sender<Msg>,
    thread: JoinHandle<Result<Vec<SecondRec>, String>>,
}

impl Writer {
    /// Starts the thread: `dir` gets `frames.jsonl` and a running `soak.json` (rewritten
    /// every `every_s` seconds' records) with `config`; `seconds` is the planned run length
    /// (the per-second records are preallocated for it).
    pub fn start(
        dir: Option<PathBuf>,
        config: Value,
        every_s: usize,
        seconds: f64,
    ) -> Result<Self, String> {
        let frames = match &dir {
            Some(d) => {
                let path = d.join("frames.jsonl");
                Some(File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?)
            }
            None => None,
        };
        let capacity = seconds.clamp(0.0, 86_400.0) as usize + 8;
        let (tx, rx) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("soak writer".into())
            .spawn(move || run(dir, frames, config, every_s.max(1), capacity, rx))
            .map_err(|e| format!("cannot start the soak writer: {e}"))?;
        Ok(Self { tx, thread })
    }

    /// Appends final frames (one write per batch of whole lines).
    pub fn frames(&self, batch: Vec<FrameRec>) {
        if !batch.is_empty() {
            let _ = self.tx.send(Msg::Frames(batch));
        }
    }

    /// A closed second: the thread adds the memory sample.
    pub fn second(&self, rec: SecondRec) {
        let _ = self.tx.send(Msg::Second(rec));
    }

    /// Waits for the thread; returns the per-second records with their memory.
    pub fn finish(self) -> Result<Vec<SecondRec>, String> {
        drop(self.tx);
        self.thread
            .join()
            .map_err(|_| "the soak writer thread panicked".to_string())?
    }
}

fn run(
    dir: Option<PathBuf>,
    mut frames: Option<File>,
    config: Value,
    every_s: usize,
    capacity: usize,
    rx: mpsc::Receiver<Msg>,
) -> Result<Vec<SecondRec>, String> {
    let page = page_bytes();
    let mut buf = Vec::new();
    let mut seconds = Vec::with_capacity(capacity);
    for msg in rx {
        match msg {
            Msg::Frames(batch) => {
                let Some(file) = &mut frames else { continue };
                buf.clear();
                for f in &batch {
                    serde_json::to_writer(&mut buf, f).map_err(|e| e.to_string())?;
                    buf.push(b'\n');
                }
                file.write_all(&buf)
                    .map_err(|e| format!("frames.jsonl: {e}"))?;
            }
            Msg::Second(mut s) => {
                let m = MemorySample::now(page);
                (s.rss_mb, s.rust_heap_mb, s.malloc_mb) = (m.rss_mb, m.rust_heap_mb, m.malloc_mb);
                seconds.push(s);
                if let Some(d) = &dir {
                    if seconds.len().is_multiple_of(every_s) {
                        let r = report("running", &config, &seconds, None);
                        write_atomic(&d.join("soak.json"), &r)?;
                    }
                }
            }
        }
    }
    Ok(seconds)
}

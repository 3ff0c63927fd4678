//! Running the test binaries under qemu-user on the bionic userland: a few at a time, each
//! with a timeout and its own log, and libtest's summaries parsed and summed.

use super::{tools, Options, TestBinary};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[derive(Default, Clone, Copy)]
pub(super) struct Counts {
    pub passed: u64,
    pub failed: u64,
    pub ignored: u64,
}

impl Counts {
    pub fn add(&mut self, o: &Counts) {
        self.passed += o.passed;
        self.failed += o.failed;
        self.ignored += o.ignored;
    }
}

pub(super) struct TestResult {
    pub name: String,
    pub counts: Counts,
    pub time: Duration,
    /// Why the binary failed: failed tests, a crash, a timeout, no summary.
    pub error: Option<String>,
}

/// libtest's `test result: ok. 5 passed; 0 failed; 1 ignored; ...` lines, summed.
fn parse_summary(log: &str) -> Option<Counts> {
    let mut found = None;
    for line in log.lines() {
        let Some(rest) = line.trim().strip_prefix("test result: ") else {
            continue;
        };
        let c: &mut Counts = found.get_or_insert_with(Counts::default);
        for part in rest.split(';') {
            let words: Vec<&str> = part.split_whitespace().collect();
            // "ok. 5 passed" / "FAILED. 5 passed" / "1 failed" / "0 ignored"
            let (Some(n), Some(what)) = (
                words
                    .iter()
                    .rev()
                    .nth(1)
                    .and_then(|w| w.parse::<u64>().ok()),
                words.last(),
            ) else {
                continue;
            };
            match *what {
                "passed" => c.passed += n,
                "failed" => c.failed += n,
                "ignored" => c.ignored += n,
                _ => {}
            }
        }
    }
    found
}

pub(super) fn run_tests(
    qemu: &Path,
    rootfs: &Path,
    work: &Path,
    binaries: &[TestBinary],
    opts: &Options,
) -> Result<Vec<TestResult>, String> {
    let logs = work.join("logs");
    let tmp = work.join("tmp");
    tools::mkdir(&logs)?;
    tools::mkdir(&tmp)?;
    println!(
        "\n=== running {} test binaries under {} ({} at a time)",
        binaries.len(),
        qemu.display(),
        opts.jobs
    );
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..opts.jobs.min(binaries.len()) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(b) = binaries.get(i) else { break };
                let r = run_one(qemu, rootfs, &logs, &tmp, b, opts.timeout);
                println!(
                    "  {} {} ({:.1}s): {}",
                    if r.error.is_none() { "ok  " } else { "FAIL" },
                    r.name,
                    r.time.as_secs_f64(),
                    match &r.error {
                        None => format!(
                            "{} passed, {} failed, {} ignored",
                            r.counts.passed, r.counts.failed, r.counts.ignored
                        ),
                        Some(e) => e.clone(),
                    }
                );
                results.lock().unwrap().push((i, r));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|(i, _)| *i);
    Ok(results.into_iter().map(|(_, r)| r).collect())
}

fn run_one(
    qemu: &Path,
    rootfs: &Path,
    logs: &Path,
    tmp: &Path,
    b: &TestBinary,
    timeout: Duration,
) -> TestResult {
    let t0 = Instant::now();
    let log_path = logs.join(format!("{}.log", b.name.replace('/', "_")));
    let result = |counts: Counts, error: Option<String>| TestResult {
        name: b.name.clone(),
        counts,
        time: t0.elapsed(),
        error,
    };
    let spawned = std::fs::File::create(&log_path)
        .and_then(|f| Ok((f.try_clone()?, f)))
        .and_then(|(out, err)| {
            Command::new(qemu)
                .arg("-L")
                .arg(rootfs)
                .arg(&b.exe)
                .current_dir(&b.cwd)
                // bionic's std::env::temp_dir() is /data/local/tmp unless TMPDIR is set.
                .env("TMPDIR", tmp)
                .stdin(Stdio::null())
                .stdout(out)
                .stderr(err)
                .spawn()
        });
    let mut child = match spawned {
        Ok(c) => c,
        Err(e) => return result(Counts::default(), Some(format!("cannot run: {e}"))),
    };
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(status),
            Ok(None) if t0.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!("timed out after {}s", timeout.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(200)),
            Err(e) => break Err(format!("wait: {e}")),
        }
    };
    let log = std::fs::read_to_string(&log_path).unwrap_or_default();
    let counts = parse_summary(&log);
    let error = match (&status, counts) {
        (Err(e), _) => Some(e.clone()),
        (Ok(s), Some(c)) if s.success() && c.failed == 0 => None,
        (Ok(s), Some(c)) if c.failed > 0 => Some(format!("{} failed ({s})", c.failed)),
        (Ok(s), Some(_)) => Some(format!("exited with {s}")),
        (Ok(s), None) => Some(format!("no libtest summary ({s})")),
    };
    if error.is_some() {
        let tail: Vec<&str> = log.lines().rev().take(40).collect();
        eprintln!("--- {} ({}), last lines:", b.name, log_path.display());
        for l in tail.iter().rev() {
            eprintln!("    {l}");
        }
    }
    result(counts.unwrap_or_default(), error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summaries() {
        let log = "running 7 tests\n\
            test result: FAILED. 2 passed; 1 failed; 4 ignored; 0 measured; 0 filtered out; \
            finished in 0.10s\n";
        let c = parse_summary(log).unwrap();
        assert_eq!((c.passed, c.failed, c.ignored), (2, 1, 4));
        let ok = "test result: ok. 12 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out";
        assert_eq!(parse_summary(ok).unwrap().passed, 12);
        assert!(parse_summary("running 0 tests\n").is_none());
    }
}

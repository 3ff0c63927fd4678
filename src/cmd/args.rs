//! Argument checks shared by every command: clap value parsers for numeric flags (finite, in
//! a sane range, so nothing is sized from an absurd value), a cap for preallocations sized
//! from them, and the output-path check every command runs before it starts its work.

use std::fmt::Display;
use std::path::Path;
use std::str::FromStr;

/// Longest run (`soak --seconds`), s: one day.
pub const MAX_SECONDS: f64 = 86_400.0;
/// Largest animation time (`render`/`pose --time`), s (clips are clamped to their length).
pub const MAX_TIME_S: f64 = 86_400.0;
/// Most frames any command runs (`play --frames`, the window's `--frames`).
pub const MAX_FRAMES: u64 = 10_000_000;
/// Frames per block of the benches' CPU timing, at least and at most.
pub const BENCH_FRAMES: (usize, usize) = (10, 100_000);
/// Rounds of the paired benches, at least (a confidence interval needs two) and at most.
pub const ROUNDS: (usize, usize) = (2, 1000);
/// Frame rates accepted (`play --fps`, `soak --target-fps`).
pub const FPS: (f64, f64) = (1.0, 1000.0);
/// Most elements preallocated for per-frame records; longer runs grow the vectors.
pub const PREALLOC_CAP: usize = 1 << 18;

/// `n` elements to preallocate for an expected `n` records: at most [`PREALLOC_CAP`].
pub fn prealloc(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX).min(PREALLOC_CAP)
}

/// An integer in `min..=max`; the error states the bound that was broken.
pub fn int_in<T>(s: &str, min: T, max: T) -> Result<T, String>
where
    T: FromStr + PartialOrd + Display + Copy,
{
    let t = s.trim();
    match t.parse::<T>() {
        Ok(v) if v < min => Err(format!("{t} is below the minimum of {min}")),
        Ok(v) if v > max => Err(format!("{t} is above the maximum of {max}")),
        Ok(v) => Ok(v),
        Err(_) if t.starts_with('-') => Err(format!("{t} is below the minimum of {min}")),
        Err(_) if !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit()) => {
            Err(format!("{t} is above the maximum of {max}"))
        }
        Err(_) => Err(format!("`{t}` is not a whole number in {min}..={max}")),
    }
}

/// A finite number in `[min, max]` (`(min, max]` when `open_min`), with `unit` for messages.
pub fn float_in(s: &str, min: f64, open_min: bool, max: f64, unit: &str) -> Result<f64, String> {
    let t = s.trim();
    let v: f64 = t
        .parse()
        .map_err(|_| format!("`{t}` is not a number of {unit}"))?;
    let range = if open_min {
        format!("greater than {min} and at most {max}")
    } else {
        format!("between {min} and {max}")
    };
    if !v.is_finite() {
        return Err(format!("{t} is not a finite number of {unit} ({range})"));
    }
    if v < min || (open_min && v == min) || v > max {
        return Err(format!("{t} {unit} is out of range ({range})"));
    }
    Ok(v)
}

/// Wall-clock duration of a run: finite, > 0, at most [`MAX_SECONDS`].
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    float_in(s, 0.0, true, MAX_SECONDS, "seconds")
}

/// A time in an animation clip: finite, ≥ 0, at most [`MAX_TIME_S`].
pub fn parse_time(s: &str) -> Result<f32, String> {
    float_in(s, 0.0, false, MAX_TIME_S, "seconds").map(|t| t as f32)
}

/// A frame rate in [`FPS`].
pub fn parse_fps(s: &str) -> Result<f64, String> {
    float_in(s, FPS.0, false, FPS.1, "frames per second")
}

/// A number of frames to run: 1..=[`MAX_FRAMES`].
pub fn parse_frames(s: &str) -> Result<u64, String> {
    int_in(s, 1, MAX_FRAMES)
}

/// `dermis play --frames`: the warm-up frames plus at least one measured frame.
pub fn parse_play_frames(s: &str) -> Result<u64, String> {
    let min = crate::cmd::play::WARM_UP + 1;
    int_in(s, min, MAX_FRAMES).map_err(|e| {
        format!(
            "{e} ({} warm-up frames plus at least one measured frame)",
            crate::cmd::play::WARM_UP
        )
    })
}

/// Frames per block of a bench's CPU timing, in [`BENCH_FRAMES`].
pub fn parse_bench_frames(s: &str) -> Result<usize, String> {
    int_in(s, BENCH_FRAMES.0, BENCH_FRAMES.1)
}

/// Rounds of a paired bench, in [`ROUNDS`].
pub fn parse_rounds(s: &str) -> Result<usize, String> {
    int_in(s, ROUNDS.0, ROUNDS.1)
}

/// `--shading` help: `what`, then every model name from the registry.
pub fn shading_help(what: &str) -> String {
    format!(
        "{what} (one of: {})",
        dermis_core::shading::ShadingModel::names()
    )
}

/// Checks, before any work, that `path` can be written: not a directory, its parent exists
/// (created when missing) and is writable, and when `ext` is given, the name ends in `.ext`.
pub fn check_out_file(path: &Path, ext: Option<&str>) -> Result<(), String> {
    let shown = path.display();
    if let Some(ext) = ext {
        let ok = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case(ext));
        if !ok {
            return Err(format!("{shown}: use .{ext} (the only format written)"));
        }
    }
    if path.is_dir() {
        return Err(format!("{shown}: is a directory"));
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    check_out_dir(parent).map_err(|e| format!("{shown}: {e}"))?;
    if path.exists() {
        std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| format!("{shown}: cannot write: {e}"))?;
    }
    Ok(())
}

/// Checks, before any work, that `dir` is (or can be created as) a writable directory.
pub fn check_out_dir(dir: &Path) -> Result<(), String> {
    let shown = dir.display();
    if dir.exists() && !dir.is_dir() {
        return Err(format!("{shown}: not a directory"));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {shown}: {e}"))?;
    let probe = dir.join(format!(".dermis-write-check-{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| format!("{shown}: not writable: {e}"))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(parse_seconds("2.5"), Ok(2.5));
        for bad in ["0", "-1", "nan", "NaN", "inf", "1e12", "x", ""] {
            assert!(parse_seconds(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_time("0"), Ok(0.0));
        for bad in ["-1", "NaN", "inf", "-inf", "1e9"] {
            assert!(parse_time(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_frames("1"), Ok(1));
        let e = parse_frames("0").unwrap_err();
        assert!(e.contains("minimum of 1"), "{e}");
        let e = parse_frames("100000000000").unwrap_err();
        assert!(e.contains("maximum"), "{e}");
        let e = parse_frames("99999999999999999999999").unwrap_err();
        assert!(e.contains("maximum"), "{e}");
        let e = parse_rounds("-3").unwrap_err();
        assert!(e.contains("minimum of 2"), "{e}");
        assert_eq!(prealloc(u64::MAX), PREALLOC_CAP);
        assert_eq!(prealloc(7), 7);
    }
}

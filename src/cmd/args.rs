//! Argument checks shared by every command: the clap value parsers of every numeric flag
//! (finite, in a sane range, so nothing is sized from an absurd value; negative values reach
//! them because every numeric flag is declared with `allow_hyphen_values`, so `--g -0.5` is a
//! value and `--seed -1` gets the range message, not clap's "unexpected argument"), a cap for
//! preallocations sized from them, and the output-path checks every command runs before it
//! starts its work.

use std::path::Path;

use glam::Vec3;

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
/// Image sides accepted (`--size WxH`), pixels.
pub const SIDE: (u64, u64) = (1, 8192);
/// Largest light coordinate (`render --light`), m.
pub const MAX_COORD_M: f64 = 1e4;
/// Largest clip or vertex index (the model decides what exists).
pub const MAX_INDEX: u64 = u32::MAX as u64;
/// Photons per channel and geometry (`sss --photons`).
pub const SSS_PHOTONS: (u64, u64) = (1000, 100_000_000);
/// Photons per channel and scene (`reference --photons`).
pub const REFERENCE_PHOTONS: (u64, u64) = (1000, 1_000_000_000);
/// Worker threads (`reference --threads`).
pub const THREADS: (u64, u64) = (1, 1024);
/// Relative index of refraction (`--eta`).
pub const ETA: (f64, f64) = (1.0, 3.0);
/// Henyey–Greenstein anisotropy (`--g`).
pub const G: (f64, f64) = (-0.99, 0.99);
/// Point-light heights (`profile --light-height-mm`), mm.
pub const LIGHT_HEIGHT_MM: (f64, f64) = (0.01, 1000.0);
/// Largest annulus edge (`profile --edges-mm`), mm.
pub const MAX_RADIUS_MM: f64 = 5000.0;
/// Window surfaces of the `surfaces` self-test.
pub const SURFACES: (u64, u64) = (1, 1000);
/// Most elements preallocated for per-frame records; longer runs grow the vectors.
pub const PREALLOC_CAP: usize = 1 << 18;

/// `n` elements to preallocate for an expected `n` records: at most [`PREALLOC_CAP`].
pub fn prealloc(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX).min(PREALLOC_CAP)
}

/// A whole number in `min..=max`; the error states the bound that was broken. Written as
/// digits or as a number with an exponent (`1e6`); a negative value, NaN, an infinity, a
/// fraction or a word gets its own message, never the standard library's "invalid digit".
pub fn int_in<T: TryFrom<u64>>(s: &str, min: u64, max: u64) -> Result<T, String> {
    let t = s.trim();
    let below = || format!("{t} is below the minimum of {min}");
    let above = || format!("{t} is above the maximum of {max}");
    let v = match t.parse::<u64>() {
        Ok(v) => v,
        Err(_) => match t.parse::<f64>() {
            Ok(f) if f.is_nan() => {
                return Err(format!("{t} is not a whole number in {min}..={max}"))
            }
            Ok(f) if f < min as f64 => return Err(below()),
            Ok(f) if f > max as f64 => return Err(above()),
            Ok(f) if f.fract() == 0.0 => f as u64,
            Ok(_) => return Err(format!("{t} is not a whole number in {min}..={max}")),
            // Digits beyond what f64 parses do not exist; a sign and digits do.
            Err(_) => return Err(format!("`{t}` is not a whole number in {min}..={max}")),
        },
    };
    if v < min {
        return Err(below());
    }
    if v > max {
        return Err(above());
    }
    T::try_from(v).map_err(|_| above())
}

/// A finite number in `[min, max]` (`(min, max]` when `open_min`); `unit` (may be empty)
/// follows the number in messages.
pub fn float_in(s: &str, min: f64, open_min: bool, max: f64, unit: &str) -> Result<f64, String> {
    let t = s.trim();
    let of = if unit.is_empty() {
        String::new()
    } else {
        format!(" of {unit}")
    };
    let range = if open_min {
        format!("greater than {min} and at most {max}")
    } else {
        format!("between {min} and {max}")
    };
    let v: f64 = t
        .parse()
        .map_err(|_| format!("`{t}` is not a number{of} ({range})"))?;
    if !v.is_finite() {
        return Err(format!("{t} is not a finite number{of} ({range})"));
    }
    let spaced = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    if v < min || (open_min && v == min) || v > max {
        return Err(format!("{t}{spaced} is out of range ({range})"));
    }
    Ok(v)
}

/// A seed: any whole number from 0 to 2⁶⁴ − 1.
pub fn parse_seed(s: &str) -> Result<u64, String> {
    int_in(s, 0, u64::MAX)
}

/// `bench tables --materials`: 1 to 1000.
pub fn parse_material_count(s: &str) -> Result<usize, String> {
    int_in(s, 1, 1000)
}

/// A clip or vertex index, 0..=[`MAX_INDEX`] (the model says which exist).
pub fn parse_index(s: &str) -> Result<usize, String> {
    int_in(s, 0, MAX_INDEX)
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
    int_in(s, BENCH_FRAMES.0 as u64, BENCH_FRAMES.1 as u64)
}

/// Rounds of a paired bench, in [`ROUNDS`].
pub fn parse_rounds(s: &str) -> Result<usize, String> {
    int_in(s, ROUNDS.0 as u64, ROUNDS.1 as u64)
}

/// `sss --photons`, in [`SSS_PHOTONS`].
pub fn parse_sss_photons(s: &str) -> Result<u64, String> {
    int_in(s, SSS_PHOTONS.0, SSS_PHOTONS.1)
}

/// `reference --photons`, in [`REFERENCE_PHOTONS`].
pub fn parse_reference_photons(s: &str) -> Result<u64, String> {
    int_in(s, REFERENCE_PHOTONS.0, REFERENCE_PHOTONS.1)
}

/// Worker threads, in [`THREADS`].
pub fn parse_threads(s: &str) -> Result<usize, String> {
    int_in(s, THREADS.0, THREADS.1)
}

/// `surfaces --count`, in [`SURFACES`].
pub fn parse_surfaces(s: &str) -> Result<u32, String> {
    int_in(s, SURFACES.0, SURFACES.1)
}

/// A relative index of refraction, in [`ETA`].
pub fn parse_eta(s: &str) -> Result<f64, String> {
    float_in(s, ETA.0, false, ETA.1, "")
}

/// A Henyey–Greenstein anisotropy, in [`G`] (negative: back-scattering).
pub fn parse_g(s: &str) -> Result<f64, String> {
    float_in(s, G.0, false, G.1, "")
}

/// A point light's height above the surface, in [`LIGHT_HEIGHT_MM`].
pub fn parse_light_height_mm(s: &str) -> Result<f64, String> {
    float_in(s, LIGHT_HEIGHT_MM.0, false, LIGHT_HEIGHT_MM.1, "mm")
}

/// One annulus edge, 0..=[`MAX_RADIUS_MM`] (the list's order is checked by `profile`).
pub fn parse_edge_mm(s: &str) -> Result<f64, String> {
    float_in(s, 0.0, false, MAX_RADIUS_MM, "mm")
}

/// An image size `WxH`, each side in [`SIDE`].
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size `{s}` is not WxH"))?;
    let side = |name: &str, v: &str| {
        int_in::<u32>(v, SIDE.0, SIDE.1).map_err(|e| format!("{name} in `{s}`: {e}"))
    };
    Ok((side("width", w)?, side("height", h)?))
}

/// A position `X,Y,Z` in metres, each coordinate finite and within ±[`MAX_COORD_M`]
/// (negative coordinates are positions like any other).
pub fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = s.split(',').collect();
    let [x, y, z] = parts[..] else {
        return Err(format!("`{s}` is not X,Y,Z"));
    };
    let c = |v: &str| {
        float_in(v, -MAX_COORD_M, false, MAX_COORD_M, "m")
            .map(|v| v as f32)
            .map_err(|e| format!("in `{s}`: {e}"))
    };
    Ok(Vec3::new(c(x)?, c(y)?, c(z)?))
}

/// `--shading` help: `what`, then every model name from the registry.
pub fn shading_help(what: &str) -> String {
    format!(
        "{what} (one of: {})",
        dermis_engine::shading::ShadingModel::names()
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

/// A shading model by its registry name.
pub fn parse_model(s: &str) -> Result<dermis_engine::shading::ShadingModel, String> {
    s.parse()
}

/// A material preset by name.
pub fn parse_material(s: &str) -> Result<dermis_engine::shading::Material, String> {
    use dermis_engine::shading::material::PRESETS;
    dermis_engine::shading::Material::preset(s).ok_or_else(|| {
        let known: Vec<&str> = PRESETS.iter().map(|m| &*m.name).collect();
        format!("unknown material `{s}` (known: {})", known.join(", "))
    })
}

/// `--skin`: `MATERIAL[=PRESET],…` or `none` (the material names are checked against the
/// character once it is read).
pub fn parse_skin(s: &str) -> Result<dermis_engine::asset::skin::SkinChoice, String> {
    s.parse()
}

/// A clip named on the command line: a clip's name, or `#N` for its index.
pub fn parse_clip(s: &str) -> Result<String, String> {
    let s = s.trim();
    if s.is_empty() {
        return Err("an empty clip name (a clip's name, or #N for its index)".into());
    }
    Ok(s.to_string())
}

/// What the game takes about a user's character besides its file: which of its materials
/// are skin and which clips the runner plays.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CharacterArgs {
    /// Which of the character's materials are skin: MATERIAL[=PRESET],… (a material by name or
    /// #N; PRESET skin1 or white-coat) or `none`; default: what its file declares
    /// (KHR_materials_volume_scatter), else materials named like skin. The game keeps it in
    /// its settings for that file.
    #[arg(long, value_parser = parse_skin)]
    pub skin: Option<dermis_engine::asset::skin::SkinChoice>,
    /// The character's idle clip (its name or #N), over the search by name.
    #[arg(long, value_parser = parse_clip)]
    pub idle_clip: Option<String>,
    /// Its run clip.
    #[arg(long, value_parser = parse_clip)]
    pub run_clip: Option<String>,
    /// Its jump clip.
    #[arg(long, value_parser = parse_clip)]
    pub jump_clip: Option<String>,
    /// Its death clip (the game-over screen).
    #[arg(long, value_parser = parse_clip)]
    pub death_clip: Option<String>,
}

impl CharacterArgs {
    /// The clips named, by role.
    pub fn clips(&self) -> Vec<(dermis_engine::anim::ClipRole, String)> {
        use dermis_engine::anim::ClipRole as R;
        [
            (R::Idle, &self.idle_clip),
            (R::Run, &self.run_clip),
            (R::Jump, &self.jump_clip),
            (R::Death, &self.death_clip),
        ]
        .into_iter()
        .filter_map(|(r, n)| n.clone().map(|n| (r, n)))
        .collect()
    }
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

    #[test]
    fn whole_numbers_in_every_spelling() {
        assert_eq!(parse_sss_photons("1e6"), Ok(1_000_000));
        assert_eq!(parse_seed("0"), Ok(0));
        assert_eq!(parse_seed("18446744073709551615"), Ok(u64::MAX));
        for (bad, needle) in [
            ("-1", "below the minimum of 0"),
            ("-inf", "below the minimum of 0"),
            ("inf", "above the maximum"),
            ("1e30", "above the maximum"),
            ("99999999999999999999999", "above the maximum"),
            ("NaN", "not a whole number"),
            ("2.5", "not a whole number"),
            ("many", "`many` is not a whole number"),
            ("", "not a whole number"),
        ] {
            let e = parse_seed(bad).unwrap_err();
            assert!(e.contains(needle), "{bad}: {e}");
        }
        let e = parse_sss_photons("1e12").unwrap_err();
        assert!(e.contains("above the maximum of 100000000"), "{e}");
        let e = parse_threads("-1").unwrap_err();
        assert!(e.contains("minimum of 1"), "{e}");
    }

    /// A missing parent is made (the command then writes there); one that cannot be made, a
    /// file in the way, a directory as the file or the wrong extension is refused.
    #[test]
    fn output_places() {
        let dir = std::env::temp_dir().join(format!("dermis-args-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let nested = dir.join("a/b/x.png");
        check_out_file(&nested, Some("png")).unwrap();
        assert!(dir.join("a/b").is_dir());
        assert!(
            !nested.exists(),
            "the check writes nothing but its probe, removed"
        );
        std::fs::write(dir.join("f"), b"").unwrap();
        for (path, needle) in [
            (dir.join("f/x.png"), "f"),
            (dir.join("a"), "use .png"),
            (dir.join("x.jpg"), "use .png"),
        ] {
            let e = check_out_file(&path, Some("png")).unwrap_err();
            assert!(e.contains(needle), "{}: {e}", path.display());
        }
        assert!(check_out_file(&dir.join("a"), None)
            .unwrap_err()
            .contains("is a directory"));
        assert!(check_out_dir(&dir.join("f"))
            .unwrap_err()
            .contains("not a directory"));
        assert!(check_out_dir(Path::new("/proc/dermis-no")).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn negatives_valid_where_they_mean_something() {
        assert_eq!(parse_g("-0.5"), Ok(-0.5));
        assert!(parse_g("-1").unwrap_err().contains("out of range"));
        assert_eq!(parse_vec3("-0.5,2,1"), Ok(Vec3::new(-0.5, 2.0, 1.0)));
        for bad in ["-1e5,2,1", "nan,0,0", "inf,0,0", "1,2", "x,y,z"] {
            assert!(parse_vec3(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_size("640x360"), Ok((640, 360)));
        let e = parse_size("-1x10").unwrap_err();
        assert!(e.contains("width") && e.contains("minimum of 1"), "{e}");
        assert!(parse_size("10x99999").unwrap_err().contains("maximum"));
        assert!(parse_eta("-1.4").is_err());
        assert!(parse_edge_mm("-1").is_err());
    }
}

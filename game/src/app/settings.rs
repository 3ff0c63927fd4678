//! Persistent settings: the chosen shading model, the best score, the play camera (the
//! follow camera or its close-up) and, per character file, which of its materials are skin
//! (`--skin`), as a tiny `key=value` text file written atomically (temp file + rename).

use std::path::Path;

use dermis_engine::asset::skin::SkinChoice;
use dermis_engine::shading::ShadingModel;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// The chosen model (its registry name only in the file).
    pub shading: ShadingModel,
    pub best: u32,
    /// Play with the close-up camera (the runner large, its skin in view) rather than the
    /// wide follow camera.
    pub close_camera: bool,
    /// The user's choice of skin materials per character file (its file name), as given
    /// (`MATERIAL[=preset],…` or `none`): `skin.FILE=CHOICE` in the file.
    pub skins: Vec<(String, String)>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            shading: ShadingModel::DEFAULT,
            best: 0,
            close_camera: false,
            skins: Vec::new(),
        }
    }
}

impl Settings {
    /// The chosen model ([`ShadingModel::DEFAULT`] until one is chosen or read).
    pub fn shading_model(&self) -> ShadingModel {
        self.shading
    }

    pub fn set_shading_model(&mut self, model: ShadingModel) {
        self.shading = model;
    }

    /// The skin choice kept for character file `file` (its file name).
    pub fn skin_for(&self, file: &str) -> Option<&str> {
        self.skins
            .iter()
            .find(|(f, _)| f == file)
            .map(|(_, c)| c.as_str())
    }

    /// Keeps `choice` for character file `file`.
    pub fn set_skin(&mut self, file: &str, choice: &str) {
        self.skins.retain(|(f, _)| f != file);
        self.skins.push((file.to_string(), choice.to_string()));
    }

    pub fn to_text(&self) -> String {
        let mut out = format!(
            "# dermis settings\nshading={}\nbest={}\ncamera={}\n",
            self.shading.name(),
            self.best,
            if self.close_camera { "close" } else { "follow" }
        );
        for (file, choice) in &self.skins {
            out.push_str(&format!("skin.{file}={choice}\n"));
        }
        out
    }

    /// Parses `to_text` output. Never fails: unknown keys, malformed lines, unknown model
    /// names and out-of-range numbers are ignored (the defaults stay).
    pub fn from_text(text: &str) -> Self {
        Self::parse(text).0
    }

    /// Parses `to_text` output like [`Settings::from_text`], and also says what was dropped:
    /// one `line N: …` message per ignored line (blank lines and `#` comments are not).
    pub fn parse(text: &str) -> (Self, Vec<String>) {
        let mut s = Self::default();
        let mut dropped = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let n = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let shown: String = line.chars().take(60).collect();
            let Some((key, value)) = line.split_once('=') else {
                dropped.push(format!("line {n}: `{shown}` ignored (not key=value)"));
                continue;
            };
            let value = value.trim();
            match key.trim() {
                "shading" => match ShadingModel::from_name(value) {
                    Some(m) => s.set_shading_model(m),
                    None => dropped.push(format!(
                        "line {n}: `{shown}` ignored (unknown shading model; known: {})",
                        ShadingModel::names()
                    )),
                },
                "best" => match value.parse::<u32>() {
                    Ok(b) => s.best = b,
                    Err(_) => dropped.push(format!(
                        "line {n}: `{shown}` ignored (best must be a whole number in 0..={})",
                        u32::MAX
                    )),
                },
                "camera" => match value {
                    "close" => s.close_camera = true,
                    "follow" => s.close_camera = false,
                    _ => dropped.push(format!(
                        "line {n}: `{shown}` ignored (camera is `follow` or `close`)"
                    )),
                },
                key if key.starts_with("skin.") && key.len() > 5 => {
                    match value.parse::<SkinChoice>() {
                        Ok(_) => s.set_skin(&key[5..], value),
                        Err(e) => dropped.push(format!("line {n}: `{shown}` ignored ({e})")),
                    }
                }
                _ => dropped.push(format!("line {n}: `{shown}` ignored (unknown key)")),
            }
        }
        (s, dropped)
    }

    /// Reads `path`; a missing or unreadable file gives the defaults. Each ignored line is
    /// logged as a warning naming the file and the line.
    pub fn load(path: &Path) -> Self {
        match std::fs::read(path) {
            Ok(bytes) => {
                let (s, dropped) = Self::parse(&String::from_utf8_lossy(&bytes));
                for d in dropped {
                    log::warn!("settings {}: {d}", path.display());
                }
                s
            }
            Err(_) => Self::default(),
        }
    }

    /// Writes `path` atomically: a temp file next to it, then a rename over it.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = std::path::PathBuf::from(tmp);
        {
            use std::io::Write;
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(self.to_text().as_bytes())?;
            f.sync_all()?;
        }
        std::fs::rename(&tmp, path).inspect_err(|_| {
            let _ = std::fs::remove_file(&tmp);
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_reports_what_it_drops() {
        let (s, dropped) = Settings::parse(
            "# c\n\nshading=bogus\nbest=-5\nbest=7\njunk\nextra=1\nshading=oss\ncamera=close\ncamera=up",
        );
        assert_eq!(
            (s.best, s.shading, s.close_camera),
            (7, ShadingModel::Oss, true)
        );
        assert_eq!(dropped.len(), 5, "{dropped:?}");
        assert!(
            dropped[4].starts_with("line 10: `camera=up`"),
            "{dropped:?}"
        );
        assert!(
            dropped[0].starts_with("line 3: `shading=bogus`"),
            "{dropped:?}"
        );
        assert!(dropped[1].starts_with("line 4: `best=-5`"), "{dropped:?}");
        assert!(dropped[2].starts_with("line 6: `junk`"), "{dropped:?}");
        assert!(dropped[3].contains("unknown key"), "{dropped:?}");
        assert!(Settings::parse(&Settings::default().to_text()).1.is_empty());
    }
}

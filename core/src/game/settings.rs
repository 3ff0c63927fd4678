//! Persistent settings: the chosen shading model and the best score, as a tiny `key=value`
//! text file written atomically (temp file + rename).

use std::path::Path;

use crate::shading::ShadingModel;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// A [`ShadingModel`] registry name.
    pub shading: String,
    pub best: u32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            shading: ShadingModel::ALL[0].name().to_string(),
            best: 0,
        }
    }
}

impl Settings {
    /// The chosen model (the default if the stored name is unknown).
    pub fn shading_model(&self) -> ShadingModel {
        ShadingModel::from_name(&self.shading).unwrap_or(ShadingModel::ALL[0])
    }

    pub fn set_shading_model(&mut self, model: ShadingModel) {
        self.shading.clear();
        self.shading.push_str(model.name());
    }

    pub fn to_text(&self) -> String {
        format!(
            "# dermis settings\nshading={}\nbest={}\n",
            self.shading, self.best
        )
    }

    /// Parses `to_text` output. Never fails: unknown keys, malformed lines, unknown model
    /// names and out-of-range numbers are ignored (the defaults stay).
    pub fn from_text(text: &str) -> Self {
        let mut s = Self::default();
        for line in text.lines() {
            let line = line.trim();
            if line.starts_with('#') {
                continue;
            }
            let Some((key, value)) = line.split_once('=') else {
                continue;
            };
            match key.trim() {
                "shading" => {
                    if let Some(m) = ShadingModel::from_name(value.trim()) {
                        s.set_shading_model(m);
                    }
                }
                "best" => {
                    if let Ok(b) = value.trim().parse::<u32>() {
                        s.best = b;
                    }
                }
                _ => {}
            }
        }
        s
    }

    /// Reads `path`; a missing or unreadable file gives the defaults.
    pub fn load(path: &Path) -> Self {
        match std::fs::read(path) {
            Ok(bytes) => Self::from_text(&String::from_utf8_lossy(&bytes)),
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

//! The game's start-up that needs no GPU, on its own thread while the shell creates the
//! window and the device: the character and the props, then the session (settings file,
//! game, pose); the showroom's scanned head decodes after them on the same thread and
//! arrives with the first frames (`GameGpu` waits for it before the second).

use std::path::PathBuf;
use std::sync::mpsc;

use super::{Session, Settings};
use dermis_engine::anim::{find_clips, ClipRole};
use dermis_engine::asset::skin::SkinChoice;
use dermis_engine::scene::{HeadLoad, SceneAssets};
use dermis_engine::shading::ShadingModel;

/// What the game loads and how its session starts.
#[derive(Clone, Debug)]
pub struct GameSetup {
    pub assets_dir: PathBuf,
    /// Another character file instead of the assets' own.
    pub character: Option<PathBuf>,
    pub seed: u64,
    /// The settings file the session reads and writes (`None`: the defaults, saved nowhere).
    pub settings: Option<PathBuf>,
    pub autoplay: bool,
    /// A shading model chosen on the command line, over the saved one.
    pub shading: Option<ShadingModel>,
    /// Whether to load the showroom's scanned head.
    pub head: bool,
    /// Which of the character's materials are skin (`--skin`), over the choice saved for its
    /// file (which this one replaces).
    pub skin: Option<SkinChoice>,
    /// Clips named on the command line (`--idle-clip` …), over the search by name.
    pub clips: Vec<(ClipRole, String)>,
}

impl GameSetup {
    /// The game's defaults for `assets_dir`: its own character, seed 1, no settings file,
    /// the head.
    pub fn new(assets_dir: PathBuf) -> Self {
        Self {
            assets_dir,
            character: None,
            seed: 1,
            settings: None,
            autoplay: false,
            shading: None,
            head: true,
            skin: None,
            clips: Vec::new(),
        }
    }
}

/// The assets and the session, as the loader thread made them.
pub type Loaded = (SceneAssets, Session);

/// The game's loader thread.
pub struct GameLoad {
    done: mpsc::Receiver<Result<Loaded, String>>,
}

impl GameLoad {
    /// Starts loading on a thread of its own.
    pub fn start(setup: GameSetup) -> Self {
        let (tx, done) = mpsc::channel();
        let spawned = std::thread::Builder::new()
            .name("dermis-load".into())
            .spawn({
                let tx = tx.clone();
                move || load(setup, &tx)
            });
        if let Err(e) = spawned {
            let _ = tx.send(Err(format!("cannot start the loader thread: {e}")));
        }
        Self { done }
    }

    /// Waits for the assets and the session (not for the head).
    pub fn wait(self) -> Result<Loaded, String> {
        self.done
            .recv()
            .unwrap_or_else(|_| Err("the loader thread stopped".into()))
    }
}

fn load(setup: GameSetup, tx: &mpsc::Sender<Result<Loaded, String>>) {
    let loaded = setup.load();
    let failed = loaded.is_err();
    let head = loaded.as_ref().map(|(a, _)| a.head.clone()).ok();
    let _ = tx.send(loaded);
    if let (false, Some(head)) = (failed, head) {
        head.finish(&setup.assets_dir);
    }
}

impl GameSetup {
    /// Loads the assets (the character's skin as the user chose or its file says, its clips
    /// found by name) and makes the session, on this thread (the head is left to
    /// [`HeadLoad::finish`]); one line naming what is wrong otherwise.
    pub fn load(&self) -> Result<Loaded, String> {
        prepare(self)
    }
}

fn prepare(setup: &GameSetup) -> Result<Loaded, String> {
    let default = setup.assets_dir.join(SceneAssets::CHARACTER);
    let file = setup.character.as_deref().unwrap_or(&default);
    let key = file
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    // The choice given now, else the one kept for this file (a kept one that no longer fits
    // the file is dropped with a warning).
    let kept = setup
        .settings
        .as_deref()
        .map(Settings::load)
        .unwrap_or_default();
    let kept = kept
        .skin_for(&key)
        .and_then(|c| c.parse::<SkinChoice>().ok());
    let given = setup.skin.is_some();
    let choice = setup.skin.clone().or(kept);
    let assets = match SceneAssets::load_chosen(
        &setup.assets_dir,
        setup.character.as_deref(),
        choice.as_ref(),
    ) {
        Err(e) if !given && choice.is_some() => {
            log::warn!("{key}: the skin choice kept in the settings no longer fits: {e}");
            SceneAssets::load(&setup.assets_dir, setup.character.as_deref())
        }
        other => other,
    }
    .map_err(|e| e.to_string())?;
    let overrides: Vec<(ClipRole, &str)> =
        setup.clips.iter().map(|(r, n)| (*r, n.as_str())).collect();
    let clips = find_clips(&assets.character, &overrides, &[ClipRole::Run])?;
    let head = if setup.head {
        HeadLoad::pending()
    } else {
        HeadLoad::default()
    };
    let assets = SceneAssets { head, ..assets };
    let mut session = Session::new(
        &assets.character,
        setup.seed,
        setup.settings.clone(),
        setup.autoplay,
    );
    session.clips = clips;
    if let Some(m) = setup.shading {
        session.settings.set_shading_model(m);
    }
    if let (Some(choice), true) = (&setup.skin, given) {
        session.settings.set_skin(&key, &choice.to_string());
        session.save_settings();
    }
    Ok((assets, session))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(dir: PathBuf) -> GameSetup {
        GameSetup::new(dir)
    }

    #[test]
    fn the_session_arrives_first_and_the_head_after_it() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
        let (assets, session) = GameLoad::start(GameSetup {
            shading: Some(ShadingModel::BASELINE),
            ..setup(dir)
        })
        .wait()
        .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(session.shading(), ShadingModel::BASELINE);
        assert!(assets.head.expected());
        let head = assets.head.wait().expect("the head loads");
        assert!(head.meshes.iter().any(|m| !m.primitives.is_empty()));
        assert!(assets.props.len() == dermis_engine::scene::PropKind::ALL.len());
    }

    #[test]
    fn a_missing_assets_folder_is_one_error_and_no_head_is_waited_for() {
        let dir = std::env::temp_dir().join(format!("dermis-no-assets-{}", std::process::id()));
        let err = GameLoad::start(setup(dir)).wait().err();
        assert!(
            err.as_ref().is_some_and(|e| e.contains("character.glb")),
            "{err:?}"
        );
    }
}

//! The game's start-up that needs no GPU, on its own thread while the shell creates the
//! window and the device: the character and the props, then the session (settings file,
//! game, pose); the showroom's scanned head decodes after them on the same thread and
//! arrives with the first frames (`GameGpu` waits for it before the second).

use std::path::PathBuf;
use std::sync::mpsc;

use super::Session;
use crate::scene::{HeadLoad, SceneAssets};
use crate::shading::ShadingModel;

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
    let assets = match SceneAssets::load(&setup.assets_dir, setup.character.as_deref()) {
        Ok(assets) => assets,
        Err(e) => {
            let _ = tx.send(Err(e.to_string()));
            return;
        }
    };
    let head = if setup.head {
        HeadLoad::pending()
    } else {
        HeadLoad::default()
    };
    let assets = SceneAssets {
        head: head.clone(),
        ..assets
    };
    let mut session = Session::new(
        &assets.character,
        setup.seed,
        setup.settings,
        setup.autoplay,
    );
    if let Some(m) = setup.shading {
        session.settings.set_shading_model(m);
    }
    let _ = tx.send(Ok((assets, session)));
    head.finish(&setup.assets_dir);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(dir: PathBuf) -> GameSetup {
        GameSetup {
            assets_dir: dir,
            character: None,
            seed: 1,
            settings: None,
            autoplay: false,
            shading: None,
            head: true,
        }
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
        assert!(assets.props.len() == crate::scene::PropKind::ALL.len());
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

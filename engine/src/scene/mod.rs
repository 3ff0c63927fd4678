//! What is loaded and where it stands: the character, the props, the light, the stage, one
//! frame as plain data, and helpers to frame the character for a camera. Nothing here holds a
//! GPU object: the game, the governor and the stills describe scenes with these types and the
//! renderer draws them.

pub mod face;
mod frame;
mod light;
mod props;
mod roles;
mod stage;

pub use frame::{DrawSet, FramePacket, FrameView, SubjectId, SubjectPose};
pub use light::Light;
pub use props::{PropInstance, PropKind};
pub use roles::{Role, Roles};
pub use stage::{key_light, CharacterBound, CHARACTER, EXPOSURE, KEY_LIGHT_OFFSET};

use std::path::Path;
use std::sync::{Arc, OnceLock};

use glam::{Mat4, Quat, Vec3};

use crate::anim::{first_skinned_mesh, skin_positions, Pose};
use crate::asset::skin::SkinChoice;
use crate::asset::{load_gltf, load_gltf_slice, AssetError, Model};

/// Everything the demo and the game load at start (nothing is read from disk later).
pub struct SceneAssets {
    pub character: Model,
    /// How the character's materials are drawn (which are skin: `asset::skin::classify`).
    pub roles: Roles,
    pub props: Vec<(PropKind, Model)>,
    /// The scanned head for the game's showroom (`face::head`), where the shell asked for it
    /// ([`SceneAssets::with_head`], or the game's loader thread); the APK does not carry it.
    pub head: HeadLoad,
}

/// The showroom's scanned head as it loads: not asked for, still decoding (on the game's
/// loader thread, after the character and the props), or done — the head, or nothing where
/// it is missing or bad (one logged line). Clones share one load.
#[derive(Clone, Default)]
pub struct HeadLoad(Option<Arc<OnceLock<Option<Model>>>>);

impl HeadLoad {
    /// A load whose result [`HeadLoad::finish`] will bring.
    pub fn pending() -> Self {
        Self(Some(Arc::new(OnceLock::new())))
    }

    /// Loads the head from `assets_dir/head/` now.
    pub fn load(assets_dir: &Path) -> Self {
        let load = Self::pending();
        load.finish(assets_dir);
        load
    }

    /// Decodes the head (albedo and normal map) into this load; a missing or bad head is
    /// logged and leaves none. A load not asked for, or done already, is left as it is.
    pub fn finish(&self, assets_dir: &Path) {
        self.finish_with(&crate::asset::dir_reader(assets_dir));
    }

    /// [`HeadLoad::finish`] reading the files through `read` (paths relative to the assets
    /// root: the Android app's asset manager).
    pub fn finish_with(&self, read: &dyn Fn(&str) -> Result<Vec<u8>, String>) {
        let Some(cell) = &self.0 else { return };
        if cell.get().is_some() {
            return;
        }
        let maps = crate::asset::head::Maps {
            albedo: true,
            normal: true,
        };
        let head = match crate::asset::head::load_from(read, maps) {
            Ok(head) => Some(head),
            Err(e) => {
                log::warn!("no scanned head in the showroom: {e}");
                None
            }
        };
        let _ = cell.set(head);
    }

    /// The head, waiting for a load in progress; `None`: not asked for, missing or bad.
    pub fn wait(&self) -> Option<&Model> {
        self.0.as_ref()?.wait().as_ref()
    }

    /// Whether a head may still be shown: asked for, and loading or loaded.
    pub fn expected(&self) -> bool {
        self.0
            .as_ref()
            .is_some_and(|cell| cell.get().is_none_or(|head| head.is_some()))
    }
}

impl SceneAssets {
    /// The character's file, relative to the assets root.
    pub const CHARACTER: &'static str = "character.glb";

    /// Loads `character` (or `assets/character.glb`) and every prop in `assets/props/` from
    /// the file system (with the loader's size and file-type checks); the character's skin
    /// as its file says (`asset::skin`, logged).
    pub fn load(assets_dir: &Path, character: Option<&Path>) -> Result<Self, AssetError> {
        Self::load_chosen(assets_dir, character, None)
    }

    /// The same with the user's choice of skin materials (`--skin`); a choice naming a
    /// material the file lacks is an error.
    pub fn load_chosen(
        assets_dir: &Path,
        character: Option<&Path>,
        skin: Option<&SkinChoice>,
    ) -> Result<Self, AssetError> {
        let default = assets_dir.join(Self::CHARACTER);
        let path = character.unwrap_or(&default);
        let character = load_gltf(path)?;
        let class = crate::asset::skin::classify(&character, skin).map_err(|e| {
            let prefix = format!("{}: ", character.source);
            let problem = e.strip_prefix(&prefix).unwrap_or(&e).to_string();
            AssetError::new(path.display().to_string(), problem)
        })?;
        log::info!("{}", class.summary);
        Ok(Self {
            roles: Roles::classified(&character, &class),
            character,
            props: Self::props(&|path| load_gltf(&assets_dir.join(path)))?,
            head: HeadLoad::default(),
        })
    }

    /// Also loads the scanned head (`assets_dir/head/`, albedo and normal map) for the
    /// showroom. A missing or bad head is one logged line and no head: the showroom then
    /// offers only the runner.
    pub fn with_head(mut self, assets_dir: &Path) -> Self {
        self.head = HeadLoad::load(assets_dir);
        self
    }

    /// Loads the character and every prop through `read`, which maps a path relative to the
    /// assets root (`/`-separated) to the file's bytes: the Android app's asset manager. A
    /// model's external files resolve relative to its folder.
    pub fn load_with(read: &dyn Fn(&str) -> Result<Vec<u8>, String>) -> Result<Self, AssetError> {
        let model = |path: &str| -> Result<Model, AssetError> {
            let bytes = read(path).map_err(|e| AssetError::new(path, e))?;
            let dir = path.rsplit_once('/').map_or("", |(d, _)| d);
            let resolve = |uri: &str| match dir {
                "" => read(uri),
                _ => read(&format!("{dir}/{uri}")),
            };
            load_gltf_slice(&bytes, path, &resolve)
        };
        let character = model(Self::CHARACTER)?;
        Ok(Self {
            roles: Roles::of(&character),
            character,
            props: Self::props(&model)?,
            head: HeadLoad::default(),
        })
    }

    /// Every prop, `props/<PropKind::file()>`, loaded by `load`.
    fn props(
        load: &dyn Fn(&str) -> Result<Model, AssetError>,
    ) -> Result<Vec<(PropKind, Model)>, AssetError> {
        PropKind::ALL
            .iter()
            .map(|&kind| Ok((kind, load(&format!("props/{}", kind.file()))?)))
            .collect()
    }
}

/// The demo room: a floor of 4 m tiles, a back wall, a table and a chair.
pub fn showroom() -> Vec<PropInstance> {
    let mut out = Vec::new();
    for x in -2..=2 {
        for z in -2..=2 {
            out.push(PropInstance {
                kind: PropKind::FloorTile,
                transform: Mat4::from_translation(Vec3::new(x as f32 * 4.0, 0.0, z as f32 * 4.0)),
            });
        }
    }
    for x in -2..=2 {
        out.push(PropInstance {
            kind: PropKind::Wall,
            transform: Mat4::from_translation(Vec3::new(x as f32 * 4.0, 0.0, -6.0)),
        });
    }
    let place = |kind, x: f32, z: f32, yaw: f32| PropInstance {
        kind,
        transform: Mat4::from_rotation_translation(
            Quat::from_rotation_y(yaw),
            Vec3::new(x, 0.0, z),
        ),
    };
    out.push(place(PropKind::Table, 2.6, -2.5, 0.3));
    out.push(place(PropKind::Chair, 1.6, -2.2, 2.2));
    out.push(place(PropKind::Obstacle, -2.5, -3.0, 0.2));
    out
}

/// Axis-aligned bounds of the first skinned mesh in `pose` (world space, before any
/// placement), or `None` when the model has no skinned mesh.
pub fn posed_bounds(model: &Model, pose: &Pose) -> Option<(Vec3, Vec3)> {
    let (_, mesh, _) = first_skinned_mesh(model)?;
    let points = skin_positions(model, mesh, pose);
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo.x <= hi.x).then_some((lo, hi))
}

/// A camera eye and target that frame the box `(lo, hi)` from the front-right, filling about
/// `fill` of the vertical field of view `fov_y`.
pub fn frame_bounds(lo: Vec3, hi: Vec3, fov_y: f32, fill: f32, aspect: f32) -> (Vec3, Vec3) {
    let center = (lo + hi) * 0.5;
    let size = hi - lo;
    let extent = size
        .y
        .max(size.x / aspect.max(0.1))
        .max(size.z * 0.5)
        .max(1e-3);
    let distance = extent * 0.5 / (fov_y * 0.5).tan() / fill.clamp(0.05, 20.0) + size.z * 0.5;
    let dir = Vec3::new(0.35, 0.12, 1.0).normalize();
    (center + dir * distance, center)
}

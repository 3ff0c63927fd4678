//! The static props a scene places: their kinds (a file each under `assets/props/`) and their
//! placements. Plain data: the renderer draws them (`render`'s props pass), the game and the
//! demo place them.

use glam::Mat4;

/// The props the game and the demo scene use; each is a file in `assets/props/`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PropKind {
    FloorTile,
    Wall,
    Table,
    Chair,
    Obstacle,
}

impl PropKind {
    pub const ALL: [PropKind; 5] = [
        Self::FloorTile,
        Self::Wall,
        Self::Table,
        Self::Chair,
        Self::Obstacle,
    ];

    /// File name under `assets/props/`.
    pub fn file(self) -> &'static str {
        match self {
            Self::FloorTile => "floor_tile.glb",
            Self::Wall => "wall.glb",
            Self::Table => "table.glb",
            Self::Chair => "chair.glb",
            Self::Obstacle => "obstacle.glb",
        }
    }
}

/// One placed prop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropInstance {
    pub kind: PropKind,
    pub transform: Mat4,
}

//! The map: chunks of props (floor tiles, walls, tables, chairs) along the track, and the
//! obstacles on it. Both live in fixed-capacity pools and are recycled behind the player.

use glam::{Mat4, Quat, Vec3};

use super::rng::Pcg32;
use dermis_engine::scene::PropKind;

/// Length of one map chunk along the track (two 4 m floor tiles).
pub const CHUNK_LEN: f32 = 8.0;
/// Props one chunk may hold.
pub const MAX_CHUNK_PROPS: usize = 16;
/// Chunk and obstacle pool capacities.
pub const MAX_CHUNKS: usize = 16;
pub const MAX_OBSTACLES: usize = 64;
/// Distance between lane centres (m).
pub const LANE_WIDTH: f32 = 1.3;
/// Half extents of the wall line and the floor (m).
const WALL_X: f32 = 6.0;

/// World x of lane `lane` (−1 = the runner's left = +x, since it runs towards +z).
pub fn lane_x(lane: i8) -> f32 {
    -(lane as f32) * LANE_WIDTH
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chunk {
    pub z: f32,
    pub count: u8,
    pub props: [(PropKind, Mat4); MAX_CHUNK_PROPS],
}

impl Chunk {
    pub fn props(&self) -> &[(PropKind, Mat4)] {
        &self.props[..self.count as usize]
    }

    fn push(&mut self, kind: PropKind, pos: Vec3, yaw: f32) {
        if (self.count as usize) < MAX_CHUNK_PROPS {
            self.props[self.count as usize] = (
                kind,
                Mat4::from_rotation_translation(Quat::from_rotation_y(yaw), pos),
            );
            self.count += 1;
        }
    }

    /// A chunk starting at `z`, furnished from `rng`.
    pub fn generate(z: f32, rng: &mut Pcg32) -> Self {
        let mut c = Chunk {
            z,
            count: 0,
            props: [(PropKind::FloorTile, Mat4::IDENTITY); MAX_CHUNK_PROPS],
        };
        for row in [2.0, 6.0] {
            for x in [-4.0, 0.0, 4.0] {
                c.push(PropKind::FloorTile, Vec3::new(x, 0.0, z + row), 0.0);
            }
            for side in [-1.0f32, 1.0] {
                c.push(
                    PropKind::Wall,
                    Vec3::new(side * WALL_X, 0.0, z + row),
                    std::f32::consts::FRAC_PI_2,
                );
            }
        }
        // Furniture beside the track: a table with chairs on either side, now and then.
        for side in [-1.0f32, 1.0] {
            if !rng.chance(0.45) {
                continue;
            }
            let tz = z + rng.range(2.0, 6.0);
            let tx = side * rng.range(3.6, 4.4);
            c.push(
                PropKind::Table,
                Vec3::new(tx, 0.0, tz),
                std::f32::consts::FRAC_PI_2 + rng.range(-0.15, 0.15),
            );
            for dz in [-1.0f32, 1.0] {
                if rng.chance(0.7) {
                    // Chairs face the table (+z is a chair's front).
                    let yaw =
                        if dz < 0.0 { 0.0 } else { std::f32::consts::PI } + rng.range(-0.3, 0.3);
                    c.push(
                        PropKind::Chair,
                        Vec3::new(tx + rng.range(-0.2, 0.2), 0.0, tz + dz * 0.75),
                        yaw,
                    );
                }
            }
        }
        c
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ObstacleKind {
    /// Low crate: jump over it.
    Low,
    /// Tall stack: change lane.
    Tall,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obstacle {
    pub kind: ObstacleKind,
    pub lane: i8,
    /// Centre along the track.
    pub z: f32,
}

impl Obstacle {
    pub const HALF_WIDTH: f32 = 0.45;
    pub const HALF_DEPTH: f32 = 0.3;

    pub fn height(&self) -> f32 {
        match self.kind {
            ObstacleKind::Low => 0.55,
            ObstacleKind::Tall => 1.9,
        }
    }

    pub fn x(&self) -> f32 {
        lane_x(self.lane)
    }

    /// Axis-aligned box `(min, max)`.
    pub fn aabb(&self) -> (Vec3, Vec3) {
        let c = Vec3::new(self.x(), 0.0, self.z);
        let h = Vec3::new(Self::HALF_WIDTH, 0.0, Self::HALF_DEPTH);
        (c - h, c + h + Vec3::Y * self.height())
    }

    /// The 1 m crate prop scaled to the obstacle's box.
    pub fn transform(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(
            Vec3::new(
                2.0 * Self::HALF_WIDTH,
                self.height(),
                2.0 * Self::HALF_DEPTH,
            ),
            Quat::IDENTITY,
            Vec3::new(self.x(), 0.0, self.z),
        )
    }
}

/// Lanes a row of obstacles blocks, as `[Option<ObstacleKind>; 3]` for lanes −1, 0, 1.
/// At least one lane is always passable (empty or low).
pub fn row_pattern(rng: &mut Pcg32, difficulty: f32) -> [Option<ObstacleKind>; 3] {
    let mut row = [None; 3];
    if rng.chance(0.12) {
        // A full row of low crates: everyone jumps.
        return [Some(ObstacleKind::Low); 3];
    }
    let blocked = if rng.chance(0.35 + 0.3 * difficulty) {
        2
    } else {
        1
    };
    let free = rng.below(3) as usize;
    let mut placed = 0;
    for (i, slot) in row.iter_mut().enumerate() {
        if i == free || placed == blocked {
            continue;
        }
        if blocked == 1 && rng.chance(0.5) {
            continue; // leave this one free and block the next
        }
        let tall = rng.chance(0.45);
        *slot = Some(if tall {
            ObstacleKind::Tall
        } else {
            ObstacleKind::Low
        });
        placed += 1;
    }
    if placed == 0 {
        let i = (free + 1) % 3;
        row[i] = Some(if rng.chance(0.45) {
            ObstacleKind::Tall
        } else {
            ObstacleKind::Low
        });
    }
    row
}

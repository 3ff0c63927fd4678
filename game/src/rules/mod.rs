//! "Xicom runner" (Lee, Kim & Chin 2014, §4.2): the runner game built on the engine.
//!
//! The simulation runs at a fixed step ([`TICK_DT`]) behind an accumulator, so the per-tick
//! state (and [`Game::state_hash`]) is the same whatever the frame rate; everything random
//! comes from the game's own [`rng::Pcg32`] seeded from [`Game::new`]'s seed. Obstacles and
//! map chunks live in fixed-capacity [`Pool`]s and are recycled, so a steady-state frame
//! allocates nothing. The game only *describes* what to draw (prop placements, the player
//! transform, the camera target, the animation blend); the app (`crate::app`: the session,
//! menus, showroom, settings, governor scheduling and the GPU side) renders it. Nothing here
//! touches the renderer.

mod bot;
mod input;
mod player;
pub mod rng;
pub mod track;

pub use bot::Bot;
pub use input::{Input, Swipe};
pub use track::{Chunk, Obstacle, ObstacleKind, LANE_WIDTH};

use glam::{Mat4, Quat, Vec3};

use dermis_engine::pool::Pool;
use dermis_engine::scene::{PropInstance, PropKind};
use rng::Pcg32;
use track::{row_pattern, CHUNK_LEN, MAX_CHUNKS, MAX_OBSTACLES};

/// Simulation rate and step.
pub const TICK_HZ: u32 = 120;
pub const TICK_DT: f32 = 1.0 / TICK_HZ as f32;
/// At most this many ticks per `update` (a long hitch is dropped rather than replayed).
pub const MAX_TICKS_PER_UPDATE: u32 = 30;

const START_SPEED: f32 = 8.0;
const MAX_SPEED: f32 = 18.0;
const ACCELERATION: f32 = 0.12;
const JUMP_SPEED: f32 = 6.0;
const GRAVITY: f32 = 20.0;
/// Fraction of the remaining lateral distance covered per tick (smooth lane change).
const LANE_FOLLOW: f32 = 0.1;
const PLAYER_HALF_WIDTH: f32 = 0.3;
const PLAYER_HALF_DEPTH: f32 = 0.25;
const PLAYER_HEIGHT: f32 = 1.7;
/// Obstacles spawn this far ahead and are recycled this far behind the player.
const SPAWN_AHEAD: f32 = 70.0;
const RECYCLE_BEHIND: f32 = 4.0;
const FIRST_ROW_Z: f32 = 30.0;
/// Game-over input is ignored for this long (no accidental replay).
const GAME_OVER_LOCK_TICKS: u32 = TICK_HZ / 2;
/// Animation crossfade duration.
const FADE_TICKS: f32 = 0.18 * TICK_HZ as f32;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screen {
    Main,
    Play,
    GameOver,
}

/// What the runner is doing, for its animation (the app maps each to one of the character's
/// clips, found by name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clip {
    Idle = 0,
    Run = 1,
    Jump = 2,
    /// After hitting an obstacle (the game-over screen), played once.
    Death = 3,
}

impl Clip {
    pub const ALL: [Clip; 4] = [Clip::Idle, Clip::Run, Clip::Jump, Clip::Death];
}

/// The character's animation blend: `blend[0]` fades out, `blend[1]` fades in; weights sum
/// to 1. `time[i]` is the playback time (seconds) of `blend[i]`'s clip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimState {
    pub blend: [(usize, f32); 2],
    pub time: [f32; 2],
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Player {
    lane: i8,
    x: f32,
    y: f32,
    vy: f32,
    z: f32,
    speed: f32,
}

impl Player {
    fn start() -> Self {
        Self {
            lane: 0,
            x: 0.0,
            y: 0.0,
            vy: 0.0,
            z: 0.0,
            speed: START_SPEED,
        }
    }
    fn grounded(&self) -> bool {
        self.y <= 0.0 && self.vy <= 0.0
    }
    fn pos(&self) -> Vec3 {
        Vec3::new(self.x, self.y, self.z)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Anim {
    from: Clip,
    to: Clip,
    /// Weight of `to`.
    t: f32,
    times: [f32; 4],
}

pub struct Game {
    seed: u64,
    runs: u32,
    screen: Screen,
    screen_ticks: u32,
    ticks: u64,
    accumulator: f64,
    player: Player,
    prev_pos: Vec3,
    prev_x_vel: f32,
    obstacles: Pool<Obstacle>,
    chunks: Pool<Chunk>,
    rng: Pcg32,
    deco_rng: Pcg32,
    next_row_z: f32,
    next_chunk_z: f32,
    score: u32,
    best: u32,
    new_best: bool,
    anim: Anim,
    pending: Input,
    paused: bool,
}

impl Game {
    /// A game on the main screen, its first run's world generated from `seed`.
    pub fn new(seed: u64) -> Self {
        let mut g = Self {
            seed,
            runs: 0,
            screen: Screen::Main,
            screen_ticks: 0,
            ticks: 0,
            accumulator: 0.0,
            player: Player::start(),
            prev_pos: Vec3::ZERO,
            prev_x_vel: 0.0,
            obstacles: Pool::with_capacity(MAX_OBSTACLES),
            chunks: Pool::with_capacity(MAX_CHUNKS),
            rng: Pcg32::new(seed, 0),
            deco_rng: Pcg32::new(seed, 1),
            next_row_z: FIRST_ROW_Z,
            next_chunk_z: 0.0,
            score: 0,
            best: 0,
            new_best: false,
            anim: Anim {
                from: Clip::Idle,
                to: Clip::Idle,
                t: 1.0,
                times: [0.0; 4],
            },
            pending: Input::NONE,
            paused: false,
        };
        g.reset_world();
        g
    }

    /// Regenerates the world for run number `self.runs` (deterministic from the seed).
    fn reset_world(&mut self) {
        let run = self.runs as u64;
        self.rng = Pcg32::new(self.seed ^ rng::splitmix64(run), 2 * run);
        self.deco_rng = Pcg32::new(self.seed ^ rng::splitmix64(run), 2 * run + 1);
        self.player = Player::start();
        self.prev_pos = self.player.pos();
        self.prev_x_vel = 0.0;
        self.obstacles.clear();
        self.chunks.clear();
        self.next_row_z = FIRST_ROW_Z;
        self.next_chunk_z = -2.0 * CHUNK_LEN;
        self.score = 0;
        self.new_best = false;
        self.stream_world();
    }

    /// Spawns chunks and obstacle rows ahead, recycles those behind.
    fn stream_world(&mut self) {
        let z = self.player.z;
        self.chunks
            .retain(|_, c| c.z + CHUNK_LEN > z - 2.0 * CHUNK_LEN);
        self.obstacles.retain(|_, o| o.z > z - RECYCLE_BEHIND);
        while self.next_chunk_z < z + SPAWN_AHEAD + CHUNK_LEN && !self.chunks.is_full() {
            let chunk = Chunk::generate(self.next_chunk_z, &mut self.deco_rng);
            self.chunks.insert(chunk);
            self.next_chunk_z += CHUNK_LEN;
        }
        while self.next_row_z < z + SPAWN_AHEAD
            && self.obstacles.capacity() - self.obstacles.len() >= 3
        {
            let difficulty =
                ((self.player.speed - START_SPEED) / (MAX_SPEED - START_SPEED)).clamp(0.0, 1.0);
            let row = row_pattern(&mut self.rng, difficulty);
            for (i, kind) in row.iter().enumerate() {
                if let Some(kind) = *kind {
                    self.obstacles.insert(Obstacle {
                        kind,
                        lane: i as i8 - 1,
                        z: self.next_row_z,
                    });
                }
            }
            // Enough room to react at the current speed, plus some randomness.
            let speed = self.player.speed.max(START_SPEED);
            self.next_row_z += speed * 0.85 + 5.0 + self.rng.range(0.0, 9.0);
        }
    }

    // ---- control ----

    /// Main screen → play (the world is already generated).
    pub fn start(&mut self) {
        match self.screen {
            Screen::Main => self.set_screen(Screen::Play),
            Screen::GameOver => self.replay(),
            Screen::Play => {}
        }
    }

    /// A new run from the start (a new world from the seed and the run number).
    pub fn replay(&mut self) {
        self.runs += 1;
        self.reset_world();
        self.set_screen(Screen::Play);
    }

    /// Back to the main screen with a fresh world.
    pub fn to_main(&mut self) {
        self.runs += 1;
        self.reset_world();
        self.set_screen(Screen::Main);
    }

    fn set_screen(&mut self, s: Screen) {
        self.screen = s;
        self.screen_ticks = 0;
        self.paused = false;
    }

    /// Pauses a run (only a run in Play pauses; elsewhere this does nothing): no tick runs
    /// and the time frames bring is dropped, so the run resumes where it stopped, without a
    /// jump. Input pressed while paused is dropped too.
    pub fn pause(&mut self) {
        if self.screen == Screen::Play {
            self.paused = true;
            self.pending = Input::NONE;
        }
    }

    /// Resumes a paused run.
    pub fn resume(&mut self) {
        self.paused = false;
    }

    /// Pauses a running run, resumes a paused one.
    pub fn toggle_pause(&mut self) {
        if self.paused {
            self.resume();
        } else {
            self.pause();
        }
    }

    pub fn is_paused(&self) -> bool {
        self.paused
    }

    pub fn set_best(&mut self, best: u32) {
        self.best = best;
    }

    // ---- simulation ----

    /// Advances by a frame of `frame_dt` seconds: runs 0..n fixed ticks. `input` (presses
    /// since the last frame) acts on the first tick; if no tick runs it is kept for the next.
    /// Returns the number of ticks run. While paused nothing runs and `frame_dt` and `input`
    /// are dropped.
    pub fn update(&mut self, frame_dt: f32, input: &Input) -> u32 {
        if self.paused {
            return 0;
        }
        self.pending.merge(input);
        self.update_with(frame_dt, |_| Input::NONE)
    }

    /// Like [`Game::update`], with the input sampled before *every* tick from `input`
    /// (e.g. the [`Bot`]), so the result does not depend on how ticks fall into frames.
    pub fn update_with(&mut self, frame_dt: f32, mut input: impl FnMut(&Game) -> Input) -> u32 {
        if self.paused {
            return 0;
        }
        let dt = if frame_dt.is_finite() {
            frame_dt.clamp(0.0, 0.25)
        } else {
            0.0
        };
        self.accumulator += dt as f64;
        let step = TICK_DT as f64;
        let mut n = 0;
        while self.accumulator >= step && n < MAX_TICKS_PER_UPDATE {
            self.accumulator -= step;
            let i = input(&*self);
            self.tick(&i);
            n += 1;
        }
        if n == MAX_TICKS_PER_UPDATE {
            self.accumulator = self.accumulator.min(step);
        }
        n
    }

    /// Fraction of a tick not yet simulated (for interpolating the player between ticks).
    pub fn alpha(&self) -> f32 {
        (self.accumulator / TICK_DT as f64).clamp(0.0, 1.0) as f32
    }

    /// One fixed step.
    pub fn tick(&mut self, input: &Input) {
        let mut input = *input;
        if !self.pending.is_empty() {
            let mut p = std::mem::take(&mut self.pending);
            p.merge(&input);
            input = p;
        }
        self.ticks += 1;
        self.screen_ticks = self.screen_ticks.saturating_add(1);
        self.prev_pos = self.player.pos();
        match self.screen {
            Screen::Main => {
                if input.jump {
                    self.set_screen(Screen::Play);
                }
            }
            Screen::GameOver => {
                if input.jump && self.screen_ticks > GAME_OVER_LOCK_TICKS {
                    self.replay();
                }
            }
            Screen::Play => self.play_tick(&input),
        }
        self.anim_tick();
    }

    fn anim_tick(&mut self) {
        let target = match self.screen {
            Screen::Play if !self.player.grounded() => Clip::Jump,
            Screen::Play => Clip::Run,
            Screen::GameOver => Clip::Death,
            Screen::Main => Clip::Idle,
        };
        if target == Clip::Death && self.anim.to != Clip::Death {
            // Played from its start each time the runner falls.
            self.anim.times[Clip::Death as usize] = 0.0;
        }
        let a = &mut self.anim;
        if target != a.to {
            if target == a.from {
                std::mem::swap(&mut a.from, &mut a.to);
                a.t = 1.0 - a.t;
            } else {
                // Fade from whichever clip currently dominates.
                if a.t >= 0.5 {
                    a.from = a.to;
                }
                a.to = target;
                a.t = 0.0;
            }
        }
        a.t = (a.t + 1.0 / FADE_TICKS).min(1.0);
        a.times[Clip::Idle as usize] += TICK_DT;
        a.times[Clip::Run as usize] += TICK_DT * (self.player.speed / START_SPEED).max(0.5);
        a.times[Clip::Jump as usize] += TICK_DT;
        a.times[Clip::Death as usize] += TICK_DT;
    }

    // ---- state ----

    pub fn screen(&self) -> Screen {
        self.screen
    }

    /// Ticks spent on the current screen.
    pub fn screen_ticks(&self) -> u32 {
        self.screen_ticks
    }

    /// Ticks simulated since construction.
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Runs started (replays) so far (0 during the first run).
    pub fn runs(&self) -> u32 {
        self.runs
    }

    /// Distance run this run, in whole metres.
    pub fn score(&self) -> u32 {
        self.score
    }

    pub fn best(&self) -> u32 {
        self.best
    }

    /// Whether the last game over set a new best score.
    pub fn is_new_best(&self) -> bool {
        self.new_best
    }

    pub fn lane(&self) -> i8 {
        self.player.lane
    }

    pub fn speed(&self) -> f32 {
        self.player.speed
    }

    pub fn is_airborne(&self) -> bool {
        !self.player.grounded()
    }

    /// The player's feet at the last tick.
    pub fn player_position(&self) -> Vec3 {
        self.player.pos()
    }

    pub fn obstacles(&self) -> impl Iterator<Item = &Obstacle> + '_ {
        self.obstacles.values()
    }

    pub fn obstacle_count(&self) -> usize {
        self.obstacles.len()
    }

    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// The player's feet (interpolated between the last two ticks) and yaw about +Y (0 =
    /// running towards +z; it leans into lane changes).
    pub fn player_transform(&self) -> (Vec3, f32) {
        let pos = self.prev_pos.lerp(self.player.pos(), self.alpha());
        let yaw = if self.screen == Screen::Play {
            (self.prev_x_vel).atan2(self.player.speed.max(1.0)) * 0.8
        } else {
            0.0
        };
        (pos, yaw)
    }

    /// The character's world matrix (feet at the origin of the model).
    pub fn player_matrix(&self) -> Mat4 {
        let (pos, yaw) = self.player_transform();
        Mat4::from_rotation_translation(Quat::from_rotation_y(yaw), pos)
    }

    /// What the follow camera should track: the feet on the ground (jumps do not bob the
    /// camera), half-way towards the lane, facing +z — for `FollowCamera::update`.
    pub fn camera_target(&self) -> (Vec3, f32) {
        let (pos, _) = self.player_transform();
        (Vec3::new(pos.x * 0.5, 0.0, pos.z), 0.0)
    }

    pub fn anim_state(&self) -> AnimState {
        let a = &self.anim;
        AnimState {
            blend: [(a.from as usize, 1.0 - a.t), (a.to as usize, a.t)],
            time: [a.times[a.from as usize], a.times[a.to as usize]],
        }
    }

    /// Fills `out` (cleared first) with every prop to draw: the map chunks' furniture and the
    /// obstacles. Does not reallocate when `out` has capacity for [`Game::MAX_PROPS`].
    pub fn props(&self, out: &mut Vec<PropInstance>) {
        out.clear();
        for c in self.chunks.values() {
            for &(kind, transform) in c.props() {
                out.push(PropInstance { kind, transform });
            }
        }
        for o in self.obstacles.values() {
            out.push(PropInstance {
                kind: PropKind::Obstacle,
                transform: o.transform(),
            });
        }
    }

    /// The most props [`Game::props`] can produce.
    pub const MAX_PROPS: usize = MAX_CHUNKS * track::MAX_CHUNK_PROPS + MAX_OBSTACLES;

    /// FNV-1a 64 over the simulation state (exact bits of every float).
    pub fn state_hash(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut put = |v: u64| {
            for b in v.to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        let p = &self.player;
        put(self.ticks);
        put(self.screen as u64);
        put(self.screen_ticks as u64);
        put(self.runs as u64);
        put(p.lane as i64 as u64);
        for v in [
            p.x,
            p.y,
            p.vy,
            p.z,
            p.speed,
            self.next_row_z,
            self.next_chunk_z,
            self.anim.t,
        ] {
            put(v.to_bits() as u64);
        }
        put(self.score as u64);
        put(self.best as u64);
        put(self.rng.state());
        put(self.deco_rng.state());
        put(((self.anim.from as u64) << 8) | self.anim.to as u64);
        for (hd, o) in self.obstacles.iter() {
            put(((hd.index as u64) << 32) | hd.generation as u64);
            put(((o.kind as u64) << 8) | (o.lane as i64 as u64 & 0xff));
            put(o.z.to_bits() as u64);
        }
        put(self.chunks.len() as u64);
        for c in self.chunks.values() {
            put(c.z.to_bits() as u64);
            put(c.count as u64);
        }
        h
    }

    /// Test hook: places an obstacle (returns false when the pool is full).
    #[doc(hidden)]
    pub fn debug_place_obstacle(&mut self, kind: ObstacleKind, lane: i8, z: f32) -> bool {
        self.obstacles
            .insert(Obstacle {
                kind,
                lane: lane.clamp(-1, 1),
                z,
            })
            .is_some()
    }

    /// Test hook: removes every obstacle and stops spawning new ones before `z`.
    #[doc(hidden)]
    pub fn debug_clear_obstacles_until(&mut self, z: f32) {
        self.obstacles.clear();
        self.next_row_z = self.next_row_z.max(z);
    }
}

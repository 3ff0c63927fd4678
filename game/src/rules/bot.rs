//! The autoplay bot: looks ahead along the track, changes lane away from tall obstacles,
//! jumps over low ones, and restarts after a game over. Its decisions depend only on the game
//! state (and its seed), so the game stays deterministic when the bot is sampled per tick.
//! It is good, not perfect: its jump timing varies per obstacle and now and then it reacts
//! too late, so runs end.

use super::rng::splitmix64;
use super::track::Obstacle;
use super::{Game, Input, ObstacleKind, Screen, TICK_HZ};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bot {
    seed: u64,
    /// Probability (per low obstacle) of a late jump, in 1/1000.
    mistakes_per_mille: u32,
    /// Whether it dodges and jumps in a run (else it runs straight on until it hits something).
    playing: bool,
}

impl Default for Bot {
    fn default() -> Self {
        Self::new(0)
    }
}

impl Bot {
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            mistakes_per_mille: 25,
            playing: true,
        }
    }

    /// A bot that never jumps late (for tests that want long runs).
    pub fn careful(seed: u64) -> Self {
        Self {
            seed,
            mistakes_per_mille: 0,
            playing: true,
        }
    }

    /// Stops dodging and jumping (it still starts and restarts runs): the run ends at the next
    /// obstacle in its lane, within seconds. `play --screenshots` uses it to reach the
    /// game-over screen once the play screen is saved.
    pub fn give_up(&mut self) {
        self.playing = false;
    }

    /// Whether it still dodges and jumps in a run.
    pub fn is_playing(&self) -> bool {
        self.playing
    }

    /// Ticks the bot waits on the main screen / game-over screen before starting.
    pub const START_DELAY: u32 = TICK_HZ / 2;
    pub const RESTART_DELAY: u32 = TICK_HZ;

    /// A per-obstacle value in [0, 1) from the bot's seed.
    fn noise(&self, o: &Obstacle, salt: u64) -> f32 {
        let h = splitmix64(
            self.seed ^ splitmix64(o.z.to_bits() as u64 ^ ((o.lane as i64 as u64) << 40) ^ salt),
        );
        (h >> 40) as f32 / (1u64 << 24) as f32
    }

    /// The input for the next tick.
    pub fn decide(&self, game: &Game) -> Input {
        let mut input = Input::NONE;
        match game.screen() {
            Screen::Main => input.jump = game.screen_ticks() > Self::START_DELAY,
            Screen::GameOver => input.jump = game.screen_ticks() > Self::RESTART_DELAY,
            Screen::Play if self.playing => self.play(game, &mut input),
            Screen::Play => {}
        }
        input
    }

    fn play(&self, game: &Game, input: &mut Input) {
        let p = game.player_position();
        let v = game.speed().max(1.0);
        let look = v * 1.1 + 4.0;
        // Distance to the first tall obstacle in `lane` within sight (MAX if none).
        let tall = |lane: i8| match nearest_of(game, lane, ObstacleKind::Tall, p.z) {
            Some(d) if d <= look => d,
            _ => f32::MAX,
        };
        // A lane can be entered (or crossed) unless something in it is about to arrive.
        let enterable = |lane: i8| {
            game.obstacles().all(|o| {
                o.lane != lane
                    || o.z - p.z > v * 0.5 + 1.0
                    || o.z + Obstacle::HALF_DEPTH < p.z - 0.3
            })
        };
        let cur = game.lane();
        let here = tall(cur);
        if here < f32::MAX {
            let mut best = cur;
            let mut best_d = here;
            // Nearest lanes first (stable order), so ties keep the shorter move.
            for lane in [cur - 1, cur + 1, cur - 2, cur + 2] {
                if !(-1..=1).contains(&lane) || !enterable(lane) {
                    continue;
                }
                if (lane - cur).abs() == 2 && !enterable((lane + cur) / 2) {
                    continue;
                }
                let d = tall(lane);
                if d > best_d + 0.5 {
                    best = lane;
                    best_d = d;
                }
            }
            if best < cur {
                input.left = true;
            } else if best > cur {
                input.right = true;
            }
        }
        // Jump over a low obstacle the body is heading into (by actual x, mid lane change too).
        if !game.is_airborne() {
            let reach = Obstacle::HALF_WIDTH + 0.3 + 0.05;
            let threat = game
                .obstacles()
                .filter(|o| (o.x() - p.x).abs() < reach && o.z + Obstacle::HALF_DEPTH > p.z - 0.25)
                .min_by(|a, b| a.z.total_cmp(&b.z));
            if let Some(o) = threat {
                if o.kind == ObstacleKind::Low {
                    let late = self.noise(o, 1) * 1000.0 < self.mistakes_per_mille as f32;
                    let lead = if late {
                        0.08
                    } else {
                        0.24 + 0.14 * self.noise(o, 2)
                    };
                    if (o.z - p.z) / v <= lead {
                        input.jump = true;
                    }
                }
            }
        }
    }
}

/// Distance ahead to the nearest obstacle of `kind` in `lane` not yet passed.
fn nearest_of(game: &Game, lane: i8, kind: ObstacleKind, z: f32) -> Option<f32> {
    game.obstacles()
        .filter(|o| o.lane == lane && o.kind == kind && o.z + Obstacle::HALF_DEPTH > z - 0.3)
        .map(|o| o.z - z)
        .min_by(|a, b| a.total_cmp(b))
}

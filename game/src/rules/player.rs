//! The runner's motion and collisions: lanes, jumps, speed, and what happens on a hit.

use glam::Vec3;

use super::track::lane_x;
use super::{
    Clip, Game, Input, Screen, Swipe, ACCELERATION, GRAVITY, JUMP_SPEED, LANE_FOLLOW, MAX_SPEED,
    PLAYER_HALF_DEPTH, PLAYER_HALF_WIDTH, PLAYER_HEIGHT, TICK_DT,
};
use dermis_engine::scene::CHARACTER;

impl Game {
    pub(super) fn play_tick(&mut self, input: &Input) {
        let p = &mut self.player;
        let left = input.left || input.swipe == Some(Swipe::Left);
        let right = input.right || input.swipe == Some(Swipe::Right);
        if left && !right {
            p.lane = (p.lane - 1).max(-1);
        } else if right && !left {
            p.lane = (p.lane + 1).min(1);
        }
        let jump = input.jump || input.tap.is_some() || input.swipe == Some(Swipe::Up);
        if jump && p.grounded() {
            p.vy = JUMP_SPEED;
            self.anim.times[Clip::Jump as usize] = 0.0;
        }
        // Lateral: close a fixed fraction of the gap per tick.
        let target = lane_x(p.lane);
        let old_x = p.x;
        p.x += (target - p.x) * LANE_FOLLOW;
        if (target - p.x).abs() < 1e-3 {
            p.x = target;
        }
        self.prev_x_vel = (p.x - old_x) / TICK_DT;
        // Vertical.
        if !p.grounded() || p.vy > 0.0 {
            p.vy -= GRAVITY * TICK_DT;
            p.y += p.vy * TICK_DT;
            if p.y <= 0.0 {
                p.y = 0.0;
                p.vy = 0.0;
            }
        }
        p.speed = (p.speed + ACCELERATION * TICK_DT).min(MAX_SPEED);
        p.z += p.speed * TICK_DT;
        self.score = p.z.max(0.0) as u32;
        self.stream_world();
        if let Some((omin, omax)) = self.colliding_box() {
            self.stand_clear_of(omin, omax);
            self.player.speed = 0.0;
            if self.score > self.best {
                self.best = self.score;
                self.new_best = true;
            }
            self.set_screen(Screen::GameOver);
        }
    }

    /// The player's collision box (min, max corners, world metres).
    pub fn player_aabb(&self) -> (Vec3, Vec3) {
        let p = self.player.pos();
        let h = Vec3::new(PLAYER_HALF_WIDTH, 0.0, PLAYER_HALF_DEPTH);
        (p - h, p + h + Vec3::Y * PLAYER_HEIGHT)
    }

    /// The box of the first obstacle the player overlaps.
    fn colliding_box(&self) -> Option<(Vec3, Vec3)> {
        let (pmin, pmax) = self.player_aabb();
        self.obstacles
            .values()
            .map(|o| o.aabb())
            .find(|(omin, omax)| pmin.cmplt(*omax).all() && omin.cmplt(pmax).all())
    }

    /// After a hit the runner stands against the obstacle, not inside it: moved back out of
    /// the box along the axis of least penetration (its front face for a head-on hit, its
    /// side for a lane change into it, its top for a landing) until the *drawn* body's bound
    /// ([`CHARACTER`]'s box, which holds any pose: a running stride, swinging arms) clears
    /// it, so the game-over screen shows the runner beside the crate, legs and all.
    fn stand_clear_of(&mut self, omin: Vec3, omax: Vec3) {
        let (pmin, pmax) = self.drawn_bounds();
        let front = pmax.z - omin.z;
        let side = if self.player.x >= 0.5 * (omin.x + omax.x) {
            omax.x - pmin.x
        } else {
            -(pmax.x - omin.x)
        };
        let top = omax.y - pmin.y;
        let p = &mut self.player;
        if front <= side.abs() && front <= top {
            p.z -= front + 1e-3;
        } else if side.abs() <= top {
            p.x += side + side.signum() * 1e-3;
        } else {
            p.y += top + 1e-3;
        }
    }

    /// The box the drawn runner stays inside whatever its pose (min, max corners, world
    /// metres): [`CHARACTER`]'s bound at the feet.
    pub fn drawn_bounds(&self) -> (Vec3, Vec3) {
        CHARACTER.box_at(self.player.pos())
    }
}

//! Fixed-step determinism: the per-tick state hashes are the same whatever the frame rate,
//! and the autoplay bot plays (and restarts) by itself.

use dermis_game::rules::{Bot, Game, Screen, TICK_HZ};

/// Runs `seconds` of frames at `hz` with the bot sampled per tick; returns each tick's hash
/// (the state the bot saw before the tick).
fn hashes(seed: u64, hz: f32, seconds: f32) -> Vec<u64> {
    let mut g = Game::new(seed);
    let bot = Bot::new(seed);
    let mut out = Vec::new();
    let frames = (seconds * hz) as usize;
    for _ in 0..frames {
        g.update_with(1.0 / hz, |g| {
            out.push(g.state_hash());
            bot.decide(g)
        });
    }
    out.push(g.state_hash());
    out
}

#[test]
fn per_tick_hashes_match_at_30_and_144_hz() {
    let seconds = 40.0;
    for seed in [1, 0xdead_beef] {
        let a = hashes(seed, 30.0, seconds);
        let b = hashes(seed, 144.0, seconds);
        let c = hashes(seed, 60.0, seconds);
        let n = a.len().min(b.len()).min(c.len());
        assert!(n as f32 >= (seconds - 0.1) * TICK_HZ as f32, "{n} ticks");
        assert_eq!(a[..n], b[..n], "seed {seed}: 30 Hz vs 144 Hz");
        assert_eq!(a[..n], c[..n], "seed {seed}: 30 Hz vs 60 Hz");
    }
}

#[test]
fn irregular_frame_times_give_the_same_ticks() {
    let a = hashes(7, 120.0, 20.0);
    let mut g = Game::new(7);
    let bot = Bot::new(7);
    let mut b = Vec::new();
    let pattern = [0.004f32, 0.031, 0.0169, 0.0071, 0.05, 0.0];
    let mut i = 0;
    while b.len() < a.len() {
        g.update_with(pattern[i % pattern.len()], |g| {
            b.push(g.state_hash());
            bot.decide(g)
        });
        i += 1;
    }
    let n = a.len().min(b.len()) - 1;
    assert_eq!(a[..n], b[..n]);
}

#[test]
fn different_seeds_give_different_worlds() {
    let a = hashes(1, 60.0, 5.0);
    let b = hashes(2, 60.0, 5.0);
    assert_ne!(a.last(), b.last());
}

#[test]
fn the_bot_survives_a_while_dies_sometimes_and_restarts() {
    let mut g = Game::new(42);
    let bot = Bot::new(42);
    let mut deaths = Vec::new();
    let mut last_runs = 0;
    let mut max_score = 0;
    // Ten simulated minutes at 60 Hz.
    for _ in 0..60 * 600 {
        let was = g.screen();
        g.update_with(1.0 / 60.0, |g| bot.decide(g));
        if was == Screen::Play && g.screen() == Screen::GameOver {
            deaths.push(g.score());
        }
        max_score = max_score.max(g.score());
        last_runs = g.runs();
    }
    assert!(!deaths.is_empty(), "the bot can die");
    assert!(
        last_runs as usize >= deaths.len().saturating_sub(1),
        "it restarts after game over"
    );
    let mean = deaths.iter().map(|&d| d as f64).sum::<f64>() / deaths.len() as f64;
    assert!(mean > 250.0, "survives a good while: deaths at {deaths:?}");
    assert_eq!(
        g.best(),
        *deaths.iter().max().unwrap(),
        "best = the best finished run"
    );
    assert!(max_score >= g.best());
    eprintln!(
        "bot: {} deaths, mean {mean:.0} m, best {max_score} m",
        deaths.len()
    );
}

#[test]
fn a_careful_bot_runs_far() {
    let mut g = Game::new(3);
    let bot = Bot::careful(3);
    let mut best = 0;
    for _ in 0..TICK_HZ * 120 {
        g.tick(&bot.decide(&g));
        best = best.max(g.score());
    }
    assert!(best > 600, "best {best}");
}

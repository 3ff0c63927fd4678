//! Game rules: collision, jumping, lanes, score, replay, best score, settings, props, animation.

use dermis_engine::scene::{PropInstance, PropKind};
use dermis_engine::shading::ShadingModel;
use dermis_game::app::Settings;
use dermis_game::rules::{Clip, Game, Input, ObstacleKind, Screen, Swipe, TICK_DT, TICK_HZ};

const NONE: Input = Input::NONE;

fn press(f: impl FnOnce(&mut Input)) -> Input {
    let mut i = Input::NONE;
    f(&mut i);
    i
}

/// A game in Play with no random obstacles for the first `clear` metres.
fn playing(clear: f32) -> Game {
    let mut g = Game::new(1);
    g.start();
    assert_eq!(g.screen(), Screen::Play);
    g.debug_clear_obstacles_until(clear);
    g
}

fn run_ticks(g: &mut Game, n: u32, input: &Input) {
    for _ in 0..n {
        g.tick(input);
    }
}

#[test]
fn starts_on_the_main_screen_and_jump_starts() {
    let mut g = Game::new(5);
    assert_eq!(g.screen(), Screen::Main);
    run_ticks(&mut g, 100, &NONE);
    assert_eq!(g.screen(), Screen::Main);
    assert_eq!(g.player_position().z, 0.0, "no running on the main screen");
    g.tick(&press(|i| i.jump = true));
    assert_eq!(g.screen(), Screen::Play);
}

#[test]
fn running_into_a_tall_obstacle_ends_the_run() {
    let mut g = playing(1000.0);
    assert!(g.debug_place_obstacle(ObstacleKind::Tall, 0, 6.0));
    // Jumping does not clear a tall obstacle.
    g.tick(&press(|i| i.jump = true));
    run_ticks(&mut g, 2 * TICK_HZ, &NONE);
    assert_eq!(g.screen(), Screen::GameOver);
    assert!(g.score() >= 4 && g.score() <= 6, "score {}", g.score());
    let z = g.player_position().z;
    run_ticks(&mut g, 60, &NONE);
    assert_eq!(g.player_position().z, z, "the player stops at game over");
    assert_stands_clear(&g);
}

/// At game over the runner stands against what it hit, not inside it: neither its collision
/// box nor the bound its drawn body stays in (legs mid-stride included) overlaps an obstacle.
fn assert_stands_clear(g: &Game) {
    for (what, (pmin, pmax)) in [("box", g.player_aabb()), ("drawn body", g.drawn_bounds())] {
        for o in g.obstacles() {
            let (omin, omax) = o.aabb();
            let inside = pmin.cmplt(omax).all() && omin.cmplt(pmax).all();
            assert!(
                !inside,
                "player {what} {pmin}–{pmax} inside obstacle {omin}–{omax}"
            );
        }
    }
}

#[test]
fn every_game_over_leaves_the_drawn_runner_clear_of_every_obstacle() {
    // A careless player: lane changes and jumps at random moments, so runs end head-on, by
    // swerving into a crate's side and by landing on one; each game over is checked.
    let mut deaths = 0;
    for seed in 1..=40u64 {
        let mut g = Game::new(seed);
        g.start();
        let mut h = seed;
        for _ in 0..120 * TICK_HZ {
            if g.screen() != Screen::Play {
                break;
            }
            h = h
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (h >> 33) % 97;
            g.tick(&press(|i| {
                i.left = r == 0;
                i.right = r == 1;
                i.jump = r == 2 || r == 3;
            }));
        }
        assert_eq!(g.screen(), Screen::GameOver, "seed {seed}");
        assert_stands_clear(&g);
        deaths += 1;
    }
    assert_eq!(deaths, 40);
}

#[test]
fn a_lane_change_into_an_obstacle_leaves_the_runner_beside_it() {
    let mut g = playing(1000.0);
    assert!(g.debug_place_obstacle(ObstacleKind::Tall, 1, 3.0));
    // Run until the obstacle is alongside, then swerve into it.
    while g.player_position().z < 3.0 {
        g.tick(&NONE);
    }
    run_ticks(&mut g, TICK_HZ, &press(|i| i.right = true));
    assert_eq!(g.screen(), Screen::GameOver);
    assert_stands_clear(&g);
}

#[test]
fn jumping_clears_a_low_obstacle_and_standing_does_not() {
    // Obstacle 4 m ahead: at 8 m/s it is reached in ~0.5 s; jump when 0.3 s away.
    let mut g = playing(1000.0);
    g.debug_place_obstacle(ObstacleKind::Low, 0, 4.0);
    while 4.0 - g.player_position().z > g.speed() * 0.3 {
        g.tick(&NONE);
    }
    g.tick(&press(|i| i.jump = true));
    assert!(g.is_airborne());
    run_ticks(&mut g, TICK_HZ, &NONE);
    assert_eq!(g.screen(), Screen::Play, "cleared the low obstacle");
    assert!(!g.is_airborne(), "landed");

    let mut g = playing(1000.0);
    g.debug_place_obstacle(ObstacleKind::Low, 0, 4.0);
    run_ticks(&mut g, TICK_HZ, &NONE);
    assert_eq!(g.screen(), Screen::GameOver);
    assert_stands_clear(&g);
}

#[test]
fn changing_lane_avoids_an_obstacle() {
    let mut g = playing(1000.0);
    g.debug_place_obstacle(ObstacleKind::Tall, 0, 5.0);
    g.tick(&press(|i| i.left = true));
    assert_eq!(g.lane(), -1);
    run_ticks(&mut g, 2 * TICK_HZ, &NONE);
    assert_eq!(g.screen(), Screen::Play);
    // Lane −1 is the runner's left: +x when running towards +z.
    assert!(g.player_position().x > 1.2, "{}", g.player_position().x);
}

#[test]
fn lanes_are_bounded_and_the_change_is_smooth() {
    let mut g = playing(1000.0);
    for _ in 0..5 {
        g.tick(&press(|i| i.right = true));
    }
    assert_eq!(g.lane(), 1);
    g.tick(&press(|i| i.swipe = Some(Swipe::Left)));
    assert_eq!(g.lane(), 0);
    for _ in 0..5 {
        g.tick(&press(|i| i.left = true));
    }
    assert_eq!(g.lane(), -1);
    // Smooth: x moves towards the lane over several ticks, never jumps there.
    let mut g = playing(1000.0);
    g.tick(&press(|i| i.right = true));
    let x1 = g.player_position().x;
    assert!(x1 < 0.0 && x1 > -0.5, "{x1}");
    run_ticks(&mut g, TICK_HZ, &NONE);
    assert!((g.player_position().x + dermis_game::rules::LANE_WIDTH).abs() < 1e-3);
}

#[test]
fn score_is_the_distance_in_whole_metres_and_speed_grows() {
    let mut g = playing(1e9);
    let v0 = g.speed();
    run_ticks(&mut g, 10 * TICK_HZ, &NONE);
    assert_eq!(g.score(), g.player_position().z as u32);
    assert!(g.score() >= 80 && g.score() <= 100, "{}", g.score());
    assert!(g.speed() > v0);
}

#[test]
fn replay_resets_the_run_and_keeps_the_best() {
    let mut g = playing(1000.0);
    g.debug_place_obstacle(ObstacleKind::Tall, 0, 20.0);
    for _ in 0..5 * TICK_HZ {
        if g.screen() == Screen::GameOver {
            break;
        }
        g.tick(&NONE);
    }
    assert_eq!(g.screen(), Screen::GameOver);
    let score = g.score();
    assert_eq!(g.best(), score);
    assert!(g.is_new_best());
    // Input right after game over is ignored (no accidental replay).
    g.tick(&press(|i| i.jump = true));
    assert_eq!(g.screen(), Screen::GameOver);
    run_ticks(&mut g, TICK_HZ, &NONE);
    g.tick(&press(|i| i.jump = true));
    assert_eq!(g.screen(), Screen::Play);
    assert_eq!(g.score(), 0);
    assert_eq!(g.runs(), 1);
    assert_eq!(g.player_position().z, 0.0);
    assert_eq!(g.best(), score);
    assert!(!g.is_new_best());
    // The replay button path.
    let mut h = playing(1000.0);
    h.debug_place_obstacle(ObstacleKind::Tall, 0, 3.0);
    run_ticks(&mut h, TICK_HZ, &NONE);
    h.replay();
    assert_eq!((h.screen(), h.score(), h.runs()), (Screen::Play, 0, 1));
}

#[test]
fn obstacles_and_chunks_come_from_bounded_pools() {
    let mut g = playing(0.0);
    let mut max = (0, 0);
    for _ in 0..30 * TICK_HZ {
        g.tick(&NONE);
        if g.screen() != Screen::Play {
            g.replay();
        }
        max = (max.0.max(g.obstacle_count()), max.1.max(g.chunk_count()));
    }
    assert!(max.0 > 0 && max.0 <= 64, "{max:?}");
    assert!(max.1 > 0 && max.1 <= 16, "{max:?}");
}

#[test]
fn every_row_leaves_a_lane_without_a_tall_obstacle() {
    for seed in 0..20 {
        let mut g = Game::new(seed);
        g.start();
        let mut rows: Vec<(u32, [Option<ObstacleKind>; 3])> = Vec::new();
        for o in g.obstacles() {
            let key = o.z.to_bits();
            let i = rows.iter().position(|r| r.0 == key).unwrap_or_else(|| {
                rows.push((key, [None; 3]));
                rows.len() - 1
            });
            rows[i].1[(o.lane + 1) as usize] = Some(o.kind);
        }
        assert!(!rows.is_empty());
        for (_, row) in rows {
            assert!(
                row.iter().any(|k| *k != Some(ObstacleKind::Tall)),
                "seed {seed}: {row:?}"
            );
        }
    }
}

#[test]
fn props_fill_a_preallocated_vec_without_reallocating() {
    let mut g = Game::new(3);
    let mut out: Vec<PropInstance> = Vec::with_capacity(Game::MAX_PROPS);
    let cap = out.capacity();
    g.start();
    for _ in 0..20 * TICK_HZ {
        g.tick(&NONE);
        if g.screen() == Screen::GameOver {
            g.replay();
        }
        g.props(&mut out);
        assert_eq!(out.capacity(), cap);
    }
    for kind in [PropKind::FloorTile, PropKind::Wall, PropKind::Obstacle] {
        assert!(out.iter().any(|p| p.kind == kind), "{kind:?}");
    }
    assert!(out
        .iter()
        .any(|p| matches!(p.kind, PropKind::Table | PropKind::Chair)));
    assert!(out.len() <= Game::MAX_PROPS);
}

#[test]
fn animation_crossfades_idle_run_jump() {
    let mut g = Game::new(9);
    let a = g.anim_state();
    assert_eq!(a.blend[1], (Clip::Idle as usize, 1.0));
    g.start();
    g.debug_clear_obstacles_until(1000.0);
    g.tick(&NONE);
    let a = g.anim_state();
    assert_eq!(a.blend[0].0, Clip::Idle as usize);
    assert_eq!(a.blend[1].0, Clip::Run as usize);
    assert!(a.blend[1].1 > 0.0 && a.blend[1].1 < 0.2, "fading in: {a:?}");
    assert!((a.blend[0].1 + a.blend[1].1 - 1.0).abs() < 1e-6);
    run_ticks(&mut g, TICK_HZ / 2, &NONE);
    assert_eq!(g.anim_state().blend[1], (Clip::Run as usize, 1.0));
    g.tick(&press(|i| i.jump = true));
    let a = g.anim_state();
    assert_eq!(
        (a.blend[0].0, a.blend[1].0),
        (Clip::Run as usize, Clip::Jump as usize)
    );
    assert!(a.time[1] < 2.0 * TICK_DT, "jump clip restarts: {a:?}");
    run_ticks(&mut g, TICK_HZ, &NONE);
    assert_eq!(
        g.anim_state().blend[1],
        (Clip::Run as usize, 1.0),
        "back to running after landing"
    );
}

#[test]
fn player_transform_and_camera_target() {
    let mut g = playing(1000.0);
    run_ticks(&mut g, TICK_HZ, &NONE);
    let (pos, yaw) = g.player_transform();
    assert!(pos.z > 7.0 && pos.y == 0.0 && yaw == 0.0);
    let (cam, cam_yaw) = g.camera_target();
    assert_eq!((cam.z, cam.y, cam_yaw), (pos.z, 0.0, 0.0));
    g.tick(&press(|i| i.left = true));
    let (_, yaw) = g.player_transform();
    assert!(yaw > 0.0, "leans towards +x when moving left: {yaw}");
    let m = g.player_matrix();
    assert!((m.w_axis.truncate() - g.player_transform().0).length() < 1e-5);
}

#[test]
fn human_input_survives_frames_without_ticks() {
    let mut g = Game::new(2);
    // 1 ms frame: no tick runs, the press is kept for the next tick.
    assert_eq!(g.update(0.001, &press(|i| i.jump = true)), 0);
    assert_eq!(g.screen(), Screen::Main);
    assert_eq!(g.update(TICK_DT, &NONE), 1);
    assert_eq!(g.screen(), Screen::Play);
    // Long hitches are capped.
    assert!(g.update(10.0, &NONE) <= dermis_game::rules::MAX_TICKS_PER_UPDATE);
    // Garbage frame times are ignored.
    assert_eq!(g.update(f32::NAN, &NONE), 0);
    assert_eq!(g.update(-1.0, &NONE), 0);
}

#[test]
fn settings_round_trip_and_survive_garbage() {
    let mut s = Settings::default();
    assert_eq!(s.shading_model(), ShadingModel::DEFAULT);
    s.set_shading_model(ShadingModel::Oss);
    s.best = 1234;
    assert_eq!(Settings::from_text(&s.to_text()), s);
    for garbage in [
        "",
        "\0\0\u{fffd}",
        "best=",
        "best=-5\nshading=nope",
        "=\n==\nbest",
        "best=99999999999999",
        "shading",
    ] {
        let g = Settings::from_text(garbage);
        assert_eq!(g, Settings::default(), "{garbage:?}");
    }
    let partial = Settings::from_text("junk\n best = 7 \nshading=dipole\nextra=1");
    assert_eq!((partial.best, partial.shading), (7, ShadingModel::Dipole));
}

#[test]
fn settings_save_is_atomic_and_load_tolerates_missing_files() {
    let dir = std::env::temp_dir().join(format!("dermis-settings-{}", std::process::id()));
    let path = dir.join("sub").join("settings.txt");
    assert_eq!(Settings::load(&path), Settings::default());
    let s = Settings {
        shading: ShadingModel::Oss,
        best: 42,
        close_camera: true,
        skins: vec![("WomanTankTop.glb".into(), "Skin=skin1".into())],
    };
    s.save(&path).unwrap();
    assert_eq!(Settings::load(&path), s);
    let s2 = Settings {
        shading: ShadingModel::Ward,
        best: 43,
        close_camera: false,
        skins: Vec::new(),
    };
    s2.save(&path).unwrap();
    assert_eq!(Settings::load(&path), s2);
    let leftovers: Vec<_> = std::fs::read_dir(path.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "no temp file left: {leftovers:?}");
    std::fs::write(&path, [0xff, 0xfe, 0x00, b'=', b'\n']).unwrap();
    assert_eq!(Settings::load(&path), Settings::default());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gestures_become_taps_and_swipes() {
    let g = |d: (f32, f32), u: (f32, f32)| Input::from_gesture(d, u, 30.0);
    assert_eq!(g((100.0, 100.0), (110.0, 95.0)).tap, Some((110.0, 95.0)));
    assert_eq!(g((100.0, 100.0), (20.0, 110.0)).swipe, Some(Swipe::Left));
    assert_eq!(g((100.0, 100.0), (180.0, 90.0)).swipe, Some(Swipe::Right));
    assert_eq!(g((100.0, 100.0), (110.0, 20.0)).swipe, Some(Swipe::Up));
    assert_eq!(g((100.0, 100.0), (90.0, 180.0)).swipe, Some(Swipe::Down));
    // A swipe up jumps, a tap in play jumps.
    let mut game = playing(1000.0);
    game.tick(&g((100.0, 100.0), (110.0, 20.0)));
    assert!(game.is_airborne());
    let mut game = playing(1000.0);
    game.tick(&g((100.0, 100.0), (100.0, 100.0)));
    assert!(game.is_airborne());
}

#[test]
fn a_bot_that_gives_up_ends_its_run_within_seconds() {
    // `play --screenshots` relies on it to reach the game-over screen.
    for seed in 1..=12u64 {
        let mut g = Game::new(seed);
        let mut bot = dermis_game::rules::Bot::new(seed);
        while g.screen() != Screen::Play || g.screen_ticks() < 2 * TICK_HZ {
            g.tick(&bot.decide(&g));
        }
        bot.give_up();
        assert!(!bot.is_playing());
        let mut ticks = 0;
        while g.screen() == Screen::Play {
            g.tick(&bot.decide(&g));
            ticks += 1;
            assert!(
                ticks < 15 * TICK_HZ,
                "seed {seed}: still running after 15 s"
            );
        }
        assert_eq!(g.screen(), Screen::GameOver);
    }
}

//! The renderer under a mid-range phone's limits (`Gpu::PHONE_LIMITS`: Khronos' Vulkan profile
//! VP_ANDROID_baseline_2022 as wgpu maps it, within wgpu's downlevel defaults): the device
//! `Gpu::headless()` (like the window and the Android app) creates has exactly those limits on
//! lavapipe, and the game, every shading model, the unlit baseline, the props and the
//! subsurface pass all run under them without a single validation error. (Every other GPU
//! test runs under them too: they all go through `Gpu::headless()`.)

use std::path::Path;
use std::sync::{Arc, Mutex};

use dermis_engine::render::{Clock, FrameDriver, Gpu, Offscreen, Output, OFFSCREEN_FORMAT};
use dermis_engine::scene::SceneAssets;
use dermis_engine::shading::{material::SKIN1, ShadingModel};
use dermis_engine::still::{Shot, StillRenderer};
use dermis_game::app::{GameFrame, GameGpu, Session};

fn gpu() -> Gpu {
    Gpu::headless().unwrap_or_else(|e| panic!("{e}"))
}

fn assets() -> SceneAssets {
    SceneAssets::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"), None)
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_device_has_exactly_the_phone_limits() {
    let gpu = gpu();
    let adapter = gpu.adapter.limits();
    let device = gpu.device.limits();
    assert_eq!(device, Gpu::phone_limits(&adapter));
    // lavapipe (like any desktop GPU) offers more than the phone everywhere, so the device gets
    // exactly the phone's limits, not the machine's.
    if gpu.is_cpu() {
        let mut over = Vec::new();
        Gpu::PHONE_LIMITS.check_limits_with_fail_fn(&adapter, false, |name, want, has| {
            over.push(format!("{name}: phone {want}, adapter {has}"))
        });
        assert!(over.is_empty(), "lavapipe below the phone: {over:?}");
    }
    if Gpu::PHONE_LIMITS.check_limits(&adapter) {
        assert_eq!(device, Gpu::PHONE_LIMITS);
    }
}

#[test]
fn the_phone_limits_are_within_the_downlevel_defaults_but_for_the_screen() {
    let down = wgpu::Limits::downlevel_defaults();
    let phone = Gpu::PHONE_LIMITS;
    // Only the texture sizes exceed GLES 3.1's minimums: a phone's swapchain is 2400 wide.
    assert!(phone
        .clone()
        .using_resolution(down.clone())
        .check_limits(&down));
    assert_eq!(phone.max_texture_dimension_2d, 4096);
    // The profile's own values where they are stricter than wgpu's downlevel defaults.
    assert_eq!(phone.max_compute_invocations_per_workgroup, 128);
    assert_eq!(phone.max_color_attachments, 3);
    assert_eq!(phone.max_uniform_buffer_binding_size, 16 << 10);
    // A weaker adapter lowers the request instead of failing device creation.
    let gles30 = wgpu::Limits::downlevel_webgl2_defaults();
    let asked = Gpu::phone_limits(&gles30);
    assert!(asked.check_limits(&gles30) && asked.check_limits(&phone));
}

#[test]
fn the_game_every_model_and_every_pass_run_under_the_phone_limits() {
    let gpu = gpu();
    let errors = Arc::new(Mutex::new(Vec::<String>::new()));
    let sink = errors.clone();
    gpu.device
        .on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap().push(e.to_string());
        }));
    let assets = assets();

    // Stills: every model with the props (main, props and — for the spatial models — the
    // subsurface pass), then the unlit baseline.
    let (w, h) = (160, 90);
    let mut still = StillRenderer::new(&gpu, &assets, w, h).unwrap();
    let mut shots: Vec<Shot> = ShadingModel::ALL
        .iter()
        .map(|&m| Shot::new(m, SKIN1))
        .collect();
    shots.push(Shot {
        shading: None,
        ..Shot::new(ShadingModel::ALL[0], SKIN1)
    });
    for shot in &shots {
        let img = still.render(&gpu, &assets, shot).unwrap();
        let first = &img.pixels[..4];
        assert!(
            img.pixels.chunks(4).any(|p| p != first),
            "{:?}: an empty image",
            shot.shading
        );
    }

    // The game: the bot plays and the player steps through every model (UI pass included).
    let mut gg = GameGpu::new(&gpu, OFFSCREEN_FORMAT, &assets, ShadingModel::DEFAULT).unwrap();
    let target = Offscreen::new(&gpu, w, h);
    let mut session = Session::new(&assets.character, 7, None, true);
    let mut driver = FrameDriver::new(Clock::Fixed(1.0 / 60.0));
    driver.sync = true;
    let mut seen = Vec::new();
    for frame in 0..(ShadingModel::ALL.len() * 8) {
        if frame % 8 == 7 {
            let next = session.shading().next();
            session.settings.set_shading_model(next);
        }
        GameFrame::new(&mut session, &mut gg, &assets.character)
            .run(&mut driver, &gpu, Output::Offscreen(&target))
            .unwrap();
        if !seen.contains(&session.shading()) {
            seen.push(session.shading());
        }
    }
    gpu.wait();
    assert_eq!(
        seen.len(),
        ShadingModel::ALL.len(),
        "models played: {seen:?}"
    );
    let errors = errors.lock().unwrap();
    assert!(
        errors.is_empty(),
        "validation errors under the phone limits:\n{}",
        errors.join("\n")
    );
}

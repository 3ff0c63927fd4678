//! The UI renderer on a real driver (lavapipe at least): the pipeline validates inside the
//! frame's MSAA pass (depth attachment, Always / no write), one draw call draws the whole UI,
//! and the pixels show the skin (panel, button, glyphs) with the authored colours.

use dermis_core::render::{Gpu, Offscreen, UiRenderer, MSAA_SAMPLES, OFFSCREEN_FORMAT};
use dermis_core::ui::{atlas_rgba, Insets, Rect, Ui};

const W: u32 = 320;
const H: u32 = 200;
const CLEAR: [f64; 3] = [0.0, 0.0, 0.0];

fn render(gpu: &Gpu, target: &Offscreen, ui_gpu: &UiRenderer) -> Vec<u8> {
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.targets.msaa,
                depth_slice: None,
                resolve_target: Some(&target.view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: CLEAR[0],
                        g: CLEAR[1],
                        b: CLEAR[2],
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &target.targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        assert_eq!(ui_gpu.draw(&mut pass), 1, "one draw call");
    }
    target.copy_out(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    target.read(gpu).pixels
}

#[test]
fn ui_renders_with_one_draw_call() {
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let (rgba, aw, ah) = atlas_rgba();
    let mut ui_gpu = UiRenderer::new(
        &gpu.device,
        &gpu.queue,
        OFFSCREEN_FORMAT,
        MSAA_SAMPLES,
        &rgba,
        aw,
        ah,
    );
    let target = Offscreen::new(&gpu, W, H);
    let mut ui = Ui::with_embedded_atlas();
    ui.begin(W as f32, H as f32, 1.0, Insets::ZERO);
    ui.fill(Rect::new(0.0, 0.0, 40.0, 40.0), [1.0, 0.0, 0.0, 1.0]);
    ui.panel(Rect::new(60.0, 20.0, 200.0, 80.0));
    ui.button("b", Rect::new(60.0, 120.0, 200.0, 60.0), "");
    ui.label([10.0, 60.0], "I", 48.0);
    ui.end();
    assert!(ui.needs_upload());
    ui_gpu.resize(&gpu.queue, W, H);
    ui_gpu.upload(&gpu.queue, ui.vertices());
    ui.mark_uploaded();
    assert_eq!(ui_gpu.vertex_count() as usize, ui.vertices().len());
    let px = render(&gpu, &target, &ui_gpu);
    if let Ok(path) = std::env::var("DERMIS_UI_GPU_PNG") {
        image::save_buffer(path, &px, W, H, image::ExtendedColorType::Rgba8).unwrap();
    }
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");
    let at = |x: u32, y: u32| {
        let i = ((y * W + x) * 4) as usize;
        [px[i], px[i + 1], px[i + 2]]
    };
    // The solid fill keeps its authored (display) colour through the sRGB target.
    assert_eq!(at(20, 20), [255, 0, 0]);
    // Nothing outside the widgets.
    assert_eq!(at(300, 10), [0, 0, 0]);
    // The panel's dark translucent fill, the button's blue, the glyph's white stroke.
    let panel = at(160, 60);
    assert!(
        panel[2] > panel[0] && panel[2] > 15 && panel[2] < 80,
        "panel {panel:?}"
    );
    let button = at(160, 150);
    assert!(
        button[2] > 120 && button[2] > button[0] + 50,
        "button {button:?}"
    );
    // 'I' at size 48 = 2 pixels per atlas texel; the quad starts 3 texels left of the pen and
    // the stem is font column 2 (texels 7..9 of the cell): pixels 18..22.
    let stem = (0..48)
        .map(|dy| at(20, 60 + dy))
        .filter(|c| c.iter().all(|v| *v > 230))
        .count();
    assert!(stem > 10, "glyph stem pixels: {stem}");
    // An empty UI draws nothing.
    ui_gpu.upload(&gpu.queue, &[]);
    let mut encoder = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.targets.msaa,
                depth_slice: None,
                resolve_target: Some(&target.view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        assert_eq!(ui_gpu.draw(&mut pass), 0);
    }
    gpu.queue.submit([encoder.finish()]);
}

#[test]
fn game_screens_render() {
    use dermis_core::app::{GameUi, Settings};
    use dermis_core::game::{Game, Screen, TICK_DT};
    const SW: u32 = 960;
    const SH: u32 = 540;
    let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let (rgba, aw, ah) = atlas_rgba();
    let mut ui_gpu = UiRenderer::new(
        &gpu.device,
        &gpu.queue,
        OFFSCREEN_FORMAT,
        MSAA_SAMPLES,
        &rgba,
        aw,
        ah,
    );
    ui_gpu.resize(&gpu.queue, SW, SH);
    let target = Offscreen::new(&gpu, SW, SH);
    let mut ui = Ui::with_embedded_atlas();
    let mut gui = GameUi::new();
    let mut game = Game::new(4);
    let mut settings = Settings::default();
    let mut shot = |ui: &mut Ui, game: &mut Game, name: &str| {
        ui.begin(
            SW as f32,
            SH as f32,
            1.0,
            Insets {
                left: 0.0,
                top: 20.0,
                right: 0.0,
                bottom: 20.0,
            },
        );
        gui.draw(ui, game, &mut settings);
        ui.end();
        if ui.needs_upload() {
            ui_gpu.upload(&gpu.queue, ui.vertices());
            ui.mark_uploaded();
        }
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: None,
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.targets.msaa,
                    depth_slice: None,
                    resolve_target: Some(&target.view),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.2,
                            g: 0.25,
                            b: 0.2,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Discard,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            assert_eq!(ui_gpu.draw(&mut pass), 1);
        }
        target.copy_out(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        let img = target.read(&gpu);
        if let Ok(dir) = std::env::var("DERMIS_UI_SCREENS") {
            let path = std::path::Path::new(&dir).join(format!("{name}.png"));
            image::save_buffer(path, &img.pixels, SW, SH, image::ExtendedColorType::Rgba8).unwrap();
        }
    };
    shot(&mut ui, &mut game, "main");
    game.start();
    for _ in 0..300 {
        game.update(TICK_DT, &dermis_core::game::Input::NONE);
    }
    shot(&mut ui, &mut game, "play");
    while game.screen() == Screen::Play {
        game.update(TICK_DT, &dermis_core::game::Input::NONE);
    }
    shot(&mut ui, &mut game, "game_over");
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");
}

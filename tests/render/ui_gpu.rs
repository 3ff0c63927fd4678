//! The UI pass on a real driver (lavapipe at least): a renderer with the UI and nothing else,
//! frames prepared from packets that hand over the UI's vertices. One draw call draws the
//! whole UI, its pixels show the skin (panel, button, glyphs) in the authored colours, and
//! each game screen shows what it says: its labels' glyphs inside their rectangles, its
//! buttons blue, the background untouched outside the widgets.

use dermis_engine::render::passes::PassId;
use dermis_engine::render::{Gpu, Offscreen, PipelineSet, RenderStats, Renderer, OFFSCREEN_FORMAT};
use dermis_engine::scene::{DrawSet, FramePacket, FrameView, Light};
use dermis_engine::ui::{Insets, Rect, Ui, UiVertex};
use glam::{Mat4, Vec3};

/// The background every UI frame is cleared to (displayed colour, 0..255).
const CLEAR: wgpu::Color = wgpu::Color {
    r: 0.0,
    g: 0.0,
    b: 0.0,
    a: 1.0,
};

/// A renderer that draws only the UI, and its target.
struct UiRig {
    gpu: Gpu,
    renderer: Renderer,
    target: Offscreen,
}

impl UiRig {
    fn new(width: u32, height: u32) -> Self {
        let gpu = Gpu::headless().unwrap_or_else(|e| panic!("{e}"));
        let nothing = PipelineSet {
            models: Vec::new(),
            unlit: false,
        };
        let mut renderer = Renderer::with_pipelines(&gpu, OFFSCREEN_FORMAT, &nothing);
        renderer.set_clear(CLEAR);
        renderer.enable(&gpu, PassId::ui);
        renderer.resize(&gpu, (width, height));
        let target = Offscreen::new(&gpu, width, height);
        Self {
            gpu,
            renderer,
            target,
        }
    }

    /// A frame of the UI alone, drawing `vertices`.
    fn draw(&mut self, vertices: &[UiVertex]) -> (RenderStats, Vec<u8>) {
        let size = (self.target.targets.width, self.target.targets.height);
        let view = FrameView {
            view_proj: Mat4::IDENTITY,
            camera_pos: Vec3::ZERO,
            light: Light::default(),
            exposure: 1.0,
        };
        let draw = DrawSet {
            shading: None,
            character: false,
            props: false,
            ui: true,
        };
        let packet = FramePacket {
            ui: vertices,
            ..FramePacket::new(size, view, draw)
        };
        let frame = self.renderer.prepare(&self.gpu, &packet);
        let stats = self
            .renderer
            .draw_offscreen(&self.gpu, &self.target, &frame)
            .unwrap();
        (stats, self.target.read(&self.gpu).pixels)
    }
}

/// The pixel at (x, y) of a `width`-wide RGBA image.
fn at(px: &[u8], width: u32, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * width + x) * 4) as usize;
    [px[i], px[i + 1], px[i + 2]]
}

/// The pixels of `r` (logical units at scale 1) that satisfy `f`, and all of them.
fn count_in(px: &[u8], width: u32, r: Rect, f: impl Fn([u8; 3]) -> bool) -> (usize, usize) {
    let (x0, y0) = (r.x.max(0.0) as u32, r.y.max(0.0) as u32);
    let (x1, y1) = ((r.x + r.w) as u32, (r.y + r.h) as u32);
    let height = (px.len() / 4) as u32 / width;
    let mut n = (0, 0);
    for y in y0..y1.min(height) {
        for x in x0..x1.min(width) {
            n.1 += 1;
            n.0 += usize::from(f(at(px, width, x, y)));
        }
    }
    n
}

#[test]
fn ui_renders_with_one_draw_call() {
    const W: u32 = 320;
    const H: u32 = 200;
    let mut rig = UiRig::new(W, H);
    let scope = rig
        .gpu
        .device
        .push_error_scope(wgpu::ErrorFilter::Validation);
    let mut ui = Ui::with_embedded_atlas();
    ui.begin(W as f32, H as f32, 1.0, Insets::ZERO);
    ui.fill(Rect::new(0.0, 0.0, 40.0, 40.0), [1.0, 0.0, 0.0, 1.0]);
    ui.panel(Rect::new(60.0, 20.0, 200.0, 80.0));
    ui.button("b", Rect::new(60.0, 120.0, 200.0, 60.0), "");
    ui.label([10.0, 60.0], "I", 48.0);
    ui.end();
    assert!(ui.needs_upload());
    let (stats, px) = rig.draw(ui.vertices());
    if let Ok(path) = std::env::var("DERMIS_UI_GPU_PNG") {
        image::save_buffer(path, &px, W, H, image::ExtendedColorType::Rgba8).unwrap();
    }
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");
    assert_eq!(stats.draw_calls, 1, "one draw call: {stats:?}");
    let at = |x, y| at(&px, W, x, y);
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
    let (stats, px) = rig.draw(&[]);
    assert_eq!(stats.draw_calls, 0, "{stats:?}");
    assert!(px.chunks_exact(4).all(|p| p[..3] == [0, 0, 0]));
}

#[test]
fn each_game_screen_shows_what_it_says() {
    use dermis_game::app::{GameUi, Settings};
    use dermis_game::rules::{Game, Input, Screen, TICK_DT};
    const SW: u32 = 960;
    const SH: u32 = 540;
    let mut rig = UiRig::new(SW, SH);
    let scope = rig
        .gpu
        .device
        .push_error_scope(wgpu::ErrorFilter::Validation);
    let mut ui = Ui::with_embedded_atlas();
    let mut gui = GameUi::new();
    let mut game = Game::new(4);
    let mut settings = Settings::default();
    let insets = Insets {
        left: 0.0,
        top: 20.0,
        right: 0.0,
        bottom: 20.0,
    };
    // Each screen's labels and buttons, and its pixels.
    let mut shot = |ui: &mut Ui, game: &mut Game, name: &str| {
        ui.begin(SW as f32, SH as f32, 1.0, insets);
        gui.draw(ui, game, &mut settings);
        ui.end();
        let (stats, px) = rig.draw(ui.vertices());
        assert_eq!(stats.draw_calls, 1, "{name}: {stats:?}");
        if let Ok(dir) = std::env::var("DERMIS_UI_SCREENS") {
            let path = std::path::Path::new(&dir).join(format!("{name}.png"));
            image::save_buffer(path, &px, SW, SH, image::ExtendedColorType::Rgba8).unwrap();
        }
        let labels: Vec<(String, Rect)> =
            ui.label_rects().map(|(t, r)| (t.to_string(), r)).collect();
        let buttons: Vec<Rect> = ui.button_rects().collect();
        let widgets: Vec<Rect> = ui
            .panel_rects()
            .chain(buttons.iter().copied())
            .chain(labels.iter().map(|(_, r)| *r))
            .collect();
        // Every label's glyphs are drawn inside its rectangle: bright pixels, and not all.
        for (text, r) in &labels {
            let (bright, all) = count_in(&px, SW, *r, |c| c.iter().any(|v| *v > 150));
            assert!(
                bright > all / 50 && bright < all,
                "{name}: label {text:?} at {r:?} shows {bright} bright of {all} pixels"
            );
        }
        // Every button is blue inside.
        for r in &buttons {
            let inner = Rect::new(r.x + 4.0, r.y + 4.0, r.w - 8.0, r.h - 8.0);
            let (blue, all) = count_in(&px, SW, inner, |c| {
                c[2] > 100 && i32::from(c[2]) > i32::from(c[0]) + 40
            });
            assert!(blue > all / 2, "{name}: button {r:?}: {blue} blue of {all}");
        }
        // Outside every widget (a pixel in each corner of the safe area), the background.
        for (x, y) in [(2, 22), (SW - 3, 22), (2, SH - 23), (SW - 3, SH - 23)] {
            let inside = widgets.iter().any(|r| r.contains([x as f32, y as f32]));
            if !inside {
                assert_eq!(at(&px, SW, x, y), [0, 0, 0], "{name}: ({x}, {y})");
            }
        }
        (labels, buttons.len())
    };
    let texts = |labels: &[(String, Rect)]| -> Vec<String> {
        labels.iter().map(|(t, _)| t.clone()).collect()
    };

    let (labels, buttons) = shot(&mut ui, &mut game, "main");
    assert!(
        buttons >= 2,
        "main: the skin option and Start: {buttons} buttons"
    );
    assert!(
        texts(&labels).iter().any(|t| t.starts_with("Best: ")),
        "main: {:?}",
        texts(&labels)
    );
    game.start();
    for _ in 0..300 {
        game.update(TICK_DT, &Input::NONE);
    }
    let (labels, buttons) = shot(&mut ui, &mut game, "play");
    let score = format!("{} m", game.score());
    assert!(
        texts(&labels).contains(&score),
        "play: {:?}",
        texts(&labels)
    );
    assert_eq!(buttons, 1, "play: the View button");
    while game.screen() == Screen::Play {
        game.update(TICK_DT, &Input::NONE);
    }
    let (labels, buttons) = shot(&mut ui, &mut game, "game_over");
    let said = texts(&labels);
    assert!(said.iter().any(|t| t == "GAME OVER"), "game over: {said:?}");
    assert!(
        said.contains(&format!("Score: {} m", game.score())),
        "game over: {said:?}"
    );
    assert_eq!(buttons, 1, "game over: Replay");
    let error = pollster::block_on(scope.pop());
    assert!(error.is_none(), "{error:?}");
}

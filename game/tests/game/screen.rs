//! Where the session's UI and character land on screen, for the layout tests.

use dermis_engine::ui::Rect;
use dermis_game::app::{Session, Viewport};
use glam::{Vec3, Vec4Swizzles};

/// Whether `a` lies inside `b` (logical units, 0.01 slack).
pub fn inside(a: &Rect, b: &Rect) -> bool {
    a.x >= b.x - 0.01
        && a.y >= b.y - 0.01
        && a.x + a.w <= b.x + b.w + 0.01
        && a.y + a.h <= b.y + b.h + 0.01
}

/// The screen rectangle (logical units) of the box `lo..hi` (world) as the session draws it.
pub fn on_screen(s: &Session, vp: &Viewport, lo: Vec3, hi: Vec3) -> Rect {
    let aspect = vp.width as f32 / vp.height as f32;
    let m = s.view().view_proj(aspect);
    let (w, h) = (vp.width as f32 / vp.scale, vp.height as f32 / vp.scale);
    let (mut a, mut b) = ([f32::MAX; 2], [f32::MIN; 2]);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let p = m * c.extend(1.0);
        assert!(p.w > 0.0);
        let ndc = p.xy() / p.w;
        let (x, y) = ((ndc.x + 1.0) * 0.5 * w, (1.0 - ndc.y) * 0.5 * h);
        a = [a[0].min(x), a[1].min(y)];
        b = [b[0].max(x), b[1].max(y)];
    }
    Rect::new(a[0], a[1], b[0] - a[0], b[1] - a[1])
}

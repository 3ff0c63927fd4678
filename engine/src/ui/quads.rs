//! The UI's vertices: pixel-snapped quads from the atlas (sprites, 9-slice panels, text)
//! with premultiplied colours, appended to the one vertex list the UI draws in one call.

use super::{Atlas, Color, Rect, Sprite, TexRect, UiVertex, MAX_VERTICES, WHITE};

pub(super) struct Builder<'a> {
    pub atlas: &'a Atlas,
    pub scale: f32,
    pub out: &'a mut Vec<UiVertex>,
}

fn premultiply(c: Color) -> [u8; 4] {
    let a = c[3].clamp(0.0, 1.0);
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    [q(c[0] * a), q(c[1] * a), q(c[2] * a), q(a)]
}

impl Builder<'_> {
    /// A logical rect in physical pixels, snapped to whole pixels.
    pub fn px(&self, r: &Rect) -> [f32; 4] {
        let s = self.scale;
        let (x0, y0) = ((r.x * s).round(), (r.y * s).round());
        let (x1, y1) = (((r.x + r.w) * s).round(), ((r.y + r.h) * s).round());
        [x0, y0, x1, y1]
    }

    /// A quad from pixel corners `[x0, y0, x1, y1]` sampling texel rect `[x, y, w, h]`.
    pub fn quad(&mut self, p: [f32; 4], t: TexRect, color: Color) {
        if p[2] <= p[0] || p[3] <= p[1] || self.out.len() + 6 > MAX_VERTICES {
            return;
        }
        let (iw, ih) = (
            1.0 / self.atlas.width as f32,
            1.0 / self.atlas.height as f32,
        );
        let uv = [t[0] * iw, t[1] * ih, (t[0] + t[2]) * iw, (t[1] + t[3]) * ih];
        let color = premultiply(color);
        let v = |x: f32, y: f32, u: f32, w: f32| UiVertex {
            pos: [x, y],
            uv: [u, w],
            color,
        };
        let (a, b, c, d) = (
            v(p[0], p[1], uv[0], uv[1]),
            v(p[2], p[1], uv[2], uv[1]),
            v(p[2], p[3], uv[2], uv[3]),
            v(p[0], p[3], uv[0], uv[3]),
        );
        self.out.extend_from_slice(&[a, b, c, a, c, d]);
    }

    /// A 9-slice sprite: corners keep their size (border drawn at 0.75 logical units per
    /// texel), edges and centre stretch.
    pub fn nine_slice(&mut self, rect: &Rect, sprite: &Sprite) {
        let p = self.px(rect);
        let t = sprite.rect;
        let bt = sprite.border;
        let bp = (bt * 0.75 * self.scale)
            .round()
            .min(((p[2] - p[0]) * 0.5).floor())
            .min(((p[3] - p[1]) * 0.5).floor());
        let xs = [p[0], p[0] + bp, p[2] - bp, p[2]];
        let ys = [p[1], p[1] + bp, p[3] - bp, p[3]];
        let us = [t[0], t[0] + bt, t[0] + t[2] - bt, t[0] + t[2]];
        let vs = [t[1], t[1] + bt, t[1] + t[3] - bt, t[1] + t[3]];
        for j in 0..3 {
            for i in 0..3 {
                self.quad(
                    [xs[i], ys[j], xs[i + 1], ys[j + 1]],
                    [us[i], vs[j], us[i + 1] - us[i], vs[j + 1] - vs[j]],
                    WHITE,
                );
            }
        }
    }

    pub fn text(&mut self, pos: [f32; 2], s: &str, size: f32, color: Color) {
        let k = size / self.atlas.line_height * self.scale;
        // Pixel-snap the pen start; glyph quads are then integer-aligned when k is.
        let mut x = (pos[0] * self.scale).round();
        let y = (pos[1] * self.scale).round();
        for c in s.bytes() {
            let g = *self.atlas.glyph(c);
            if c != b' ' {
                let x0 = x + g.offset[0] * k;
                let y0 = y + g.offset[1] * k;
                self.quad(
                    [x0, y0, x0 + g.rect[2] * k, y0 + g.rect[3] * k],
                    g.rect,
                    color,
                );
            }
            x += g.advance * k;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn premultiplied_colours() {
        assert_eq!(premultiply([1.0, 0.5, 0.0, 0.5]), [128, 64, 0, 128]);
    }
}

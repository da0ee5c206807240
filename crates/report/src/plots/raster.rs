//! The PNG pass: a bitmap backend that draws anti-aliased lines and the
//! embedded font's glyphs, and the PNG encoding.

use super::text::font_ref;
use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};

/// A bitmap backend drawing anti-aliased paths and text with the embedded
/// font, glyphs placed by their own bearings (plotters' bitmap text drops
/// the left bearing, which spaces letters unevenly). Anything else is drawn
/// by the wrapped backend.
pub(super) struct Smooth<B> {
    inner: B,
    font: &'static FontRef<'static>,
}

impl<B: DrawingBackend> Smooth<B> {
    pub(super) fn new(inner: B) -> Result<Self, &'static str> {
        let font = font_ref().ok_or("the embedded font could not be loaded")?;
        Ok(Smooth { inner, font })
    }

    /// Blends `color` at coverage `cov` into each pixel.
    fn blend(
        &mut self,
        pixels: Vec<((i32, i32), f32)>,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        for (p, cov) in pixels {
            if cov > 0.0 {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(cov.min(1.0)),
                    rgb: color.rgb,
                };
                self.inner.draw_pixel(p, c)?;
            }
        }
        Ok(())
    }
}

/// Coverage of the pixels within `width / 2` of the polyline `path` (pixel
/// centres at integer coordinates, as the backend's), each pixel counted
/// once with its largest coverage.
fn stroke_coverage(path: &[(i32, i32)], width: f64, (w, h): (u32, u32)) -> Vec<((i32, i32), f32)> {
    let half = 0.5 * width.max(1.0);
    let mut cov: std::collections::HashMap<(i32, i32), f32> = std::collections::HashMap::new();
    for seg in path.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let (ax, ay, bx, by) = (f64::from(a.0), f64::from(a.1), f64::from(b.0), f64::from(b.1));
        let reach = half + 1.0;
        let x0 = (ax.min(bx) - reach).floor().max(0.0) as i32;
        let x1 = (ax.max(bx) + reach).ceil().min(f64::from(w) - 1.0) as i32;
        let y0 = (ay.min(by) - reach).floor().max(0.0) as i32;
        let y1 = (ay.max(by) + reach).ceil().min(f64::from(h) - 1.0) as i32;
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = dx * dx + dy * dy;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (f64::from(x) - ax, f64::from(y) - ay);
                let t = if len2 > 0.0 {
                    ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (px - t * dx).hypot(py - t * dy);
                let c = (half + 0.5 - d).clamp(0.0, 1.0) as f32;
                if c > 0.0 {
                    let e = cov.entry((x, y)).or_insert(0.0);
                    *e = e.max(c);
                }
            }
        }
    }
    cov.into_iter().collect()
}

impl<B: DrawingBackend> DrawingBackend for Smooth<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.draw_path([from, to], style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let path: Vec<_> = path.into_iter().collect();
        let pixels = stroke_coverage(&path, f64::from(style.stroke_width()), self.get_size());
        self.blend(pixels, style.color())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let font = self.font.as_scaled(style.size() as f32);
        let mut pen = 0.0f32;
        let mut prev = None;
        let mut glyphs = Vec::with_capacity(text.len());
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                pen += font.kern(p, id);
            }
            glyphs.push((id, pen));
            pen += font.h_advance(id);
            prev = Some(id);
        }
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * pen,
            HPos::Right => -pen,
        };
        let (ascent, descent) = (font.ascent(), font.descent());
        let baseline = match anchor.v_pos {
            VPos::Top => ascent,
            VPos::Center => 0.5 * (ascent + descent),
            VPos::Bottom => descent,
        };
        let trans = style.transform();
        let mut pixels = Vec::new();
        for (id, x) in glyphs {
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(x + dx, baseline));
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let min = outline.px_bounds().min;
                outline.draw(|gx, gy, c| {
                    let (lx, ly) = (min.x as i32 + gx as i32, min.y as i32 + gy as i32);
                    let (tx, ty) = trans.transform(lx, ly);
                    pixels.push(((pos.0 + tx, pos.1 + ty), c));
                });
            }
        }
        self.blend(pixels, color)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }
}

pub(super) fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(out)
}

//! [`Image`]: an RGB canvas with a depth buffer; filled triangles with depth, anti-aliased
//! thick lines (coverage from the distance to the segment), PNG encoding (`png` crate).

use super::{BACKGROUND, Rgb};
use crate::report::ReportError;
use std::ops::RangeInclusive;
use std::path::Path;

/// An RGB image with a depth buffer (larger depth = nearer the viewer).
#[derive(Clone, Debug)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Pixels, row after row from the top, in single precision (an 8-bit picture needs no
    /// more, and a picture's buffers are made fresh at the end of every run, where the user
    /// waits).
    pub pixels: Vec<[f32; 3]>,
    /// Depth of the nearest surface drawn at each pixel (`-inf` where none); empty until the
    /// first triangle is drawn (a picture of lines alone never needs it).
    pub depth: Vec<f64>,
}

impl Image {
    /// A blank image of the background colour.
    pub fn new(width: usize, height: usize) -> Image {
        Image {
            width,
            height,
            pixels: vec![BACKGROUND.map(|c| c as f32); width * height],
            depth: Vec::new(),
        }
    }

    /// The depth of the nearest surface drawn at pixel `i` (`-inf` where none).
    fn depth_at(&self, i: usize) -> f64 {
        self.depth.get(i).copied().unwrap_or(f64::NEG_INFINITY)
    }

    /// Blends `color` over pixel `(x, y)` with opacity `alpha` (ignored outside the image).
    pub fn blend(&mut self, x: i64, y: i64, color: Rgb, alpha: f64) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 || alpha <= 0.0 {
            return;
        }
        let a = alpha.min(1.0);
        let p = &mut self.pixels[y as usize * self.width + x as usize];
        for k in 0..3 {
            p[k] = (f64::from(p[k]) * (1.0 - a) + color[k] * a) as f32;
        }
    }

    /// Fills an axis-aligned rectangle.
    pub fn fill_rect(&mut self, x0: i64, y0: i64, w: i64, h: i64, color: Rgb, alpha: f64) {
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.blend(x, y, color, alpha);
            }
        }
    }

    /// The columns and rows of the pixels in the box from `lo` to `hi` (image coordinates)
    /// that lie in the image; `None` when none does.
    fn pixels_in(
        &self,
        lo: (f64, f64),
        hi: (f64, f64),
    ) -> Option<(RangeInclusive<usize>, RangeInclusive<usize>)> {
        let (x0, y0) = (lo.0.floor().max(0.0), lo.1.floor().max(0.0));
        let x1 = hi.0.ceil().min(self.width as f64 - 1.0);
        let y1 = hi.1.ceil().min(self.height as f64 - 1.0);
        (x0 <= x1 && y0 <= y1).then_some((x0 as usize..=x1 as usize, y0 as usize..=y1 as usize))
    }

    /// Fills a triangle given in screen coordinates `(x, y, depth)`, shaded `color`, with a
    /// depth test and depth writes.
    pub fn triangle(&mut self, p: [[f64; 3]; 3], color: Rgb) {
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if !(area.abs() > 1e-12) {
            return;
        }
        let [xs, ys] = [0, 1].map(|k| p.map(|q| q[k]));
        let lo = |v: [f64; 3]| v.into_iter().fold(f64::INFINITY, f64::min);
        let hi = |v: [f64; 3]| v.into_iter().fold(f64::NEG_INFINITY, f64::max);
        let Some((cols, rows)) = self.pixels_in((lo(xs), lo(ys)), (hi(xs), hi(ys))) else {
            return;
        };
        if self.depth.is_empty() {
            self.depth = vec![f64::NEG_INFINITY; self.width * self.height];
        }
        for y in rows {
            for x in cols.clone() {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let w0 = ((p[1][0] - px) * (p[2][1] - py) - (p[2][0] - px) * (p[1][1] - py)) / area;
                let w1 = ((p[2][0] - px) * (p[0][1] - py) - (p[0][0] - px) * (p[2][1] - py)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                    continue;
                }
                let d = w0 * p[0][2] + w1 * p[1][2] + w2 * p[2][2];
                let i = y * self.width + x;
                if d > self.depth[i] {
                    self.depth[i] = d;
                    self.pixels[i] = color.map(|c| c as f32);
                }
            }
        }
    }

    /// Draws an anti-aliased line of `width` pixels from `a` to `b` (screen `(x, y, depth)`),
    /// its colour interpolated from `ca` to `cb`. Where the depth buffer holds something
    /// nearer (by more than `bias`), the line is drawn with opacity `hidden_alpha` instead of 1.
    pub fn line(
        &mut self,
        a: [f64; 3],
        b: [f64; 3],
        width: f64,
        ca: Rgb,
        cb: Rgb,
        hidden_alpha: f64,
        bias: f64,
    ) {
        let r = 0.5 * width;
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let Some((cols, rows)) = self.pixels_in(
            (a[0].min(b[0]) - r - 1.0, a[1].min(b[1]) - r - 1.0),
            (a[0].max(b[0]) + r + 1.0, a[1].max(b[1]) + r + 1.0),
        ) else {
            return;
        };
        for y in rows {
            for x in cols.clone() {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let t = if len2 > 0.0 {
                    (((px - a[0]) * dx + (py - a[1]) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (qx, qy) = (a[0] + t * dx, a[1] + t * dy);
                let dist = ((px - qx).powi(2) + (py - qy).powi(2)).sqrt();
                let cover = (r + 0.5 - dist).clamp(0.0, 1.0);
                if cover <= 0.0 {
                    continue;
                }
                let d = a[2] + t * (b[2] - a[2]);
                let i = y * self.width + x;
                let alpha = if self.depth_at(i) > d + bias {
                    hidden_alpha
                } else {
                    1.0
                };
                let c = [
                    ca[0] + t * (cb[0] - ca[0]),
                    ca[1] + t * (cb[1] - ca[1]),
                    ca[2] + t * (cb[2] - ca[2]),
                ];
                self.blend(x as i64, y as i64, c, cover * alpha);
            }
        }
    }

    /// A 2D anti-aliased line with no depth.
    pub fn line2d(&mut self, a: (f64, f64), b: (f64, f64), width: f64, color: Rgb) {
        self.line(
            [a.0, a.1, f64::INFINITY],
            [b.0, b.1, f64::INFINITY],
            width,
            color,
            color,
            1.0,
            0.0,
        );
    }

    /// The image as 8-bit RGB bytes, row after row.
    pub fn rgb_bytes(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (f64::from(c).clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }

    /// The image as a PNG file.
    pub fn to_png(&self) -> Result<Vec<u8>, ReportError> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            // Fast: the pictures are written at the end of every run, where the user waits;
            // a smaller file is not worth the time (`docs/benchmarks.md`, *Figures behind the
            // code's rules*).
            enc.set_compression(png::Compression::Fast);
            let mut w = enc.write_header().map_err(|e| e.to_string())?;
            w.write_image_data(&self.rgb_bytes())
                .map_err(|e| e.to_string())?;
            w.finish().map_err(|e| e.to_string())?;
        }
        Ok(out)
    }

    /// Writes the image as a PNG file (atomically).
    pub fn write_png(&self, path: &Path) -> Result<(), ReportError> {
        let bytes = self.to_png()?;
        crate::io::write_atomic(path, &bytes).map_err(|e| ReportError::io(path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_triangles_draw_inside() {
        let mut img = Image::new(40, 30);
        img.triangle(
            [[2.0, 2.0, 0.0], [30.0, 2.0, 0.0], [2.0, 25.0, 0.0]],
            [0.0; 3],
        );
        assert_eq!(img.pixels[5 * 40 + 5], [0.0; 3]);
        assert_eq!(img.pixels[28 * 40 + 38], BACKGROUND.map(|c| c as f32));
        img.line2d((0.0, 28.0), (39.0, 28.0), 2.0, [1.0, 0.0, 0.0]);
        assert!(img.pixels[28 * 40 + 20][1] < 0.1);
        let png = img.to_png().expect("encodes");
        assert_eq!(&png[1..4], b"PNG");
    }
}

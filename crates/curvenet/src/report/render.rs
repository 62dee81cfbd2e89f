//! A small software rasteriser for the pictures of a run (`final.png`, `mode.png`) and the
//! plots of [`super::plot`].
//!
//! - [`Image`]: an RGB canvas with a depth buffer; filled triangles with depth, anti-aliased
//!   thick lines (coverage from the distance to the segment), text in a built-in 5×7 bitmap font,
//!   PNG encoding (`png` crate);
//! - [`View`]: an orthographic camera looking at a bounding box from an azimuth and elevation
//!   (z up), fitted to a rectangle of the image;
//! - [`network_picture`] and [`mode_picture`]: the two pictures of a run.
//!
//! Everything is computed in a fixed order from the inputs alone, so the PNG bytes are the same
//! from run to run. The surface is drawn opaque and light; curve pieces hidden by it are drawn
//! faintly, which reads as a translucent surface.

use super::export::{RunFolder, positions_at};
use crate::geom::Vec3;
use std::path::Path;

/// An RGB colour with components in `[0, 1]`.
pub type Rgb = [f64; 3];

/// A colour from 8-bit components.
pub const fn rgb8(r: u8, g: u8, b: u8) -> Rgb {
    [r as f64 / 255.0, g as f64 / 255.0, b as f64 / 255.0]
}

/// Background of every picture.
pub const BACKGROUND: Rgb = rgb8(255, 255, 255);
/// Text colour.
pub const INK: Rgb = rgb8(30, 30, 36);
/// Colour of kept curves.
pub const KEPT: Rgb = rgb8(28, 86, 170);
/// Colour of removed curves.
pub const REMOVED: Rgb = rgb8(214, 96, 77);
/// Colour of the surface.
pub const SURFACE: Rgb = rgb8(222, 218, 206);

/// An RGB image with a depth buffer (larger depth = nearer the viewer).
#[derive(Clone, Debug)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Pixels, row after row from the top.
    pub pixels: Vec<Rgb>,
    /// Depth of the nearest surface drawn at each pixel (`-inf` where none).
    pub depth: Vec<f64>,
}

impl Image {
    /// A blank image of the background colour.
    pub fn new(width: usize, height: usize) -> Image {
        Image {
            width,
            height,
            pixels: vec![BACKGROUND; width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
        }
    }

    /// Blends `color` over pixel `(x, y)` with opacity `alpha` (ignored outside the image).
    pub fn blend(&mut self, x: i64, y: i64, color: Rgb, alpha: f64) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 || alpha <= 0.0 {
            return;
        }
        let a = alpha.min(1.0);
        let p = &mut self.pixels[y as usize * self.width + x as usize];
        for k in 0..3 {
            p[k] = p[k] * (1.0 - a) + color[k] * a;
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

    /// Fills a triangle given in screen coordinates `(x, y, depth)`, shaded `color`, with a
    /// depth test and depth writes.
    pub fn triangle(&mut self, p: [[f64; 3]; 3], color: Rgb) {
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if !(area.abs() > 1e-12) {
            return;
        }
        let min_x = p
            .iter()
            .map(|q| q[0])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0);
        let max_x = p
            .iter()
            .map(|q| q[0])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil()
            .min(self.width as f64 - 1.0);
        let min_y = p
            .iter()
            .map(|q| q[1])
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0);
        let max_y = p
            .iter()
            .map(|q| q[1])
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil()
            .min(self.height as f64 - 1.0);
        if !(min_x <= max_x && min_y <= max_y) {
            return;
        }
        for y in min_y as usize..=max_y as usize {
            for x in min_x as usize..=max_x as usize {
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
                    self.pixels[i] = color;
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
        let x0 = (a[0].min(b[0]) - r - 1.0).floor().max(0.0);
        let x1 = (a[0].max(b[0]) + r + 1.0)
            .ceil()
            .min(self.width as f64 - 1.0);
        let y0 = (a[1].min(b[1]) - r - 1.0).floor().max(0.0);
        let y1 = (a[1].max(b[1]) + r + 1.0)
            .ceil()
            .min(self.height as f64 - 1.0);
        if !(x0 <= x1 && y0 <= y1) {
            return;
        }
        for y in y0 as usize..=y1 as usize {
            for x in x0 as usize..=x1 as usize {
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
                let alpha = if self.depth[i] > d + bias {
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

    /// Draws `text` with its top-left corner at `(x, y)`, each font pixel a `scale × scale`
    /// square. Returns the x after the last character.
    pub fn text(&mut self, x: i64, y: i64, text: &str, scale: i64, color: Rgb) -> i64 {
        let mut cx = x;
        for ch in text.chars() {
            let rows = glyph(ch);
            let dy = descent(ch);
            for (r, row) in rows.iter().enumerate() {
                for (c, bit) in row.bytes().enumerate() {
                    if bit == b'#' {
                        self.fill_rect(
                            cx + c as i64 * scale,
                            y + (r as i64 + dy) * scale,
                            scale,
                            scale,
                            color,
                            1.0,
                        );
                    }
                }
            }
            cx += ADVANCE * scale;
        }
        cx
    }

    /// Draws `text` rotated a quarter turn counter-clockwise (reading bottom to top), its
    /// top-left corner (in the rotated frame's terms, the bottom-left of the drawn block) at
    /// `(x, y)`.
    pub fn text_vertical(&mut self, x: i64, y: i64, text: &str, scale: i64, color: Rgb) {
        let mut cy = y;
        for ch in text.chars() {
            let rows = glyph(ch);
            let dy = descent(ch);
            for (r, row) in rows.iter().enumerate() {
                for (c, bit) in row.bytes().enumerate() {
                    if bit == b'#' {
                        self.fill_rect(
                            x + (r as i64 + dy) * scale,
                            cy - (c as i64 + 1) * scale,
                            scale,
                            scale,
                            color,
                            1.0,
                        );
                    }
                }
            }
            cy -= ADVANCE * scale;
        }
    }

    /// The image as 8-bit RGB bytes, row after row.
    pub fn rgb_bytes(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }

    /// The image as a PNG file.
    pub fn to_png(&self) -> Result<Vec<u8>, String> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            enc.set_compression(png::Compression::High);
            let mut w = enc.write_header().map_err(|e| e.to_string())?;
            w.write_image_data(&self.rgb_bytes())
                .map_err(|e| e.to_string())?;
            w.finish().map_err(|e| e.to_string())?;
        }
        Ok(out)
    }

    /// Writes the image as a PNG file (atomically).
    pub fn write_png(&self, path: &Path) -> Result<(), String> {
        let bytes = self.to_png()?;
        crate::io::write_atomic(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// Horizontal advance of one character, in font pixels.
pub const ADVANCE: i64 = 6;
/// Height of one line of text, in font pixels.
pub const LINE_HEIGHT: i64 = 10;

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: i64) -> i64 {
    (text.chars().count() as i64 * ADVANCE - 1).max(0) * scale
}

/// Rows by which `ch` is drawn lower than the others: glyphs with a descender (`g p q y ,`)
/// use their 7 rows for the x-height and the descender.
pub fn descent(ch: char) -> i64 {
    if matches!(ch, 'g' | 'p' | 'q' | 'y' | ',') {
        2
    } else {
        0
    }
}

/// The 5×7 glyph of `ch`, rows from the top, `#` for ink (`?` for unknown characters).
pub fn glyph(ch: char) -> [&'static str; 7] {
    let g: &str = match ch {
        ' ' => ".....|.....|.....|.....|.....|.....|.....",
        '!' => "..#..|..#..|..#..|..#..|..#..|.....|..#..",
        '"' => ".#.#.|.#.#.|.....|.....|.....|.....|.....",
        '#' => ".#.#.|.#.#.|#####|.#.#.|#####|.#.#.|.#.#.",
        '$' => "..#..|.####|#.#..|.###.|..#.#|####.|..#..",
        '%' => "##...|##..#|...#.|..#..|.#...|#..##|...##",
        '&' => ".##..|#..#.|#.#..|.#...|#.#.#|#..#.|.##.#",
        '\'' => "..#..|..#..|.....|.....|.....|.....|.....",
        '(' => "...#.|..#..|.#...|.#...|.#...|..#..|...#.",
        ')' => ".#...|..#..|...#.|...#.|...#.|..#..|.#...",
        '*' => ".....|..#..|#.#.#|.###.|#.#.#|..#..|.....",
        '+' => ".....|..#..|..#..|#####|..#..|..#..|.....",
        ',' => ".....|.....|.....|.##..|.##..|..#..|.#...",
        '-' | '−' | '–' | '—' => ".....|.....|.....|#####|.....|.....|.....",
        '.' => ".....|.....|.....|.....|.....|.##..|.##..",
        '/' => ".....|....#|...#.|..#..|.#...|#....|.....",
        '0' => ".###.|#...#|#..##|#.#.#|##..#|#...#|.###.",
        '1' => "..#..|.##..|..#..|..#..|..#..|..#..|.###.",
        '2' => ".###.|#...#|....#|...#.|..#..|.#...|#####",
        '3' => "#####|...#.|..#..|...#.|....#|#...#|.###.",
        '4' => "...#.|..##.|.#.#.|#..#.|#####|...#.|...#.",
        '5' => "#####|#....|####.|....#|....#|#...#|.###.",
        '6' => "..##.|.#...|#....|####.|#...#|#...#|.###.",
        '7' => "#####|....#|...#.|..#..|.#...|.#...|.#...",
        '8' => ".###.|#...#|#...#|.###.|#...#|#...#|.###.",
        '9' => ".###.|#...#|#...#|.####|....#|...#.|.##..",
        ':' => ".....|.##..|.##..|.....|.##..|.##..|.....",
        ';' => ".....|.##..|.##..|.....|.##..|..#..|.#...",
        '<' => "...#.|..#..|.#...|#....|.#...|..#..|...#.",
        '=' => ".....|.....|#####|.....|#####|.....|.....",
        '>' => ".#...|..#..|...#.|....#|...#.|..#..|.#...",
        '?' => ".###.|#...#|....#|...#.|..#..|.....|..#..",
        '@' => ".###.|#...#|....#|.##.#|#.#.#|#.#.#|.###.",
        'A' => ".###.|#...#|#...#|#####|#...#|#...#|#...#",
        'B' => "####.|#...#|#...#|####.|#...#|#...#|####.",
        'C' => ".###.|#...#|#....|#....|#....|#...#|.###.",
        'D' => "###..|#..#.|#...#|#...#|#...#|#..#.|###..",
        'E' => "#####|#....|#....|####.|#....|#....|#####",
        'F' => "#####|#....|#....|####.|#....|#....|#....",
        'G' => ".###.|#...#|#....|#.###|#...#|#...#|.####",
        'H' => "#...#|#...#|#...#|#####|#...#|#...#|#...#",
        'I' => ".###.|..#..|..#..|..#..|..#..|..#..|.###.",
        'J' => "..###|...#.|...#.|...#.|...#.|#..#.|.##..",
        'K' => "#...#|#..#.|#.#..|##...|#.#..|#..#.|#...#",
        'L' => "#....|#....|#....|#....|#....|#....|#####",
        'M' => "#...#|##.##|#.#.#|#.#.#|#...#|#...#|#...#",
        'N' => "#...#|#...#|##..#|#.#.#|#..##|#...#|#...#",
        'O' => ".###.|#...#|#...#|#...#|#...#|#...#|.###.",
        'P' => "####.|#...#|#...#|####.|#....|#....|#....",
        'Q' => ".###.|#...#|#...#|#...#|#.#.#|#..#.|.##.#",
        'R' => "####.|#...#|#...#|####.|#.#..|#..#.|#...#",
        'S' => ".####|#....|#....|.###.|....#|....#|####.",
        'T' => "#####|..#..|..#..|..#..|..#..|..#..|..#..",
        'U' => "#...#|#...#|#...#|#...#|#...#|#...#|.###.",
        'V' => "#...#|#...#|#...#|#...#|#...#|.#.#.|..#..",
        'W' => "#...#|#...#|#...#|#.#.#|#.#.#|#.#.#|.#.#.",
        'X' => "#...#|#...#|.#.#.|..#..|.#.#.|#...#|#...#",
        'Y' => "#...#|#...#|.#.#.|..#..|..#..|..#..|..#..",
        'Z' => "#####|....#|...#.|..#..|.#...|#....|#####",
        '[' => ".###.|.#...|.#...|.#...|.#...|.#...|.###.",
        '\\' => ".....|#....|.#...|..#..|...#.|....#|.....",
        ']' => ".###.|...#.|...#.|...#.|...#.|...#.|.###.",
        '^' => "..#..|.#.#.|#...#|.....|.....|.....|.....",
        '_' => ".....|.....|.....|.....|.....|.....|#####",
        '`' => ".#...|..#..|.....|.....|.....|.....|.....",
        'a' => ".....|.....|.###.|....#|.####|#...#|.####",
        'b' => "#....|#....|#.##.|##..#|#...#|#...#|####.",
        'c' => ".....|.....|.###.|#....|#....|#...#|.###.",
        'd' => "....#|....#|.##.#|#..##|#...#|#...#|.####",
        'e' => ".....|.....|.###.|#...#|#####|#....|.###.",
        'f' => "..##.|.#..#|.#...|###..|.#...|.#...|.#...",
        'g' => ".####|#...#|#...#|#...#|.####|....#|.###.",
        'h' => "#....|#....|#.##.|##..#|#...#|#...#|#...#",
        'i' => "..#..|.....|.##..|..#..|..#..|..#..|.###.",
        'j' => "...#.|.....|..##.|...#.|...#.|#..#.|.##..",
        'k' => "#....|#....|#..#.|#.#..|##...|#.#..|#..#.",
        'l' => ".##..|..#..|..#..|..#..|..#..|..#..|.###.",
        'm' => ".....|.....|##.#.|#.#.#|#.#.#|#...#|#...#",
        'n' => ".....|.....|#.##.|##..#|#...#|#...#|#...#",
        'o' => ".....|.....|.###.|#...#|#...#|#...#|.###.",
        'p' => "####.|#...#|#...#|#...#|####.|#....|#....",
        'q' => ".####|#...#|#...#|#...#|.####|....#|....#",
        'r' => ".....|.....|#.##.|##..#|#....|#....|#....",
        's' => ".....|.....|.###.|#....|.###.|....#|####.",
        't' => ".#...|.#...|###..|.#...|.#...|.#..#|..##.",
        'u' => ".....|.....|#...#|#...#|#...#|#..##|.##.#",
        'v' => ".....|.....|#...#|#...#|#...#|.#.#.|..#..",
        'w' => ".....|.....|#...#|#...#|#.#.#|#.#.#|.#.#.",
        'x' => ".....|.....|#...#|.#.#.|..#..|.#.#.|#...#",
        'y' => "#...#|#...#|#...#|#...#|.####|....#|.###.",
        'z' => ".....|.....|#####|...#.|..#..|.#...|#####",
        '{' => "...#.|..#..|..#..|.#...|..#..|..#..|...#.",
        '|' => "..#..|..#..|..#..|..#..|..#..|..#..|..#..",
        '}' => ".#...|..#..|..#..|...#.|..#..|..#..|.#...",
        '~' => ".....|.....|.#...|#.#.#|...#.|.....|.....",
        'λ' => ".#...|..#..|..#..|..#..|.#.#.|.#.#.|#...#",
        'ε' => ".....|.....|.###.|#....|.##..|#....|.###.",
        '×' => ".....|#...#|.#.#.|..#..|.#.#.|#...#|.....",
        '·' => ".....|.....|.....|..#..|.....|.....|.....",
        '²' => ".##..|...#.|..#..|.###.|.....|.....|.....",
        '≤' => "...#.|..#..|.#...|..#..|...#.|.....|#####",
        _ => ".###.|#...#|....#|...#.|..#..|.....|..#..",
    };
    let mut rows = [""; 7];
    for (r, part) in rows.iter_mut().zip(g.split('|')) {
        *r = part;
    }
    rows
}

/// An orthographic camera: world points to screen `(x, y, depth)`.
#[derive(Clone, Copy, Debug)]
pub struct View {
    right: Vec3,
    up: Vec3,
    toward_eye: Vec3,
    center: Vec3,
    scale: f64,
    screen_center: (f64, f64),
}

impl View {
    /// Looks from azimuth `azimuth_deg` (around z, from +x) and elevation `elevation_deg` at
    /// `points`, fitted into the rectangle `(x, y, width, height)` of the image.
    pub fn fit(
        points: &[Vec3],
        azimuth_deg: f64,
        elevation_deg: f64,
        rect: (f64, f64, f64, f64),
    ) -> View {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.to_radians());
        let e = Vec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let right = Vec3::new(0.0, 0.0, 1.0).cross(e).normalized();
        let up = e.cross(right);
        let mut lo = (f64::INFINITY, f64::INFINITY);
        let mut hi = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in points.iter().filter(|p| p.is_finite()) {
            let (x, y) = (p.dot(right), p.dot(up));
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        if !(lo.0 <= hi.0) {
            lo = (-1.0, -1.0);
            hi = (1.0, 1.0);
        }
        let (w, h) = ((hi.0 - lo.0).max(1e-300), (hi.1 - lo.1).max(1e-300));
        let scale = (rect.2 / w).min(rect.3 / h);
        let cx = 0.5 * (lo.0 + hi.0);
        let cy = 0.5 * (lo.1 + hi.1);
        View {
            right,
            up,
            toward_eye: e,
            center: right * cx + up * cy,
            scale,
            screen_center: (rect.0 + 0.5 * rect.2, rect.1 + 0.5 * rect.3),
        }
    }

    /// Screen position and depth of `p`.
    pub fn project(&self, p: Vec3) -> [f64; 3] {
        let q = p - self.center;
        [
            self.screen_center.0 + q.dot(self.right) * self.scale,
            self.screen_center.1 - q.dot(self.up) * self.scale,
            p.dot(self.toward_eye) * self.scale,
        ]
    }

    /// Unit vector from the scene toward the viewer.
    pub fn toward_eye(&self) -> Vec3 {
        self.toward_eye
    }

    /// Pixels per scene unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

/// Draws a mesh shaded by a light at the viewer.
pub fn draw_mesh(img: &mut Image, view: &View, vertices: &[Vec3], faces: &[[u32; 3]]) {
    let e = view.toward_eye();
    for f in faces {
        let Some(p) = f
            .iter()
            .map(|&i| vertices.get(i as usize).copied())
            .collect::<Option<Vec<Vec3>>>()
        else {
            continue;
        };
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let nn = n.norm();
        let shade = if nn > 0.0 {
            0.72 + 0.28 * (n.dot(e) / nn).abs()
        } else {
            0.72
        };
        // A few shades only: smooth enough, and the PNG stays small.
        let shade = (shade * 64.0).round() / 64.0;
        let c = SURFACE.map(|x| x * shade);
        img.triangle(
            [view.project(p[0]), view.project(p[1]), view.project(p[2])],
            c,
        );
    }
}

/// One polyline to draw: points with a colour each.
#[derive(Clone, Debug)]
pub struct Stroke {
    /// Points in world coordinates.
    pub points: Vec<Vec3>,
    /// One colour per point.
    pub colors: Vec<Rgb>,
    /// Joins the last point to the first.
    pub closed: bool,
    /// Line width in pixels.
    pub width: f64,
    /// Opacity where the surface hides the stroke.
    pub hidden_alpha: f64,
}

/// Draws strokes: all their segments sorted far to near (ties by order), each with a depth
/// test against the surface only.
pub fn draw_strokes(img: &mut Image, view: &View, strokes: &[Stroke], bias: f64) {
    struct Segment {
        depth: f64,
        order: usize,
        a: [f64; 3],
        b: [f64; 3],
        ca: Rgb,
        cb: Rgb,
        width: f64,
        hidden_alpha: f64,
    }
    let mut segs: Vec<Segment> = Vec::new();
    for s in strokes {
        let n = s.points.len();
        let count = if s.closed { n } else { n.saturating_sub(1) };
        for j in 0..count {
            let (i0, i1) = (j, (j + 1) % n);
            let a = view.project(s.points[i0]);
            let b = view.project(s.points[i1]);
            if !(a.iter().chain(&b).all(|x| x.is_finite())) {
                continue;
            }
            segs.push(Segment {
                depth: 0.5 * (a[2] + b[2]),
                order: segs.len(),
                a,
                b,
                ca: s.colors[i0],
                cb: s.colors[i1],
                width: s.width,
                hidden_alpha: s.hidden_alpha,
            });
        }
    }
    segs.sort_by(|x, y| x.depth.total_cmp(&y.depth).then(x.order.cmp(&y.order)));
    for s in segs {
        img.line(s.a, s.b, s.width, s.ca, s.cb, s.hidden_alpha, bias);
    }
}

/// A colour map from dark blue (0) through teal and yellow to red (1).
pub fn colormap(t: f64) -> Rgb {
    const STOPS: [Rgb; 5] = [
        rgb8(48, 18, 110),
        rgb8(33, 120, 180),
        rgb8(60, 180, 120),
        rgb8(235, 200, 40),
        rgb8(200, 30, 30),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * (STOPS.len() - 1) as f64;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - i as f64;
    [0, 1, 2].map(|k| STOPS[i][k] + f * (STOPS[i + 1][k] - STOPS[i][k]))
}

/// Width and height of the pictures.
pub const PICTURE_SIZE: (usize, usize) = (960, 720);

/// Azimuth and elevation of the pictures' camera.
const CAMERA: (f64, f64) = (-60.0, 28.0);

fn fit_points(run: &RunFolder, extra: &[Vec3]) -> Vec<Vec3> {
    let mut pts: Vec<Vec3> = run.network.positions.clone();
    if let Some(m) = &run.mesh {
        pts.extend_from_slice(&m.vertices);
    }
    pts.extend_from_slice(extra);
    pts
}

fn title(img: &mut Image, lines: &[String]) {
    for (i, l) in lines.iter().enumerate() {
        let color = if i == 0 { INK } else { rgb8(90, 90, 100) };
        img.text(16, 14 + i as i64 * 24, l, 2, color);
    }
}

fn legend(img: &mut Image, y: i64, items: &[(Rgb, &str)]) {
    let mut x = 16;
    for (c, label) in items {
        img.fill_rect(x, y + 5, 28, 4, *c, 1.0);
        x = img.text(x + 36, y, label, 2, INK) + 28;
    }
}

/// Formats a number with `sig` significant digits in the style of `summary.txt`.
pub fn fmt_sci(v: f64, sig: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    if (-3..5).contains(&e) {
        let decimals = (sig as i32 - 1 - e).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{:.*e}", sig.saturating_sub(1), v)
    }
}

/// The picture of iteration `k`: the surface, the removed curves at rest (thin, faint) and the
/// kept curves at equilibrium.
pub fn network_picture(run: &RunFolder, k: usize) -> Result<Image, String> {
    let rec = run.record(k)?;
    let net = &run.network;
    let u = run.displacement(k)?;
    let eq = positions_at(net, Some(&u));
    let rest = positions_at(net, None);
    let (w, h) = PICTURE_SIZE;
    let mut img = Image::new(w, h);
    let view = View::fit(
        &fit_points(run, &eq),
        CAMERA.0,
        CAMERA.1,
        (30.0, 80.0, w as f64 - 60.0, h as f64 - 140.0),
    );
    if let Some(m) = &run.mesh {
        draw_mesh(&mut img, &view, &m.vertices, &m.faces);
    }
    let kept: std::collections::BTreeSet<usize> = rec.curves.iter().copied().collect();
    // Removed curves first, underneath the kept ones.
    let (mut removed, mut kept_strokes) = (Vec::new(), Vec::new());
    for (c, rod) in net.rods.iter().enumerate() {
        let on = kept.contains(&c);
        let pos = if on { &eq } else { &rest };
        let color = if on { KEPT } else { REMOVED };
        let stroke = Stroke {
            points: rod.vertices.iter().map(|&v| pos[v as usize]).collect(),
            colors: vec![color; rod.vertices.len()],
            closed: rod.closed,
            width: if on { 3.0 } else { 1.4 },
            hidden_alpha: if on { 0.35 } else { 0.15 },
        };
        if on {
            kept_strokes.push(stroke);
        } else {
            removed.push(stroke);
        }
    }
    let bias = 1e-3 * view.scale() * diag(&rest);
    draw_strokes(&mut img, &view, &removed, bias);
    draw_strokes(&mut img, &view, &kept_strokes, bias);
    let total = run.result.setup.total_length;
    title(
        &mut img,
        &[
            format!(
                "iteration {k}: {} of {} curves, length {} ({}% of {})",
                rec.curves.len(),
                net.rods.len(),
                fmt_sci(rec.length, 6),
                fmt_sci(100.0 * rec.length / total.max(f64::MIN_POSITIVE), 3),
                fmt_sci(total, 6)
            ),
            format!(
                "λ_eq = {}   budget {}   supports {}",
                fmt_sci(rec.lambda, 4),
                fmt_sci(run.result.budget, 6),
                net.supports.name()
            ),
        ],
    );
    legend(
        &mut img,
        h as i64 - 40,
        &[
            (KEPT, "kept curves (equilibrium)"),
            (REMOVED, "removed curves (rest)"),
        ],
    );
    Ok(img)
}

fn diag(points: &[Vec3]) -> f64 {
    let b = crate::geom::Aabb::of_points(points);
    if b.is_empty() { 1.0 } else { b.extent().norm() }
}

/// The worst-case mode of iteration `k`: the equilibrium (thin, grey) and the equilibrium
/// displaced along the mode, scaled so the largest displacement is 8% of the network's size,
/// coloured by the displacement's magnitude.
pub fn mode_picture(run: &RunFolder, k: usize) -> Result<Image, String> {
    let rec = run.record(k)?;
    let net = &run.network;
    let u = run.displacement(k)?;
    let mode = run.mode(k)?;
    let eq = positions_at(net, Some(&u));
    let kept: Vec<usize> = rec.curves.clone();
    let mut on = vec![false; net.positions.len()];
    for &c in &kept {
        for &v in &net.rods[c].vertices {
            on[v as usize] = true;
        }
    }
    let mag: Vec<f64> = (0..net.positions.len())
        .map(|v| {
            if on[v] {
                (mode[3 * v].powi(2) + mode[3 * v + 1].powi(2) + mode[3 * v + 2].powi(2)).sqrt()
            } else {
                0.0
            }
        })
        .collect();
    let max = mag.iter().copied().fold(0.0, f64::max);
    let kept_points: Vec<Vec3> = kept
        .iter()
        .flat_map(|&c| net.rods[c].vertices.iter().map(|&v| eq[v as usize]))
        .collect();
    let size = diag(&kept_points);
    let amp = if max > 0.0 { 0.08 * size / max } else { 0.0 };
    let moved: Vec<Vec3> = eq
        .iter()
        .enumerate()
        .map(|(v, &p)| p + Vec3::new(mode[3 * v], mode[3 * v + 1], mode[3 * v + 2]) * amp)
        .collect();
    let (w, h) = PICTURE_SIZE;
    let mut img = Image::new(w, h);
    let mut fit: Vec<Vec3> = kept_points.clone();
    fit.extend(
        kept.iter()
            .flat_map(|&c| net.rods[c].vertices.iter().map(|&v| moved[v as usize])),
    );
    if let Some(m) = &run.mesh {
        fit.extend_from_slice(&m.vertices);
    }
    let view = View::fit(
        &fit,
        CAMERA.0,
        CAMERA.1,
        (30.0, 80.0, w as f64 - 130.0, h as f64 - 140.0),
    );
    if let Some(m) = &run.mesh {
        draw_mesh(&mut img, &view, &m.vertices, &m.faces);
    }
    let bias = 1e-3 * view.scale() * size;
    let grey = rgb8(150, 150, 160);
    let base: Vec<Stroke> = kept
        .iter()
        .map(|&c| {
            let rod = &net.rods[c];
            Stroke {
                points: rod.vertices.iter().map(|&v| eq[v as usize]).collect(),
                colors: vec![grey; rod.vertices.len()],
                closed: rod.closed,
                width: 1.2,
                hidden_alpha: 0.3,
            }
        })
        .collect();
    draw_strokes(&mut img, &view, &base, bias);
    let shown: Vec<Stroke> = kept
        .iter()
        .map(|&c| {
            let rod = &net.rods[c];
            Stroke {
                points: rod.vertices.iter().map(|&v| moved[v as usize]).collect(),
                colors: rod
                    .vertices
                    .iter()
                    .map(|&v| {
                        colormap(if max > 0.0 {
                            mag[v as usize] / max
                        } else {
                            0.0
                        })
                    })
                    .collect(),
                closed: rod.closed,
                width: 3.0,
                hidden_alpha: 0.35,
            }
        })
        .collect();
    draw_strokes(&mut img, &view, &shown, bias);
    // Colour bar.
    let (bx, by, bh) = (w as i64 - 70, 110i64, 300i64);
    for i in 0..bh {
        let t = 1.0 - i as f64 / (bh - 1) as f64;
        img.fill_rect(bx, by + i, 18, 1, colormap(t), 1.0);
    }
    img.text(bx - 16, by - 22, "|v|", 2, INK);
    img.text(bx + 24, by - 4, "max", 2, INK);
    img.text(bx + 24, by + bh - 10, "0", 2, INK);
    title(
        &mut img,
        &[
            format!(
                "worst-case mode, iteration {k}: λ_eq = {} ({} curves)",
                fmt_sci(rec.lambda, 4),
                kept.len()
            ),
            format!(
                "grey: equilibrium; colour: along the mode ×{} (largest move 8% of size)",
                fmt_sci(amp, 3)
            ),
        ],
    );
    Ok(img)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_are_5_by_7() {
        for c in (32u8..127).map(char::from).chain("λε×·²≤".chars()) {
            let g = glyph(c);
            for row in g {
                assert_eq!(row.len(), 5, "{c:?}");
                assert!(row.bytes().all(|b| b == b'#' || b == b'.'), "{c:?}");
            }
        }
        assert_ne!(glyph('A'), glyph('B'));
    }

    #[test]
    fn lines_and_triangles_draw_inside() {
        let mut img = Image::new(40, 30);
        img.triangle(
            [[2.0, 2.0, 0.0], [30.0, 2.0, 0.0], [2.0, 25.0, 0.0]],
            [0.0; 3],
        );
        assert_eq!(img.pixels[5 * 40 + 5], [0.0; 3]);
        assert_eq!(img.pixels[28 * 40 + 38], BACKGROUND);
        img.line2d((0.0, 28.0), (39.0, 28.0), 2.0, [1.0, 0.0, 0.0]);
        assert!(img.pixels[28 * 40 + 20][1] < 0.1);
        let png = img.to_png().expect("encodes");
        assert_eq!(&png[1..4], b"PNG");
    }

    #[test]
    fn numbers_format() {
        assert_eq!(fmt_sci(1234.5678, 6), "1234.57");
        assert_eq!(fmt_sci(2.301247e-9, 4), "2.301e-9");
        assert_eq!(fmt_sci(0.0, 4), "0");
    }
}

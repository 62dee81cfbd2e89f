//! Drawing a 3D scene: the orthographic camera ([`View`]), shaded meshes, strokes sorted far to
//! near, and the colour map of the mode picture.

use super::raster::Image;
use super::{Rgb, SURFACE, rgb8};
use crate::geom::Vec3;

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
    // Each segment: its depth (at its middle), its place in the input (ties), its ends on the
    // screen, its stroke and its ends' points.
    type Segment<'a> = (f64, usize, [f64; 3], [f64; 3], &'a Stroke, [usize; 2]);
    let mut segs: Vec<Segment<'_>> = Vec::new();
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
            segs.push((0.5 * (a[2] + b[2]), segs.len(), a, b, s, [i0, i1]));
        }
    }
    segs.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    for (_, _, a, b, s, [i0, i1]) in segs {
        img.line(
            a,
            b,
            s.width,
            s.colors[i0],
            s.colors[i1],
            s.hidden_alpha,
            bias,
        );
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

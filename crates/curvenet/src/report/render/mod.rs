//! A small software rasteriser for the pictures of a run (`final.png`, `mode.png`) and the
//! plots of [`super::plot`].
//!
//! - [`raster`]: [`Image`], an RGB canvas with a depth buffer; filled triangles with depth,
//!   anti-aliased thick lines, PNG encoding;
//! - [`font`]: text in a built-in 5×7 bitmap font;
//! - [`scene`]: [`View`], an orthographic camera looking at a bounding box from an azimuth and
//!   elevation (z up), fitted to a rectangle of the image; meshes and strokes drawn through it;
//! - [`pictures`]: [`network_picture`] and [`mode_picture`], the two pictures of a run;
//! - [`slide`]: [`slide_picture`], a slid run's curves before and after they slid.
//!
//! Hand-written rather than taken from a plotting library: a few hundred lines give
//! byte-identical PNGs from run to run with no system fonts or GPU.
//!
//! Everything is computed in a fixed order from the inputs alone, so the PNG bytes are the same
//! from run to run. The surface is drawn opaque and light; curve pieces hidden by it are drawn
//! faintly, which reads as a translucent surface.

pub mod font;
pub mod pictures;
pub mod raster;
pub mod scene;
pub mod slide;

pub use font::{ADVANCE, LINE_HEIGHT, descent, glyph, text_width};
pub use pictures::{PICTURE_SIZE, mode_picture, network_picture};
pub use raster::Image;
pub use scene::{Stroke, View, colormap, draw_mesh, draw_strokes};
pub use slide::slide_picture;

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

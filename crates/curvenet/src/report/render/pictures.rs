//! The two pictures of a run: the network ([`network_picture`], `final.png`) and its worst-case
//! mode ([`mode_picture`], `mode.png`).

use super::raster::Image;
use super::scene::{Stroke, View, colormap, draw_mesh, draw_strokes};
use super::{INK, KEPT, REMOVED, Rgb, rgb8};
use crate::fmt::significant;
use crate::geom::Vec3;
use crate::network::Network;
use crate::report::ReportError;
use crate::run_folder::{Chosen, RunFolder, Which, positions_at};

/// Width and height of the pictures.
pub const PICTURE_SIZE: (usize, usize) = (960, 720);

/// Azimuth and elevation of the pictures' camera.
const CAMERA: (f64, f64) = (-60.0, 28.0);

/// A blank picture with a view that fits `fit` and the run's surface into the picture less a
/// margin (`right` pixels on the right), the surface drawn.
pub(super) fn canvas(run: &RunFolder, mut fit: Vec<Vec3>, right: f64) -> (Image, View) {
    let (w, h) = PICTURE_SIZE;
    let mut img = Image::new(w, h);
    if let Some(m) = &run.mesh {
        fit.extend_from_slice(&m.vertices);
    }
    let rect = (30.0, 80.0, w as f64 - right, h as f64 - 140.0);
    let view = View::fit(&fit, CAMERA.0, CAMERA.1, rect);
    if let Some(m) = &run.mesh {
        draw_mesh(&mut img, &view, &m.vertices, &m.faces);
    }
    (img, view)
}

pub(super) fn title(img: &mut Image, lines: &[String]) {
    for (i, l) in lines.iter().enumerate() {
        let color = if i == 0 { INK } else { rgb8(90, 90, 100) };
        img.text(16, 14 + i as i64 * 24, l, 2, color);
    }
}

pub(super) fn legend(img: &mut Image, y: i64, items: &[(Rgb, &str)]) {
    let mut x = 16;
    for (c, label) in items {
        img.fill_rect(x, y + 5, 28, 4, *c, 1.0);
        x = img.text(x + 36, y, label, 2, INK) + 28;
    }
}

/// The picture of a network of the run (an iteration, the answer or an alternative): the
/// surface, the removed curves at rest (thin, faint) and the kept curves at equilibrium.
pub fn network_picture(run: &RunFolder, which: impl Into<Which>) -> Result<Image, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let net = &run.network;
    let u = run.displacement_of(which)?;
    let eq = positions_at(net, Some(&u));
    let rest = positions_at(net, None);
    let (mut img, view) = canvas(run, [&net.positions[..], &eq].concat(), 60.0);
    let kept: std::collections::BTreeSet<usize> = rec.curves.iter().copied().collect();
    // Removed curves first, underneath the kept ones.
    let (mut removed, mut kept_strokes) = (Vec::new(), Vec::new());
    for c in 0..net.rods.len() {
        if kept.contains(&c) {
            kept_strokes.push(curve_stroke(net, c, &eq, |_| KEPT, 3.0, 0.35));
        } else {
            removed.push(curve_stroke(net, c, &rest, |_| REMOVED, 1.4, 0.15));
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
                "{}: {} of {} curves, length {} ({}% of {})",
                rec.what,
                rec.curves.len(),
                net.rods.len(),
                significant(rec.length, 6),
                significant(100.0 * rec.length / total.max(f64::MIN_POSITIVE), 3),
                significant(total, 6)
            ),
            format!(
                "{} = {}{}   budget {}   supports {}",
                run.result.setup.stability.objective.value_symbol(),
                significant(rec.lambda, 4),
                unstable_note(&rec),
                significant(run.result.budget, 6),
                net.supports.name()
            ),
        ],
    );
    legend(
        &mut img,
        PICTURE_SIZE.1 as i64 - 40,
        &[
            (KEPT, "kept curves (equilibrium)"),
            (REMOVED, "removed curves (rest)"),
        ],
    );
    Ok(img)
}

/// `  UNSTABLE: …` after a recorded network's `λ_eq` in a title when it is unstable.
fn unstable_note(rec: &Chosen) -> String {
    rec.unstable.as_ref().map_or_else(String::new, |w| {
        format!("  {}", w.replacen("unstable", "UNSTABLE", 1))
    })
}

fn diag(points: &[Vec3]) -> f64 {
    let b = crate::geom::Aabb::of_points(points);
    if b.is_empty() { 1.0 } else { b.extent().norm() }
}

/// The stroke of curve `c` through `positions`, one colour per vertex from `color`.
fn curve_stroke(
    net: &Network,
    c: usize,
    positions: &[Vec3],
    color: impl Fn(u32) -> Rgb,
    width: f64,
    hidden_alpha: f64,
) -> Stroke {
    let rod = &net.rods[c];
    Stroke {
        points: rod
            .vertices
            .iter()
            .map(|&v| positions[v as usize])
            .collect(),
        colors: rod.vertices.iter().map(|&v| color(v)).collect(),
        closed: rod.closed,
        width,
        hidden_alpha,
    }
}

/// The magnitude of `mode` at every vertex of `curves` (0 elsewhere) and the largest one.
fn mode_magnitudes(net: &Network, curves: &[usize], mode: &[f64]) -> (Vec<f64>, f64) {
    let mut mag = vec![0.0; net.positions.len()];
    for &c in curves {
        for &v in &net.rods[c].vertices {
            let v = v as usize;
            mag[v] =
                (mode[3 * v].powi(2) + mode[3 * v + 1].powi(2) + mode[3 * v + 2].powi(2)).sqrt();
        }
    }
    let max = mag.iter().copied().fold(0.0, f64::max);
    (mag, max)
}

/// The colour bar of the mode picture, at the right edge of an image `w` wide.
fn colour_bar(img: &mut Image, w: usize) {
    let (bx, by, bh) = (w as i64 - 70, 110i64, 300i64);
    for i in 0..bh {
        let t = 1.0 - i as f64 / (bh - 1) as f64;
        img.fill_rect(bx, by + i, 18, 1, colormap(t), 1.0);
    }
    img.text(bx - 16, by - 22, "|v|", 2, INK);
    img.text(bx + 24, by - 4, "max", 2, INK);
    img.text(bx + 24, by + bh - 10, "0", 2, INK);
}

/// The worst-case mode of iteration `k`: the equilibrium (thin, grey) and the equilibrium
/// displaced along the mode, scaled so the largest displacement is 8% of the network's size,
/// coloured by the displacement's magnitude.
pub fn mode_picture(run: &RunFolder, which: impl Into<Which>) -> Result<Image, ReportError> {
    let which = which.into();
    let rec = run.network_of(which)?;
    let net = &run.network;
    let eq = positions_at(net, Some(&run.displacement_of(which)?));
    let mode = run.mode_of(which)?;
    let kept = &rec.curves;
    let (mag, max) = mode_magnitudes(net, kept, &mode);
    let on_kept = |pos: &[Vec3]| -> Vec<Vec3> {
        kept.iter()
            .flat_map(|&c| net.rods[c].vertices.iter().map(|&v| pos[v as usize]))
            .collect()
    };
    let size = diag(&on_kept(&eq));
    let amp = if max > 0.0 { 0.08 * size / max } else { 0.0 };
    let moved: Vec<Vec3> = eq
        .iter()
        .enumerate()
        .map(|(v, &p)| p + Vec3::new(mode[3 * v], mode[3 * v + 1], mode[3 * v + 2]) * amp)
        .collect();
    let (mut img, view) = canvas(run, [on_kept(&eq), on_kept(&moved)].concat(), 130.0);
    let bias = 1e-3 * view.scale() * size;
    let grey = rgb8(150, 150, 160);
    let base: Vec<Stroke> = kept
        .iter()
        .map(|&c| curve_stroke(net, c, &eq, |_| grey, 1.2, 0.3))
        .collect();
    draw_strokes(&mut img, &view, &base, bias);
    let shade = |v: u32| {
        colormap(if max > 0.0 {
            mag[v as usize] / max
        } else {
            0.0
        })
    };
    let shown: Vec<Stroke> = kept
        .iter()
        .map(|&c| curve_stroke(net, c, &moved, shade, 3.0, 0.35))
        .collect();
    draw_strokes(&mut img, &view, &shown, bias);
    colour_bar(&mut img, PICTURE_SIZE.0);
    title(
        &mut img,
        &[
            format!(
                "worst-case mode, {}: {} = {}{} ({} curves)",
                rec.what,
                run.result.setup.stability.objective.value_symbol(),
                significant(rec.lambda, 4),
                unstable_note(&rec),
                kept.len()
            ),
            format!(
                "grey: equilibrium; colour: along the mode ×{} (largest move 8% of size)",
                significant(amp, 3)
            ),
        ],
    );
    Ok(img)
}

//! The before/after picture of a slid run ([`slide_picture`], `slide.png`): the surface, the
//! curves as they were before they slid (thin, faint) and the slid curves (bold), both at
//! rest, so the picture shows how far each curve moved on the surface.

use super::pictures::{PICTURE_SIZE, canvas, legend, title};
use super::raster::Image;
use super::scene::{Stroke, draw_strokes};
use super::{KEPT, Rgb, rgb8};
use crate::fmt::{length, significant};
use crate::geom::Vec3;
use crate::report::ReportError;
use crate::run_folder::{RunFolder, positions_at};

/// Colour of the curves before they slid.
pub const BEFORE: Rgb = rgb8(150, 150, 160);

/// The before/after picture of a slid run (`None` for a run that did not slide, or whose
/// `before.obj` cannot be read).
pub fn slide_picture(run: &RunFolder) -> Result<Option<Image>, ReportError> {
    let Some(record) = &run.result.slide else {
        return Ok(None);
    };
    let Ok(text) = run.files.read_text("before.obj") else {
        return Ok(None);
    };
    let Ok(before) = crate::io::parse_obj_polylines(&text, "before.obj") else {
        return Ok(None);
    };
    let net = &run.network;
    let rest = positions_at(net, None);
    let drawn: Vec<Vec3> = before
        .curves
        .iter()
        .flat_map(|c| c.points.clone())
        .collect();
    let (mut img, view) = canvas(run, [&rest[..], &drawn].concat(), 60.0);
    let stroke = |points: Vec<Vec3>, closed: bool, color: Rgb, width: f64, hidden: f64| Stroke {
        colors: vec![color; points.len()],
        points,
        closed,
        width,
        hidden_alpha: hidden,
    };
    let faint: Vec<Stroke> = (before.curves.iter())
        .map(|c| stroke(c.points.clone(), c.closed, BEFORE, 1.6, 0.15))
        .collect();
    let bold: Vec<Stroke> = (net.rods.iter())
        .map(|r| {
            let points = r.vertices.iter().map(|&v| rest[v as usize]).collect();
            stroke(points, r.closed, KEPT, 3.2, 0.35)
        })
        .collect();
    let bias = 1e-3 * view.scale() * crate::geom::Aabb::of_points(&rest).extent().norm();
    draw_strokes(&mut img, &view, &faint, bias);
    draw_strokes(&mut img, &view, &bold, bias);
    let symbol = run.result.setup.stability.objective.value_symbol();
    let gain = if record.lambda_before > 0.0 {
        format!(
            " ({}×)",
            significant(record.lambda_after / record.lambda_before, 4)
        )
    } else {
        String::new()
    };
    let mut lines = vec![
        format!(
            "slid: {symbol} {} -> {}{gain}",
            significant(record.lambda_before, 4),
            significant(record.lambda_after, 4)
        ),
        format!(
            "largest move {} (at most {})   joints +{} -{}",
            length(record.largest_move),
            length(record.max_move),
            record.joints_added,
            record.joints_removed
        ),
    ];
    if record.stopped {
        lines[1] += "   (stopped early)";
    }
    title(&mut img, &lines);
    legend(
        &mut img,
        PICTURE_SIZE.1 as i64 - 40,
        &[(BEFORE, "before sliding"), (KEPT, "slid curves")],
    );
    Ok(Some(img))
}

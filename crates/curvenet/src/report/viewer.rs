//! The interactive viewer (`curvenet view`) and the files written next to a run's result.
//!
//! [`viewer_html`] makes ONE self-contained HTML page from a run folder: a small hand-written
//! WebGL viewer (`report/viewer/viewer.js`, no library, no network access) and the run's data
//! embedded as JSON. The page shows the surface (translucent), the curves (kept and removed in
//! different colours), buttons for the answer and each alternative (`λ_eq`, length, curves;
//! the answer first, opened on; one that is not a greedy iteration shown with its own
//! equilibrium, mode and gravity deflection), a slider over every greedy iteration (network, curve count, total
//! length, `λ_eq`), the worst-case mode as an animated deformation with an amplitude control,
//! the gravity deflection, and the equilibrium shape against the designed (rest) one; the
//! mouse orbits (left), pans (right or shift) and zooms (wheel); a click on a curve shows its
//! id, rest length, supports and joints.
//!
//! The gravity deflection is computed here, per iteration: `H u = f` with `H` the Hessian of
//! the iteration's structure at its recorded equilibrium and `f` the run's gravity load
//! (`setup.stability.gravity`: a weight per unit rest length, half of each edge's weight on
//! each of its ends), solved by the stability facade ([`Analyzer::gravity_at`]); after a
//! greedy run, most are solved already, while the greedy ran ([`super::gravity_ahead`]).
//! Structures that are not positive definite have none.
//!
//! Embedded arrays are compact: rest positions and mesh vertices as base64 little-endian
//! `f32`, mesh faces as base64 `u32`, and the per-iteration fields (equilibrium displacement,
//! mode, gravity deflection) as base64 `i16` with one scale per array, over the vertices of
//! that iteration's curves only (ascending vertex index). A few MB for the paper's tower.
//!
//! [`app_html`] is the same page in its app mode, which `curvenet serve` answers at `/`: one
//! live structure, and `report/viewer/app.js` editing it over the server's JSON API.
//!
//! [`write_run_outputs`] writes everything a finished run gets besides the result files:
//! `final.png`, `mode.png`, `lambda.png` ([`super::render`], [`super::plot`]), `viewer.html`
//! and `fabrication.csv` (the final network, [`super::export::fabrication_csv`]).

use super::export::{fabrication_csv, rod_joints, rod_supports};
use super::gravity_ahead::Deflections;
use super::plot::lambda_plot;
use super::render::{Image, mode_picture, network_picture};
use crate::io::{Polyline, TriMesh};
use crate::network::Network;
use crate::report::ReportError;
use crate::rod::ActiveSet;
use crate::run_folder::{RunFolder, Which};
use crate::stability::Analyzer;
use base64::Engine as _;
use base64::engine::general_purpose::STANDARD as BASE64;
use rayon::prelude::*;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

const TEMPLATE: &str = include_str!("viewer/viewer.html");
const SCRIPT: &str = include_str!("viewer/viewer.js");
const STYLE: &str = include_str!("viewer/viewer.css");
const APP_SCRIPT: &str = include_str!("viewer/app.js");

/// Standard base64 (with padding) of `bytes`.
pub fn base64(bytes: &[u8]) -> String {
    BASE64.encode(bytes)
}

/// Decodes standard base64 (for tests and tools); `None` on a malformed string.
pub fn base64_decode(s: &str) -> Option<Vec<u8>> {
    BASE64.decode(s).ok()
}

/// `{"f32": base64}` of `values` as little-endian `f32`.
pub fn encode_f32(values: impl IntoIterator<Item = f64>) -> Value {
    let bytes: Vec<u8> = values
        .into_iter()
        .flat_map(|v| (v as f32).to_le_bytes())
        .collect();
    json!({ "f32": base64(&bytes) })
}

/// `{"i16": base64, "scale": s, "max": m}`: `values[i] ≈ s · q[i]`, `q` little-endian `i16`,
/// `m` the largest absolute value.
pub fn encode_i16(values: &[f64]) -> Value {
    let max = values
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let scale = if max > 0.0 { max / 32767.0 } else { 1.0 };
    let bytes: Vec<u8> = values
        .iter()
        .flat_map(|&v| {
            let q = if v.is_finite() {
                (v / scale).round().clamp(-32767.0, 32767.0) as i16
            } else {
                0
            };
            q.to_le_bytes()
        })
        .collect();
    json!({ "i16": base64(&bytes), "scale": scale, "max": max })
}

/// Decodes [`encode_i16`] (for tests).
pub fn decode_i16(v: &Value) -> Option<Vec<f64>> {
    let bytes = base64_decode(v.get("i16")?.as_str()?)?;
    let scale = v.get("scale")?.as_f64()?;
    Some(
        bytes
            .chunks_exact(2)
            .map(|c| f64::from(i16::from_le_bytes([c[0], c[1]])) * scale)
            .collect(),
    )
}

/// Decodes [`encode_f32`] (for tests).
pub fn decode_f32(v: &Value) -> Option<Vec<f64>> {
    let bytes = base64_decode(v.get("f32")?.as_str()?)?;
    Some(
        bytes
            .chunks_exact(4)
            .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
            .collect(),
    )
}

/// Vertices of `curves` in ascending index order (the order of the per-iteration arrays).
pub fn active_vertices(run: &RunFolder, curves: &[usize]) -> Vec<usize> {
    let mut on = vec![false; run.network.positions.len()];
    for &c in curves {
        for &v in &run.network.rods[c].vertices {
            on[v as usize] = true;
        }
    }
    (0..on.len()).filter(|&v| on[v]).collect()
}

fn restrict(values: &[f64], vertices: &[usize]) -> Vec<f64> {
    vertices
        .iter()
        .flat_map(|&v| values[3 * v..3 * v + 3].iter().copied())
        .collect()
}

/// The gravity deflection `u = H⁻¹ f` of `curves` at displacements `u0` (`None` when the
/// Hessian is not positive definite), from the stability facade.
pub fn gravity_deflection(analyzer: &Analyzer, curves: &[usize], u0: &[f64]) -> Option<Vec<f64>> {
    let active = ActiveSet::from_curves(analyzer.network().rods.len(), curves);
    analyzer.gravity_at(&active, u0).map(|(u, _)| u)
}

/// Options of the viewer page.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Compute and embed the gravity deflection of every iteration.
    pub gravity: bool,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions { gravity: true }
    }
}

/// The data embedded in the viewer page.
pub fn viewer_data(run: &RunFolder, options: &ViewerOptions) -> Result<Value, ReportError> {
    viewer_data_with(run, options, &Deflections::default())
}

/// [`viewer_data`] with the gravity deflections already solved in `ahead` (those of other
/// curves, or missing, are solved here).
fn viewer_data_with(
    run: &RunFolder,
    options: &ViewerOptions,
    ahead: &Deflections,
) -> Result<Value, ReportError> {
    let net = &run.network;
    let r = &run.result;
    let n = run.iteration_count();
    // Each iteration's files are read and parsed on a thread of their own.
    let states: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|k| run.displacement(k))
        .collect::<Result<_, _>>()?;
    let modes: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|k| run.mode(k))
        .collect::<Result<_, _>>()?;
    let gravity: Vec<Option<Vec<f64>>> = if options.gravity {
        let missing = (0..n).any(|k| ahead.get(k, &r.iterations[k].curves).is_none());
        let analyzer = missing.then(|| analyzer_of(run)).transpose()?;
        (0..n)
            .into_par_iter()
            .map(|k| {
                let curves = &r.iterations[k].curves;
                match (ahead.get(k, curves), &analyzer) {
                    (Some(d), _) => d.clone(),
                    (None, Some(an)) => gravity_deflection(an, curves, &states[k]),
                    (None, None) => None,
                }
            })
            .collect()
    } else {
        vec![None; n]
    };
    let rods = rods_json(net);
    // When each curve was removed.
    let mut removed_at: Vec<Option<usize>> = vec![None; net.rods.len()];
    for (k, it) in r.iterations.iter().enumerate() {
        if let Some(c) = it.removed {
            removed_at[c] = Some(k);
        }
    }
    let iterations: Vec<Value> = r
        .iterations
        .iter()
        .enumerate()
        .map(|(k, it)| {
            let verts = active_vertices(run, &it.curves);
            let g = gravity[k].as_ref().map(|g| gravity_field(g, &verts));
            json!({
                "curves": it.curves,
                "length": it.length,
                "lambda": it.lambda,
                "eigenvalues": it.eigenvalues,
                "zero_modes": it.zero_modes,
                "negative_modes": it.negative_modes,
                "unstable": crate::run_folder::record_instability(it),
                // Its relaxation stopped short of equilibrium: the page says so beside `λ`.
                "unrelaxed": !it.newton.converged,
                "removed": it.removed,
                "score": it.score,
                "newton_iterations": it.newton.iterations,
                "physical": it.physical,
                "u": encode_i16(&restrict(&states[k], &verts)),
                "mode": encode_i16(&restrict(&modes[k], &verts)),
                "gravity": g,
            })
        })
        .collect();
    let chosen = chosen_data(run, options)?;
    let mesh = mesh_json(run.mesh.as_ref());
    let s = &r.setup;
    Ok(json!({
        "format": "curvenet-viewer",
        "version": 1,
        "title": title_of(run),
        "start": run.shown_index(),
        "answer": r.answer.is_some(),
        // What the iterations' `lambda` and `score` are: the labels the panel and the chart use.
        "objective": {
            "name": s.stability.objective.name(),
            "value": s.stability.objective.value_symbol(),
            "score": s.stability.objective.score_symbol(),
        },
        "setup": {
            "example": s.input.example,
            "mesh": s.input.mesh,
            "curve_files": s.input.curve_files,
            "supports": net.supports.name(),
            "material": s.stability.material,
            "gravity": s.stability.gravity,
            "edge_length": s.build.edge_length,
            "budget": r.budget,
            "total_length": s.total_length,
            "complete": r.complete,
            "stop": r.stop,
            // The physical mode's scene unit: the lengths shown carry it.
            "units": r.length_unit(),
        },
        "positions": encode_f32(net.positions.iter().flat_map(|p| p.to_array())),
        "rods": rods,
        "removed_at": removed_at,
        "iterations": iterations,
        "chosen": chosen,
        "mesh": mesh,
        "before": before_json(run),
    }))
}

/// A slid run's curves before they slid (`before.obj`), each as base64 `f32` points and
/// whether it is closed; `null` for any other run (or when the file cannot be read).
fn before_json(run: &RunFolder) -> Value {
    before_curves(run).map_or(Value::Null, |c| curves_json(&c))
}

/// A slid run's curves before they slid (`before.obj`, in the slid run's curve order); `None`
/// for any other run, or when the file cannot be read.
pub fn before_curves(run: &RunFolder) -> Option<Vec<Polyline>> {
    run.result.slide.as_ref()?;
    let text = run.files.read_text("before.obj").ok()?;
    let file = crate::io::parse_obj_polylines(&text, "before.obj").ok()?;
    Some(file.curves)
}

/// `curves` as the viewer's `before`: each as base64 `f32` points and whether it is closed.
fn curves_json(curves: &[Polyline]) -> Value {
    let curves: Vec<Value> = (curves.iter())
        .map(|c| {
            json!({
                "points": encode_f32(c.points.iter().flat_map(|p| p.to_array())),
                "closed": c.closed,
            })
        })
        .collect();
    Value::from(curves)
}

/// The surface as the viewer draws it: vertices as base64 `f32`, faces as base64 `u32`.
fn mesh_json(mesh: Option<&TriMesh>) -> Value {
    let Some(m) = mesh else {
        return Value::Null;
    };
    let faces: Vec<u8> = m
        .faces
        .iter()
        .flat_map(|f| f.iter().flat_map(|i| i.to_le_bytes()))
        .collect();
    json!({
        "vertices": encode_f32(m.vertices.iter().flat_map(|p| p.to_array())),
        "faces": { "u32": base64(&faces) },
    })
}

/// The viewer's description of every rod of `net`: vertices, closed, rest length, anchors,
/// supports and joints.
fn rods_json(net: &Network) -> Vec<Value> {
    let all: Vec<usize> = (0..net.rods.len()).collect();
    net.rods
        .iter()
        .enumerate()
        .map(|(c, rod)| {
            let joints: Vec<Value> = rod_joints(net, c, &all)
                .iter()
                .map(|j| json!([j.index, round6(j.s), j.vertex, j.meets]))
                .collect();
            json!({
                "v": rod.vertices,
                "closed": rod.closed,
                "length": round6(rod.rest_length()),
                "anchors": rod.anchors,
                "supports": rod_supports(rod),
                "ends": end_kinds(rod),
                "joints": joints,
            })
        })
        .collect()
}

/// How the viewer draws each end of `rod`: `clamped`, `pinned`, `partial` (some translations
/// fixed, or only the rotation held) or `free` (also a closed rod's).
fn end_kinds(rod: &crate::network::Rod) -> [&'static str; 2] {
    use crate::material::EndSupport;
    [true, false].map(|at_start| match rod.end_support(at_start) {
        Some(EndSupport::CLAMPED) => "clamped",
        Some(EndSupport::PINNED) => "pinned",
        Some(s) if s.is_support() => "partial",
        _ => "free",
    })
}

/// The answer and the alternatives for the viewer's list: label, where each comes from, its
/// curves, length, `λ_eq` and modes; those that are not greedy iterations with their own
/// equilibrium, mode and gravity deflection (as an iteration's).
fn chosen_data(run: &RunFolder, options: &ViewerOptions) -> Result<Vec<Value>, ReportError> {
    let r = &run.result;
    let mut which: Vec<(Which, String)> = Vec::new();
    if r.answer.is_some() {
        which.push((Which::Answer, "the answer".into()));
    }
    for n in 1..=r.alternatives.len() {
        which.push((Which::Alternative(n), format!("alternative {n}")));
    }
    let gravity = options.gravity && !which.is_empty();
    let analyzer = gravity.then(|| analyzer_of(run)).transpose()?;
    let answers = r.answer.iter().chain(&r.alternatives);
    let mut out = Vec::new();
    for ((w, label), a) in which.iter().zip(answers) {
        let mut e = json!({
            "label": label,
            "source": a.found.source,
            "iteration": a.found.iteration,
            "curves": a.found.curves,
            "length": a.found.length,
            "lambda": a.found.lambda,
            "zero_modes": a.zero_modes,
            "negative_modes": a.negative_modes,
        });
        if a.found.iteration.is_none() {
            let u = run.displacement_of(*w)?;
            let mode = run.mode_of(*w)?;
            let verts = active_vertices(run, &a.found.curves);
            let g = analyzer
                .as_ref()
                .and_then(|an| gravity_deflection(an, &a.found.curves, &u))
                .map(|g| gravity_field(&g, &verts));
            e["u"] = encode_i16(&restrict(&u, &verts));
            e["mode"] = encode_i16(&restrict(&mode, &verts));
            e["gravity"] = json!(g);
        }
        out.push(e);
    }
    Ok(out)
}

/// An analyzer of the run's network with its stability settings.
fn analyzer_of(run: &RunFolder) -> Result<Analyzer, ReportError> {
    Analyzer::new(run.network.clone(), run.result.setup.stability.clone())
        .map_err(|e| format!("{}: {e}", run.dir.join("result.json").display()).into())
}

/// The gravity deflection over `verts`, encoded with its largest displacement and the vertex
/// where it is.
fn gravity_field(deflection: &[f64], verts: &[usize]) -> Value {
    let restricted = restrict(deflection, verts);
    let (mut vmax, mut dmax) = (0usize, 0.0f64);
    for (i, c) in restricted.chunks(3).enumerate() {
        let d = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        if d > dmax {
            (vmax, dmax) = (verts[i], d);
        }
    }
    let mut e = encode_i16(&restricted);
    e["max_displacement"] = json!(dmax);
    e["vertex"] = json!(vmax);
    e
}

fn round6(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let e = v.abs().log10().floor() as i32;
    let f = 10f64.powi(5 - e);
    (v * f).round() / f
}

fn title_of(run: &RunFolder) -> String {
    let s = &run.result.setup.input;
    let what = s
        .example
        .clone()
        .or_else(|| s.curve_files.first().cloned())
        .unwrap_or_else(|| "run".into());
    format!("curvenet: {what}")
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The self-contained viewer page of a run.
pub fn viewer_html(run: &RunFolder, options: &ViewerOptions) -> Result<String, ReportError> {
    page(&title_of(run), &viewer_data(run, options)?, "")
}

/// The page `curvenet serve` answers at `/`: the viewer in its app mode, with the app's script
/// (`report/viewer/app.js`) that edits the structure over the server's JSON API. The data is
/// the run page's with one live structure in place of the iterations: `setup` as a run's
/// (`total_length`, `material`, ...; `budget` null), `live` as an iteration's with `u`, `mode`
/// and `gravity` given in full (`{"full": [3 numbers per vertex]}`), the surface `mesh` when
/// known, `objective` as a run's (its name and the symbols of its value and score) and, for a
/// slid run's network, `before`: its curves before they slid (the viewer's toggle shows them).
pub fn app_html(
    net: &Network,
    title: &str,
    setup: Value,
    live: Value,
    mesh: Option<&TriMesh>,
    objective: Value,
    before: Option<&[Polyline]>,
) -> Result<String, ReportError> {
    let data = json!({
        "format": "curvenet-viewer",
        "version": 1,
        "app": true,
        "title": title,
        "start": 0,
        "answer": false,
        "objective": objective,
        "setup": setup,
        "positions": encode_f32(net.positions.iter().flat_map(|p| p.to_array())),
        "rods": rods_json(net),
        "removed_at": vec![None::<usize>; net.rods.len()],
        "iterations": [live],
        "mesh": mesh_json(mesh),
        "before": before.map_or(Value::Null, curves_json),
    });
    page(title, &data, &format!("<script>\n{APP_SCRIPT}\n</script>"))
}

/// The viewer's template filled: `title` (escaped), the data's JSON (`</` escaped) and the app's
/// script element (empty for a run's page).
fn page(title: &str, data: &Value, app: &str) -> Result<String, ReportError> {
    let json = serde_json::to_string(data).map_err(|e| e.to_string())?;
    // Inside <script>, "</" could close the element: JSON allows "\/" for "/".
    let json = json.replace("</", "<\\/");
    Ok(fill_template(
        TEMPLATE,
        &[
            ("TITLE", &html_escape(title)),
            ("STYLE", STYLE),
            ("SCRIPT", SCRIPT),
            ("DATA", &json),
            ("APP", app),
        ],
    ))
}

/// Replaces every `{{NAME}}` of `template` (and only of the template: values are not scanned)
/// by its value.
fn fill_template(template: &str, values: &[(&str, &str)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(i) = rest.find("{{") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        match after.find("}}").and_then(|j| {
            let name = &after[..j];
            values.iter().find(|v| v.0 == name).map(|v| (j, v.1))
        }) {
            Some((j, value)) => {
                out.push_str(value);
                rest = &after[j + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// Writes the viewer page of `run` to `path`.
pub fn write_viewer(
    run: &RunFolder,
    path: &Path,
    options: &ViewerOptions,
) -> Result<(), ReportError> {
    let html = viewer_html(run, options)?;
    crate::io::write_atomic(path, html.as_bytes()).map_err(|e| ReportError::io(path, e))
}

/// Writes `final.png`, `mode.png` (the answer, wherever it comes from; without one, or
/// without its state, the iteration of [`RunFolder::shown_index`]), `lambda.png` and, for a
/// slid run, `slide.png` (before and after it slid) into the run folder.
pub fn write_pictures(run: &RunFolder) -> Result<Vec<PathBuf>, ReportError> {
    let which = if run.result.answer.is_some() && run.displacement_of(Which::Answer).is_ok() {
        Which::Answer
    } else {
        Which::Iteration(run.shown_index())
    };
    // The three pictures are drawn and written side by side (each on a thread of its own).
    let save = |name: &str, image: Result<Image, ReportError>| -> Result<PathBuf, ReportError> {
        let p = run.dir.join(name);
        image?.write_png(&p)?;
        Ok(p)
    };
    let ((network, mode), lambda) = rayon::join(
        || {
            rayon::join(
                || save("final.png", network_picture(run, which)),
                || save("mode.png", mode_picture(run, which)),
            )
        },
        || save("lambda.png", Ok(lambda_plot(&run.result))),
    );
    let mut out = vec![network?, mode?, lambda?];
    if let Some(img) = super::render::slide_picture(run)? {
        out.push(save("slide.png", Ok(img))?);
    }
    Ok(out)
}

/// What [`write_run_outputs`] wrote.
#[derive(Clone, Debug, Default)]
pub struct RunOutputs {
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Problems met on the way (the run's own files are untouched by them).
    pub warnings: Vec<String>,
}

/// Writes the pictures, `fabrication.csv` of the answer (and `alternative-N.csv`, each
/// alternative's fabrication table) and, last, `viewer.html` into the run folder `dir`. A run
/// without an answer gets no fabrication table (a warning says why): its networks within the
/// budget are not something to build.
pub fn write_run_outputs(dir: &Path) -> Result<RunOutputs, ReportError> {
    write_run_outputs_with(dir, &Deflections::default())
}

/// [`write_run_outputs`] with the gravity deflections solved while the greedy ran
/// ([`super::gravity_ahead`]): the same files, sooner.
pub fn write_run_outputs_with(dir: &Path, ahead: &Deflections) -> Result<RunOutputs, ReportError> {
    let run = RunFolder::open(dir)?;
    let mut out = RunOutputs {
        warnings: run.warnings.clone(),
        ..Default::default()
    };
    // The viewer page (every iteration's files read back, the gravity deflections) is made
    // and written under a temporary name while the pictures and tables are drawn; it takes
    // its place last: a run folder with its viewer page has every file of this stage (a run
    // stopped before it draws them again when resumed).
    let p = dir.join("viewer.html");
    let (tables, staged) = rayon::join(
        || write_pictures_and_tables(&run, &mut out),
        || -> Result<_, ReportError> {
            let data = viewer_data_with(&run, &ViewerOptions::default(), ahead)?;
            let html = page(&title_of(&run), &data, "")?;
            crate::io::stage_atomic(&p, html.as_bytes()).map_err(|e| ReportError::io(&p, e))
        },
    );
    tables?;
    staged?.commit().map_err(|e| ReportError::io(&p, e))?;
    out.files.push(p);
    Ok(out)
}

/// The pictures, `fabrication.csv` and each `alternative-N.csv` of [`write_run_outputs`].
fn write_pictures_and_tables(run: &RunFolder, out: &mut RunOutputs) -> Result<(), ReportError> {
    let dir = &run.dir;
    out.files.extend(write_pictures(run)?);
    let p = dir.join("fabrication.csv");
    match fabrication_csv(run, Which::Answer).ok() {
        Some(csv) => {
            crate::io::write_atomic(&p, csv.as_bytes()).map_err(|e| ReportError::io(&p, e))?;
            out.files.push(p);
        }
        None => {
            if p.exists() {
                std::fs::remove_file(&p).map_err(|e| ReportError::io(&p, e))?;
            }
            let why = run.result.no_answer.as_ref().map_or_else(
                || "the run has no answer".to_string(),
                |n| n.reason.render(&crate::words::Recorded),
            );
            out.warnings
                .push(format!("no fabrication table: nothing to build ({why})"));
        }
    }
    for n in 1..=run.result.alternatives.len() {
        let p = dir.join(format!("alternative-{n}.csv"));
        let csv = fabrication_csv(run, Which::Alternative(n))?;
        crate::io::write_atomic(&p, csv.as_bytes()).map_err(|e| ReportError::io(&p, e))?;
        out.files.push(p);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trip() {
        assert_eq!(base64(b"Man"), "TWFu");
        assert_eq!(base64(b"Ma"), "TWE=");
        assert_eq!(base64(b"M"), "TQ==");
        for n in 0..20u8 {
            let v: Vec<u8> = (0..n).map(|i| i.wrapping_mul(37)).collect();
            assert_eq!(base64_decode(&base64(&v)).as_deref(), Some(&v[..]));
        }
        assert!(base64_decode("TQ=").is_none());
    }

    #[test]
    fn quantized_arrays() {
        let v = [0.0, -2.5e-9, 1.0e-9, 2.5e-9];
        let e = encode_i16(&v);
        let d = decode_i16(&e).unwrap();
        for (a, b) in v.iter().zip(&d) {
            assert!((a - b).abs() <= 2.5e-9 / 32767.0);
        }
        assert_eq!(round6(1234.56789), 1234.57);
        assert_eq!(round6(-0.000123456789), -0.000123457);
    }
}

//! Line plots drawn with [`super::render`]: `lambda.png`, the greedy path.
//!
//! Two panels share the x axis, the number of curves in the network (decreasing from left to
//! right, as the greedy goes): `λ_eq` above, the total rest length below with the budget as a
//! dashed line. Axes carry ticks at "nice" values, and a common power of ten goes into the axis
//! label when the values are very small or very large.

use super::render::{INK, Image, KEPT, REMOVED, Rgb, rgb8, text_width};
use crate::fmt::significant;
use crate::run_folder::ResultFile;
use crate::simplify::greedy::IterationRecord;

/// Size of `lambda.png`.
pub const PLOT_SIZE: (usize, usize) = (960, 800);

const GRID: Rgb = rgb8(225, 225, 230);
const AXIS: Rgb = rgb8(80, 80, 90);

/// "Nice" tick values covering `[lo, hi]`: steps of 1, 2 or 5 times a power of ten.
pub fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let pad = if lo != 0.0 { lo.abs() * 0.1 } else { 1.0 };
        (lo - pad, hi + pad)
    };
    let raw = (hi - lo) / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).floor() as i64;
    let last = (hi / step).ceil() as i64;
    let ticks = (first..=last).map(|i| i as f64 * step).collect();
    (ticks, step)
}

/// The power of ten to factor out of axis labels (0 when the values read well as they are).
pub fn common_exponent(values: &[f64]) -> i32 {
    let m = values.iter().map(|v| v.abs()).fold(0.0, f64::max);
    if m == 0.0 || !m.is_finite() {
        return 0;
    }
    let e = m.log10().floor() as i32;
    if (-2..5).contains(&e) { 0 } else { e }
}

fn tick_label(v: f64, step: f64, exp: i32) -> String {
    let scaled = v / 10f64.powi(exp);
    let s = step / 10f64.powi(exp);
    let decimals = if s >= 1.0 {
        0
    } else {
        (-s.log10().floor()) as usize
    };
    let t = format!("{scaled:.decimals$}");
    if t.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        t
    }
}

/// A series to plot: its points, its colour, and whether it is dashed (dashed series have no
/// markers).
pub type Series<'a> = (&'a [(f64, f64)], Rgb, bool);

/// One panel: a frame with ticks, and series of points.
pub struct Panel<'a> {
    /// Pixel rectangle of the plotting area `(x, y, w, h)`.
    pub rect: (f64, f64, f64, f64),
    /// x range (may be decreasing).
    pub x_range: (f64, f64),
    /// Label of the y axis (the common power of ten is appended).
    pub y_label: &'a str,
    /// Label of the x axis (none for an upper panel).
    pub x_label: Option<&'a str>,
}

impl Panel<'_> {
    fn sx(&self, x: f64) -> f64 {
        let (a, b) = self.x_range;
        self.rect.0 + (x - a) / (b - a) * self.rect.2
    }

    /// Draws the panel with `series` (points, colour, dashed) and returns nothing; the y range
    /// covers all series.
    pub fn draw(&self, img: &mut Image, series: &[Series<'_>]) {
        let ys: Vec<f64> = series
            .iter()
            .flat_map(|s| s.0.iter().map(|p| p.1))
            .filter(|y| y.is_finite())
            .collect();
        let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        let (ticks, step) = nice_ticks(lo, hi, 5);
        let (y0, y1) = (ticks[0], *ticks.last().unwrap_or(&1.0));
        let (rx, ry, rw, rh) = self.rect;
        let sy = |y: f64| ry + rh - (y - y0) / (y1 - y0).max(f64::MIN_POSITIVE) * rh;
        let exp = common_exponent(&ticks);
        // Grid and y ticks.
        for &t in &ticks {
            let y = sy(t);
            img.line2d((rx, y), (rx + rw, y), 1.0, GRID);
            let label = tick_label(t, step, exp);
            let w = text_width(&label, 2);
            img.text((rx - 10.0) as i64 - w, y as i64 - 7, &label, 2, INK);
        }
        // x ticks: integers (curve counts).
        let (xa, xb) = self.x_range;
        let (xlo, xhi) = (xa.min(xb), xa.max(xb));
        let (xt, xstep) = nice_ticks(xlo, xhi, 8);
        let xstep = xstep.max(1.0);
        for &t in xt.iter().filter(|&&t| t >= xlo - 1e-9 && t <= xhi + 1e-9) {
            let x = self.sx(t);
            img.line2d((x, ry), (x, ry + rh), 1.0, GRID);
            img.line2d((x, ry + rh), (x, ry + rh + 6.0), 1.5, AXIS);
            if self.x_label.is_some() {
                let label = tick_label(t, xstep, 0);
                let w = text_width(&label, 2);
                img.text(x as i64 - w / 2, (ry + rh + 12.0) as i64, &label, 2, INK);
            }
        }
        // Frame.
        img.line2d((rx, ry), (rx, ry + rh), 1.5, AXIS);
        img.line2d((rx, ry + rh), (rx + rw, ry + rh), 1.5, AXIS);
        img.line2d((rx, ry), (rx + rw, ry), 1.0, AXIS);
        img.line2d((rx + rw, ry), (rx + rw, ry + rh), 1.0, AXIS);
        // Labels.
        let y_label = if exp != 0 {
            format!("{} (×1e{exp})", self.y_label)
        } else {
            self.y_label.to_string()
        };
        let w = text_width(&y_label, 2);
        img.text_vertical(16, (ry + 0.5 * rh) as i64 + w / 2, &y_label, 2, INK);
        if let Some(xl) = self.x_label {
            let w = text_width(xl, 2);
            img.text(
                (rx + 0.5 * rw) as i64 - w / 2,
                (ry + rh + 40.0) as i64,
                xl,
                2,
                INK,
            );
        }
        // Series.
        for (pts, color, dashed) in series {
            let p: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.1.is_finite())
                .map(|&(x, y)| (self.sx(x), sy(y)))
                .collect();
            for w in p.windows(2) {
                if *dashed {
                    let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
                    let len = (dx * dx + dy * dy).sqrt();
                    let n = (len / 8.0).ceil().max(1.0) as usize;
                    for i in (0..n).step_by(2) {
                        let (t0, t1) = (i as f64 / n as f64, ((i + 1) as f64 / n as f64).min(1.0));
                        img.line2d(
                            (w[0].0 + t0 * dx, w[0].1 + t0 * dy),
                            (w[0].0 + t1 * dx, w[0].1 + t1 * dy),
                            2.0,
                            *color,
                        );
                    }
                } else {
                    img.line2d(w[0], w[1], 2.5, *color);
                }
            }
            if !dashed {
                for &(x, y) in &p {
                    img.fill_rect(x as i64 - 3, y as i64 - 3, 7, 7, *color, 1.0);
                }
            }
        }
    }
}

/// `lambda.png`: `λ_eq` (`μ_min` under the frequency objective) and total rest length
/// against the number of curves along the greedy.
pub fn lambda_plot(result: &ResultFile) -> Image {
    let value = result.setup.stability.objective.value_symbol();
    let (w, h) = PLOT_SIZE;
    let mut img = Image::new(w, h);
    let its = &result.iterations;
    // A figure of each iteration against its number of curves.
    let series = |f: fn(&IterationRecord) -> f64| -> Vec<(f64, f64)> {
        its.iter().map(|i| (i.curves.len() as f64, f(i))).collect()
    };
    let (lam, len) = (series(|i| i.lambda), series(|i| i.length));
    let first = its.first().map_or(1.0, |i| i.curves.len() as f64);
    let last = its.last().map_or(0.0, |i| i.curves.len() as f64);
    let x_range = if first > last {
        (first + 0.5, last - 0.5)
    } else {
        (first + 0.5, first - 1.5)
    };
    let (left, right) = (150.0, 30.0);
    let top = Panel {
        rect: (left, 80.0, w as f64 - left - right, 280.0),
        x_range,
        y_label: value,
        x_label: None,
    };
    top.draw(&mut img, &[(&lam, KEPT, false)]);
    let bottom = Panel {
        rect: (left, 420.0, w as f64 - left - right, 280.0),
        x_range,
        y_label: "total rest length",
        x_label: Some("number of curves (the greedy removes one per step, left to right)"),
    };
    let budget = [(x_range.0, result.budget), (x_range.1, result.budget)];
    bottom.draw(
        &mut img,
        &[(&len, rgb8(40, 130, 90), false), (&budget, REMOVED, true)],
    );
    let n0 = its.first().map_or(0, |i| i.curves.len());
    let (nk, lk) = its.last().map_or((0, 0.0), |i| (i.curves.len(), i.lambda));
    img.text(
        16,
        14,
        &format!(
            "greedy path: {n0} -> {nk} curves, final {value} = {}",
            significant(lk, 4)
        ),
        2,
        INK,
    );
    img.text(
        16,
        40,
        &format!(
            "top: {value} at each step; bottom: total rest length, dashed: budget {}",
            significant(result.budget, 6)
        ),
        2,
        rgb8(90, 90, 100),
    );
    img
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice() {
        let (t, s) = nice_ticks(0.13, 0.91, 5);
        assert_eq!(s, 0.2);
        assert!(t[0] <= 0.13 && *t.last().unwrap() >= 0.91);
        let (t, _) = nice_ticks(2.3e-9, 2.3e-9, 5);
        assert!(t.len() >= 2);
        assert_eq!(common_exponent(&[1e-8, 2.5e-8]), -8);
        assert_eq!(common_exponent(&[10.0, 2000.0]), 0);
        assert_eq!(tick_label(2.0e-8, 5e-9, -8), "2.0");
        assert_eq!(tick_label(40000.0, 20000.0, 0), "40000");
    }
}

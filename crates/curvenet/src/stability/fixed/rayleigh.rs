//! Rayleigh certificates: test vectors turned into upper bounds on `λ_fix` valid for every
//! subset (see the module documentation of [`super`]).

use super::FixedProblem;
use faer::MatRef;
use rayon::prelude::*;
use std::sync::Arc;

/// Relative width of an eigenvalue cluster treated as one repeated eigenvalue.
const CLUSTER: f64 = 1e-6;
/// Modes per eigen solve whose Rayleigh certificates are kept.
const CERT_MODES: usize = 3;

/// A test-vector certificate: `a_c = Σ_k z_k x_kᵀH_cx_k` per curve and `w` summed per vertex
/// group (see the module documentation). Valid for every subset, whatever `x` was.
#[derive(Clone, Debug)]
pub struct Rayleigh {
    pub(super) a: Vec<f64>,
    pub(super) g: Vec<f64>,
}

impl Rayleigh {
    /// Total weight `Σ_v w_v` (the denominator when every vertex is covered).
    pub(super) fn mass(&self) -> f64 {
        self.g.iter().sum()
    }

    /// `a_c`: the certificate's quadratic form of curve `c`'s terms.
    pub(super) fn weight(&self, c: usize) -> f64 {
        self.a[c]
    }

    /// The same certificate scaled to unit mass (None when it has none).
    pub(super) fn normalized(&self) -> Option<Rayleigh> {
        let m = self.mass();
        if !(m > 0.0 && m.is_finite()) {
            return None;
        }
        Some(Rayleigh {
            a: self.a.iter().map(|x| x / m).collect(),
            g: self.g.iter().map(|x| x / m).collect(),
        })
    }

    /// `(1 − z)·self + z·other`: the certificate of the union of the two weighted vector sets.
    fn mix(&self, other: &Rayleigh, z: f64) -> Rayleigh {
        Rayleigh {
            a: self
                .a
                .iter()
                .zip(&other.a)
                .map(|(x, y)| (1.0 - z) * x + z * y)
                .collect(),
            g: self
                .g
                .iter()
                .zip(&other.g)
                .map(|(x, y)| (1.0 - z) * x + z * y)
                .collect(),
        }
    }
}

/// The best mixture `(1 − z)·base + z·r` for a bound `f` (quasi-convex in `z`: its sublevel
/// sets are convex), by golden-section search over `t = logit(z)` plus both ends.
pub(super) fn best_mixture(
    base: &Rayleigh,
    r: &Rayleigh,
    f: &dyn Fn(&Rayleigh) -> f64,
) -> (Rayleigh, f64) {
    let (Some(b), Some(r)) = (base.normalized(), r.normalized()) else {
        let fb = f(base);
        let fr = f(r);
        return if fr < fb {
            (r.clone(), fr)
        } else {
            (base.clone(), fb)
        };
    };
    let fb = f(&b);
    let fr = f(&r);
    let mut best = if fr < fb {
        (r.clone(), fr)
    } else {
        (b.clone(), fb)
    };
    let at = |t: f64| -> (Rayleigh, f64) {
        let z = 1.0 / (1.0 + (-t).exp());
        let m = b.mix(&r, z);
        let v = f(&m);
        (m, v)
    };
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (-24.0f64, 24.0f64);
    let mut x1 = hi - phi * (hi - lo);
    let mut x2 = lo + phi * (hi - lo);
    let mut f1 = at(x1);
    let mut f2 = at(x2);
    for _ in 0..28 {
        if f1.1 <= f2.1 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - phi * (hi - lo);
            f1 = at(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + phi * (hi - lo);
            f2 = at(x2);
        }
    }
    for cand in [f1, f2] {
        if cand.1 < best.1 {
            best = cand;
        }
    }
    best
}

impl FixedProblem<'_> {
    /// Certificates from modes `x` (columns, eigenvalues `values` ascending): each of the
    /// lowest [`CERT_MODES`] alone, and the equal-weight mixture of the lowest cluster when the
    /// smallest eigenvalue is repeated.
    pub(super) fn certificates_of(&self, x: MatRef<'_, f64>, values: &[f64]) -> Vec<Arc<Rayleigh>> {
        let k = x.ncols().min(values.len());
        if k == 0 {
            return Vec::new();
        }
        let model = self.analyzer.model();
        let n = self.curve_count();
        // Curves touching the support.
        let mut nonzero = vec![false; model.vertex_count()];
        for (v, nz) in nonzero.iter_mut().enumerate() {
            *nz = (0..k).any(|j| (0..3).any(|a| x[(3 * v + a, j)] != 0.0));
        }
        let touched: Vec<usize> = (0..n)
            .filter(|&c| model.curve_vertices(c).iter().any(|&v| nonzero[v as usize]))
            .collect();
        // Per-mode quadratic forms x_jᵀ H_c x_j.
        let forms: Vec<(usize, Vec<f64>)> = touched
            .par_iter()
            .map(|&c| {
                let hx = model.curve_hessian_product(&self.locals, c, x);
                let verts = model.curve_vertices(c);
                let mut f = vec![0.0; k];
                for (s, &v) in verts.iter().enumerate() {
                    for a in 0..3 {
                        let row = 3 * v as usize + a;
                        for (j, fj) in f.iter_mut().enumerate() {
                            *fj += x[(row, j)] * hx[(3 * s + a, j)];
                        }
                    }
                }
                (c, f)
            })
            .collect();
        let mut gw = vec![vec![0.0; k]; self.groups.len()];
        for (gi, g) in self.groups.iter().enumerate() {
            for &v in &g.vertices {
                if !nonzero[v as usize] {
                    continue;
                }
                for (j, w) in gw[gi].iter_mut().enumerate() {
                    for a in 0..3 {
                        let e = x[(3 * v as usize + a, j)];
                        *w += e * e;
                    }
                }
            }
        }
        let make = |z: &[f64]| -> Arc<Rayleigh> {
            let mut a = vec![0.0; n];
            for (c, f) in &forms {
                a[*c] = f.iter().zip(z).map(|(x, y)| x * y).sum();
            }
            let g = gw
                .iter()
                .map(|w| w.iter().zip(z).map(|(x, y)| x * y).sum())
                .collect();
            Arc::new(Rayleigh { a, g })
        };
        let mut out = Vec::new();
        for j in 0..k.min(CERT_MODES) {
            let mut z = vec![0.0; k];
            z[j] = 1.0;
            out.push(make(&z));
        }
        let lo = values[0];
        let tol = CLUSTER * lo.abs().max(self.margin);
        let m = values[..k].iter().take_while(|&&v| v - lo <= tol).count();
        if m > 1 {
            let mut z = vec![0.0; k];
            for zj in z.iter_mut().take(m) {
                *zj = 1.0 / m as f64;
            }
            out.push(make(&z));
        }
        out
    }
}

//! The model a run analyses, as a user sets it ([`ModelOptions`]: the paper's material, the
//! number of eigenvalues, the objective, the physical mode's options) turned into the
//! stability parameters and, in the physical mode, the physical parameters: one place for
//! every front end.

use crate::app::AppError;
use crate::material::CurveSpec;
use crate::physics::{PhysicalOptions, PhysicalParams};
use crate::rod::Material;
use crate::stability::{Objective, StabilityParams};
use crate::words::{Opt, given, message};

/// The most eigenvalues an analysis reports (and, in the physical mode, frequencies): the
/// solver's one limit.
pub use crate::solve::MAX_EIGEN_COUNT;

/// The model's options, as a user gives them (`None`: the default).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelOptions {
    /// Rod radius: the paper's model's (scene units, default 2) or, in the physical mode,
    /// the physical rods' solid section.
    pub radius: Option<f64>,
    /// Young's modulus: a plain number in the paper's mode (default 1); with a stress unit
    /// (`210GPa`) in the physical mode, overriding the material's.
    pub young: Option<String>,
    /// The paper's anchor weight µ (default 500).
    pub anchor_weight: Option<f64>,
    /// How many of the smallest eigenvalues an analysis reports (1 to
    /// [`MAX_EIGEN_COUNT`]); in the physical mode also how many frequencies.
    pub eigen_count: usize,
    /// What the searches maximise.
    pub objective: Objective,
    /// The physical mode's options (its `young` and `radius` are taken from the fields
    /// above).
    pub physical: PhysicalOptions,
}

impl Default for ModelOptions {
    fn default() -> Self {
        ModelOptions {
            radius: None,
            young: None,
            anchor_weight: None,
            eigen_count: 4,
            objective: Objective::Lambda,
            physical: PhysicalOptions::default(),
        }
    }
}

/// The model resolved: the paper's model's parameters (what `λ` and the searches use) and, in
/// the physical mode, the physical parameters and the options they came from (what a run
/// folder records and a resume must match).
#[derive(Clone, Debug)]
pub struct Model {
    /// The stability parameters (the paper's model, maximising the objective).
    pub stability: StabilityParams,
    /// The physical mode's parameters (`None` in the paper's mode).
    pub physical: Option<PhysicalParams>,
    /// The physical mode's options as given (`None` in the paper's mode).
    pub physical_options: Option<PhysicalOptions>,
}

impl ModelOptions {
    /// The physical mode's options as given, `young` and `radius` included.
    pub fn physical_options(&self) -> PhysicalOptions {
        PhysicalOptions {
            young: self.young.clone(),
            radius: self.radius.map(|r| r.to_string()),
            ..self.physical.clone()
        }
    }

    /// The model of these options for curves whose files declare `file_units` and `specs`.
    /// In the physical mode `radius` and `young` describe the physical rods, so the paper's
    /// model (its `λ`, the searches' objective) keeps its defaults and chooses as without
    /// the physical options.
    pub fn resolve(
        &self,
        file_units: Option<&str>,
        specs: &[CurveSpec],
    ) -> Result<Model, AppError> {
        if !(1..=MAX_EIGEN_COUNT).contains(&self.eigen_count) {
            return Err(AppError::usage(message![
                given(Opt::EigenCount, self.eigen_count),
                format!(": give 1 to {MAX_EIGEN_COUNT}")
            ]));
        }
        let options = self.physical_options();
        let physical = options
            .resolve(file_units, specs)
            .map_err(AppError::Usage)?;
        let paper = match &physical {
            Some(_) => ModelOptions {
                young: None,
                radius: None,
                ..self.clone()
            },
            None => self.clone(),
        };
        let mut stability = paper.stability_params()?;
        stability.objective = self.objective;
        let physical = physical.map(|mut p| {
            p.frequencies = self.eigen_count;
            p
        });
        Ok(Model {
            physical_options: physical.is_some().then_some(options),
            physical,
            stability,
        })
    }

    /// The paper's model's stability parameters (defaults where unset), checked.
    fn stability_params(&self) -> Result<StabilityParams, AppError> {
        let mut s = StabilityParams::default();
        let d = Material::default();
        for (opt, v) in [
            (Opt::Radius, self.radius),
            (Opt::AnchorWeight, self.anchor_weight),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v > 0.0)
            {
                return Err(AppError::usage(message![
                    given(opt, v),
                    ": must be a positive number"
                ]));
            }
        }
        s.material = Material {
            radius: self.radius.unwrap_or(d.radius),
            young: match &self.young {
                Some(t) => t
                    .trim()
                    .parse()
                    .ok()
                    .filter(|y: &f64| y.is_finite() && *y > 0.0)
                    .ok_or_else(|| {
                        AppError::usage(message![
                            given(Opt::Young, format!("{t:?}")),
                            ": the paper's mode takes a plain positive number (default 1); a \
                             modulus with a unit such as 210GPa needs the physical mode (",
                            Opt::Units,
                            " mm|cm|m, or ",
                            Opt::Material,
                            " NAME)"
                        ])
                    })?,
                None => d.young,
            },
            anchor_weight: self.anchor_weight.unwrap_or(d.anchor_weight),
        };
        s.eigen = s.eigen.with_count(self.eigen_count);
        let m = &s.material;
        let (lo, hi) = crate::rod::STIFFNESS_RANGE;
        for (name, k, formula) in [
            ("stretching", m.ks(), "E π r²"),
            ("bending", m.kb(), "E π r⁴ / 4"),
        ] {
            if !(lo..=hi).contains(&k) {
                return Err(AppError::usage(message![
                    given(Opt::Radius, format!("{:e}", m.radius)),
                    " and ",
                    given(Opt::Young, format!("{:e}", m.young)),
                    format!(
                        " give a {name} stiffness {formula} = {k:e}, out of the range the \
                         solvers handle ({lo:e} to {hi:e}); choose scene units where the \
                         radius is nearer 1"
                    )
                ]));
            }
        }
        if !(lo..=hi).contains(&(2.0 * m.anchor_weight)) {
            return Err(AppError::usage(message![
                given(Opt::AnchorWeight, format!("{:e}", m.anchor_weight)),
                format!(": an anchor's stiffness 2µ must lie between {lo:e} and {hi:e}")
            ]));
        }
        s.validate().map_err(AppError::Usage)?;
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The physical mode reports as many frequencies as eigenvalues, up to the one limit.
    #[test]
    fn the_physical_mode_takes_every_eigen_count_the_model_allows() {
        let options = |eigen_count| ModelOptions {
            eigen_count,
            physical: PhysicalOptions {
                units: Some("mm".into()),
                ..PhysicalOptions::default()
            },
            ..ModelOptions::default()
        };
        let model = options(MAX_EIGEN_COUNT)
            .resolve(None, &[])
            .expect("resolved");
        let physical = model.physical.expect("the physical mode");
        assert_eq!(physical.frequencies, MAX_EIGEN_COUNT);
        physical
            .validate()
            .expect("as many frequencies as eigenvalues");
        assert_eq!(model.stability.eigen.count, MAX_EIGEN_COUNT);
        let refused = options(MAX_EIGEN_COUNT + 1).resolve(None, &[]).unwrap_err();
        assert!(refused.to_string().contains("eigen_count"), "{refused}");
    }
}

//! [`Setup`]: a run's validated start — the inputs read ([`super::inputs`]), the model
//! resolved ([`super::model`]) and, once built, the rod network with its build's findings.

use super::inputs::{InputSpec, Inputs, read_inputs};
use super::model::{Model, ModelOptions};
use crate::app::AppError;
use crate::network::{BuildInfo, Network, build_network};
use crate::stability::Analyzer;
use crate::words::{Message, Opt, message};

/// The inputs read, the model resolved, the network built on demand.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The inputs.
    pub inputs: Inputs,
    /// The model.
    pub model: Model,
    built: Option<(Network, BuildInfo)>,
}

impl Setup {
    /// Reads `input` and resolves `model` against what the curve files declare (their units
    /// and per-curve specs). The network is not built yet ([`Self::build`]).
    pub fn new(input: &InputSpec, model: &ModelOptions) -> Result<Setup, AppError> {
        let inputs = read_inputs(input)?;
        let model = model.resolve(inputs.file_units.as_deref(), &inputs.specs)?;
        Ok(Setup {
            inputs,
            model,
            built: None,
        })
    }

    /// A set-up of inputs read and a model resolved already (a slid network's).
    pub(crate) fn from_parts(inputs: Inputs, model: Model) -> Setup {
        Setup {
            inputs,
            model,
            built: None,
        }
    }

    /// Builds the network (once; later calls keep it).
    pub fn build(&mut self) -> Result<&(Network, BuildInfo), AppError> {
        if self.built.is_none() {
            self.built = Some(build_network(&self.inputs.curves, &self.inputs.build)?);
        }
        Ok(self.built.as_ref().expect("built above"))
    }

    /// The network and its build's findings, when built.
    pub fn built(&self) -> Option<&(Network, BuildInfo)> {
        self.built.as_ref()
    }

    /// How many curves the inputs hold.
    pub fn curve_count(&self) -> usize {
        self.inputs.curves.len()
    }

    /// The analyzer of the built network in the model (building it first when needed).
    pub fn analyzer(&mut self) -> Result<Analyzer, AppError> {
        let network = self.build()?.0.clone();
        let mut analyzer = Analyzer::new(network, self.model.stability.clone())?;
        if let Some(p) = &self.model.physical {
            analyzer = analyzer.with_physical(p.clone())?;
        }
        Ok(analyzer)
    }

    /// The build's findings (overlapping curves, short edges, floating closed curves), once
    /// built.
    pub fn build_warnings(&self) -> Vec<Message> {
        self.built
            .as_ref()
            .map(|(_, info)| info.warnings.clone())
            .unwrap_or_default()
    }
}

/// Refuses curve ids that `option` names when the input (`n` curves) lacks one.
pub fn check_curve_ids(option: Opt, ids: &[usize], n: usize) -> Result<(), AppError> {
    match ids.iter().find(|&&c| c >= n) {
        Some(&bad) => Err(AppError::usage(message![
            option,
            format!(
                " names curve {bad}, but the input has {n} curves (ids 0..{})",
                n.saturating_sub(1)
            )
        ])),
        None => Ok(()),
    }
}

//! Sliding a drawing's structure: the kept curves of the design moved on the surface by the
//! slide feature's search ([`crate::slide::Slider`]), the removed curves left as they are;
//! the slid curves then replace the drawn ones as one edit ([`DrawEdit::Replace`]).

use super::{DrawEdit, DrawError, Drawing};
use crate::constraints::{Constraints, SymmetryOption};
use crate::io::Polyline;
use crate::physics::PhysicalParams;
use crate::slide::{SlideParams, SlideProblem, Slider};

impl Drawing {
    /// The slider of the structure `kept` (ids of the drawing's curves, ascending): its
    /// curves as drawn, each with its own end supports, `budget` (a length) and the design
    /// constraints `constraints` bound to the drawing's network (groups and symmetry orbits
    /// move together; the keep list stays), searched with `params`.
    ///
    /// # Errors
    ///
    /// An unknown curve, no curve kept, or a model that cannot be resolved.
    ///
    /// In the physical mode each network is analysed as the page analyses the design (each
    /// curve its own material, section and rest shape), without the load cases (the
    /// objective does not use them; the adopted design's analysis has them again).
    pub fn slider(
        &self,
        kept: &[usize],
        budget: f64,
        constraints: &Constraints,
        params: SlideParams,
    ) -> Result<Slider, DrawError> {
        for &c in kept {
            self.check_id(c)?;
        }
        if kept.is_empty() {
            return Err(DrawError::Slide(
                "the structure has no curve to slide: keep at least one".into(),
            ));
        }
        let i = &self.inputs;
        let model = self.options.resolve(i.file_units.as_deref(), &i.specs)?;
        let curves: Vec<Polyline> = kept.iter().map(|&c| i.curves[c].clone()).collect();
        let position = |ids: &[usize]| -> Vec<usize> {
            (kept.iter().enumerate())
                .filter(|(_, c)| ids.contains(c))
                .map(|(p, _)| p)
                .collect()
        };
        let settings = constraints.params();
        let mut fixed = position(constraints.keep());
        let mut ties = Vec::new();
        if settings.groups.iter().any(|g| g.curves.len() > 1)
            || settings.symmetry != SymmetryOption::None
        {
            let (tied, stay) = crate::slide::ties::ties_of(constraints, kept, &curves);
            ties = tied;
            fixed.extend(stay);
        }
        fixed.sort_unstable();
        fixed.dedup();
        let problem = SlideProblem {
            physical: model.physical.map(|p| physical_for(p, kept)),
            curves,
            ids: kept.to_vec(),
            drawn: Vec::new(),
            build: super::super::slide::build_for(&i.build, kept),
            stability: model.stability,
            budget,
            fixed,
            ties,
            constraints: crate::constraints::ConstraintParams {
                groups: Vec::new(),
                symmetry: SymmetryOption::None,
                ..settings.clone()
            },
        };
        Slider::new(problem, Some(&self.mesh), params).map_err(|e| match e {
            crate::slide::SlideError::Failed(m) => DrawError::Failed(m),
            e => DrawError::Slide(e.message()),
        })
    }

    /// The edit that puts the slid `curves` (one per curve of `kept`, in order) in place of
    /// the drawn ones.
    pub fn slid_edit(kept: &[usize], curves: &[Polyline]) -> DrawEdit {
        DrawEdit::Replace(kept.iter().copied().zip(curves.iter().cloned()).collect())
    }
}

/// The drawing's physical parameters `p` (by the drawing's curve ids) for the network of its
/// curves `kept`, in that order: each curve's own material, section and rest shape carried to
/// its position; no load cases.
fn physical_for(mut p: PhysicalParams, kept: &[usize]) -> PhysicalParams {
    p.physical.curves = p.physical.overrides_for(kept);
    p.rest = kept
        .iter()
        .map(|&id| p.rest.get(id).copied().unwrap_or_default())
        .collect();
    p.loads = None;
    p
}

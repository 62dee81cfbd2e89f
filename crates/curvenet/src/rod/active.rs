//! A structure: which curves of a network it holds.

/// Which curves make up the structure being evaluated.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ActiveSet {
    active: Vec<bool>,
}

impl ActiveSet {
    /// Every curve of a network with `n` curves.
    pub fn all(n: usize) -> Self {
        ActiveSet {
            active: vec![true; n],
        }
    }

    /// Exactly the listed curves.
    pub fn from_curves(n: usize, curves: &[usize]) -> Self {
        let mut active = vec![false; n];
        for &c in curves {
            active[c] = true;
        }
        ActiveSet { active }
    }

    /// This set without curve `c`.
    pub fn without(&self, c: usize) -> Self {
        let mut s = self.clone();
        s.active[c] = false;
        s
    }

    /// Removes curve `c` in place.
    pub fn remove(&mut self, c: usize) {
        self.active[c] = false;
    }

    /// True when curve `c` is part of the structure.
    pub fn contains(&self, c: usize) -> bool {
        self.active[c]
    }

    /// Number of curves in the network (active or not).
    pub fn universe(&self) -> usize {
        self.active.len()
    }

    /// Active curve ids, ascending.
    pub fn curves(&self) -> Vec<usize> {
        (0..self.active.len()).filter(|&c| self.active[c]).collect()
    }

    /// Number of active curves.
    pub fn len(&self) -> usize {
        self.active.iter().filter(|&&a| a).count()
    }

    /// True when no curve is active.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

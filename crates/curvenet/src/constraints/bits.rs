//! Sets of curves as bit sets: the constraint tests run on every subset a search meets
//! (exhaustive search meets hundreds of thousands), so membership, subset and intersection
//! tests are word operations.
//!
//! Hand-written: a few lines over `Vec<u64>`; the sets hold at most a few hundred curves.

/// A set of curve ids below a fixed count.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CurveSet {
    words: Vec<u64>,
}

impl CurveSet {
    /// The empty set over `n` curves.
    pub fn new(n: usize) -> Self {
        CurveSet {
            words: vec![0; n.div_ceil(64)],
        }
    }

    /// The set of `curves` (ids below `n`).
    pub fn from_curves(n: usize, curves: &[usize]) -> Self {
        let mut s = CurveSet::new(n);
        for &c in curves {
            s.insert(c);
        }
        s
    }

    /// Adds `c`.
    #[inline]
    pub fn insert(&mut self, c: usize) {
        self.words[c / 64] |= 1 << (c % 64);
    }

    /// Removes `c`.
    #[inline]
    pub fn remove(&mut self, c: usize) {
        self.words[c / 64] &= !(1 << (c % 64));
    }

    /// Whether `c` is in the set.
    #[inline]
    pub fn contains(&self, c: usize) -> bool {
        self.words
            .get(c / 64)
            .is_some_and(|w| w & (1 << (c % 64)) != 0)
    }

    /// Number of curves in the set.
    pub fn len(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// True for the empty set.
    pub fn is_empty(&self) -> bool {
        self.words.iter().all(|&w| w == 0)
    }

    /// Whether every curve of `self` is in `other`.
    pub fn is_subset(&self, other: &CurveSet) -> bool {
        self.words
            .iter()
            .zip(&other.words)
            .all(|(a, b)| a & !b == 0)
    }

    /// Whether the two sets share a curve.
    pub fn intersects(&self, other: &CurveSet) -> bool {
        self.words.iter().zip(&other.words).any(|(a, b)| a & b != 0)
    }

    /// Adds every curve of `other`.
    pub fn union_with(&mut self, other: &CurveSet) {
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            *a |= b;
        }
    }

    /// Removes every curve of `other`.
    pub fn difference_with(&mut self, other: &CurveSet) {
        for (a, b) in self.words.iter_mut().zip(&other.words) {
            *a &= !b;
        }
    }

    /// The curves, ascending.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.words.iter().enumerate().flat_map(|(i, &w)| {
            let mut w = w;
            std::iter::from_fn(move || {
                if w == 0 {
                    return None;
                }
                let b = w.trailing_zeros() as usize;
                w &= w - 1;
                Some(64 * i + b)
            })
        })
    }

    /// The curves, ascending.
    pub fn to_vec(&self) -> Vec<usize> {
        self.iter().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_operations_match_a_plain_list() {
        let a = CurveSet::from_curves(130, &[0, 5, 64, 129]);
        let b = CurveSet::from_curves(130, &[5, 64]);
        assert_eq!(a.to_vec(), vec![0, 5, 64, 129]);
        assert_eq!(a.len(), 4);
        assert!(b.is_subset(&a) && !a.is_subset(&b));
        assert!(a.intersects(&b));
        assert!(!CurveSet::from_curves(130, &[1, 2]).intersects(&b));
        let mut c = a.clone();
        c.difference_with(&b);
        assert_eq!(c.to_vec(), vec![0, 129]);
        c.union_with(&b);
        assert_eq!(c, a);
        c.remove(129);
        assert!(!c.contains(129) && c.contains(64));
        assert!(!c.contains(1000));
        assert!(CurveSet::new(3).is_empty() && CurveSet::new(0).is_empty());
    }
}

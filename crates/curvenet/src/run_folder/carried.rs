//! `states/carried.bin`: the test vectors the candidates of the last recorded iteration hand
//! the next one (`docs/model.md`, *Greedy simplification*). A resumed run needs them to go on
//! exactly as an uninterrupted one.

use crate::stability::candidates::{Carried, CarriedVector};
use std::path::Path;

/// The carried test vectors' file (see [`carried_bytes`]).
pub const CARRIED_FILE: &str = "states/carried.bin";

/// The carried test vectors to resume after iteration `k` with: those of `CARRIED_FILE` if
/// they belong to iteration `k`, else none. Absent (a run without them) or newer (a run
/// stopped between writing them and its record) is normal; unreadable, damaged or older is
/// a warning: the run goes on with the same removals, its bounds start afresh, so its
/// `result.json` will differ from an uninterrupted run's in the recorded bounds.
pub fn read_carried(
    dir: &Path,
    curves: usize,
    dofs: usize,
    k: usize,
    warnings: &mut Vec<String>,
) -> Carried {
    let path = dir.join(CARRIED_FILE);
    let consequence = "the run goes on without the carried test vectors (the same removals; \
                       the recorded bounds will differ from an uninterrupted run's)";
    let bytes = match std::fs::read(&path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Vec::new(),
        Err(e) => {
            warnings.push(format!("{}: {e}; {consequence}", path.display()));
            return Vec::new();
        }
    };
    match carried_from_bytes(&bytes, curves, dofs) {
        Some((iteration, carried)) if iteration == k => carried,
        Some((iteration, _)) if iteration > k => Vec::new(),
        Some((iteration, _)) => {
            warnings.push(format!(
                "{}: holds the vectors of iteration {iteration}, not of the last recorded one \
                 ({k}); {consequence}",
                path.display()
            ));
            Vec::new()
        }
        None => {
            warnings.push(format!(
                "{}: damaged ({} bytes, not the vectors of {curves} curves with {dofs} \
                 unknowns); {consequence}",
                path.display(),
                bytes.len()
            ));
            Vec::new()
        }
    }
}

/// `carried.bin`: the index of the iteration that handed the vectors on (u64), the curve count
/// (u64), then per curve a flag byte (1: a vector follows) and, with a vector, its value
/// (f64) and its coordinates (f32 each, the network's degrees of freedom); little-endian.
pub fn carried_bytes(iteration: usize, carried: &Carried) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(&(iteration as u64).to_le_bytes());
    out.extend_from_slice(&(carried.len() as u64).to_le_bytes());
    for c in carried {
        match c {
            Some(v) => {
                out.push(1);
                out.extend_from_slice(&v.value.to_le_bytes());
                for x in &v.vector {
                    out.extend_from_slice(&x.to_le_bytes());
                }
            }
            None => out.push(0),
        }
    }
    out
}

/// Reads [`carried_bytes`] for a network of `curves` curves and `dofs` degrees of freedom:
/// the iteration and the vectors, `None` if the bytes do not match.
pub fn carried_from_bytes(bytes: &[u8], curves: usize, dofs: usize) -> Option<(usize, Carried)> {
    fn take<'b>(b: &mut &'b [u8], n: usize) -> Option<&'b [u8]> {
        if b.len() < n {
            return None;
        }
        let (head, tail) = b.split_at(n);
        *b = tail;
        Some(head)
    }
    let mut b = bytes;
    let u64_of = |s: &[u8]| u64::from_le_bytes(s.try_into().unwrap_or([0; 8]));
    let iteration = u64_of(take(&mut b, 8)?) as usize;
    if u64_of(take(&mut b, 8)?) as usize != curves {
        return None;
    }
    let mut carried = Vec::with_capacity(curves);
    for _ in 0..curves {
        match take(&mut b, 1)?[0] {
            0 => carried.push(None),
            1 => {
                let value = f64::from_le_bytes(take(&mut b, 8)?.try_into().ok()?);
                let vector = take(&mut b, 4 * dofs)?
                    .chunks_exact(4)
                    .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                    .collect();
                carried.push(Some(CarriedVector { value, vector }));
            }
            _ => return None,
        }
    }
    b.is_empty().then_some((iteration, carried))
}

#[cfg(test)]
mod tests {

    #[test]
    fn carried_vectors_round_trip_and_bad_files_are_refused() {
        use super::{CarriedVector, carried_bytes, carried_from_bytes};
        let carried = vec![
            Some(CarriedVector {
                value: 2.5e-7,
                vector: vec![1.0, -2.0, 0.5, 3.25, 0.0, -1e-3],
            }),
            None,
            Some(CarriedVector {
                value: -1.0,
                vector: vec![0.0; 6],
            }),
        ];
        let bytes = carried_bytes(7, &carried);
        assert_eq!(carried_from_bytes(&bytes, 3, 6), Some((7, carried.clone())));
        // Another network (curve count, degrees of freedom) or a damaged file: nothing
        // (the resumed run then starts its bounds afresh, with the same removals).
        assert_eq!(carried_from_bytes(&bytes, 4, 6), None);
        assert_eq!(carried_from_bytes(&bytes, 3, 5), None);
        for cut in [0, 7, 15, 16, 17, bytes.len() - 1] {
            assert_eq!(
                carried_from_bytes(&bytes[..cut], 3, 6),
                None,
                "cut at {cut}"
            );
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert_eq!(carried_from_bytes(&longer, 3, 6), None);
        let mut bad_flag = bytes.clone();
        bad_flag[16] = 2;
        assert_eq!(carried_from_bytes(&bad_flag, 3, 6), None);
    }
}

//! `states/carried.0.bin`, `states/carried.1.bin`: the test vectors the candidates of an
//! iteration hand the next one (`docs/model.md`, *Greedy simplification*). A resumed run needs
//! those of the last recorded iteration to go on exactly as an uninterrupted one.
//!
//! Iteration `k` hands its vectors on before it is recorded, into slot `k mod 2`: a run
//! stopped (a signal, a kill, a failed write) between the two leaves the slot of the last
//! recorded iteration, `k − 1`, untouched, and that slot is overwritten only once iteration
//! `k + 1` starts handing on, after iteration `k` is recorded (the run folder's files are
//! written in order).

use crate::stability::candidates::{Carried, CarriedVector};
use std::path::Path;

pub use crate::run_layout::{CARRIED_FILES, carried_file};

/// The carried test vectors to resume after iteration `k` with: those of [`carried_file`]`(k)`
/// if they belong to iteration `k`. Anything else (absent, unreadable, damaged, of another
/// iteration) is a warning: the run goes on with the same removals, its bounds start afresh,
/// so its `result.json` will differ from an uninterrupted run's in the recorded bounds.
pub fn read_carried(
    dir: &Path,
    curves: usize,
    dofs: usize,
    k: usize,
    warnings: &mut Vec<String>,
) -> Carried {
    let path = dir.join(carried_file(k));
    let problem = match std::fs::read(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            format!("missing (the test vectors iteration {k} handed on)")
        }
        Err(e) => format!("cannot be read ({e})"),
        Ok(bytes) => match carried_from_bytes(&bytes, curves, dofs) {
            Some((iteration, carried)) if iteration == k => return carried,
            Some((iteration, _)) => format!(
                "holds the test vectors of iteration {iteration}, not of iteration {k}, the last \
                 recorded"
            ),
            None => format!(
                "damaged ({} bytes, not the test vectors of {curves} curves with {dofs} unknowns)",
                bytes.len()
            ),
        },
    };
    warnings.push(format!(
        "{}: {problem}; the run goes on without them: the same removals, but the recorded \
         bounds will differ from an uninterrupted run's in the last digits",
        path.display()
    ));
    Vec::new()
}

/// The carried vectors' file: the index of the iteration that handed the vectors on (u64), the
/// curve count (u64; 0 when it handed none on), then per curve a flag byte (1: a vector follows) and, with a vector, its value
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
    let count = u64_of(take(&mut b, 8)?) as usize;
    if count != curves && count != 0 {
        return None;
    }
    let mut carried = Vec::with_capacity(count);
    for _ in 0..count {
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
        // None handed on: an empty list, whatever the network.
        let none = carried_bytes(4, &Vec::new());
        assert_eq!(carried_from_bytes(&none, 3, 6), Some((4, Vec::new())));
    }

    #[test]
    fn the_vectors_of_the_last_recorded_iteration_are_read_and_anything_else_warns() {
        use super::{CarriedVector, carried_bytes, carried_file, read_carried};
        let dir = std::env::temp_dir().join(format!("curvenet-carried-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("states")).unwrap();
        let v = vec![Some(CarriedVector {
            value: 1.0,
            vector: vec![0.5; 3],
        })];
        // Iteration 5 recorded; iteration 6 handed its vectors on before a kill.
        std::fs::write(dir.join(carried_file(5)), carried_bytes(5, &v)).unwrap();
        std::fs::write(dir.join(carried_file(6)), carried_bytes(6, &v)).unwrap();
        let mut warnings = Vec::new();
        assert_eq!(read_carried(&dir, 1, 3, 5, &mut warnings), v);
        assert!(warnings.is_empty(), "{warnings:?}");
        // Resuming after iteration 6 (recorded) and 7 (its slot holds iteration 5's): a
        // warning naming the file and the iterations.
        assert_eq!(read_carried(&dir, 1, 3, 6, &mut warnings), v);
        assert_eq!(read_carried(&dir, 1, 3, 7, &mut warnings), Vec::new());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains("carried.1.bin")
                && warnings[0].contains("iteration 5, not of iteration 7"),
            "{}",
            warnings[0]
        );
        // Missing: a warning too.
        std::fs::remove_file(dir.join(carried_file(6))).unwrap();
        assert_eq!(read_carried(&dir, 1, 3, 6, &mut warnings), Vec::new());
        assert!(warnings[1].contains("missing"), "{}", warnings[1]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

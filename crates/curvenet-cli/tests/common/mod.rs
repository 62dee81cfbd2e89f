//! What the command-line tests share: the binary, the 2 × 2 grid of straight curves, fresh
//! temporary folders and 24 geodesics on the built-in dome.
//!
//! Not every test file uses every helper.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_curvenet");

/// A flat 2 × 2 grid of straight curves crossing at four points (reference text format): 0, 1
/// along x; 2, 3 along y.
pub const GRID: &str = "CURVE 0\n-1 -0.5 0\n0 -0.5 0\n1 -0.5 0\n\
                        CURVE 1\n-1 0.5 0\n0 0.5 0\n1 0.5 0\n\
                        CURVE 2\n-0.5 -1 0\n-0.5 0 0\n-0.5 1 0\n\
                        CURVE 3\n0.5 -1 0\n0.5 0 0\n0.5 1 0\n";

/// A fresh temporary folder, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    /// An empty folder `curvenet-TAG-PID-N`, a new one at every call.
    pub fn new(tag: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("curvenet-{tag}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temporary folder");
        TempDir(dir)
    }

    /// A folder holding the grid as `grid.txt`.
    pub fn with_grid(tag: &str) -> Self {
        let dir = TempDir::new(tag);
        dir.write("grid.txt", GRID);
        dir
    }

    /// Writes `content` to `name` in the folder (creating its parent folders); its path.
    pub fn write(&self, name: &str, content: impl AsRef<[u8]>) -> PathBuf {
        let p = self.0.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).expect("input folder");
        }
        std::fs::write(&p, content).expect("input written");
        p
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// 24 geodesics traced on the built-in dome (seed 1), in `dir/name`: a run long enough to
/// interrupt or to overlap another.
pub fn dome_curves(dir: &Path, name: &str) -> PathBuf {
    let curves = dir.join(name);
    let status = Command::new(BIN)
        .args([
            "trace",
            "--mesh",
            "dome",
            "--geodesics",
            "24",
            "--seed",
            "1",
        ])
        .arg("--out")
        .arg(&curves)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("trace runs");
    assert!(status.success(), "trace failed");
    curves
}

/// The arguments of a `simplify` run of the dome's curves `curves` into `out` (edge length
/// 100, budget 0.3): a run long enough to interrupt or to overlap another.
pub fn dome_run(curves: &str, out: &str) -> Vec<String> {
    [
        "simplify",
        "--mesh",
        "dome",
        "--curves",
        curves,
        "--edge-length",
        "100",
        "--budget",
        "0.3",
        "--out",
        out,
    ]
    .map(String::from)
    .to_vec()
}

//! Build script: links the system's OpenBLAS when the `sdp-check` feature is on (Clarabel's
//! SDP support calls BLAS and LAPACK but brings no library of its own with the plain `sdp`
//! feature; its `sdp-openblas` feature would build OpenBLAS from downloaded sources unless
//! told otherwise). Does nothing in the default build.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_SDP_CHECK").is_some() {
        println!("cargo:rustc-link-lib=dylib=openblas");
    }
}

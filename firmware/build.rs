//! Makes the firmware's own `memory.x` the one `link.x` (cortex-m-rt) includes.

use std::env;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    // The linker resolves `INCLUDE memory.x` through its search path; put this directory on it.
    println!("cargo:rustc-link-search={}", manifest_dir.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}

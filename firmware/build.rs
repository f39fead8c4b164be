//! Makes the repository's top-level `memory.x` (the STM32G474RE application slot of
//! softfinger-update's `layout::G474`) the one `link.x` (cortex-m-rt) includes.

use std::env;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let top = manifest_dir.parent().unwrap_or(&manifest_dir).to_path_buf();
    // The linker resolves `INCLUDE memory.x` through its search path; put the top level on it.
    println!("cargo:rustc-link-search={}", top.display());
    println!("cargo:rerun-if-changed={}", top.join("memory.x").display());
    println!("cargo:rerun-if-changed=build.rs");
}

//! Makes the right `memory.x` the one `link.x` (cortex-m-rt) includes: this crate's own
//! (STM32G474RE) for the product, `src/board/mps2/memory.x` (with its `device.x`) for the emulated
//! board (feature `mps2-an386`).

use std::env;
use std::path::PathBuf;

fn main() {
    let manifest_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    // The linker resolves `INCLUDE memory.x` through its search path; put the board's on it.
    let dir = if env::var_os("CARGO_FEATURE_MPS2_AN386").is_some() {
        manifest_dir.join("src/board/mps2")
    } else {
        manifest_dir.clone()
    };
    println!("cargo:rustc-link-search={}", dir.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=src/board/mps2/memory.x");
    println!("cargo:rerun-if-changed=src/board/mps2/device.x");
    println!("cargo:rerun-if-changed=build.rs");
}

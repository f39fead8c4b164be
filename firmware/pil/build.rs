//! Puts this crate's memory.x and device.x (QEMU mps2-an386) on the linker search path for
//! cortex-m-rt's link.x.

use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    for file in ["memory.x", "device.x"] {
        if let Err(e) = fs::copy(file, out.join(file)) {
            println!("cargo:warning=copying {file} failed: {e}");
        }
        println!("cargo:rerun-if-changed={file}");
    }
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=build.rs");
}

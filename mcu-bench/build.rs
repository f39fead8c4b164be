//! Puts this crate's memory.x (QEMU mps2-an386) on the linker search path for cortex-m-rt's link.x,
//! and embeds the protocol decoder's committed fuzz corpus
//! (`protocol/tests/fuzz_corpus/protocol_decode/`, a few kB) for the on-target tests: writes
//! `$OUT_DIR/protocol_corpus.rs`, one `include_bytes!` per file, sorted by name.

use std::{env, fs, path::PathBuf};

const CORPUS_DIR: &str = "../protocol/tests/fuzz_corpus/protocol_decode";

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    embed_corpus(&out);
}

fn embed_corpus(out: &std::path::Path) {
    println!("cargo:rerun-if-changed={CORPUS_DIR}");
    let dir = fs::canonicalize(CORPUS_DIR).expect("the protocol fuzz corpus directory exists");
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .expect("read the protocol fuzz corpus")
        .map(|e| e.expect("read a corpus entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let mut src = String::from("/// The protocol decoder's fuzz corpus: (file name, bytes).\n");
    src.push_str("pub static CORPUS: &[(&str, &[u8])] = &[\n");
    for f in &files {
        let name = f.file_name().expect("a file name").to_string_lossy();
        src.push_str(&format!(
            "    ({name:?}, include_bytes!({:?})),\n",
            f.display().to_string()
        ));
    }
    src.push_str("];\n");
    fs::write(out.join("protocol_corpus.rs"), src).expect("write protocol_corpus.rs");
}

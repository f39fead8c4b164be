//! Puts this crate's memory.x (QEMU mps2-an386) on the linker search path for cortex-m-rt's link.x,
//! and embeds the protocol decoder's committed fuzz corpus
//! (`protocol/tests/fuzz_corpus/protocol_decode/`, a few kB) for the on-target tests: writes
//! `$OUT_DIR/protocol_corpus.rs`, one `include_bytes!` per file, sorted by name; and turns the
//! math checks' golden values (`src/bin/ontarget_tests/golden.tsv`, written by
//! `scripts/mcu-bench --record-golden`) into one table of f32 bits per backend,
//! `$OUT_DIR/golden_tables.rs`.

use std::{env, fs, path::PathBuf};

const CORPUS_DIR: &str = "../protocol/tests/fuzz_corpus/protocol_decode";
const GOLDEN_TSV: &str = "src/bin/ontarget_tests/golden.tsv";

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("copy memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    embed_corpus(&out);
    golden_tables(&out);
}

/// `golden.tsv`: `#` lines are comments; every other line is `check, then bits and distance per
/// backend` (libm, micromath, fast), tab-separated, bits as `0x` and 8 hex digits.
fn golden_tables(out: &std::path::Path) {
    println!("cargo:rerun-if-changed={GOLDEN_TSV}");
    let text = fs::read_to_string(GOLDEN_TSV).expect("read the golden values");
    let mut tables: [Vec<String>; 3] = Default::default();
    for (n, line) in text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#'))
    {
        let fields: Vec<&str> = line.split('\t').collect();
        assert!(
            fields.len() == 7,
            "{GOLDEN_TSV}:{}: 7 tab-separated fields expected",
            n + 1
        );
        for (table, bits) in tables.iter_mut().zip([fields[1], fields[3], fields[5]]) {
            let hex = bits.strip_prefix("0x").filter(|h| h.len() == 8);
            let valid = hex.is_some_and(|h| u32::from_str_radix(h, 16).is_ok());
            assert!(
                valid,
                "{GOLDEN_TSV}:{}: '{bits}' is not 0x and 8 hex digits",
                n + 1
            );
            table.push(format!("{bits}, // {}", fields[0]));
        }
    }
    let mut src = String::new();
    for (name, table) in ["LIBM", "MICROMATH", "FAST"].iter().zip(&tables) {
        src.push_str(&format!(
            "/// The {name} column of `golden.tsv`.\npub const {name}: &[u32] = &[\n"
        ));
        for row in table {
            src.push_str(&format!("    {row}\n"));
        }
        src.push_str("];\n");
    }
    fs::write(out.join("golden_tables.rs"), src).expect("write golden_tables.rs");
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

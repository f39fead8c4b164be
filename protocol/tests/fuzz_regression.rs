//! Replays the kept fuzz corpus of the protocol decoder (`tests/fuzz_corpus/protocol_decode/`)
//! through the harness of the `protocol_decode` fuzz target, so every input the fuzzer found
//! interesting is re-checked by `cargo test`.

mod fuzz_harness;

use std::path::PathBuf;

#[test]
fn corpus_keeps_the_invariants() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_corpus/protocol_decode");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("readable corpus entry").path())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "empty corpus in {}", dir.display());
    let (mut decoded, mut rejected) = (0, 0);
    for f in &files {
        let data = std::fs::read(f).expect("readable corpus file");
        match fuzz_harness::protocol_decode(&data) {
            Ok(s) => {
                decoded += s.decoded;
                rejected += s.rejected;
            }
            Err(e) => panic!("{}: {e}", f.display()),
        }
    }
    // The corpus holds valid frames of both directions and rejected frames of every kind.
    assert!(
        decoded > 0 && rejected > 0,
        "{decoded} decoded, {rejected} rejected"
    );
}

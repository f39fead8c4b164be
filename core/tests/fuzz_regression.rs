//! Replays the kept fuzz corpus (`tests/fuzz_corpus/<target>/`, minimised with `cargo fuzz cmin`)
//! through the same decoder and invariants as the fuzz targets (`tests/fuzz_harness/mod.rs`), so
//! every input the fuzzer found interesting, and every input that once broke an invariant, is
//! re-checked by `cargo test`.

mod fuzz_harness;

use std::path::PathBuf;

fn corpus(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_corpus")
        .join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("readable corpus entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&p).expect("readable corpus file"))
        })
        .collect()
}

fn replay(target: &str, run: fn(&[u8]) -> Result<fuzz_harness::Summary, String>) {
    let files = corpus(target);
    // The corpus is committed: an empty directory means it was lost, not that all is well.
    assert!(files.len() >= 10, "{target}: only {} files", files.len());
    let mut failures = Vec::new();
    let (mut accepted, mut steps, mut internal_nan) = (0usize, 0usize, 0usize);
    for (name, data) in &files {
        match run(data) {
            Ok(s) => {
                accepted += s.accepted as usize;
                steps += s.steps;
                internal_nan += s.internal_non_finite as usize;
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    println!(
        "{target}: {} inputs, {accepted} with accepted parameters, {steps} steps, \
         {internal_nan} with an internal NaN caught by the output guard",
        files.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The corpus must exercise the model, not only the parameter rejection.
    assert!(accepted * 4 >= files.len(), "{target}: {accepted} accepted");
}

#[test]
fn contact_step_corpus_keeps_every_invariant() {
    replay("contact_step", fuzz_harness::contact_step);
}

#[test]
fn control_tick_corpus_keeps_every_invariant() {
    replay("control_tick", fuzz_harness::control_tick);
}

//! The fuzz harness: decoder and invariants, shared with `core/tests/fuzz_regression.rs` (which
//! replays the kept corpus in `cargo test`). See `README.md`.

#[path = "../../core/tests/fuzz_harness/mod.rs"]
pub mod harness;

/// The protocol decoder's harness, shared with `protocol/tests/fuzz_regression.rs`.
#[path = "../../protocol/tests/fuzz_harness/mod.rs"]
pub mod protocol_harness;

//! The protocol's frame decoder on arbitrary bytes, both directions; see
//! `protocol/tests/fuzz_harness/mod.rs` for the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = softfinger_fuzz::protocol_harness::protocol_decode(data) {
        panic!("invariant violated: {e}");
    }
});

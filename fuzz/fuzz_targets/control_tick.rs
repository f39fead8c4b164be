//! Controller::tick on arbitrary configurations, encoder sequences and fault inputs; see the
//! harness.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = softfinger_fuzz::harness::control_tick(data) {
        panic!("invariant violated: {e}");
    }
});

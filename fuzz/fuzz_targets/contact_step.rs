//! ContactModel::contact_step on arbitrary parameters and input sequences; see the harness.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = softfinger_fuzz::harness::contact_step(data) {
        panic!("invariant violated: {e}");
    }
});

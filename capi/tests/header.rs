//! The checked-in C header is the one cbindgen makes from this crate now.

#[test]
fn checked_in_header_is_current() {
    let fresh = include_str!(concat!(env!("OUT_DIR"), "/softfinger.h"));
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/include/softfinger.h");
    let checked_in = std::fs::read_to_string(path).expect("capi/include/softfinger.h exists");
    assert!(
        checked_in == fresh,
        "capi/include/softfinger.h is stale; update it with\n  cp {}/softfinger.h {path}",
        env!("OUT_DIR")
    );
}

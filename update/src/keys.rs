//! Signing keys.
//!
//! [`DEV_PUBLIC_KEY`] is the public half of `update/keys/dev-signing-key.hex`, the development
//! key committed to this repository: anyone can sign for it, so a device that trusts it trusts
//! everyone. A device maker generates their own key pair (`softfinger-sign keygen`), keeps the
//! secret half off the repository, and builds the firmware and the bootloader with their public
//! key (`SOFTFINGER_UPDATE_PUBLIC_KEY=<64 hex digits>` at build time; see the update README).

/// The development public key (ed25519, 32 bytes).
pub const DEV_PUBLIC_KEY: [u8; 32] = [
    0xde, 0xd6, 0x01, 0x25, 0xf6, 0x21, 0xfd, 0x17, 0x4b, 0x33, 0x04, 0xc0, 0x41, 0xf7, 0x03, 0xc9,
    0x77, 0xcd, 0x29, 0xf4, 0xa1, 0x2e, 0x17, 0xa6, 0xb9, 0x3a, 0x2d, 0xbe, 0x5f, 0x58, 0x58, 0x96,
];

/// The public key this build trusts: `SOFTFINGER_UPDATE_PUBLIC_KEY` (64 hex digits) at build
/// time, else [`DEV_PUBLIC_KEY`]. A malformed variable fails the build.
pub const TRUSTED_PUBLIC_KEY: [u8; 32] = match option_env!("SOFTFINGER_UPDATE_PUBLIC_KEY") {
    Some(hex) => parse_hex_key(hex),
    None => DEV_PUBLIC_KEY,
};

const fn nibble(c: u8) -> u8 {
    match c {
        b'0'..=b'9' => c - b'0',
        b'a'..=b'f' => c - b'a' + 10,
        b'A'..=b'F' => c - b'A' + 10,
        _ => panic!("SOFTFINGER_UPDATE_PUBLIC_KEY: not a hex digit"),
    }
}

/// 64 hex digits to 32 bytes, at compile time (a malformed key stops the build).
pub const fn parse_hex_key(hex: &str) -> [u8; 32] {
    let b = hex.as_bytes();
    assert!(
        b.len() == 64,
        "SOFTFINGER_UPDATE_PUBLIC_KEY: 64 hex digits expected"
    );
    let mut out = [0u8; 32];
    let mut i = 0;
    while i < 32 {
        out[i] = nibble(b[2 * i]) << 4 | nibble(b[2 * i + 1]);
        i += 1;
    }
    out
}

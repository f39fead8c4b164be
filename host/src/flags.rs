//! Names of the flag bits in a state sample (`softfinger_core::Flags`; the table and the
//! meanings are `softfinger_protocol::flag_names`).

pub use softfinger_protocol::flag_names::{raised, FLAGS, HOLD_FORCE_DOWN};

/// The names of the raised bits, joined by `|`; unnamed bits as `bitN`; empty for none.
pub fn describe(bits: u32) -> String {
    let mut parts: Vec<String> = raised(bits).map(|(n, _)| n.to_string()).collect();
    let unnamed = softfinger_protocol::flag_names::unnamed(bits);
    for b in 0..32 {
        if unnamed & (1 << b) != 0 {
            parts.push(format!("bit{b}"));
        }
    }
    parts.join("|")
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_core::Flags;

    #[test]
    fn names_and_unknown_bits() {
        assert_eq!(describe(0), "");
        assert_eq!(
            describe((Flags::COMM_TIMEOUT | Flags::ZERO_AXIS).0),
            "zero-axis|comm-timeout"
        );
        assert_eq!(describe(1 << 31), "bit31");
    }
}

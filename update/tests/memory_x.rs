//! The repository's top-level `memory.x` (the STM32G474RE application's linker memory map, which
//! firmware/build.rs links) places the application exactly in `layout::G474`'s active slot.

use softfinger_update::layout::{G474, G474_FLASH_LEN};

/// Flash base address of the STM32G474RE.
const FLASH_BASE: u32 = 0x0800_0000;

/// `(origin, length)` of the `name` region in a linker script's `MEMORY { .. }` block.
fn region(script: &str, name: &str) -> Option<(u32, u32)> {
    let body = script.split("MEMORY").nth(1)?.split('}').next()?;
    let line = body
        .lines()
        .find(|l| l.split(':').next().map(str::trim) == Some(name))?;
    let field = |key: &str| -> Option<u32> {
        let v = line
            .split(key)
            .nth(1)?
            .split(['=', ','].as_ref())
            .nth(1)?
            .trim();
        if let Some(hex) = v.strip_prefix("0x") {
            u32::from_str_radix(hex, 16).ok()
        } else if let Some(k) = v.strip_suffix('K') {
            k.parse::<u32>().ok().map(|k| k * 1024)
        } else {
            v.parse().ok()
        }
    };
    Some((field("ORIGIN")?, field("LENGTH")?))
}

fn memory_x() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../memory.x");
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn the_application_is_linked_into_the_active_slot() {
    let (origin, length) = region(&memory_x(), "FLASH").expect("a FLASH region in memory.x");
    assert_eq!(origin, FLASH_BASE + G474.active.start);
    assert_eq!(length, G474.active.end - G474.active.start);
    assert!(G474.check(G474_FLASH_LEN).is_ok());
}

#[test]
fn the_region_parser_reads_what_it_is_given() {
    let s = "MEMORY\n{\n  FLASH : ORIGIN = 0x08000000, LENGTH = 24K\n  RAM : ORIGIN = 0x20000000, LENGTH = 98304\n}";
    assert_eq!(region(s, "FLASH"), Some((0x0800_0000, 24 * 1024)));
    assert_eq!(region(s, "RAM"), Some((0x2000_0000, 98_304)));
    assert_eq!(region(s, "CCMRAM"), None);
}

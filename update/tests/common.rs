//! A small device for the update tests: the G474 flash model (2 KiB pages, 8-byte writes) with
//! an 8-page active slot, its DFU and state slots and a settings store, and signed images.
#![allow(dead_code)]

use std::cell::RefCell;

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embedded_storage::nor_flash::NorFlash;
use softfinger_store::flash_model::{G474Flash, PAGE_SIZE};
use softfinger_update::package::{sign, ImageTrailer, FLAG_SIMULATE_SELF_TEST_FAILURE};
use softfinger_update::session::chunk_crc;
use softfinger_update::{Layout, Slots, UpdateError, UpdateSession, CHUNK_LEN};

pub const P: u32 = PAGE_SIZE as u32;
pub const PAGES: usize = 24;

/// State page 0, active pages 1..9, DFU 9..18, store 18..22.
pub fn layout() -> Layout {
    Layout {
        state: 0..P,
        active: P..9 * P,
        dfu: 9 * P..18 * P,
        store: 18 * P..22 * P,
    }
}

pub fn seed() -> [u8; 32] {
    softfinger_update::keys::parse_hex_key(include_str!("../keys/dev-signing-key.hex").trim())
}

/// An image of `len` payload bytes (deterministic from `tag`) and a trailer `version`.
pub fn image(tag: u8, len: usize, version: &str, fail_self_test: bool) -> Vec<u8> {
    let mut x = u32::from(tag).wrapping_mul(2_654_435_761) | 1;
    let mut v: Vec<u8> = (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    let flags = if fail_self_test {
        FLAG_SIMULATE_SELF_TEST_FAILURE
    } else {
        0
    };
    v.extend_from_slice(&ImageTrailer::new(version, flags).unwrap().to_bytes());
    v
}

pub type Flash = Mutex<NoopRawMutex, RefCell<G474Flash>>;

pub fn flash_from(image: &[u8]) -> Flash {
    Mutex::new(RefCell::new(G474Flash::from_image(image)))
}

/// A new device with `img` in its active slot (as a probe would flash it).
pub fn device_with(img: &[u8]) -> Flash {
    let f = flash_from(&vec![0xFF; PAGES * PAGE_SIZE]);
    {
        let slots = Slots::new(&f, layout());
        let mut a = slots.active();
        let mut padded = img.to_vec();
        padded.resize(img.len().div_ceil(8) * 8, 0xFF);
        a.write(0, &padded).unwrap();
    }
    f
}

/// Send `img` (signed `sig`) from `from` to the end, in chunks.
pub fn send(
    s: &mut UpdateSession,
    slots: &Slots<'_, G474Flash>,
    img: &[u8],
    from: u32,
) -> Result<u32, UpdateError> {
    let mut off = from;
    while (off as usize) < img.len() {
        let end = (off as usize + CHUNK_LEN).min(img.len());
        let c = &img[off as usize..end];
        off = s.chunk(slots, off, c, chunk_crc(c), false)?;
    }
    Ok(off)
}

/// The whole update as the host and the device run it: begin, chunks, finish.
pub fn transfer(slots: &Slots<'_, G474Flash>, img: &[u8]) -> Result<(), UpdateError> {
    let sig = sign(img, &seed());
    let mut s = UpdateSession::new();
    s.begin(slots, img.len() as u32, &sig, false)?;
    send(&mut s, slots, img, 0)?;
    s.finish(slots, &softfinger_update::keys::DEV_PUBLIC_KEY, false)
}

/// The active slot's first `n` bytes.
pub fn active(slots: &Slots<'_, G474Flash>, n: usize) -> Vec<u8> {
    let mut v = vec![0u8; n];
    slots.read_active(0, &mut v).unwrap();
    v
}

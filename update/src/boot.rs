//! After a reset: the bootloader's swap, and the new image's trial boot.
//!
//! [`run_bootloader`] is what `firmware/bootloader` does on the MCU (embassy-boot's
//! `prepare_boot` over the same slots): with a marked image it swaps the active and DFU slots page
//! by page, recording its progress in the state slot so a power cut resumes the swap; the
//! swapped-in image then runs *on trial*. The image calls [`confirm`] with its self-test: passed,
//! the trial ends (`mark_booted`); failed (or never called), the next reset swaps back.

use embassy_boot::{AlignedBuffer, BlockingFirmwareState, BootLoader, BootLoaderConfig, State};
use embedded_storage::nor_flash::{NorFlash, ReadNorFlash};

use crate::package::{ImageTrailer, TRAILER_LEN};
use crate::session::{Slots, UpdateError};

/// The swap buffer, bytes (divides the 2 KiB page).
const SWAP_BUF: usize = 256;

/// What the running image is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BootState {
    /// Confirmed (or never updated).
    Normal,
    /// Just swapped in; not yet confirmed.
    Trial,
    /// The bootloader swapped the previous image back (the last update failed its trial).
    RolledBack,
}

/// The self-test a new image passes before it confirms itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SelfTest {
    /// The clock tree locked (HSE and PLL at their frequencies).
    pub clock: bool,
    /// Every encoder counter reads and counts.
    pub encoders: bool,
    /// The control tick ran at its period for the test window without an overrun.
    pub tick: bool,
    /// The settings store loaded (any status: read, migrated or defaults with a flag).
    pub store: bool,
}

impl SelfTest {
    /// All passed.
    pub fn passed(&self) -> bool {
        self.clock && self.encoders && self.tick && self.store
    }
}

/// The bootloader's step (what `firmware/bootloader` runs before jumping to the active slot).
pub fn run_bootloader<F: NorFlash>(slots: &Slots<'_, F>) -> Result<State, UpdateError> {
    let mut buf = AlignedBuffer([0u8; SWAP_BUF]);
    let mut bl = BootLoader::new(BootLoaderConfig {
        active: slots.active(),
        dfu: slots.dfu(),
        state: slots.state(),
    });
    bl.prepare_boot(&mut buf.0).map_err(|_| UpdateError::Flash)
}

/// The running image's boot state.
pub fn boot_state<F: NorFlash>(slots: &Slots<'_, F>) -> Result<BootState, UpdateError> {
    let mut aligned = AlignedBuffer([0u8; 8]);
    let mut st = BlockingFirmwareState::new(slots.state(), &mut aligned.0);
    Ok(match st.get_state().map_err(|_| UpdateError::Flash)? {
        State::Swap => BootState::Trial,
        State::Revert => BootState::RolledBack,
        State::Boot | State::DfuDetach => BootState::Normal,
    })
}

/// End a trial boot if `test` passed. Returns whether the image is now confirmed: `false` means
/// the self-test failed on a trial image, which stays unconfirmed (the next reset rolls back).
pub fn confirm<F: NorFlash>(slots: &Slots<'_, F>, test: &SelfTest) -> Result<bool, UpdateError> {
    if boot_state(slots)? != BootState::Trial {
        return Ok(true);
    }
    if !test.passed() {
        return Ok(false);
    }
    let mut aligned = AlignedBuffer([0u8; 8]);
    let mut st = BlockingFirmwareState::new(slots.state(), &mut aligned.0);
    st.mark_booted().map_err(|_| UpdateError::Flash)?;
    Ok(true)
}

/// The version trailer of the image in the active slot: the 32 bytes ending at the slot's last
/// byte that is not erased (an image is followed by erased flash, and a trailer's last byte, its
/// flags, is never 0xFF).
pub fn active_trailer<F: NorFlash>(slots: &Slots<'_, F>) -> Option<ImageTrailer> {
    let mut p = slots.active();
    let cap = p.capacity() as u32;
    let mut buf = [0u8; 256];
    let mut end = cap;
    while end > 0 {
        let start = end.saturating_sub(buf.len() as u32);
        let chunk = &mut buf[..(end - start) as usize];
        p.read(start, chunk).ok()?;
        if let Some(i) = chunk.iter().rposition(|b| *b != 0xFF) {
            let last = start + i as u32 + 1;
            if last < TRAILER_LEN as u32 {
                return None;
            }
            let mut t = [0u8; TRAILER_LEN];
            p.read(last - TRAILER_LEN as u32, &mut t).ok()?;
            return ImageTrailer::read(&t).ok();
        }
        end = start;
    }
    None
}

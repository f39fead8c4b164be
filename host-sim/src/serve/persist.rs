//! The virtual device's flash: its settings store and its firmware update, through the firmware's
//! own code (`softfinger_app::persist::DeviceStore`, over `softfinger-store`, `softfinger-update`
//! and embassy-boot) on a model of the STM32G474's 512 KiB flash (2 KiB pages, 8-byte writes), at
//! the firmware's layout (`softfinger_update::layout::G474`). With `--flash FILE` the flash is
//! that file, so settings and an installed image survive a restart (and a SIGKILL: each flash
//! write is one `pwrite` of what it changed); without it, RAM.
//!
//! What is the virtual device's own: it does not execute images, so an image's version comes
//! from its trailer and its self-test passes unless the trailer's simulate-failure flag is set
//! (`softfinger-sign sign --fail-self-test`), so a rollback can be shown; and its reset is a call
//! (the bootloader's step, the self-test, the store's load) instead of a reset of the MCU.

use std::path::Path;

use embedded_storage::nor_flash::NorFlash;
use softfinger_app::boot_defaults::BootDefaults;
use softfinger_app::persist::{DeviceStore, Persistence};
use softfinger_protocol::{AckResult, DeviceMsg, ErrorCode, Request};
use softfinger_store::flash_model::{G474Flash, PAGE_SIZE};
use softfinger_store::schema::PRESETS;
use softfinger_store::{LoadStatus, Settings};
use softfinger_update::boot::{active_trailer, run_bootloader};
use softfinger_update::layout::{G474, G474_FLASH_LEN};
use softfinger_update::package::{ImageTrailer, FLAG_SIMULATE_SELF_TEST_FAILURE};
use softfinger_update::SelfTest;

/// The virtual device's version, as its factory image's trailer carries it.
const VERSION: &str = concat!("host-sim ", env!("CARGO_PKG_VERSION"));

/// The virtual device's flash and what it keeps.
pub struct Persist {
    store: DeviceStore<G474Flash>,
}

impl std::fmt::Debug for Persist {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.store.fmt(f)
    }
}

/// The image the virtual device ships with: host-sim's version in a trailer.
fn factory_image() -> Vec<u8> {
    let mut img = b"softfinger virtual device image".to_vec();
    img.resize(img.len().div_ceil(8) * 8, 0);
    let t = ImageTrailer::new(VERSION, 0)
        .unwrap_or_else(|_| ImageTrailer::new("host-sim", 0).expect("short version"));
    img.extend_from_slice(&t.to_bytes());
    img
}

impl Persist {
    /// The flash in RAM (settings last as long as the process).
    pub fn in_ram() -> Persist {
        Self::boot_from(G474Flash::new(G474_FLASH_LEN as usize / PAGE_SIZE))
            .expect("a fresh RAM flash boots")
    }

    /// The flash kept in `path` (created erased if absent).
    pub fn open(path: &Path) -> Result<Persist, String> {
        let f = G474Flash::open_file(path, G474_FLASH_LEN as usize / PAGE_SIZE)
            .map_err(|e| format!("--flash {}: {e}", path.display()))?;
        Self::boot_from(f).map_err(|e| format!("--flash {}: {e}", path.display()))
    }

    fn boot_from(flash: G474Flash) -> Result<Persist, String> {
        let mut p = Persist {
            store: DeviceStore::boot(flash, G474, VERSION),
        };
        if active_trailer(&p.store.slots()).is_none() {
            p.install_factory_image()?;
        }
        p.reset()?;
        Ok(p)
    }

    fn install_factory_image(&mut self) -> Result<(), String> {
        let img = factory_image();
        let slots = self.store.slots();
        let mut a = slots.active();
        a.erase(0, 2 * PAGE_SIZE as u32)
            .map_err(|e| format!("flash: {e:?}"))?;
        a.write(0, &img).map_err(|e| format!("flash: {e:?}"))
    }

    /// A reset: the bootloader (swap or roll back), the store's load and the boot state, the
    /// image's self-test and confirm; a trial image that fails it resets again (as the firmware
    /// does), which rolls it back.
    pub fn reset(&mut self) -> Result<(), String> {
        self.bootloader()?;
        let flash = self.take_flash();
        self.store = DeviceStore::boot(flash, G474, VERSION);
        let image_ok = active_trailer(&self.store.slots())
            .is_some_and(|t| t.flags & FLAG_SIMULATE_SELF_TEST_FAILURE == 0);
        let test = SelfTest {
            clock: true,
            encoders: true,
            tick: image_ok,
            store: self.store.status() != LoadStatus::FlashError,
        };
        let confirmed = self
            .store
            .confirm(&test)
            .map_err(|e| format!("confirm: {e}"))?;
        if !confirmed {
            self.bootloader()?;
            let flash = self.take_flash();
            self.store = DeviceStore::boot(flash, G474, VERSION);
        }
        Ok(())
    }

    /// The bootloader's step on the flash (what `firmware/bootloader` runs at a reset).
    fn bootloader(&self) -> Result<(), String> {
        run_bootloader(&self.store.slots())
            .map(|_| ())
            .map_err(|e| format!("bootloader: {e}"))
    }

    /// The flash, out of the store (to boot a new one on it).
    fn take_flash(&mut self) -> G474Flash {
        let placeholder = DeviceStore::boot(G474Flash::new(0), G474, VERSION);
        std::mem::replace(&mut self.store, placeholder).into_flash()
    }

    /// What the load found.
    pub fn status(&self) -> LoadStatus {
        self.store.status()
    }

    /// The settings in force.
    pub fn settings(&self) -> &Settings {
        self.store.settings()
    }

    /// What the settings loaded at the last boot change (`softfinger_app::boot_defaults`).
    pub fn boot_defaults(&self) -> BootDefaults {
        self.store.boot_defaults()
    }

    /// The running image's version.
    pub fn version(&self) -> String {
        self.store.version().to_string()
    }

    /// The name the user gave the device, if any (device info's name).
    pub fn device_name(&self) -> Option<&str> {
        self.store.device_name()
    }

    /// Device info's settings flags.
    pub fn settings_flags(&self) -> u8 {
        self.store.settings_flags()
    }

    /// Answer a settings, update or reboot request, or refuse an `Arm` the store's arm check
    /// refuses (`None`: none of these). `armed`: the device renders force or homes.
    pub fn handle(&mut self, seq: u16, req: &Request, armed: bool) -> Option<DeviceMsg> {
        let ack = |result| DeviceMsg::Ack { seq, result };
        if matches!(req, Request::Arm) && self.store.arm_refusal().is_some() {
            return Some(ack(AckResult::Err(ErrorCode::WrongMode)));
        }
        let reply = self.store.handle(seq, req, armed)?;
        if self.store.take_reset_request() {
            return Some(match self.reset() {
                Ok(()) => reply,
                Err(_) => ack(AckResult::Err(ErrorCode::Busy)),
            });
        }
        Some(reply)
    }
}

/// The number of presets, for clients that walk them.
pub const PRESET_COUNT: usize = PRESETS;

#[cfg(test)]
mod tests {
    use super::*;

    /// A flash whose store holds a record that fails its CRC.
    fn corrupt_store() -> G474Flash {
        let mut f = G474Flash::new(G474_FLASH_LEN as usize / PAGE_SIZE);
        {
            let mut st = softfinger_store::Store::new(&mut f, G474.store.clone()).unwrap();
            embassy_futures::block_on(st.save_raw_record(&[0xFF, 0x7F, 1, 2, 3, 4, 5, 6])).unwrap();
        }
        f
    }

    #[test]
    fn a_store_it_cannot_read_refuses_arm_until_reset() {
        let mut p = Persist::boot_from(corrupt_store()).unwrap();
        assert_eq!(p.status(), LoadStatus::Corrupt);
        let refused = p.handle(1, &Request::Arm, false);
        assert_eq!(
            refused,
            Some(DeviceMsg::Ack {
                seq: 1,
                result: AckResult::Err(ErrorCode::WrongMode)
            })
        );
        let reset = p.handle(2, &Request::ConfigReset, false);
        assert!(matches!(
            reset,
            Some(DeviceMsg::Ack {
                result: AckResult::Ok,
                ..
            })
        ));
        // Not the store's to answer any more: the pipeline arms.
        assert_eq!(p.handle(3, &Request::Arm, false), None);
    }

    #[test]
    fn a_blank_store_lets_a_new_device_arm() {
        let mut p = Persist::in_ram();
        assert_eq!(p.status(), LoadStatus::Absent);
        assert_eq!(p.handle(1, &Request::Arm, false), None);
    }
}

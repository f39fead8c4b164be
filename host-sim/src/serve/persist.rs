//! The virtual device's flash: its settings store and its firmware update, through the same code
//! as the firmware (`softfinger-store`, `softfinger-update` and embassy-boot) over a model of the
//! STM32G474's 512 KiB flash (2 KiB pages, 8-byte writes), at the firmware's layout
//! (`softfinger_update::layout::G474`). With `--flash FILE` the flash is that file, so settings
//! and an installed image survive a restart (and a SIGKILL: each flash write is one `pwrite` of
//! what it changed); without it, RAM.
//!
//! The virtual device does not execute images: an image's version comes from its trailer, and
//! its self-test passes unless the trailer's simulate-failure flag is set
//! (`softfinger-sign sign --fail-self-test`), so a rollback can be shown.

use std::cell::RefCell;
use std::path::Path;

use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embedded_storage::nor_flash::NorFlash;
use softfinger_protocol::config::{ConfigRefusal, ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::update::{BootStateWire, UpdatePhase, UpdateRefusal, UpdateStatus};
use softfinger_protocol::{AckResult, DeviceMsg, ErrorCode, Request};
use softfinger_store::flash_model::{G474Flash, PAGE_SIZE};
use softfinger_store::schema::PRESETS;
use softfinger_store::{LoadStatus, SaveError, Settings, Store, SCHEMA_VERSION};
use softfinger_update::boot::{active_trailer, boot_state, confirm, run_bootloader};
use softfinger_update::layout::{G474, G474_FLASH_LEN};
use softfinger_update::package::{ImageTrailer, FLAG_SIMULATE_SELF_TEST_FAILURE};
use softfinger_update::{BootState, SelfTest, Slots, Status, UpdateError, UpdateSession};

type Flash = Mutex<NoopRawMutex, RefCell<G474Flash>>;

/// The virtual device's flash and what it keeps.
pub struct Persist {
    flash: Flash,
    /// The settings in force.
    live: Settings,
    /// What the boot's load found.
    status: LoadStatus,
    /// Changed since the last load or save.
    unsaved: bool,
    update: UpdateSession,
    boot: BootState,
    /// Refuse to arm on a calibration not read from the store (with `--flash`).
    gate_arming: bool,
}

impl std::fmt::Debug for Persist {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Persist")
            .field("status", &self.status)
            .field("boot", &self.boot)
            .finish()
    }
}

/// The image the virtual device ships with: host-sim's version in a trailer.
fn factory_image() -> Vec<u8> {
    let mut img = b"softfinger virtual device image".to_vec();
    img.resize(img.len().div_ceil(8) * 8, 0);
    let v = concat!("host-sim ", env!("CARGO_PKG_VERSION"));
    let t = ImageTrailer::new(v, 0)
        .unwrap_or_else(|_| ImageTrailer::new("host-sim", 0).expect("short version"));
    img.extend_from_slice(&t.to_bytes());
    img
}

impl Persist {
    /// The flash in RAM (settings last as long as the process).
    pub fn in_ram() -> Persist {
        Self::boot_from(G474Flash::new(G474_FLASH_LEN as usize / PAGE_SIZE), false)
            .expect("a fresh RAM flash boots")
    }

    /// The flash kept in `path` (created erased if absent).
    pub fn open(path: &Path) -> Result<Persist, String> {
        let f = G474Flash::open_file(path, G474_FLASH_LEN as usize / PAGE_SIZE)
            .map_err(|e| format!("--flash {}: {e}", path.display()))?;
        Self::boot_from(f, true).map_err(|e| format!("--flash {}: {e}", path.display()))
    }

    fn boot_from(flash: G474Flash, gate_arming: bool) -> Result<Persist, String> {
        let mut p = Persist {
            flash: Mutex::new(RefCell::new(flash)),
            live: Settings::default(),
            status: LoadStatus::Absent,
            unsaved: false,
            update: UpdateSession::new(),
            boot: BootState::Normal,
            gate_arming,
        };
        if active_trailer(&p.slots()).is_none() {
            p.install_factory_image()?;
        }
        p.reset()?;
        Ok(p)
    }

    fn install_factory_image(&mut self) -> Result<(), String> {
        let img = factory_image();
        let slots = self.slots();
        let mut a = slots.active();
        a.erase(0, 2 * PAGE_SIZE as u32)
            .map_err(|e| format!("flash: {e:?}"))?;
        a.write(0, &img).map_err(|e| format!("flash: {e:?}"))
    }

    fn slots(&self) -> Slots<'_, G474Flash> {
        Slots::new(&self.flash, G474)
    }

    /// A reset: the bootloader (swap or roll back), the image's self-test and confirm, the
    /// store's load.
    pub fn reset(&mut self) -> Result<(), String> {
        let slots = self.slots();
        run_bootloader(&slots).map_err(|e| format!("bootloader: {e}"))?;
        let boot = boot_state(&slots).map_err(|e| format!("boot state: {e}"))?;
        let loaded = self.flash.lock(|c| {
            let mut f = c.borrow_mut();
            match Store::new(&mut *f, G474.store.clone()) {
                Ok(mut s) => s.load_blocking(),
                Err(_) => softfinger_store::Loaded {
                    settings: Settings::default(),
                    status: LoadStatus::FlashError,
                },
            }
        });
        let image_ok =
            active_trailer(&slots).is_some_and(|t| t.flags & FLAG_SIMULATE_SELF_TEST_FAILURE == 0);
        let test = SelfTest {
            clock: true,
            encoders: true,
            tick: image_ok,
            store: true,
        };
        let confirmed = confirm(&slots, &test).map_err(|e| format!("confirm: {e}"))?;
        self.boot = if confirmed {
            boot.min_normal()
        } else {
            // A trial image that fails its self-test resets the device (as the firmware does):
            // the bootloader swaps the previous image back.
            run_bootloader(&slots).map_err(|e| format!("bootloader: {e}"))?;
            boot_state(&slots).map_err(|e| format!("boot state: {e}"))?
        };
        self.live = loaded.settings;
        self.status = loaded.status;
        self.unsaved = false;
        self.update = UpdateSession::new();
        Ok(())
    }

    /// What the load found.
    pub fn status(&self) -> LoadStatus {
        self.status
    }

    /// The settings in force.
    pub fn settings(&self) -> &Settings {
        &self.live
    }

    /// The running image's version.
    pub fn version(&self) -> String {
        active_trailer(&self.slots())
            .map(|t| t.version().to_string())
            .unwrap_or_default()
    }

    /// Answer a settings or update request (`None`: not one of them). `armed`: the device
    /// renders force or homes.
    pub fn handle(&mut self, seq: u16, req: &Request, armed: bool) -> Option<DeviceMsg> {
        let refuse = |key: &str, reason: &str| DeviceMsg::ConfigRefused {
            seq,
            refusal: ConfigRefusal::new(key, reason),
        };
        let ack = |result| DeviceMsg::Ack { seq, result };
        Some(match req {
            Request::Arm if self.gate_arming && !self.may_arm() => {
                ack(AckResult::Err(ErrorCode::WrongMode))
            }
            Request::ConfigGet(section) => match self.get(*section) {
                Some(value) => DeviceMsg::Config { seq, value },
                None => refuse("presets", "no such preset index"),
            },
            Request::ConfigSet(value) => {
                if armed {
                    return Some(refuse(
                        section_key(value),
                        "refused while armed: disarm first",
                    ));
                }
                match self.set(value) {
                    Ok(()) => ack(AckResult::Ok),
                    Err((k, r)) => refuse(k, r),
                }
            }
            Request::ConfigSave => match self.save(armed) {
                Ok(()) => ack(AckResult::Ok),
                Err(SaveError::Armed) => refuse("store", "refused while armed: disarm first"),
                Err(SaveError::Invalid(e)) => refuse(e.key, e.reason),
                Err(SaveError::Storage) => refuse("store", "the flash write failed"),
            },
            Request::ConfigReset => {
                if armed {
                    return Some(refuse("store", "refused while armed: disarm first"));
                }
                let r = self.flash.lock(|c| {
                    let mut f = c.borrow_mut();
                    Store::new(&mut *f, G474.store.clone())
                        .map_err(|_| SaveError::Storage)?
                        .erase_blocking(false)
                });
                match r {
                    Ok(()) => {
                        self.live = Settings::default();
                        self.status = LoadStatus::Absent;
                        self.unsaved = false;
                        ack(AckResult::Ok)
                    }
                    Err(_) => refuse("store", "the flash erase failed"),
                }
            }
            Request::UpdateBegin { len, signature } => {
                let Ok(sig) = <[u8; 64]>::try_from(signature.as_slice()) else {
                    return Some(DeviceMsg::UpdateRefused {
                        seq,
                        refusal: UpdateRefusal::BadSignatureLength,
                    });
                };
                let r = self
                    .update
                    .begin(&Slots::new(&self.flash, G474), *len, &sig, armed);
                self.update_reply(seq, r.map(|_| ()))
            }
            Request::UpdateChunk(c) => {
                let r = self.update.chunk(
                    &Slots::new(&self.flash, G474),
                    c.offset,
                    &c.data,
                    c.crc,
                    armed,
                );
                self.update_reply(seq, r.map(|_| ()))
            }
            Request::UpdateFinish => {
                let key = softfinger_update::keys::TRUSTED_PUBLIC_KEY;
                let r = self
                    .update
                    .finish(&Slots::new(&self.flash, G474), &key, armed);
                self.update_reply(seq, r)
            }
            Request::UpdateStatus => self.update_reply(seq, Ok(())),
            Request::Reboot => {
                if armed {
                    return Some(ack(AckResult::Err(ErrorCode::WrongMode)));
                }
                match self.reset() {
                    Ok(()) => ack(AckResult::Ok),
                    Err(_) => ack(AckResult::Err(ErrorCode::Busy)),
                }
            }
            _ => return None,
        })
    }

    /// The arm check's input: the calibration was read from the store.
    pub fn may_arm(&self) -> bool {
        self.status.from_store() && self.live.calibration.is_some()
    }

    fn get(&self, section: ConfigSection) -> Option<ConfigValue> {
        let s = &self.live;
        Some(match section {
            ConfigSection::Status => ConfigValue::Status {
                store: StoreStatus::from(self.status),
                schema_version: SCHEMA_VERSION,
                may_arm: self.may_arm(),
                unsaved: self.unsaved,
            },
            ConfigSection::Identity => ConfigValue::Identity(s.identity.clone()),
            ConfigSection::Calibration => ConfigValue::Calibration(s.calibration.clone()),
            ConfigSection::Preset(i) => {
                let preset = s.presets.get(usize::from(i))?.clone();
                ConfigValue::Preset { index: i, preset }
            }
            ConfigSection::Stream => ConfigValue::Stream(s.stream),
            ConfigSection::Watchdog => ConfigValue::Watchdog(s.watchdog),
        })
    }

    fn set(&mut self, value: &ConfigValue) -> Result<(), (&'static str, &'static str)> {
        let mut next = self.live.clone();
        match value {
            ConfigValue::Status { .. } => return Err(("status", "read-only")),
            ConfigValue::Identity(v) => next.identity = v.clone(),
            ConfigValue::Calibration(v) => next.calibration = v.clone(),
            ConfigValue::Preset { index, preset } => {
                let slot = next
                    .presets
                    .get_mut(usize::from(*index))
                    .ok_or(("presets", "no such preset index"))?;
                *slot = preset.clone();
            }
            ConfigValue::Stream(v) => next.stream = *v,
            ConfigValue::Watchdog(v) => next.watchdog = *v,
        }
        next.validate().map_err(|e| (e.key, e.reason))?;
        if next != self.live {
            self.unsaved = true;
            // A calibration set by hand is one the device read (from the operator), not one it
            // failed to read: arming follows the saved state only after a save.
        }
        self.live = next;
        Ok(())
    }

    fn save(&mut self, armed: bool) -> Result<(), SaveError> {
        let live = self.live.clone();
        self.flash.lock(|c| {
            let mut f = c.borrow_mut();
            Store::new(&mut *f, G474.store.clone())
                .map_err(|_| SaveError::Storage)?
                .save_blocking(&live, armed)
        })?;
        self.status = LoadStatus::Read;
        self.unsaved = false;
        Ok(())
    }

    fn update_reply(&self, seq: u16, r: Result<(), UpdateError>) -> DeviceMsg {
        match r {
            Err(e) => DeviceMsg::UpdateRefused {
                seq,
                refusal: refusal(e),
            },
            Ok(()) => {
                let phase = match self.update.status() {
                    Status::Idle => UpdatePhase::Idle,
                    Status::Receiving { len, received } => UpdatePhase::Receiving { len, received },
                    Status::Verified => UpdatePhase::Verified,
                };
                let boot = match self.boot {
                    BootState::Normal => BootStateWire::Normal,
                    BootState::Trial => BootStateWire::Trial,
                    BootState::RolledBack => BootStateWire::RolledBack,
                };
                let mut version = heapless::String::new();
                for ch in self.version().chars() {
                    if version.push(ch).is_err() {
                        break;
                    }
                }
                DeviceMsg::Update {
                    seq,
                    status: UpdateStatus {
                        phase,
                        boot,
                        version,
                    },
                }
            }
        }
    }
}

fn section_key(v: &ConfigValue) -> &'static str {
    match v {
        ConfigValue::Status { .. } => "status",
        ConfigValue::Identity(_) => "identity",
        ConfigValue::Calibration(_) => "calibration",
        ConfigValue::Preset { .. } => "presets",
        ConfigValue::Stream(_) => "stream",
        ConfigValue::Watchdog(_) => "watchdog",
    }
}

/// The wire form of an update refusal.
pub fn refusal(e: UpdateError) -> UpdateRefusal {
    match e {
        UpdateError::Armed => UpdateRefusal::Armed,
        UpdateError::NotReceiving => UpdateRefusal::NotReceiving,
        UpdateError::Empty => UpdateRefusal::Empty,
        UpdateError::TooLarge { len, max } => UpdateRefusal::TooLarge { len, max },
        UpdateError::OutOfOrder { expected } => UpdateRefusal::OutOfOrder { expected },
        UpdateError::ChunkCrc { offset } => UpdateRefusal::ChunkCrc { offset },
        UpdateError::ChunkLen { offset } => UpdateRefusal::ChunkLen { offset },
        UpdateError::Truncated { received, len } => UpdateRefusal::Truncated { received, len },
        UpdateError::BadSignature => UpdateRefusal::BadSignature,
        UpdateError::TrialNotConfirmed => UpdateRefusal::TrialNotConfirmed,
        UpdateError::Flash => UpdateRefusal::Flash,
    }
}

trait AfterConfirm {
    /// The state once confirmed: a trial that passed is a normal boot.
    fn min_normal(self) -> BootState;
}

impl AfterConfirm for BootState {
    fn min_normal(self) -> BootState {
        match self {
            BootState::Trial => BootState::Normal,
            other => other,
        }
    }
}

/// The number of presets, for clients that walk them.
pub const PRESET_COUNT: usize = PRESETS;

//! The device's flash, as the host link sees it: the settings store (`softfinger-store`) and the
//! firmware update (`softfinger-update` on embassy-boot) behind the link's config and update
//! requests. Board-independent and `no_std`: the firmware runs it on the STM32G474's flash
//! (embassy-stm32's blocking driver) and the virtual device (`host-sim serve --flash FILE`) on
//! `softfinger_store::flash_model::G474Flash`, both at `softfinger_update::layout::G474`.
//!
//! Never called from the tick: a save erases flash pages (milliseconds each on the G474; bank 2,
//! so the application's bank 1 and the tick's CCM SRAM keep running). The caller says whether the
//! device is armed (rendering force or homing); every write is refused then.
//!
//! Arming: a device whose store held settings it could not read (corrupt, of an unknown schema,
//! or a flash error) refuses to arm until they are replaced (`config save`) or erased
//! (`config reset`): it never arms on a calibration it could not read. [`DeviceStore::arm_refusal`]
//! says why; the firmware's arm paths (link and button) ask it.

use core::cell::RefCell;

use crate::boot_defaults::BootDefaults;

use embassy_embedded_hal::adapter::BlockingAsync;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embedded_storage::nor_flash::NorFlash;
use softfinger_protocol::config::{ConfigRefusal, ConfigSection, ConfigValue, StoreStatus};
use softfinger_protocol::update::{BootStateWire, UpdatePhase, UpdateRefusal, UpdateStatus};
use softfinger_protocol::{AckResult, DeviceMsg, ErrorCode, Request};
use softfinger_store::boot::BootLoad;
use softfinger_store::{LoadStatus, Loaded, SaveError, Settings, Store, SCHEMA_VERSION};
use softfinger_update::boot::{active_trailer, boot_state, confirm};
use softfinger_update::{BootState, Layout, SelfTest, Slots, Status, UpdateError, UpdateSession};

/// The update's version text on the wire, bytes.
const VERSION_LEN: usize = 23;

/// The flash behind a mutex, as embassy-boot's partitions share it.
pub type SharedFlash<F> = Mutex<NoopRawMutex, RefCell<F>>;

/// The settings in force, what the boot's load found, and the update in progress.
pub struct DeviceStore<F: NorFlash> {
    flash: SharedFlash<F>,
    layout: Layout,
    /// The settings in force.
    live: Settings,
    /// What the settings loaded at boot change.
    boot_defaults: BootDefaults,
    /// What the boot's load (or the last save or reset) found.
    status: LoadStatus,
    /// Changed since the last load or save.
    unsaved: bool,
    update: UpdateSession,
    boot: BootState,
    /// The running image's version when its slot has no trailer (an image flashed by a probe).
    fallback_version: &'static str,
    /// A `Reboot` was accepted: the caller resets once the answer is sent.
    reset_requested: bool,
}

impl<F: NorFlash> core::fmt::Debug for DeviceStore<F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("DeviceStore")
            .field("status", &self.status)
            .field("boot", &self.boot)
            .field("unsaved", &self.unsaved)
            .finish_non_exhaustive()
    }
}

/// Read the store in `region`: the settings or the defaults, never an error.
fn load<F: NorFlash>(flash: &mut F, region: core::ops::Range<u32>) -> Loaded {
    match Store::new(BlockingAsync::new(flash), region) {
        Ok(mut s) => s.load_blocking(),
        Err(_) => Loaded {
            settings: Settings::default(),
            status: LoadStatus::FlashError,
        },
    }
}

impl<F: NorFlash> DeviceStore<F> {
    /// At boot: load the settings from `layout.store` of `flash` and read the boot state.
    /// Never fails: an unreadable store gives the defaults with its status, an unreadable boot
    /// state reads as a normal boot.
    pub fn boot(flash: F, layout: Layout, fallback_version: &'static str) -> Self {
        let flash = Mutex::new(RefCell::new(flash));
        let loaded = flash.lock(|c| load(&mut *c.borrow_mut(), layout.store.clone()));
        let mut s = DeviceStore {
            flash,
            layout,
            boot_defaults: BootDefaults::of(&loaded.settings),
            live: loaded.settings,
            status: loaded.status,
            unsaved: false,
            update: UpdateSession::new(),
            boot: BootState::Normal,
            fallback_version,
            reset_requested: false,
        };
        s.boot = boot_state(&s.slots()).unwrap_or(BootState::Normal);
        s
    }

    /// The flash, for the board's own use of it (the bootloader step of the virtual device).
    pub fn flash(&self) -> &SharedFlash<F> {
        &self.flash
    }

    /// Give the flash back (the virtual device's reset boots a new store on it).
    pub fn into_flash(self) -> F {
        self.flash.into_inner().into_inner()
    }

    /// The slots of this store's layout.
    pub fn slots(&self) -> Slots<'_, F> {
        Slots::new(&self.flash, self.layout.clone())
    }

    /// The boot-time load's report: flags for device info, the log line.
    pub fn boot_load(&self) -> BootLoad {
        BootLoad {
            loaded: Loaded {
                settings: self.live.clone(),
                status: self.status,
            },
        }
    }

    /// What the load found.
    pub fn status(&self) -> LoadStatus {
        self.status
    }

    /// The settings in force.
    pub fn settings(&self) -> &Settings {
        &self.live
    }

    /// The running image: normal, on trial (not yet confirmed), or rolled back.
    pub fn boot_state(&self) -> BootState {
        self.boot
    }

    /// What the settings loaded at boot change (the defaults' when the load fell back to them):
    /// applied to the pipeline and the link before the first tick ([`crate::boot_defaults`]).
    /// Later `config set`s act from the next boot, after a save.
    pub fn boot_defaults(&self) -> BootDefaults {
        self.boot_defaults
    }

    /// The calibration was read from the store.
    pub fn calibration_read(&self) -> bool {
        self.status.from_store() && self.live.calibration.is_some()
    }

    /// Why the device must not arm, or `None`: the store held settings it could not read.
    pub fn arm_refusal(&self) -> Option<&'static str> {
        match self.status {
            LoadStatus::Corrupt => {
                Some("the settings store is corrupt: config reset (or save) before arming")
            }
            LoadStatus::UnknownVersion(_) => Some(
                "the settings store is of a newer schema: config reset (or save) before arming",
            ),
            LoadStatus::FlashError => Some("the settings store could not be read"),
            LoadStatus::Read | LoadStatus::Migrated { .. } | LoadStatus::Absent => None,
        }
    }

    /// End a trial boot with the self-test's result: passed, the image is confirmed; failed, it
    /// stays on trial and the caller resets (the bootloader swaps the previous image back).
    /// Returns whether the running image is now confirmed (always true outside a trial).
    pub fn confirm(&mut self, test: &SelfTest) -> Result<bool, UpdateError> {
        let confirmed = confirm(&self.slots(), test)?;
        if confirmed && self.boot == BootState::Trial {
            self.boot = BootState::Normal;
        }
        Ok(confirmed)
    }

    /// A `Reboot` was accepted since the last call (the caller sends the answer, then resets).
    pub fn take_reset_request(&mut self) -> bool {
        core::mem::take(&mut self.reset_requested)
    }

    /// The running image's version: its trailer's, else the fallback.
    pub fn version(&self) -> heapless::String<VERSION_LEN> {
        let trailer = active_trailer(&self.slots());
        let v = trailer
            .as_ref()
            .map(|t| t.version())
            .unwrap_or(self.fallback_version);
        let mut out = heapless::String::new();
        for ch in v.chars() {
            if out.push(ch).is_err() {
                break;
            }
        }
        out
    }

    /// Answer a settings, update or reboot request (`None`: not one of them). `armed`: the
    /// device renders force or homes (every write is refused).
    pub fn handle(&mut self, seq: u16, req: &Request, armed: bool) -> Option<DeviceMsg> {
        let refuse = |key: &str, reason: &str| DeviceMsg::ConfigRefused {
            seq,
            refusal: ConfigRefusal::new(key, reason),
        };
        let ack = |result| DeviceMsg::Ack { seq, result };
        let disarm_first = "refused while armed: disarm first";
        Some(match req {
            Request::ConfigGet(section) => match self.get(*section) {
                Some(value) => DeviceMsg::Config { seq, value },
                None => refuse("presets", "no such preset index"),
            },
            Request::ConfigSet(value) if armed => refuse(section_key(value), disarm_first),
            Request::ConfigSet(value) => match self.set(value) {
                Ok(()) => ack(AckResult::Ok),
                Err((k, r)) => refuse(k, r),
            },
            Request::ConfigSave => match self.save(armed) {
                Ok(()) => ack(AckResult::Ok),
                Err(SaveError::Armed) => refuse("store", disarm_first),
                Err(SaveError::Invalid(e)) => refuse(e.key, e.reason),
                Err(SaveError::Storage) => refuse("store", "the flash write failed"),
            },
            Request::ConfigReset => match self.erase(armed) {
                Ok(()) => ack(AckResult::Ok),
                Err(SaveError::Armed) => refuse("store", disarm_first),
                Err(_) => refuse("store", "the flash erase failed"),
            },
            Request::UpdateBegin { len, signature } => {
                let Ok(sig) = <[u8; 64]>::try_from(signature.as_slice()) else {
                    return Some(DeviceMsg::UpdateRefused {
                        seq,
                        refusal: UpdateRefusal::BadSignatureLength,
                    });
                };
                let slots = Slots::new(&self.flash, self.layout.clone());
                let r = self.update.begin(&slots, *len, &sig, armed);
                self.update_reply(seq, r.map(|_| ()))
            }
            Request::UpdateChunk(c) => {
                let slots = Slots::new(&self.flash, self.layout.clone());
                let r = self.update.chunk(&slots, c.offset, &c.data, c.crc, armed);
                self.update_reply(seq, r.map(|_| ()))
            }
            Request::UpdateFinish => {
                let key = softfinger_update::keys::TRUSTED_PUBLIC_KEY;
                let slots = Slots::new(&self.flash, self.layout.clone());
                let r = self.update.finish(&slots, &key, armed);
                self.update_reply(seq, r)
            }
            Request::UpdateStatus => self.update_reply(seq, Ok(())),
            Request::Reboot if armed => ack(AckResult::Err(ErrorCode::WrongMode)),
            Request::Reboot => {
                self.reset_requested = true;
                ack(AckResult::Ok)
            }
            _ => return None,
        })
    }

    fn get(&self, section: ConfigSection) -> Option<ConfigValue> {
        let s = &self.live;
        Some(match section {
            ConfigSection::Status => ConfigValue::Status {
                store: StoreStatus::from(self.status),
                schema_version: SCHEMA_VERSION,
                may_arm: self.arm_refusal().is_none(),
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

    /// Change one section of the settings in force, validated as a whole.
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
        }
        self.live = next;
        Ok(())
    }

    /// Write the settings in force to the store.
    fn save(&mut self, armed: bool) -> Result<(), SaveError> {
        let region = self.layout.store.clone();
        let live = &self.live;
        self.flash.lock(|c| {
            let mut f = c.borrow_mut();
            Store::new(BlockingAsync::new(&mut *f), region)
                .map_err(|_| SaveError::Storage)?
                .save_blocking(live, armed)
        })?;
        self.status = LoadStatus::Read;
        self.unsaved = false;
        Ok(())
    }

    /// Erase the store; the defaults are in force.
    fn erase(&mut self, armed: bool) -> Result<(), SaveError> {
        let region = self.layout.store.clone();
        self.flash.lock(|c| {
            let mut f = c.borrow_mut();
            Store::new(BlockingAsync::new(&mut *f), region)
                .map_err(|_| SaveError::Storage)?
                .erase_blocking(armed)
        })?;
        self.live = Settings::default();
        self.status = LoadStatus::Absent;
        self.unsaved = false;
        Ok(())
    }

    fn update_reply(&self, seq: u16, r: Result<(), UpdateError>) -> DeviceMsg {
        if let Err(e) = r {
            return DeviceMsg::UpdateRefused {
                seq,
                refusal: refusal(e),
            };
        }
        let phase = match self.update.status() {
            Status::Idle => UpdatePhase::Idle,
            Status::Receiving { len, received } => UpdatePhase::Receiving { len, received },
            Status::Verified => UpdatePhase::Verified,
        };
        DeviceMsg::Update {
            seq,
            status: UpdateStatus {
                phase,
                boot: boot_wire(self.boot),
                version: self.version(),
            },
        }
    }
}

/// The section a value belongs to, as a refusal's key.
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

/// The wire form of a boot state.
pub fn boot_wire(b: BootState) -> BootStateWire {
    match b {
        BootState::Normal => BootStateWire::Normal,
        BootState::Trial => BootStateWire::Trial,
        BootState::RolledBack => BootStateWire::RolledBack,
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

/// Set by the link session whenever its store refuses arming ([`DeviceStore::arm_refusal`]); read by
/// the operator's button, so that no arm path arms on a calibration the device could not read.
pub static ARM_REFUSED: core::sync::atomic::AtomicBool = core::sync::atomic::AtomicBool::new(false);

/// A flash whose long operations keep the thread-mode heartbeat going: an erase is done page by
/// page and a write in pieces of a page at most, with [`crate::tick::thread_heartbeat`] before
/// each, and each read beats too. A save or an update's erase of the DFU slot (115 pages, ~22 ms each on the G474) blocks
/// the link task for far longer than the tick's thread watchdog (`THREAD_STALE_S`, 50 ms), but
/// no single page operation does (RM0440: page erase 22 ms typical, 40 ms at most).
#[derive(Debug)]
pub struct PacedFlash<F>(pub F);

impl<F: embedded_storage::nor_flash::ErrorType> embedded_storage::nor_flash::ErrorType
    for PacedFlash<F>
{
    type Error = F::Error;
}

impl<F: embedded_storage::nor_flash::ReadNorFlash> embedded_storage::nor_flash::ReadNorFlash
    for PacedFlash<F>
{
    const READ_SIZE: usize = F::READ_SIZE;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        // The signature check hashes the whole received image chunk by chunk (SHA-512 in
        // software, ~0.2 s for a full slot): each read is a heartbeat too.
        crate::tick::thread_heartbeat();
        self.0.read(offset, bytes)
    }
    fn capacity(&self) -> usize {
        self.0.capacity()
    }
}

impl<F: NorFlash> NorFlash for PacedFlash<F> {
    const WRITE_SIZE: usize = F::WRITE_SIZE;
    const ERASE_SIZE: usize = F::ERASE_SIZE;
    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        let mut page = from;
        while page < to {
            crate::tick::thread_heartbeat();
            let next = page.saturating_add(F::ERASE_SIZE as u32).min(to);
            self.0.erase(page, next)?;
            page = next;
        }
        Ok(())
    }
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        // A whole number of write units per piece (ERASE_SIZE is one).
        let piece = F::ERASE_SIZE.max(F::WRITE_SIZE);
        let mut at = offset;
        for chunk in bytes.chunks(piece) {
            crate::tick::thread_heartbeat();
            self.0.write(at, chunk)?;
            at = at.saturating_add(chunk.len() as u32);
        }
        Ok(())
    }
}

/// The device's flash as the link session uses it: its settings, update and reboot requests,
/// the settings flags for device info, and the arm check.
pub trait Persistence {
    /// Answer a settings, update or reboot request (`None`: not one of them). `armed`: the
    /// device renders force or homes.
    fn handle(&mut self, seq: u16, req: &Request, armed: bool) -> Option<DeviceMsg>;
    /// Device info's `settings_flags` (`softfinger_store::boot::FLAG_*`).
    fn settings_flags(&self) -> u8;
    /// Why the device must not arm, or `None`.
    fn arm_refusal(&self) -> Option<&'static str>;
    /// A `Reboot` was accepted since the last call: reset once its answer is sent.
    fn take_reset_request(&mut self) -> bool;
    /// The name the user gave the device (`identity.name`), if any: device info's name.
    fn device_name(&self) -> Option<&str>;
    /// What the settings loaded at boot change ([`crate::boot_defaults`]).
    fn boot_defaults(&self) -> BootDefaults;
}

impl<F: NorFlash> Persistence for DeviceStore<F> {
    fn handle(&mut self, seq: u16, req: &Request, armed: bool) -> Option<DeviceMsg> {
        DeviceStore::handle(self, seq, req, armed)
    }
    fn settings_flags(&self) -> u8 {
        self.boot_load().flags()
    }
    fn arm_refusal(&self) -> Option<&'static str> {
        DeviceStore::arm_refusal(self)
    }
    fn take_reset_request(&mut self) -> bool {
        DeviceStore::take_reset_request(self)
    }
    fn device_name(&self) -> Option<&str> {
        let name = self.live.identity.name.as_str();
        (!name.is_empty()).then_some(name)
    }
    fn boot_defaults(&self) -> BootDefaults {
        DeviceStore::boot_defaults(self)
    }
}

/// A board without a settings store (the emulated board): settings, update and reboot requests
/// are refused, naming why; arming is never refused for it.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoStore;

impl Persistence for NoStore {
    fn handle(&mut self, seq: u16, req: &Request, _armed: bool) -> Option<DeviceMsg> {
        let no_store = || DeviceMsg::ConfigRefused {
            seq,
            refusal: ConfigRefusal::new("store", "this board has no settings store"),
        };
        Some(match req {
            Request::ConfigGet(_)
            | Request::ConfigSet(_)
            | Request::ConfigSave
            | Request::ConfigReset => no_store(),
            Request::UpdateBegin { .. }
            | Request::UpdateChunk(_)
            | Request::UpdateFinish
            | Request::UpdateStatus => DeviceMsg::UpdateRefused {
                seq,
                refusal: UpdateRefusal::Flash,
            },
            Request::Reboot => DeviceMsg::Ack {
                seq,
                result: AckResult::Err(ErrorCode::Unsupported),
            },
            _ => return None,
        })
    }
    fn settings_flags(&self) -> u8 {
        softfinger_store::boot::FLAG_DEFAULTS | softfinger_store::boot::FLAG_FLASH_ERROR
    }
    fn arm_refusal(&self) -> Option<&'static str> {
        None
    }
    fn take_reset_request(&mut self) -> bool {
        false
    }
    fn device_name(&self) -> Option<&str> {
        None
    }
    fn boot_defaults(&self) -> BootDefaults {
        BootDefaults::BUILT_IN
    }
}

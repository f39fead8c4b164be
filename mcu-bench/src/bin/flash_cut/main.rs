//! The power-cut campaign on the emulated Cortex-M4F: the settings store and the update path
//! (softfinger-store, softfinger-update, embassy-boot's swap as `firmware/bootloader` runs it)
//! against the G474's flash kept in a host file (`softfinger_mcu_bench::semiflash`), so a kill of
//! QEMU is a power cut and the next QEMU run is the next power-on. Driven by `scripts/flash-cut`.
//!
//! Every run powers on and **boots** as the device does: the bootloader's step (a marked or
//! half-swapped image is swapped in, an unconfirmed one swapped back), the self-test (the core's
//! control pipeline ticks with no force before homing; the store loads through
//! `softfinger_store::load_at_boot`), the trial image confirmed or rolled back. Then the action
//! in the file `cmd` (in QEMU's working directory, next to `flash.bin`):
//!
//! ```text
//! init                 an image of generation 1 in the active slot, settings of serial 1 saved
//! check                boot only
//! boot-cut [CUT]       boot only, CUT counted from the power-on (a cut in the boot's own writes:
//!                      a resumed swap, a confirm, a roll back); prints the boot's `OPS` first
//! save N [CUT]         N saves, each of the next serial (CUT: stop before flash operation CUT)
//! update FAIL [CUT]    the image of the next generation (FAIL=1: one that fails its self-test)
//!                      sent in 128-byte chunks, verified, marked; then a reset (the swap, the
//!                      self-test, confirm or roll back)
//! refusals             a wrong signature, a truncated image, a corrupted chunk: each refused,
//!                      the active slot unchanged
//! measure              instructions of 150 saves and of a boot (run under -icount shift=0)
//! ```
//!
//! Output lines: `BOOT image=G match=0|1 state=S serial=N status=S flags=F tick=0|1`,
//! `SAVED N`, `MARKED G OPS` (the flash operations until then), `OPS N W E` (flash operations, double words, pages), `CUT N`,
//! `CHECK name 0|1 detail`, `MEASURE name instructions`, `DONE`.
#![no_std]
#![no_main]

use core::cell::RefCell;

use cortex_m_semihosting::{hprintln, syscall};
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embedded_storage::nor_flash::NorFlash;
use softfinger_core::Fast;
use softfinger_mcu_bench::counter::{Counter, INSTRUCTIONS_PER_COUNT};
use softfinger_mcu_bench::exit::exit;
use softfinger_mcu_bench::rig::Rig;
use softfinger_mcu_bench::semiflash::{SemiFlash, FLASH_LEN};
use softfinger_store::{
    load_at_boot_blocking, BootLoad, Calibration, LoadStatus, MotorConstants, Settings, Store,
};
use softfinger_update::boot::{active_trailer, boot_state, confirm, run_bootloader};
use softfinger_update::keys::{parse_hex_key, TRUSTED_PUBLIC_KEY};
use softfinger_update::layout::G474;
use softfinger_update::package::{sign, ImageTrailer, FLAG_SIMULATE_SELF_TEST_FAILURE};
use softfinger_update::session::chunk_crc;
use softfinger_update::{BootState, SelfTest, Slots, UpdateError, UpdateSession, CHUNK_LEN};

softfinger_mcu_bench::install_fault_handler!();

type Flash = Mutex<NoopRawMutex, RefCell<SemiFlash>>;

/// An update image, bytes (payload and trailer): four pages, so a swap moves real data.
const IMAGE_LEN: usize = 8 * 1024;

static mut MEM: [u8; FLASH_LEN] = [0; FLASH_LEN];
static mut IMAGE: [u8; IMAGE_LEN] = [0; IMAGE_LEN];

/// The development key's secret half (public, committed): the harness signs the campaign's images
/// with it, as `softfinger-sign` would; the device checks them against `TRUSTED_PUBLIC_KEY`.
fn dev_seed() -> [u8; 32] {
    parse_hex_key(include_str!("../../../../update/keys/dev-signing-key.hex").trim_ascii())
}

/// The image of generation `g` (deterministic payload, version `fc-G`, optional fail flag).
fn image(g: u32, fail: bool) -> &'static [u8; IMAGE_LEN] {
    let img = unsafe { &mut *core::ptr::addr_of_mut!(IMAGE) };
    let mut x = g.wrapping_mul(2_654_435_761) | 1;
    let (payload, trailer) = img.split_at_mut(IMAGE_LEN - 32);
    for b in payload.iter_mut() {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        *b = x as u8;
    }
    let mut v: heapless::String<23> = heapless::String::new();
    let _ = core::fmt::write(&mut v, format_args!("fc-{g}"));
    let flags = if fail {
        FLAG_SIMULATE_SELF_TEST_FAILURE
    } else {
        0
    };
    match ImageTrailer::new(&v, flags) {
        Ok(t) => trailer.copy_from_slice(&t.to_bytes()),
        Err(_) => fail_with("trailer"),
    }
    img
}

/// The generation of a trailer's version `fc-G`.
fn generation(t: &ImageTrailer) -> Option<u32> {
    t.version().strip_prefix("fc-")?.parse().ok()
}

/// The settings of serial `s`: every section set, a calibration that differs per serial.
fn settings(s: u32) -> Settings {
    let mut x = Settings::default();
    x.identity.serial = s;
    x.identity.name.clear();
    let _ = core::fmt::write(&mut x.identity.name, format_args!("cut-{s}"));
    let k = (s % 1000) as i32;
    x.calibration = Some(Calibration {
        homing_offset_counts: [k, -k, 2 * k],
        wrist_zero_counts: [k as i16, 1, 2],
        encoder_direction: [1, -1, 1, -1, 1, -1],
        motors: [MotorConstants {
            torque_constant_nm_per_a: 0.03 + (s % 7) as f32 * 0.001,
            resistance_ohm: 1.1,
        }; 3],
    });
    x.stream.rate_hz = (s % 1000) as u16 + 1;
    x.watchdog.timeout_ms = 100 + (s % 100) as u16;
    x
}

fn fail_with(what: &str) -> ! {
    hprintln!("ERROR {}", what);
    exit(false)
}

/// The action line from `cmd`.
fn read_cmd(buf: &mut [u8; 64]) -> &str {
    let path = "cmd\0";
    let fd = unsafe {
        syscall!(
            OPEN,
            path.as_ptr(),
            cortex_m_semihosting::nr::open::R_BINARY,
            path.len() - 1
        )
    };
    if (fd as isize) < 0 {
        fail_with("no cmd file");
    }
    let len = unsafe { syscall!(FLEN, fd) }.min(buf.len());
    let left = unsafe { syscall!(READ, fd, buf.as_mut_ptr(), len) };
    unsafe { syscall!(CLOSE, fd) };
    core::str::from_utf8(&buf[..len - left.min(len)])
        .unwrap_or("")
        .trim()
}

/// What a boot found.
struct Boot {
    image: Option<u32>,
    matches: bool,
    state: BootState,
    load: BootLoad,
    tick: bool,
}

/// The control pipeline's self-test: ten ticks of a powered, unhomed pipeline, every one with
/// zero compare (no force before homing).
fn tick_self_test() -> bool {
    let Some(mut rig) = Rig::<Fast>::powered() else {
        return false;
    };
    (0..10).all(|_| rig.tick([0; 6]).bridges.compare == [0; 3])
}

/// Does the active slot hold the image of generation `g` byte for byte?
fn active_is(slots: &Slots<'_, SemiFlash>, g: u32, fail: bool) -> bool {
    let want = image(g, fail);
    let mut buf = [0u8; 256];
    want.chunks(256).enumerate().all(|(i, w)| {
        slots
            .read_active((i * 256) as u32, &mut buf[..w.len()])
            .is_ok()
            && buf[..w.len()] == *w
    })
}

/// Power-on: the bootloader, the self-test, confirm or roll back (see the module doc).
fn boot(flash: &Flash) -> Boot {
    let slots = Slots::new(flash, G474);
    if run_bootloader(&slots).is_err() {
        fail_with("bootloader");
    }
    let Ok(state) = boot_state(&slots) else {
        fail_with("boot state")
    };
    let tick = tick_self_test();
    let load = flash.lock(|c| load_at_boot_blocking(&mut *c.borrow_mut(), G474.store.clone()));
    let trailer = active_trailer(&slots);
    let failing = trailer.is_some_and(|t| t.flags & FLAG_SIMULATE_SELF_TEST_FAILURE != 0);
    let test = SelfTest {
        clock: true,
        encoders: true,
        tick: tick && !failing,
        store: true,
    };
    let state = match confirm(&slots, &test) {
        Ok(true) => {
            if state == BootState::Trial {
                BootState::Normal
            } else {
                state
            }
        }
        Ok(false) => {
            // A trial image failing its self-test resets the device: the bootloader swaps back.
            if run_bootloader(&slots).is_err() {
                fail_with("bootloader (roll back)");
            }
            match boot_state(&slots) {
                Ok(s) => s,
                Err(_) => fail_with("boot state"),
            }
        }
        Err(_) => fail_with("confirm"),
    };
    let trailer = active_trailer(&slots);
    let g = trailer.as_ref().and_then(generation);
    let fail = trailer.is_some_and(|t| t.flags & FLAG_SIMULATE_SELF_TEST_FAILURE != 0);
    let matches = g.is_some_and(|g| active_is(&slots, g, fail));
    Boot {
        image: g,
        matches,
        state,
        load,
        tick,
    }
}

fn report(b: &Boot) {
    let status = match b.load.status() {
        LoadStatus::Read => "read",
        LoadStatus::Migrated { .. } => "migrated",
        LoadStatus::Absent => "absent",
        LoadStatus::Corrupt => "corrupt",
        LoadStatus::UnknownVersion(_) => "unknown-version",
        LoadStatus::FlashError => "flash-error",
    };
    let state = match b.state {
        BootState::Normal => "normal",
        BootState::Trial => "trial",
        BootState::RolledBack => "rolled-back",
    };
    hprintln!(
        "BOOT image={} match={} state={} serial={} status={} flags={} tick={}",
        b.image.unwrap_or(0),
        b.matches as u8,
        state,
        b.load.settings().identity.serial,
        status,
        b.load.flags(),
        b.tick as u8
    );
}

fn parse_cut(s: Option<&str>) -> Option<u32> {
    s.and_then(|s| s.parse().ok())
}

fn ops_line(flash: &Flash) {
    flash.lock(|c| {
        let f = c.borrow();
        hprintln!("OPS {} {} {}", f.ops(), f.words_written, f.pages_erased);
    });
}

fn save(flash: &Flash, serial: u32) -> bool {
    flash.lock(|c| {
        let mut f = c.borrow_mut();
        match Store::new(&mut *f, G474.store.clone()) {
            Ok(mut s) => s.save_blocking(&settings(serial), false).is_ok(),
            Err(_) => false,
        }
    })
}

/// Send the image of generation `g` and mark it: the device's side of `softfinger update`.
fn send_update(
    flash: &Flash,
    img: &[u8],
    sig: &[u8; 64],
    corrupt_at: Option<u32>,
    stop_at: Option<u32>,
) -> Result<(), UpdateError> {
    let slots = Slots::new(flash, G474);
    let mut s = UpdateSession::new();
    let mut off = s.begin(&slots, img.len() as u32, sig, false)?;
    while (off as usize) < img.len() {
        if stop_at.is_some_and(|x| off >= x) {
            break;
        }
        let end = (off as usize + CHUNK_LEN).min(img.len());
        let data = &img[off as usize..end];
        let mut crc = chunk_crc(data);
        if corrupt_at == Some(off) {
            crc ^= 1 << 7;
        }
        off = s.chunk(&slots, off, data, crc, false)?;
    }
    s.finish(&slots, &TRUSTED_PUBLIC_KEY, false)
}

fn check(name: &str, ok: bool, detail: core::fmt::Arguments<'_>) -> bool {
    hprintln!("CHECK {} {} {}", name, ok as u8, detail);
    ok
}

/// Each bad update refused, naming why, and the running image untouched.
fn refusals(flash: &Flash, running: u32, state: BootState) -> bool {
    let next = running + 1;
    let img = image(next, false);
    let good = sign(img, &dev_seed());
    let slots = Slots::new(flash, G474);
    let mut all = true;

    let mut bad = good;
    bad[5] ^= 0x10;
    let r = send_update(flash, img, &bad, None, None);
    all &= check(
        "wrong-signature",
        r == Err(UpdateError::BadSignature) && active_is(&slots, running, false),
        format_args!("{:?}", r),
    );
    let other = sign(img, &[7u8; 32]);
    let r = send_update(flash, img, &other, None, None);
    all &= check(
        "other-key",
        r == Err(UpdateError::BadSignature) && active_is(&slots, running, false),
        format_args!("{:?}", r),
    );
    let r = send_update(flash, img, &good, None, Some(IMAGE_LEN as u32 / 2));
    all &= check(
        "truncated",
        r == Err(UpdateError::Truncated {
            received: IMAGE_LEN as u32 / 2,
            len: IMAGE_LEN as u32,
        }) && active_is(&slots, running, false),
        format_args!("{:?}", r),
    );
    let r = send_update(flash, img, &good, Some(1024), None);
    all &= check(
        "corrupted-chunk",
        r == Err(UpdateError::ChunkCrc { offset: 1024 }) && active_is(&slots, running, false),
        format_args!("{:?}", r),
    );
    // None of them marked anything: a reset boots the same image, in the same state.
    let b = boot(flash);
    all &= check(
        "reset-after-refusals",
        b.image == Some(running) && b.matches && b.state == state,
        format_args!("image {:?} state {:?}", b.image, b.state),
    );
    all
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let mut cmd_buf = [0u8; 64];
    let cmd = read_cmd(&mut cmd_buf);
    let mut words = cmd.split_ascii_whitespace();
    let action = words.next().unwrap_or("");
    let mem = unsafe { &mut *core::ptr::addr_of_mut!(MEM) };
    let Some(f) = SemiFlash::power_on("flash.bin\0", mem) else {
        fail_with("flash.bin: cannot open or short")
    };
    let flash: Flash = Mutex::new(RefCell::new(f));

    if action == "init" {
        let slots = Slots::new(&flash, G474);
        let img = image(1, false);
        if slots.active().write(0, img).is_err() || !save(&flash, 1) {
            fail_with("init");
        }
    }
    if action == "boot-cut" {
        // A cut during this power-on's boot (the resumed swap, the confirm or the roll back).
        flash.lock(|c| {
            let mut f = c.borrow_mut();
            f.count_from_here();
            f.cut_at(parse_cut(words.next()));
        });
    }
    let b = boot(&flash);
    if action == "boot-cut" {
        ops_line(&flash);
    }
    report(&b);
    let Some(running) = b.image else {
        fail_with("no image in the active slot")
    };
    let mut ok = true;
    flash.lock(|c| c.borrow_mut().count_from_here());
    match action {
        "init" | "check" | "boot-cut" => {}
        "save" => {
            let n: u32 = words.next().and_then(|s| s.parse().ok()).unwrap_or(1);
            flash.lock(|c| c.borrow_mut().cut_at(parse_cut(words.next())));
            let mut serial = b.load.settings().identity.serial;
            for _ in 0..n {
                serial += 1;
                if !save(&flash, serial) {
                    fail_with("save");
                }
                hprintln!("SAVED {}", serial);
            }
        }
        "update" => {
            let fail = words.next() == Some("1");
            flash.lock(|c| c.borrow_mut().cut_at(parse_cut(words.next())));
            let next = running + 1;
            let img = image(next, fail);
            let sig = sign(img, &dev_seed());
            if let Err(e) = send_update(&flash, img, &sig, None, None) {
                hprintln!("ERROR update refused: {:?}", e);
                exit(false);
            }
            hprintln!("MARKED {} {}", next, flash.lock(|c| c.borrow().ops()));
            let b = boot(&flash); // the reset
            report(&b);
        }
        "refusals" => ok = refusals(&flash, running, b.state),
        "measure" => {
            // 150 saves: enough to fill the store's pages and make it migrate and erase.
            let counter = Counter::new(unsafe { cortex_m::Peripherals::steal() }.SYST);
            let serial = b.load.settings().identity.serial;
            let (mut min, mut max, mut sum) = (u32::MAX, 0u32, 0u64);
            let (mut max_words, mut max_erases, mut erases) = (0u32, 0u32, 0u32);
            const SAVES: u32 = 150;
            for i in 1..=SAVES {
                flash.lock(|c| c.borrow_mut().count_from_here());
                let t0 = counter.now();
                let saved = save(&flash, serial + i);
                let t1 = counter.now();
                if !saved {
                    fail_with("save");
                }
                let n = Counter::elapsed(t0, t1) * INSTRUCTIONS_PER_COUNT;
                (min, max, sum) = (min.min(n), max.max(n), sum + u64::from(n));
                flash.lock(|c| {
                    let f = c.borrow();
                    max_words = max_words.max(f.words_written);
                    max_erases = max_erases.max(f.pages_erased);
                    erases += f.pages_erased;
                });
            }
            hprintln!(
                "MEASURE save saves={} min={} mean={} max={} max_words={} max_erases={} erases={}",
                SAVES,
                min,
                sum / u64::from(SAVES),
                max,
                max_words,
                max_erases,
                erases
            );
            flash.lock(|c| c.borrow_mut().count_from_here());
            let t0 = counter.now();
            let _ = boot(&flash);
            let t1 = counter.now();
            hprintln!(
                "MEASURE boot {}",
                Counter::elapsed(t0, t1) * INSTRUCTIONS_PER_COUNT
            );
        }
        other => fail_with(if other.is_empty() {
            "empty cmd"
        } else {
            "unknown action"
        }),
    }
    ops_line(&flash);
    hprintln!("DONE");
    exit(ok)
}

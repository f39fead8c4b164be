//! Ctrl-C: a flag the long-running commands poll, so they stop cleanly (temporary files
//! removed, the device disarmed where the command armed it) instead of dying mid-write.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Once;

static REQUESTED: AtomicBool = AtomicBool::new(false);
static INSTALL: Once = Once::new();

/// The exit status of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Catch Ctrl-C from now on (idempotent). Without a handler (none could be installed) Ctrl-C
/// ends the process as usual.
pub fn install() {
    INSTALL.call_once(|| {
        let _ = ctrlc::set_handler(|| REQUESTED.store(true, Relaxed));
    });
}

/// The flag itself, for library calls that poll a stop flag (`bench`'s `BenchConfig::stop`).
pub fn flag() -> &'static AtomicBool {
    &REQUESTED
}

/// True once Ctrl-C was pressed.
pub fn requested() -> bool {
    REQUESTED.load(Relaxed)
}

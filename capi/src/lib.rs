//! # softfinger-c
//!
//! The softfinger host library ([`softfinger_host::Device`]) as a C ABI: `libsoftfinger.so`,
//! `libsoftfinger.a` and the header `include/softfinger.h` (generated from this crate by
//! cbindgen; threading, units and error codes are described at its top).
//!
//! Every function checks its pointers (null returns `SF_ERR_NULL`) and its numbers (out of range
//! returns `SF_ERR_BAD_VALUE`) before it sends anything, and never unwinds into C: a panic in the
//! library is caught and returned as `SF_ERR_INTERNAL`.

// The C names are the API.
#![allow(non_camel_case_types)]
// Every pointer argument is checked for null and documented in the header; the functions are
// `extern "C"` entry points, not Rust API.
#![allow(clippy::missing_safety_doc)]

pub mod error;
pub mod types;

pub use error::*;
pub use types::*;

use softfinger_host::{Device, LatestState, LinkError, StateQueue, Target};
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// The longest wait any call accepts, s (a day).
const MAX_WAIT_S: f64 = 86_400.0;

/// An open device. Opaque to C.
pub struct sf_device {
    dev: Mutex<Device>,
    latest: Arc<LatestState>,
    states: StateQueue,
    rate_hz: u32,
}

/// Run `f`, turning a panic into `SF_ERR_INTERNAL`.
fn guard(f: impl FnOnce() -> c_int) -> c_int {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(SF_ERR_INTERNAL)
}

/// `result` as a return code.
fn code(result: Result<(), LinkError>) -> c_int {
    match result {
        Ok(()) => SF_OK,
        Err(e) => error::code_of(&e),
    }
}

/// The device behind `dev`, or `SF_ERR_NULL`.
unsafe fn device<'a>(dev: *mut sf_device) -> Result<&'a sf_device, c_int> {
    // SAFETY: the caller passes a handle from `sf_open` not yet closed (or null, refused here).
    unsafe { dev.as_ref() }.ok_or(SF_ERR_NULL)
}

/// Run a request on the handle's device.
unsafe fn with_device(
    dev: *mut sf_device,
    f: impl FnOnce(&mut Device, &sf_device) -> c_int,
) -> c_int {
    guard(|| {
        // SAFETY: forwarded from the caller.
        let h = match unsafe { device(dev) } {
            Ok(h) => h,
            Err(c) => return c,
        };
        match h.dev.lock() {
            Ok(mut d) => f(&mut d, h),
            Err(_) => SF_ERR_INTERNAL,
        }
    })
}

/// A wait in seconds as a duration: finite, 0 ..= a day.
fn wait(timeout_s: f64) -> Result<Duration, c_int> {
    if timeout_s.is_finite() && (0.0..=MAX_WAIT_S).contains(&timeout_s) {
        Ok(Duration::from_secs_f64(timeout_s))
    } else {
        Err(SF_ERR_BAD_VALUE)
    }
}

fn open(target: *const c_char) -> Result<Box<sf_device>, c_int> {
    if target.is_null() {
        return Err(SF_ERR_NULL);
    }
    // SAFETY: a non-null target is a NUL-terminated string (the header's contract).
    let text = unsafe { CStr::from_ptr(target) }
        .to_str()
        .map_err(|_| SF_ERR_BAD_TARGET)?;
    let target: Target = text.parse().map_err(|e| error::code_of(&e))?;
    let mut dev = Device::connect(&target).map_err(|e| error::code_of(&e))?;
    let info = dev.info().map_err(|e| error::code_of(&e))?;
    Ok(Box::new(sf_device {
        latest: dev.latest(),
        states: dev.state_queue(),
        rate_hz: info.control_rate_hz,
        dev: Mutex::new(dev),
    }))
}

/// Open a device: `"tcp:HOST:PORT"` (the virtual device of `host-sim serve`, e.g.
/// `"tcp:127.0.0.1:7700"`), `"usb"` (the first softfinger USB device) or `"usb:/dev/ttyACM0"`.
/// Returns the handle, or NULL with the error code in `*err` (`err` may be NULL); on success
/// `*err` is `SF_OK`. Close the handle with `sf_close`.
#[no_mangle]
pub unsafe extern "C" fn sf_open(target: *const c_char, err: *mut c_int) -> *mut sf_device {
    let result = catch_unwind(|| open(target)).unwrap_or(Err(SF_ERR_INTERNAL));
    let (handle, c) = match result {
        Ok(h) => (Box::into_raw(h), SF_OK),
        Err(c) => (std::ptr::null_mut(), c),
    };
    // SAFETY: a non-null `err` points to an int (the header's contract).
    if let Some(e) = unsafe { err.as_mut() } {
        *e = c;
    }
    handle
}

/// Close a device (stops its stream and the library's threads for it). NULL is ignored. The
/// handle must not be used afterwards, nor by another thread meanwhile.
#[no_mangle]
pub unsafe extern "C" fn sf_close(dev: *mut sf_device) {
    if dev.is_null() {
        return;
    }
    let _ = catch_unwind(|| {
        // SAFETY: a handle from `sf_open`, closed once (the header's contract).
        let h = unsafe { Box::from_raw(dev) };
        if let Ok(mut d) = h.dev.lock() {
            // Best effort: the device stops streaming before the socket closes.
            let _ = d.set_stream(0);
        }
        drop(h);
    });
}

/// The device's description (and its fingertip radius) into `*out`. Returns `SF_OK` or an
/// error.
#[no_mangle]
pub unsafe extern "C" fn sf_info(dev: *mut sf_device, out: *mut sf_info_t) -> c_int {
    if out.is_null() {
        return SF_ERR_NULL;
    }
    // SAFETY: forwarded; `out` checked above.
    unsafe {
        with_device(dev, |d, _| {
            match d.info().and_then(|i| Ok((i, d.contact_params()?))) {
                Ok((i, p)) => {
                    *out = sf_info_t::of(&i, p.fingertip_radius_m);
                    SF_OK
                }
                Err(e) => error::code_of(&e),
            }
        })
    }
}

/// Home the device and return when it is homed (`SF_OK`), failed (`SF_ERR_HOMING_FAILED`) or
/// `timeout_s` (0 < timeout_s <= 86400) passed (`SF_ERR_TIMEOUT`). The handle's other requests
/// wait meanwhile; `sf_latest_state` does not.
#[no_mangle]
pub unsafe extern "C" fn sf_home(dev: *mut sf_device, timeout_s: f64) -> c_int {
    let t = match wait(timeout_s) {
        Ok(t) if !t.is_zero() => t,
        _ => return SF_ERR_BAD_VALUE,
    };
    // SAFETY: forwarded.
    unsafe { with_device(dev, |d, _| code(d.home_and_wait(t))) }
}

/// Arm: the device renders force (ramped in). Needs homing (else
/// `SF_ERR_REFUSED_WRONG_MODE`).
#[no_mangle]
pub unsafe extern "C" fn sf_arm(dev: *mut sf_device) -> c_int {
    // SAFETY: forwarded.
    unsafe { with_device(dev, |d, _| code(d.arm())) }
}

/// Disarm: no force.
#[no_mangle]
pub unsafe extern "C" fn sf_disarm(dev: *mut sf_device) -> c_int {
    // SAFETY: forwarded.
    unsafe { with_device(dev, |d, _| code(d.disarm())) }
}

/// Clear latched faults (the device is then disarmed).
#[no_mangle]
pub unsafe extern "C" fn sf_clear(dev: *mut sf_device) -> c_int {
    // SAFETY: forwarded.
    unsafe { with_device(dev, |d, _| code(d.clear_faults())) }
}

/// Send a local model; the device blends it in from its next tick. `SF_ERR_BAD_VALUE` for a
/// shape outside `SF_SHAPE_*`, a non-finite value or `max_age_ms` > 65535 (nothing sent); the
/// device refuses the rest of what is out of range (`SF_ERR_REFUSED_INVALID_VALUE`,
/// `SF_ERR_REFUSED_STALE_SEQUENCE`, ...).
#[no_mangle]
pub unsafe extern "C" fn sf_set_local_model(
    dev: *mut sf_device,
    m: *const sf_local_model,
) -> c_int {
    // SAFETY: a non-null `m` points to a model (the header's contract).
    let Some(m) = (unsafe { m.as_ref() }) else {
        return SF_ERR_NULL;
    };
    let wire = match m.to_wire() {
        Ok(w) => w,
        Err(c) => return c,
    };
    // SAFETY: forwarded.
    unsafe { with_device(dev, |d, _| code(d.set_local_model(wire))) }
}

/// Stream state samples at `rate_hz` (0: stop). The device makes a sample every
/// round(control rate / rate_hz) ticks, so the rate is the nearest it can make; faster than the
/// device's fastest (`sf_info_t.max_stream_hz`) is refused (`SF_ERR_REFUSED_STREAM_TOO_FAST`).
/// Negative, non-finite, above the control rate or below control rate / 65535 is
/// `SF_ERR_BAD_VALUE`.
#[no_mangle]
pub unsafe extern "C" fn sf_set_stream(dev: *mut sf_device, rate_hz: f64) -> c_int {
    if !(rate_hz.is_finite() && rate_hz >= 0.0) {
        return SF_ERR_BAD_VALUE;
    }
    // SAFETY: forwarded.
    unsafe {
        with_device(dev, |d, h| {
            let divisor = if rate_hz == 0.0 {
                0.0
            } else {
                (f64::from(h.rate_hz) / rate_hz).round()
            };
            if rate_hz > f64::from(h.rate_hz) || divisor > f64::from(u16::MAX) {
                return SF_ERR_BAD_VALUE;
            }
            code(d.set_stream(divisor as u16))
        })
    }
}

/// The next state sample in arrival order into `*out`, waiting up to `timeout_s`
/// (0 ..= 86400; 0 only takes what is queued). Returns 1 with a sample, 0 on timeout, or an
/// error (`SF_ERR_DISCONNECTED` once the connection is gone and the queue empty). Samples queue
/// up (65 536 at most; newer ones are then dropped) until taken.
#[no_mangle]
pub unsafe extern "C" fn sf_next_state(
    dev: *mut sf_device,
    out: *mut sf_state,
    timeout_s: f64,
) -> c_int {
    guard(|| {
        // SAFETY: forwarded.
        let h = match unsafe { device(dev) } {
            Ok(h) => h,
            Err(c) => return c,
        };
        if out.is_null() {
            return SF_ERR_NULL;
        }
        let t = match wait(timeout_s) {
            Ok(t) => t,
            Err(c) => return c,
        };
        match h.states.next(t) {
            Ok(Some(s)) => {
                // SAFETY: `out` checked above.
                unsafe { *out = sf_state::of(&s, h.rate_hz) };
                1
            }
            Ok(None) => 0,
            Err(e) => error::code_of(&e),
        }
    })
}

/// The newest state sample into `*out`, without waiting: returns 1 with a sample, 0 if none has
/// arrived yet. Takes nothing from the `sf_next_state` queue. Safe to call from a servo loop on
/// any thread while another thread makes requests.
#[no_mangle]
pub unsafe extern "C" fn sf_latest_state(dev: *mut sf_device, out: *mut sf_state) -> c_int {
    guard(|| {
        // SAFETY: forwarded.
        let h = match unsafe { device(dev) } {
            Ok(h) => h,
            Err(c) => return c,
        };
        if out.is_null() {
            return SF_ERR_NULL;
        }
        match h.latest.get() {
            Some(l) => {
                // SAFETY: `out` checked above.
                unsafe { *out = sf_state::of(&l.sample, h.rate_hz) };
                1
            }
            None => 0,
        }
    })
}

/// The text of an error code (a static string, never NULL, never to be freed); unknown codes
/// get "unknown softfinger error code".
#[no_mangle]
pub extern "C" fn sf_strerror(code: c_int) -> *const c_char {
    error::text_ptr(code)
}

/// For measurements from Rust: the arrival time of the newest sample and its count (see
/// [`softfinger_host::Latest`]), next to what `sf_latest_state` returns.
///
/// # Safety
/// `dev` is a handle from `sf_open` that is not closed (or null: `None`).
pub unsafe fn latest_with_arrival(dev: *mut sf_device) -> Option<softfinger_host::Latest> {
    // SAFETY: forwarded.
    unsafe { device(dev) }.ok()?.latest.get()
}

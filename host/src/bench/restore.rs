//! What the benchmark found on the device, and putting it back: the contact parameters, the
//! local model (sent again with a newer sequence number), the watchdog timeout, the simulated
//! hand on its script, and the mode (armed or disarmed, with no watchdog timeout left latched
//! by the benchmark's silence). A device found unhomed stays homed (homing cannot be undone);
//! one found faulted is left disarmed (a fault is not recreated); both are said in the report.

use crate::{Device, LinkError};
use serde::Serialize;
use softfinger_core::Flags;
use softfinger_protocol::{ContactParamsWire, DeviceStatus, ErrorCode, LocalModel, Mode};
use std::time::{Duration, Instant};

/// The device as the benchmark found it.
#[derive(Clone, Debug)]
pub struct Snapshot {
    params: ContactParamsWire,
    status: DeviceStatus,
    watchdog_ms: u16,
}

/// How the device was left.
#[derive(Clone, Debug, Serialize)]
pub struct RestoreReport {
    /// Mode found, and mode left.
    pub mode_found: String,
    pub mode_left: String,
    /// Contact parameters, model (all but its sequence number) and watchdog as found.
    pub params_restored: bool,
    pub model_restored: bool,
    pub watchdog_restored: bool,
    /// What could not be put back, and why.
    pub notes: Vec<String>,
}

impl RestoreReport {
    /// Everything is as found.
    pub fn complete(&self) -> bool {
        self.mode_found == self.mode_left
            && self.params_restored
            && self.model_restored
            && self.watchdog_restored
    }
}

/// Read what `d` has now.
pub fn snapshot(d: &mut Device) -> Result<Snapshot, LinkError> {
    Ok(Snapshot {
        params: d.contact_params()?,
        status: d.status()?,
        watchdog_ms: d.info()?.watchdog_ms,
    })
}

/// The same model, ignoring its sequence number.
fn same_model(a: &LocalModel, b: &LocalModel) -> bool {
    LocalModel { seq: 0, ..*a } == LocalModel { seq: 0, ..*b }
}

/// Put `found` back on `d`.
pub fn restore(d: &mut Device, found: &Snapshot) -> Result<RestoreReport, LinkError> {
    let mut notes = Vec::new();
    let _ = d.release_hand();
    d.set_watchdog_ms(found.watchdog_ms)?;
    if d.contact_params()? != found.params {
        d.set_contact_params(found.params)?;
    }
    let now = d.status()?;
    if !same_model(&now.model, &found.status.model) {
        // Newer than the model in force; if one is still queued behind it, newer than that.
        let model = |seq: u32| LocalModel {
            seq,
            ..found.status.model
        };
        match d.set_local_model(model(now.model.seq.wrapping_add(1))) {
            Err(LinkError::Refused(ErrorCode::StaleSequence)) => {
                d.set_local_model(model(now.model.seq.wrapping_add(1 << 16)))?
            }
            other => other?,
        }
        // Applied at a tick boundary, in force once the blend is half way.
        let end = Instant::now() + Duration::from_secs(1);
        while !same_model(&d.status()?.model, &found.status.model) && Instant::now() < end {
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    let timed_out = |st: &DeviceStatus| st.flags & Flags::COMM_TIMEOUT.0 != 0;
    match found.status.mode {
        Mode::Armed => d.arm()?,
        Mode::Disarmed | Mode::Unhomed | Mode::Faulted | Mode::Homing => {
            if now.mode == Mode::Armed {
                d.disarm()?;
            }
            // The benchmark's silence latched a watchdog timeout that was not there before:
            // re-arming clears it (from zero force, the arming ramp), then disarm again.
            if timed_out(&d.status()?) && !timed_out(&found.status) && d.arm().is_ok() {
                d.disarm()?;
            }
            if found.status.mode == Mode::Unhomed {
                notes.push("found unhomed, left homed (the benchmark homes the device)".into());
            }
            if found.status.mode == Mode::Faulted {
                notes.push(format!(
                    "found faulted ({}), left disarmed with the fault cleared",
                    crate::flags::describe(found.status.latched)
                ));
            }
        }
    }
    let after = d.status()?;
    Ok(RestoreReport {
        mode_found: found.status.mode.name().into(),
        mode_left: after.mode.name().into(),
        params_restored: d.contact_params()? == found.params,
        model_restored: same_model(&after.model, &found.status.model),
        watchdog_restored: d.info()?.watchdog_ms == found.watchdog_ms,
        notes,
    })
}

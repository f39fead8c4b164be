//! Refusals explained: which mode the device is in and what it needs before the command can
//! run, from the device's own status.

use softfinger_host::flags;
use softfinger_host::protocol::{DeviceStatus, ErrorCode, Mode};
use softfinger_host::{Device, LinkError};

/// Why the device refused `action` (`"arm"`, `"home"`, ...) and what it needs, for a device in
/// the state `st`.
pub fn explain(action: &str, code: ErrorCode, st: &DeviceStatus) -> String {
    let latched = if st.latched == 0 {
        String::new()
    } else {
        format!(" (latched: {})", flags::describe(st.latched))
    };
    let need = match (action, st.mode) {
        (_, Mode::Faulted) => format!(
            "a fault is latched{latched}: clear it first (`softfinger clear`; the device is then disarmed, and unhomed if the fault made the encoder zero doubtful)"
        ),
        (_, Mode::Homing) => {
            "homing is in progress (it takes a few seconds): wait for it (`softfinger home` waits; `softfinger status` shows the mode)".to_string()
        }
        ("arm", Mode::Unhomed) => "it needs homing first: `softfinger home`".to_string(),
        ("home", Mode::Armed) => "disarm first: `softfinger disarm`".to_string(),
        // A disarmed device refuses Arm for one reason only: the fingertip is inside the
        // surface of the model in force (the force would push it out over the arming ramp).
        ("arm", Mode::Disarmed) if code == ErrorCode::WrongMode => {
            "the fingertip is inside the surface, and the device arms only clear of it (the force would push the handle out): move the handle clear of the surface, or the surface away (`softfinger scene`), then arm".to_string()
        }
        _ => format!("{code:?}"),
    };
    format!("{action} refused: the device is {}; {need}", st.mode.name())
}

/// `e` as a message for `action`: a refusal for the mode explained from the device's status
/// (asked on `dev`), anything else as it is.
pub fn message(action: &str, e: LinkError, dev: &mut Device) -> String {
    match e {
        LinkError::Refused(code @ (ErrorCode::WrongMode | ErrorCode::Faulted)) => {
            match dev.status() {
                Ok(st) => explain(action, code, &st),
                Err(_) => format!("{action} refused: {code:?}"),
            }
        }
        e => format!("{action}: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use softfinger_host::protocol::{LocalModel, SurfaceShape};

    fn status(mode: Mode, latched: u32) -> DeviceStatus {
        DeviceStatus {
            tick: 0,
            mode,
            flags: latched,
            latched,
            model: LocalModel {
                seq: 0,
                shape: SurfaceShape::Plane,
                position_m: [0.0; 3],
                orientation: [1.0, 0.0, 0.0, 0.0],
                stiffness_n_per_m: 2000.0,
                damping_n_s_per_m: 2.0,
                mu_s: 0.8,
                mu_k: 0.6,
                spin_stiffness_nm_per_rad: 0.01,
                max_age_ms: 0,
            },
        }
    }

    #[test]
    fn each_refusal_names_the_mode_and_the_need() {
        let m = explain("arm", ErrorCode::WrongMode, &status(Mode::Homing, 0));
        assert!(m.contains("is homing") && m.contains("wait"), "{m}");
        let m = explain("arm", ErrorCode::WrongMode, &status(Mode::Unhomed, 0));
        assert!(
            m.contains("is unhomed") && m.contains("softfinger home"),
            "{m}"
        );
        let m = explain("arm", ErrorCode::WrongMode, &status(Mode::Disarmed, 0));
        assert!(
            m.contains("is disarmed") && m.contains("inside the surface"),
            "{m}"
        );
        let m = explain("home", ErrorCode::WrongMode, &status(Mode::Armed, 0));
        assert!(m.contains("is armed") && m.contains("disarm"), "{m}");
        let f = softfinger_core::Flags::DRIVER_FAULT.0;
        let m = explain("arm", ErrorCode::Faulted, &status(Mode::Faulted, f));
        assert!(
            m.contains("driver-fault") && m.contains("softfinger clear"),
            "{m}"
        );
    }
}

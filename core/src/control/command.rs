//! The operator commands the pipeline applies at a tick boundary ([`Command`]) and why it refuses
//! one ([`CommandError`]). Below the contact stages, which answer the local-model and watchdog
//! commands, and the pipeline, whose mode machine ([`crate::control::pipeline::Mode`]) they move.

use crate::contact::params::ContactParams;
use crate::control::local_model::{LocalModelSpec, ModelError};
use crate::validate::ParamError;

/// An operator command, applied at a tick boundary by [`crate::control::pipeline::Pipeline::command`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Command {
    /// Start homing. The handle must be held in the wrist calibration pose when this is given:
    /// the wrist zero is taken from the wrist encoders at this instant. From `Unhomed` or
    /// `Disarmed` (re-homing).
    Home,
    /// Render forces (ramping in). From `Disarmed` only, and only with the probe outside the
    /// surface (the force then ramps from the surface, never from inside it).
    Arm,
    /// Stop rendering: `Armed` → `Disarmed`; aborts homing (`Homing` → `Unhomed`).
    Disarm,
    /// Clear latched faults: `Faulted` → `Disarmed` (homed) or `Unhomed`. A fault whose cause is
    /// still present latches again on the next tick.
    ClearFaults,
    /// New contact parameters (validated; invalid ones are rejected and the old ones stay).
    SetContactParams(ContactParams),
    /// A new local model, switched to at a tick boundary without a force step (local-model
    /// environment only; see [`crate::control::local_model::renderer`]). Any mode: it changes no mode.
    SetLocalModel(LocalModelSpec),
    /// The communication watchdog's timeout, s, in [0, 60]; 0 turns it off (local-model environment
    /// only). Setting it counts as link activity.
    SetWatchdog {
        /// Timeout, s.
        timeout_s: f32,
    },
}

/// Logged by name (a local model by its sequence number): the firmware's flash holds no
/// formatter of a whole model.
#[cfg(feature = "defmt")]
impl defmt::Format for Command {
    fn format(&self, f: defmt::Formatter) {
        match self {
            Command::Home => defmt::write!(f, "Home"),
            Command::Arm => defmt::write!(f, "Arm"),
            Command::Disarm => defmt::write!(f, "Disarm"),
            Command::ClearFaults => defmt::write!(f, "ClearFaults"),
            Command::SetContactParams(p) => defmt::write!(f, "SetContactParams({})", p),
            Command::SetLocalModel(m) => defmt::write!(f, "SetLocalModel(seq {})", m.seq),
            Command::SetWatchdog { timeout_s } => {
                defmt::write!(f, "SetWatchdog({} s)", timeout_s)
            }
        }
    }
}

/// Why a command was refused. A refused command changes nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CommandError {
    /// `Arm` before homing completed.
    NotHomed,
    /// A fault is latched: clear it first.
    Faulted,
    /// `Home` while armed: disarm first.
    Armed,
    /// `Arm` or `Home` while homing is in progress.
    Homing,
    /// Contact parameters rejected.
    InvalidParams(ParamError),
    /// A local model rejected (old sequence number, bad pose, size, age or material).
    InvalidModel(ModelError),
    /// The environment cannot do this (a local model or watchdog command on a fixed surface).
    Unsupported,
    /// `Arm` while the probe is inside the surface (in contact on the last disarmed tick):
    /// arming would push it out with the contact's force. Lift the handle off first.
    InsideSurface,
    /// A host armed the device: its communication watchdog cannot be turned off until it
    /// disarms.
    WatchdogRequired,
}

impl core::fmt::Display for CommandError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CommandError::NotHomed => f.write_str("not homed: home before arming"),
            CommandError::Faulted => f.write_str("a fault is latched: clear it first"),
            CommandError::Armed => f.write_str("armed: disarm before homing"),
            CommandError::Homing => f.write_str("homing is in progress"),
            CommandError::InvalidParams(e) => write!(f, "contact parameters rejected: {e}"),
            CommandError::InvalidModel(e) => write!(f, "local model rejected: {e}"),
            CommandError::Unsupported => f.write_str("the scene does not support this command"),
            CommandError::InsideSurface => {
                f.write_str("the probe is inside the surface: lift it off before arming")
            }
            CommandError::WatchdogRequired => f.write_str(
                "a host armed the device: the communication watchdog stays on until it disarms",
            ),
        }
    }
}

impl core::error::Error for CommandError {}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    /// The message says why, and carries the rejected parameter's name.
    #[test]
    fn display_says_why() {
        let e: &dyn core::error::Error = &CommandError::NotHomed;
        assert_eq!(e.to_string(), "not homed: home before arming");
        assert_eq!(
            CommandError::InvalidParams(ParamError::NotFinite("mu_k")).to_string(),
            "contact parameters rejected: mu_k is not finite"
        );
        assert_eq!(
            CommandError::InvalidModel(ModelError::BadSize).to_string(),
            "local model rejected: size is out of range for the model kind"
        );
    }
}

//! The operator commands the pipeline applies at a tick boundary ([`Command`]) and why it refuses
//! one ([`CommandError`]). Below the contact stages, which answer the local-model and watchdog
//! commands, and the pipeline, whose mode machine ([`crate::control::pipeline::Mode`]) they move.

use crate::contact::params::ContactParams;
use crate::control::local_model::{LocalModelSpec, ModelError};
use crate::validate::{Checked, ParamError};

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

/// A [`Command`] whose arguments passed every check that needs nothing but the command
/// ([`Command::check`], the only maker of the checked variants): contact parameters validated, a
/// local model's pose, size, age and material checked. What is left for the tick that applies it
/// ([`crate::control::pipeline::Pipeline::apply`]) depends on the pipeline's state: the mode, a
/// model's sequence number and fit. The firmware checks a host's command in thread mode, where it
/// arrives, so the control interrupt only applies it, by reference (a command is 92 bytes: each
/// copy of it costs the tick about 90 instructions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CheckedCommand {
    /// [`Command::Home`].
    Home,
    /// [`Command::Arm`].
    Arm,
    /// [`Command::Disarm`].
    Disarm,
    /// [`Command::ClearFaults`].
    ClearFaults,
    /// [`Command::SetContactParams`], validated.
    SetContactParams(Checked<ContactParams>),
    /// [`Command::SetLocalModel`], checked.
    SetLocalModel(Checked<LocalModelSpec>),
    /// [`Command::SetWatchdog`] (its range is the stage's check: a few instructions).
    SetWatchdog {
        /// Timeout, s.
        timeout_s: f32,
    },
}

impl CheckedCommand {
    /// The command, unchecked again (for a log or an acknowledgement).
    pub fn command(&self) -> Command {
        match self {
            CheckedCommand::Home => Command::Home,
            CheckedCommand::Arm => Command::Arm,
            CheckedCommand::Disarm => Command::Disarm,
            CheckedCommand::ClearFaults => Command::ClearFaults,
            CheckedCommand::SetContactParams(p) => Command::SetContactParams(**p),
            CheckedCommand::SetLocalModel(m) => Command::SetLocalModel(**m),
            CheckedCommand::SetWatchdog { timeout_s } => Command::SetWatchdog {
                timeout_s: *timeout_s,
            },
        }
    }
}

impl Command {
    /// Check the arguments (see [`CheckedCommand`]); a refusal names what and why.
    pub fn check(self) -> Result<CheckedCommand, CommandError> {
        Ok(match self {
            Command::Home => CheckedCommand::Home,
            Command::Arm => CheckedCommand::Arm,
            Command::Disarm => CheckedCommand::Disarm,
            Command::ClearFaults => CheckedCommand::ClearFaults,
            Command::SetContactParams(p) => {
                CheckedCommand::SetContactParams(p.checked().map_err(CommandError::InvalidParams)?)
            }
            Command::SetLocalModel(m) => {
                CheckedCommand::SetLocalModel(m.checked().map_err(CommandError::InvalidModel)?)
            }
            Command::SetWatchdog { timeout_s } => CheckedCommand::SetWatchdog { timeout_s },
        })
    }
}

/// A command by its kind (a local model with its sequence number): 8 bytes where a command
/// is 92, so a tick reports what it applied without copying the command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CommandKey {
    /// [`Command::Home`].
    Home,
    /// [`Command::Arm`].
    Arm,
    /// [`Command::Disarm`].
    Disarm,
    /// [`Command::ClearFaults`].
    ClearFaults,
    /// [`Command::SetContactParams`].
    SetContactParams,
    /// [`Command::SetLocalModel`] of this sequence number.
    SetLocalModel(u32),
    /// [`Command::SetWatchdog`].
    SetWatchdog,
}

impl Command {
    /// The command's [`CommandKey`].
    pub fn key(&self) -> CommandKey {
        match self {
            Command::Home => CommandKey::Home,
            Command::Arm => CommandKey::Arm,
            Command::Disarm => CommandKey::Disarm,
            Command::ClearFaults => CommandKey::ClearFaults,
            Command::SetContactParams(_) => CommandKey::SetContactParams,
            Command::SetLocalModel(m) => CommandKey::SetLocalModel(m.seq),
            Command::SetWatchdog { .. } => CommandKey::SetWatchdog,
        }
    }
}

impl CheckedCommand {
    /// The command's [`CommandKey`].
    pub fn key(&self) -> CommandKey {
        match self {
            CheckedCommand::Home => CommandKey::Home,
            CheckedCommand::Arm => CommandKey::Arm,
            CheckedCommand::Disarm => CommandKey::Disarm,
            CheckedCommand::ClearFaults => CommandKey::ClearFaults,
            CheckedCommand::SetContactParams(_) => CommandKey::SetContactParams,
            CheckedCommand::SetLocalModel(m) => CommandKey::SetLocalModel(m.seq),
            CheckedCommand::SetWatchdog { .. } => CommandKey::SetWatchdog,
        }
    }
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

    /// The checks a command gets where it arrives: bad contact parameters and a bad model are
    /// refused naming why; a good one keeps its arguments and its key.
    #[test]
    fn check_refuses_bad_arguments_and_keeps_good_ones() {
        use crate::control::local_model::ModelPose;
        let bad = ContactParams {
            mu_s: f32::NAN,
            ..ContactParams::DEFAULT
        };
        assert_eq!(
            Command::SetContactParams(bad).check(),
            Err(CommandError::InvalidParams(ParamError::NotFinite("mu_s")))
        );
        let model = LocalModelSpec::plane(7, ModelPose::IDENTITY, &ContactParams::DEFAULT);
        let far = LocalModelSpec {
            max_age_s: -1.0,
            ..model
        };
        assert_eq!(
            Command::SetLocalModel(far).check(),
            Err(CommandError::InvalidModel(ModelError::BadAge))
        );
        for c in [
            Command::Home,
            Command::Arm,
            Command::Disarm,
            Command::ClearFaults,
            Command::SetContactParams(ContactParams::DEFAULT),
            Command::SetLocalModel(model),
            Command::SetWatchdog { timeout_s: 0.5 },
        ] {
            let checked = c.check().unwrap();
            assert_eq!(checked.command(), c);
            assert_eq!(checked.key(), c.key());
        }
        assert_eq!(
            Command::SetLocalModel(model).key(),
            CommandKey::SetLocalModel(7)
        );
    }

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

//! The wire types and the core's, converted in one place for every device (the firmware's link,
//! host-sim's virtual device) and for the host library.
//!
//! Where the core's type is what the wire carries (the mode, the contact state, the surface
//! shape), the wire uses it as it is (see [`crate::state`] and [`crate::model`]). Where the wire
//! has its own form, the conversion is here: a [`LocalModel`] carries arrays and milliseconds, a
//! request is a pipeline command, a refused command is an [`ErrorCode`]. The contact parameters'
//! subset converts where it is defined ([`crate::ContactParamsWire::of`],
//! [`crate::ContactParamsWire::over`]).

use crate::messages::{AckResult, ErrorCode, Request};
use crate::model::LocalModel;
use softfinger_core::contact::params::ContactParams;
use softfinger_core::control::local_model::{LocalModelSpec, ModelError, ModelPose};
use softfinger_core::control::pipeline::{Command, CommandError};
use softfinger_core::{Quat, Vec3};

impl LocalModel {
    /// The core's spec of this model, field for field; the renderer validates it when the tick
    /// applies it (a bad pose, size, age or material is refused there, with its error code). The
    /// pose is in the base frame; the quaternion is `[w, x, y, z]`; the maximum age goes from ms
    /// to s.
    pub fn spec(&self) -> LocalModelSpec {
        let [w, x, y, z] = self.orientation;
        LocalModelSpec {
            seq: self.seq,
            kind: self.shape,
            pose: ModelPose {
                position_m: Vec3::from_array(self.position_m),
                orientation: Quat::new(w, x, y, z),
            },
            stiffness_n_per_m: self.stiffness_n_per_m,
            damping_n_s_per_m: self.damping_n_s_per_m,
            mu_s: self.mu_s,
            mu_k: self.mu_k,
            spin_stiffness_nm_per_rad: self.spin_stiffness_nm_per_rad,
            max_age_s: seconds(self.max_age_ms),
        }
    }
}

/// A wire duration (ms) in seconds.
fn seconds(ms: u16) -> f32 {
    f32::from(ms) * 1e-3
}

impl Request {
    /// The pipeline command this request asks for, or `None` for a request the link answers
    /// itself. `base`: the contact parameters in force, which keep the fields the wire does not
    /// carry. Values are not checked here: the pipeline refuses invalid ones
    /// (`Pipeline::command`). The watchdog timeout goes from ms (0: off) to s.
    pub fn command(&self, base: &ContactParams) -> Option<Command> {
        Some(match self {
            Request::Home => Command::Home,
            Request::Arm => Command::Arm,
            Request::Disarm => Command::Disarm,
            Request::ClearFaults => Command::ClearFaults,
            Request::SetContactParams(w) => Command::SetContactParams(w.over(base)),
            Request::SetLocalModel(m) => Command::SetLocalModel(m.spec()),
            Request::SetWatchdog { timeout_ms } => Command::SetWatchdog {
                timeout_s: seconds(*timeout_ms),
            },
            Request::GetInfo
            | Request::GetCounters
            | Request::GetContactParams
            | Request::Ping
            | Request::SetStream { .. }
            | Request::DriveHand(_)
            | Request::ReleaseHand => return None,
        })
    }
}

impl From<CommandError> for ErrorCode {
    /// The code of a command the pipeline refused.
    fn from(e: CommandError) -> ErrorCode {
        match e {
            CommandError::NotHomed
            | CommandError::Armed
            | CommandError::Homing
            | CommandError::InsideSurface => ErrorCode::WrongMode,
            CommandError::Faulted => ErrorCode::Faulted,
            CommandError::InvalidParams(_) => ErrorCode::InvalidValue,
            CommandError::InvalidModel(ModelError::StaleSequence) => ErrorCode::StaleSequence,
            CommandError::InvalidModel(_) => ErrorCode::InvalidValue,
            CommandError::Unsupported => ErrorCode::Unsupported,
            CommandError::WatchdogRequired => ErrorCode::InvalidValue,
        }
    }
}

impl From<Result<(), CommandError>> for AckResult {
    /// The acknowledgement of a pipeline outcome.
    fn from(result: Result<(), CommandError>) -> AckResult {
        match result {
            Ok(()) => AckResult::Ok,
            Err(e) => AckResult::Err(e.into()),
        }
    }
}

#[cfg(test)]
mod tests;

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
use crate::status::FieldRange;
use softfinger_core::contact::params::{ContactParams, ParamError};
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

impl LocalModel {
    /// The wire form of `spec` (the inverse of [`LocalModel::spec`]; the maximum age rounds to
    /// whole ms and saturates at `u16::MAX`).
    pub fn of(spec: &LocalModelSpec) -> LocalModel {
        let q = spec.pose.orientation;
        let ms = spec.max_age_s * 1e3;
        LocalModel {
            seq: spec.seq,
            shape: spec.kind,
            position_m: spec.pose.position_m.to_array(),
            orientation: [q.w, q.x, q.y, q.z],
            stiffness_n_per_m: spec.stiffness_n_per_m,
            damping_n_s_per_m: spec.damping_n_s_per_m,
            mu_s: spec.mu_s,
            mu_k: spec.mu_k,
            spin_stiffness_nm_per_rad: spec.spin_stiffness_nm_per_rad,
            max_age_ms: if ms.is_finite() && ms > 0.0 {
                (ms + 0.5).min(u16::MAX as f32) as u16
            } else {
                0
            },
        }
    }
}

impl FieldRange {
    /// `field` with its range.
    pub fn new(field: &str, min: f32, min_exclusive: bool, max: f32) -> FieldRange {
        let mut name = crate::info::Text::new();
        for c in field.chars() {
            if name.push(c).is_err() {
                break;
            }
        }
        FieldRange {
            field: name,
            min,
            min_exclusive,
            max,
        }
    }

    /// True when `v` is in the range.
    pub fn contains(&self, v: f32) -> bool {
        let above = if self.min_exclusive {
            v > self.min
        } else {
            v >= self.min
        };
        above && v <= self.max
    }

    /// The range [`ContactParams::validate`] accepts for the field it refused with `e`, given
    /// the parameters `p` it refused (μ_k's upper end is `p.mu_s`), or `None` for an error that
    /// names no field of the contact parameters. `max_force_n`'s upper end is `device_max_force_n`
    /// when that is below the core's own limit.
    pub fn of_param_error(
        e: &ParamError,
        p: &ContactParams,
        device_max_force_n: f32,
    ) -> Option<FieldRange> {
        let name = match e {
            ParamError::NotFinite(n)
            | ParamError::NotPositive(n)
            | ParamError::Negative(n)
            | ParamError::OutOfRange(n) => *n,
            ParamError::KineticAboveStatic => "mu_k",
            ParamError::Device(_) => return None,
        };
        let m = &ContactParams::MAX;
        let (min, excl, max) = match name {
            "fingertip_radius_m" => (
                ContactParams::MIN_FINGERTIP_RADIUS_M,
                false,
                m.fingertip_radius_m,
            ),
            "normal_stiffness" => (0.0, false, m.normal_stiffness),
            "normal_damping" => (0.0, false, m.normal_damping),
            "tangential_stiffness" => (0.0, false, m.tangential_stiffness),
            "tangential_damping" => (0.0, false, m.tangential_damping),
            "mu_s" => (0.0, true, m.mu_s),
            "mu_k" => (0.0, true, p.mu_s.min(m.mu_k)),
            "spin_stiffness" => (0.0, false, m.spin_stiffness),
            "patch_radius_m" => (0.0, false, m.patch_radius_m),
            "patch_ref_force_n" => (0.0, true, m.patch_ref_force_n),
            "patch_exponent" => (0.0, false, m.patch_exponent),
            "k_tau" => (0.0, true, m.k_tau),
            "max_force_n" => (
                ContactParams::MIN_MAX_FORCE_N,
                false,
                m.max_force_n.min(device_max_force_n),
            ),
            _ => return None,
        };
        Some(FieldRange::new(name, min, excl, max))
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
            | Request::ReleaseHand
            | Request::GetStatus
            | Request::ConfigGet(_)
            | Request::ConfigSet(_)
            | Request::ConfigSave
            | Request::ConfigReset
            | Request::UpdateBegin { .. }
            | Request::UpdateChunk(_)
            | Request::UpdateFinish
            | Request::UpdateStatus
            | Request::Reboot => return None,
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

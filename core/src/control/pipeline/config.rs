//! What a [`super::Pipeline`] is built from: a named device, the board timing, and the environment.

use crate::contact::params::ContactParams;
use crate::contact::surface::Plane;
use crate::control::controller::{ControllerConfig, Environment};
use crate::control::device_definition::DeviceDefinition;
use crate::math::vec3::Vec3;
use crate::validate::ParamError;

use super::board::{BoardTiming, TimingError};

/// Everything the pipeline needs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PipelineConfig<S: Environment = Plane> {
    /// The device (named explicitly, e.g. [`crate::omega_like::OMEGA_LIKE`]).
    pub device: DeviceDefinition,
    /// Timer clock, PWM and control rates (the control rate is the controller's).
    pub timing: BoardTiming,
    /// The contact model.
    pub contact: ContactParams,
    /// The environment: a fixed surface, or the local model
    /// ([`LocalModelEnvironment`](crate::control::local_model::LocalModelEnvironment)).
    pub surface: S,
    /// Origin of the object frame in the device base frame, m.
    pub object_origin_m: Vec3,
    /// Telemetry records per second (0: none).
    pub log_rate_hz: u32,
}

/// Why a pipeline could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PipelineError {
    /// The board timing is invalid.
    Timing(TimingError),
    /// A device, limit, homing or contact parameter is invalid.
    Params(ParamError),
}

impl core::fmt::Display for PipelineError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PipelineError::Timing(e) => write!(f, "board timing: {e}"),
            PipelineError::Params(e) => write!(f, "parameters: {e}"),
        }
    }
}

impl core::error::Error for PipelineError {}

impl<S: Environment> PipelineConfig<S> {
    /// The controller configuration this pipeline runs.
    pub fn controller_config(&self) -> ControllerConfig<S> {
        ControllerConfig {
            rate_hz: self.timing.control_hz as f32,
            device: self.device.params,
            contact: self.contact,
            surface: self.surface,
            object_origin_m: self.object_origin_m,
            limits: self.device.limits,
        }
    }

    /// Check every part.
    pub fn validate(&self) -> Result<(), PipelineError> {
        self.timing.validate().map_err(PipelineError::Timing)?;
        self.device.validate().map_err(PipelineError::Params)?;
        self.controller_config()
            .validate()
            .map_err(PipelineError::Params)?;
        Ok(())
    }
}

impl PipelineConfig<Plane> {
    /// `device` on `timing` with the plane environment at height `plane_z_m` (base frame) and the
    /// default contact parameters, logging at the default telemetry rate.
    pub fn plane(device: DeviceDefinition, timing: BoardTiming, plane_z_m: f32) -> Self {
        PipelineConfig {
            device,
            timing,
            contact: ContactParams::DEFAULT,
            surface: Plane::default(),
            object_origin_m: Vec3::new(0.0, 0.0, plane_z_m),
            log_rate_hz: crate::control::telemetry::DEFAULT_LOG_RATE_HZ,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    /// The message says which part failed, then the part's own message.
    #[test]
    fn display_names_the_part() {
        let e: &dyn core::error::Error = &PipelineError::Params(ParamError::Negative("max_age_s"));
        assert_eq!(e.to_string(), "parameters: max_age_s must be >= 0");
        assert_eq!(
            PipelineError::Timing(TimingError::ZeroRate).to_string(),
            "board timing: timer_clock_hz, pwm_hz and control_hz must be > 0"
        );
    }
}

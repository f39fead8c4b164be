//! The haptic device's hardware: its description, kinematics and encoders. Depends on `math` and
//! `flags` alone. The device definition sits in the control layer and the named device above it
//! ([`crate::control::device_definition`], [`crate::omega_like`]).
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`hardware`] | motors, capstans, H-bridge supply, PWM timer, encoders, wrist gimbal |
//! | [`delta`] | the delta linkage's forward kinematics and Jacobian |
//! | [`channels`] | the six encoder channels by name ([`channels::EncoderCounts`]) |
//! | [`encoder`] | count extension of the 16-bit timer counters |

pub mod channels;
pub mod delta;
pub mod encoder;
pub mod hardware;

pub use hardware::{DeviceParamError, DeviceParamField, DeviceParams, MotorParams};

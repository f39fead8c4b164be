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
// The old paths of the device definition and the named device, kept for the firmware until it
// names the new ones: the one upward arrow of the crate (see the layer table in `lib.rs`).
#[doc(no_inline)]
pub use crate::control::device_definition::DeviceDefinition;
#[doc(no_inline)]
pub use crate::omega_like::OMEGA_LIKE;

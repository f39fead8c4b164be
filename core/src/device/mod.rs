//! The haptic device: its hardware description, kinematics, encoders and the named device instances.
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`hardware`] | motors, capstans, H-bridge supply, PWM timer, encoders, wrist gimbal |
//! | [`delta`] | the delta linkage's forward kinematics and Jacobian |
//! | [`encoder`] | count extension of the 16-bit timer counters |
//! | [`definition`] | [`DeviceDefinition`]: everything a build needs to know about one device |
//! | [`omega_like`] | the Omega.6-like device, the one instance this project ships |

pub mod definition;
pub mod delta;
pub mod encoder;
pub mod hardware;
pub mod omega_like;

pub use definition::DeviceDefinition;
pub use hardware::{DeviceParamError, DeviceParamField, DeviceParams, MotorParams};
pub use omega_like::OMEGA_LIKE;

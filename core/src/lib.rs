//! # softfinger-core
//!
//! The soft-finger contact model with rolling of Salvietti, Malvezzi and Prattichizzo, in `no_std`
//! f32, plus the hardware-independent haptic controller tick that the firmware runs.
//!
//! Frames used throughout:
//! - **plane frame** `P` (contact frame of the scene): z is the contact normal pointing out of the
//!   object towards the fingertip; x, y span the tangent plane.
//! - **fingertip frame** `S`: fixed in the fingertip sphere, origin at its centre.
//! - An orientation `q` / `R` of the fingertip maps `S` vectors to `P`: `v_P = R · v_S`.
//!
//! Units are SI (m, rad, N, N·m, s) unless a name says otherwise.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_debug_implementations)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod contact;
pub mod contact_state;
pub mod controller;
pub mod decompose;
pub mod delta;
pub mod device;
pub mod devices;
pub mod encoder;
pub mod fixed;
pub mod flags;
pub mod limit_surface;
pub mod local_model;
pub mod math;
pub mod output_guard;
pub mod params;
pub mod pipeline;
pub mod quat;
pub mod rolling;
pub mod rot3;
pub mod spin;
pub mod surface;
pub mod telemetry;
pub mod vec3;

pub use flags::Flags;
pub use math::{Fast, Libm, Math, Micromath};
pub use quat::Quat;
pub use rot3::Rot3;
pub use vec3::Vec3;

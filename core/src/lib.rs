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
pub mod control;
pub mod device;
pub mod flags;
pub mod grasp;
pub mod math;
pub mod omega_like;
pub mod prelude;
pub mod validate;

pub use flags::Flags;
pub use math::{Fast, Libm, Math, Micromath, Quat, Rot3, Vec3};

//! # softfinger-core
//!
//! The soft-finger contact model with rolling of Salvietti, Malvezzi and Prattichizzo, in `no_std`
//! f32, plus the hardware-independent haptic controller tick that the firmware runs.
//!
//! # Layers
//!
//! Each module imports only from its own layer and from the rows above it in this table; no file
//! imports a file that imports it back (inside a layer too). `scripts/core-imports` checks both
//! from the code's imports (it holds this table as its `LAYERS` list).
//!
//! | # | modules | what | why here |
//! | --- | --- | --- | --- |
//! | 1 | [`flags`], [`math`] | status bits; vectors, rotations, the math backends | need nothing: everything else computes with them |
//! | 2 | [`device`] | the hardware: motors, encoders, delta kinematics ([`device::hardware`], [`device::delta`], [`device::encoder`], [`device::channels`]) | pure description and geometry, only math; the contact model does not need it and the control layer drives it |
//! | 3 | [`validate`] | [`validate::ParamError`] and the range checks every parameter set is made of | one error type for every layer's parameters; it wraps the hardware's own error ([`device::DeviceParamError`]), so it sits just above the device |
//! | 4 | [`contact`] | the contact model: surfaces, decomposition, rolling, spin, limit surface, state machine, the step | the paper's model; frames and math only, validated by layer 3 |
//! | 5 | [`control`] | commands, the controller (with its passivity stage), the output guard, local models, the device definition, the pipeline, telemetry, the operator's button | joins the contact model to the device: needs both |
//! | 6 | [`omega_like`], [`grasp`] | the one named device; two fingertips on a free body | instances and applications of everything below: an instance names values of every layer |
//! | 7 | [`prelude`] | the common imports | re-exports only |
//!
//! No arrow points up (`scripts/core-imports` checks every file's imports against this table).
//!
//! # Frames
//!
//! Every doc comment names its frame by this table's word (and letter, where a formula needs one).
//!
//! | frame | letter | origin and axes | where it is defined |
//! | --- | --- | --- | --- |
//! | base | `B` | the delta's base: origin at the centre of the motor axes' circle, z the mechanism's axis pointing from the effector to the base, x towards motor 0 | [`device::delta`] |
//! | object | `O` | fixed to the object the fingertip touches: for a fixed surface the base frame translated by the configuration's `object_origin_m` (no rotation); for a local model placed in the base frame by its pose, `p_B = o + R·p_O` ([`control::local_model::ModelPose`]). For the plane, z is its normal (towards the fingertip) and z = 0 its surface | [`contact::surface`] |
//! | contact | `C` | origin at the contact point on the object, z along the normal pointing out of the object towards the fingertip, x and y tangent. For the plane: the object frame translated to the contact point | [`contact::surface::Surface`] |
//! | handle | `H` | the wrist gimbal's last link, which holds the fingertip; the wrist angles map handle-frame vectors to the base frame | [`device::hardware`] |
//! | fingertip | `F` | fixed in the fingertip sphere, origin at its centre | [`contact::rolling`] |
//! | world | `W` | the room, in which a grasped body and the devices' mounts are placed (two-finger grasps only; a grasped body's own frame is its object frame) | [`grasp`] |
//!
//! An orientation `q` / `R` of the fingertip maps fingertip-frame vectors to the object frame:
//! `v_O = R · v_F`. A device mount maps base-frame points to the world: `p_W = o + R·p_B`.
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

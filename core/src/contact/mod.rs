//! The contact model of Salvietti, Malvezzi and Prattichizzo: what happens at the fingertip.
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`surface`] | the object surfaces (plane, sphere, bowl, cylinder): distance, normal, frames |
//! | [`decompose`] | the relative rotation split into spin about the normal and tilts |
//! | [`rolling`] | the contact point moved on both surfaces by rolling |
//! | [`spin`] | the torsional spring and its friction limit |
//! | [`limit_surface`] | the shared friction budget of twist and slide |
//! | [`state`] | the rolling / sliding / broken state machine |
//! | [`params`] | the validated contact parameters |
//! | [`parts`] | the model's parts as compile-time choices (point contact, + rolling or + spin, both, + limit surface) |
//! | [`step`] | [`ContactModel`]: one contact step, made of the stages above |

pub mod decompose;
pub mod limit_surface;
pub mod params;
pub mod parts;
pub mod rolling;
pub mod spin;
pub mod state;
pub mod step;
pub mod surface;

pub use params::{ContactParams, ParamError};
pub use parts::{Full, ModelChoice, Parts, PointFriction, RollingOnly, WithRolling, WithSpin};
pub use state::ContactState;
pub use step::{
    ContactInput, ContactModel, ContactOutput, MAX_DT_S, MAX_PROBE_M, MAX_PROBE_SPEED_M_S, MIN_DT_S,
};
pub use surface::Surface;

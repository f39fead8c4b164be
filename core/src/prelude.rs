//! The names almost every user of the crate needs, in one import:
//! `use softfinger_core::prelude::*;`.
//!
//! It holds the value types and the entry points (the contact model, the controller, the
//! pipeline, the device instance); modules stay the place for everything else.

pub use crate::contact::surface::{Bowl, Cylinder, Plane, Sphere, Surface};
pub use crate::contact::{ContactInput, ContactModel, ContactOutput, ContactParams, ContactState};
pub use crate::control::controller::{Controller, ControllerConfig, Limits};
pub use crate::control::device_definition::DeviceDefinition;
pub use crate::control::pipeline::{Pipeline, PipelineConfig};
pub use crate::device::DeviceParams;
pub use crate::flags::Flags;
pub use crate::math::{Fast, Libm, Math, Micromath, Quat, Rot3, Vec3};
pub use crate::omega_like::OMEGA_LIKE;

//! Two soft fingertips holding a free rigid body.
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`body`] | the rigid body (mass, inertia, pose, velocity) and its semi-implicit Euler step |
//! | [`fingertip_contact`] | one fingertip's soft-finger contact with the body, as equal and opposite wrenches |
//! | [`two_fingers`] | [`Grasp`]: the body and two contacts, one control tick |
//! | [`remote`] | the body on the host, each device rendering its surface as a local model |
//!
//! Each contact is the one-fingertip contact model ([`crate::contact::ContactModel`]) run in the
//! body's frame, so a grasp has what a single contact has: the normal spring and damper, the
//! friction proxy, the limit surface coupling twist and slide, rolling on both surfaces and the
//! rolling / sliding / broken state machine. Two point contacts cannot resist a moment about the
//! line through them; two soft fingers can, up to the sum of their torsional limits.

pub mod body;
pub mod fingertip_contact;
pub mod remote;
#[cfg(test)]
mod tests;
pub mod two_fingers;

pub use body::{BodyError, BodyParams, BodyState, RigidBody};
pub use fingertip_contact::{ContactReport, Fingertip, FingertipContact, Wrench};
pub use remote::{DeviceContact, DeviceMount};
pub use two_fingers::{Grasp, GraspError, GraspFlags, GraspStep};

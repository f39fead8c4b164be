//! Local model updates and the communication watchdog: what the device renders when an
//! application, not the firmware, decides what the finger touches (multirate haptics: the
//! application updates the model at 100 Hz–1 kHz, the device renders it at the control rate).
//!
//! - [`spec`]: the model an application sends (surface kind and size, pose in the device base
//!   frame, material, sequence number, maximum age) and its validation;
//! - [`surface`]: [`ModelSurface`], a surface whose kind is chosen at run time;
//! - [`pose`]: the object frame's pose and the probe sample expressed in it;
//! - [`ramp`]: a gain that moves linearly towards its target (every fade and blend here);
//! - [`renderer`]: [`LocalModelRenderer`], which switches models at a tick boundary without a
//!   force step (pose changes are slewed, other changes cross-faded), keeps the contact state
//!   consistent across the switch, and fades the force of a stale model;
//! - [`watchdog`]: [`CommWatchdog`], no message for T fades the force to zero and latches
//!   [`Flags::COMM_TIMEOUT`](crate::Flags::COMM_TIMEOUT) until re-armed;
//! - [`stage`]: [`LocalModelEnvironment`] / [`LocalModelStage`], the renderer and the watchdog as the
//!   control pipeline's contact stage.
//!
//! Frames: the device **base frame** of [`crate::device::delta`]; each model has its own object frame
//! (the plane z = 0, or a sphere centred at the origin), placed in the base frame by its pose.

pub mod pose;
pub mod ramp;
pub mod renderer;
pub mod spec;
pub mod stage;
pub mod surface;
pub mod watchdog;

pub use pose::{ModelPose, ProbeSample};
pub use ramp::Ramp;
pub use renderer::{LocalModelRenderer, RenderOutput, RendererConfig};
pub use spec::{LocalModelSpec, ModelError, ModelKind};
pub use stage::{LocalModelEnvironment, LocalModelStage};

pub use surface::ModelSurface;
pub use watchdog::CommWatchdog;

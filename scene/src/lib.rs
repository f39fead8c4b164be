//! # softfinger-scene
//!
//! Scene files, the TOML under `host-sim/scenes/` (built in by name as well), shared by host-sim
//! and the `softfinger` command line without the simulator:
//!
//! - [`file`]: the file format, its loader and its range checks;
//! - [`model`]: a scene as the core's contact parameters and local-model spec (the surface placed
//!   where the simulator's plant puts it);
//! - [`wire`]: the same as the protocol's messages, for sending to a device.

pub mod file;
pub mod model;
pub mod wire;

pub use file::{Scene, SceneError, SceneProblem, SurfaceSpec};

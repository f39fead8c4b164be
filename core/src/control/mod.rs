//! The haptic control tick, from encoder counts to PWM duties.
//!
//! | module | what it holds |
//! | --- | --- |
//! | [`command`] | the operator commands and why one is refused |
//! | [`device_definition`] | [`device_definition::DeviceDefinition`]: everything a build needs to know about one device |
//! | [`controller`] | the controller tick: velocities, contact force, joint torques, duties |
//! | [`output_guard`] | the last check on every output: limits, faults, zero torque |
//! | [`pipeline`] | the one control pipeline the firmware and the simulator run |
//! | [`local_model`] | local models an application streams to the device |
//! | [`operator`] | the operator's button: what a press means in each mode |
//! | [`telemetry`] | the per-tick records the firmware logs and the host reads |

pub mod command;
pub mod controller;
pub mod device_definition;
pub mod local_model;
pub mod operator;
pub mod output_guard;
pub mod pipeline;
pub mod telemetry;

//! The host link, board-independent: bytes from any transport (the emulated board's UART, USB on
//! the STM32) → the protocol's frame decoder (`softfinger_protocol::DeviceEndpoint`) → requests →
//! the pipeline's commands, through the tick's command queue (the tick applies them at a tick
//! boundary); acknowledgements with typed error codes once the tick has applied (or refused)
//! them; device info; a state stream of the points the tick takes at the divisor the host asks for
//! (`crate::stream`); link counters.
//!
//! Nothing here runs in the tick or waits for it: requests reach the tick through its lock-free
//! command queue, the tick's stream points and command outcomes come back through lock-free queues the
//! low-priority tasks drain, and every byte out goes through [`tx::TxRing`], which drops a whole
//! frame (counted) rather than wait when the host stops reading.
//!
//! - [`requests`]: what each request becomes (a pipeline command, an answer, a typed refusal).
//! - [`acks`]: requests waiting for the tick's outcome, and the error code of a refusal.
//! - [`info`]: the device description.
//! - [`state`]: state samples from the tick's stream points.
//! - [`tx`]: the non-blocking byte ring a transport drains.
//! - [`session`]: one connection: the pieces above around the protocol's endpoint.
//! - `task`: the low-priority task that polls a byte transport (firmware builds only).
//!
//! These files use no HAL, executor or logging type, so host tests check them
//! (`tests/firmware_link.rs`).

pub mod acks;
pub mod info;
pub mod requests;
pub mod session;
pub mod state;
// The task needs the executor's timer and the tick's types: firmware builds only.
#[cfg(target_os = "none")]
pub mod task;
pub mod tx;

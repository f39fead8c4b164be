//! The softfinger firmware's app: everything that runs on the device and does not depend on the
//! board. Each board is a binary written against [`board`]'s traits that depends on this crate:
//! the NUCLEO-G474RE (`firmware/src/main.rs`), the emulated Cortex-M4F of the processor-in-the-loop
//! runs (`firmware/src/board/mps2`) and the instruction counter `firmware/tick-count`; the host
//! tests (`tests/firmware_link.rs`) use its host-link modules.
//!
//! - [`board`]: the hardware traits (what the control interrupt, the LED and the button offer).
//! - [`tick`]: the control tick (read -> control -> write) a board's highest-priority timer
//!   interrupt runs; [`isr_cell`] hands it its state without a lock; [`queues`], [`stream`],
//!   [`tap`]: what it exchanges with the tasks.
//! - [`logger`], [`supervisor`], [`operator`]: the low-priority tasks (telemetry log, fault report
//!   and blink code, the operator's button).
//! - [`link`]: the host link, transport-independent.
//! - [`persist`]: the device's flash behind the link: the settings store and the firmware update.
//! - [`scripted_app`]: the application session the processor-in-the-loop run plays (board and
//!   in-process reference alike).
//! - [`reset_cause`]: why the MCU last reset (logged, and in the device info).
//! - [`config`]: the device, the board timing, queue sizes and task periods.
//! - [`critical_section_basepri`], [`failsafe`]: the critical section and the fault handlers each
//!   board binary installs with its own mask and emergency stop.
//!
//! The control logic itself is `softfinger-core`, tested on the host.
#![no_std]
#![deny(unsafe_code)]

pub mod board;
pub mod boot_defaults;
pub mod config;
#[cfg(target_os = "none")]
#[allow(unsafe_code)] // implementing `critical_section::Impl` is unsafe by definition
pub mod critical_section_basepri;
#[cfg(target_os = "none")]
pub mod failsafe;
#[allow(unsafe_code)] // the lock-free handoff to the interrupt; each block justified in place
pub mod isr_cell;
pub mod link;
#[cfg(target_os = "none")]
pub mod logger;
#[cfg(target_os = "none")]
pub mod operator;
pub mod persist;
#[cfg(target_os = "none")]
pub mod queues;
pub mod reset_cause;
pub mod scripted_app;
pub mod stream;
pub mod stream_point;
#[cfg(target_os = "none")]
pub mod supervisor;
pub mod tap;
pub mod tick;

#[doc(hidden)]
pub mod __private {
    #[cfg(target_os = "none")]
    pub use cortex_m;
    #[cfg(target_os = "none")]
    pub use cortex_m_rt;
    pub use critical_section;
    #[cfg(feature = "defmt")]
    pub use defmt;
}

//! Shared pieces of the on-target programs that run on QEMU `mps2-an386` (an emulated Cortex-M4F):
//! the SysTick instruction counter ([`counter`]), the benchmark harness ([`bench`], the
//! [`bench!`] macro), the on-target check harness ([`check`]) and the semihosting reporting and exit
//! path ([`exit`], which also provides the panic handler), a homed, armed control pipeline
//! ([`rig`]), and sample messages and frames of the host link ([`link`]).
//!
//! Everything reports through semihosting, one record per line, so the host script
//! `scripts/mcu-bench` can parse it:
//!
//! ```text
//! BENCH <name> <backend> <instructions per call>
//! SANITY <name> <expected> <measured>
//! INFO <free text>
//! ```
#![no_std]

pub mod bench;
pub mod check;
pub mod counter;
pub mod exit;
pub mod link;
pub mod rig;
pub mod semiflash;

/// Short alias for [`core::hint::black_box`], for benchmark closures.
pub use core::hint::black_box as bb;

#[doc(hidden)]
pub use softfinger_core::Math as __Math;

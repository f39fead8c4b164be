//! What the app needs from a board (`softfinger_app::board`: the traits), and the board this binary
//! runs on.
//!
//! The app (`tick`, `logger`, `supervisor`, `operator`) is written against those traits only and
//! holds no HAL type, so the same app runs on the STM32G474 ([`stm32g474`]) and on the emulated
//! board (`board/mps2`).
//!
//! - `ControlHw`: everything the control interrupt touches. It is owned by that interrupt alone
//!   (see `isr_cell`), so its methods take `&mut self` and never lock.
//! - `Indicator` and `OperatorButton`: the LED and the user button, owned by low-priority tasks.
//! - Two board-specific items the fail-safe code needs: `emergency_stop` (zero the bridges from
//!   any context) and `BASEPRI_BELOW_TICK` (the critical section's mask).

#[allow(unsafe_code)]
// interrupt priorities, unmasking the tick, the tick's handoff; justified in place
pub mod stm32g474;

pub use softfinger_app::board::*;
pub use stm32g474::{emergency_stop, BASEPRI_BELOW_TICK};
